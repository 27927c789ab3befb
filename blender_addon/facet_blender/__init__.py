"""Facet render engine for Blender: the Facet core (physically based reflection models after
Cohen & Wallace, ch. 2) renders F12 stills and animations natively through the `facet` module.

This module holds bl_info and the registration; each other module says its job in its own
docstring."""
bl_info = {
    "name": "Facet",
    "author": "Facet",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > Facet; File > Import/Export > Facet scene",
    "description": "Facet render engine: Lambert, mirror, Blinn, Beckmann and GGX models "
                   "rendered natively by the Facet core",
    "category": "Render",
}

# The modules, each after the ones it imports (reloaded in this order by F8 / "Reload Scripts").
# hooks: what tests read; native: the core; export: depsgraph -> scene data; final and
# viewport: the two render sessions; engine: the RenderEngine that hands modes to them.
if "bpy" in locals():
    import importlib
    for _m in _all:  # noqa: F821
        importlib.reload(_m)
else:
    from . import native  # raises a NativeImportError that says what is missing
    from . import (hooks, units, pixels, properties, materials, export, importer, final,
                   viewport, engine, plot, ui, operators)
    _all = (hooks, native, units, pixels, properties, materials, export, importer, final,
            viewport, engine, plot, ui, operators)

import bpy  # noqa: E402,F401  (the marker the reload test above looks for)

# Registered in this order, unregistered in reverse.
_modules = (properties, engine, operators, ui)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
