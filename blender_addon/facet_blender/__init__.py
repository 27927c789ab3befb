"""Facet render engine for Blender: the Facet core (physically based reflection models after
Cohen & Wallace, ch. 2) renders F12 stills and animations natively through the `facet` module."""
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

if "bpy" in locals():
    import importlib
    for _m in (native, units, properties, materials, export, importer, engine, ui, operators):  # noqa: F821
        importlib.reload(_m)
else:
    from . import native  # raises a NativeImportError that says what is missing
    from . import units, properties, materials, export, importer, engine, ui, operators

import bpy  # noqa: E402

_modules = (properties, engine, operators, ui)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
