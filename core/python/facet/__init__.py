"""Facet: physically based reflection models and the Facet renderer, from Python.

The native extension ``facet._facet`` (pybind11) binds the C++ API with the same names in
snake_case: ``models()``, ``make_material()``, ``SceneDescription``, ``build_scene()``,
``load_scene()``, ``render()``, ``RenderSession``, ``RenderPart``, ``merge_parts()``,
``read_image()`` / ``write_image()``. Images are float32 numpy arrays of shape (h, w, 3), linear
RGB, row 0 at the top. See docs/python.md.
"""

from ._facet import *  # noqa: F401,F403
from ._facet import __version__  # noqa: F401

__all__ = [name for name in dir() if not name.startswith("_")]
