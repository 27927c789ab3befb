"""Facet's properties: Scene.facet (render settings) and Material.facet (a material of the
core's model table, with the core's model and parameter names, built from facet.models() at
register time: no hand copy of the table)."""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)

from . import native


class FacetRenderSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(
        name="Integrator", default="path",
        items=[("path", "Path", "path tracing with next-event estimation and MIS"),
               ("direct", "Direct", "direct light with shadow rays plus perfect mirror recursion")])
    spp: IntProperty(name="Samples", default=16, min=1, max=1 << 20,
                     description="samples per pixel (with a time budget: the cap)")
    time_budget: FloatProperty(name="Time Budget", default=0.0, min=0.0, unit='TIME_ABSOLUTE',
                               description="seconds; > 0 renders until the budget is spent")
    max_depth: IntProperty(name="Max Bounces", default=8, min=0, max=1024)
    # Adaptive sampling (RenderOptions::adaptive_threshold): Cycles' Noise Threshold measure,
    # decided per tile of 16 x 16 pixels (docs/performance.md).
    adaptive_threshold: FloatProperty(
        name="Noise Threshold", default=0.0, min=0.0, max=1.0, precision=4,
        description="adaptive sampling: a 16 x 16 tile stops taking samples once its pixels' "
                    "noise estimate (as Cycles measures it) is below this on average (root mean "
                    "square) and nowhere 4 times above; 0 = off")
    adaptive_min_samples: IntProperty(
        name="Min Samples", default=0, min=0, max=1 << 20,
        description="adaptive sampling: samples every pixel takes first (0 = automatic)")
    # The path integrator's choice of the light for each shadow ray (RenderOptions::
    # light_selection). Auto, the default: the light tree with 12 or more lamps, else View;
    # View measures each light's contribution from the camera when the scene is built; Power is
    # pbrt's; Uniform is Cycles 3.4's for lamps; Tree the light tree (docs/blender.md;
    # bench/light_selection_bench.py).
    light_selection: EnumProperty(
        name="Light Selection", default="auto",
        items=[("auto", "Auto", "the light tree with 12 or more lamps, else View (measured: "
                                "docs/performance.md)"),
               ("view", "View", "choose the light for each shadow ray in proportion to its "
                                "contribution to what the camera sees (measured when the scene "
                                "is built)"),
               ("power", "Power", "choose the light for each shadow ray in proportion to its "
                                  "power"),
               ("uniform", "Uniform", "choose every light equally often, as Cycles 3.4 does "
                                      "for lamps"),
               ("tree", "Tree", "the light tree: per shaded point, by each lamp's bounds, "
                                "power and orientation (for many lamps)")])
    # What a lamp's Radius (point, spot) and the Sun's Angle become (sync_light.py): Cycles 3.4's
    # models, the default (Blender 3.4 renders them), or the physical ones (Cycles 4's sphere
    # lamp; a sun cone of uniform radiance keeping the irradiance), reported per lamp
    # (gaps.light_gaps; docs/blender.md).
    lamp_model: EnumProperty(
        name="Lamp Model", default="cycles34",
        items=[("cycles34", "Cycles 3.4", "a point or spot lamp's Radius is a disc facing each "
                                          "shaded point and the Sun's Angle darkens the sun, as "
                                          "Blender 3.4's Cycles renders them"),
               ("physical", "Physical", "a point or spot lamp's Radius is a sphere of uniform "
                                        "radiance (Cycles 4) and the Sun's Angle a cone of "
                                        "uniform radiance with the irradiance kept")])
    seed: IntProperty(name="Seed", default=0, min=0, description="sampler seed")
    denoise: BoolProperty(name="Denoise", default=False,
                          description="denoise the final render (feature-guided, no trained "
                                      "weights): two half-buffers and the albedo, normal and "
                                      "depth of the first hit; the image is then no longer an "
                                      "unbiased estimate and can blur detail no feature shows")
    viewport_spp: IntProperty(name="Viewport Samples", default=256, min=1, max=1 << 20,
                              description="samples per pixel the viewport refines to")
    # The viewport's adaptive sampling, apart from the final render's as Cycles keeps them
    # (its viewport Noise Threshold is off by default); Min Samples automatic.
    viewport_adaptive_threshold: FloatProperty(
        name="Viewport Noise Threshold", default=0.0, min=0.0, max=1.0, precision=4,
        description="adaptive sampling in the viewport (as Noise Threshold, Min Samples "
                    "automatic); 0 = off. Off while Denoise Viewport is on (its half-buffers "
                    "are sample ranges)")
    viewport_denoise: BoolProperty(name="Denoise Viewport", default=False,
                                   description="denoise the viewport image once refinement "
                                               "ends (all Viewport Samples done): the samples "
                                               "are rendered as two half-buffers, shown merged "
                                               "while refining")
    animated_seed: BoolProperty(name="Animated Seed", default=False,
                                description="add the frame number to the seed")
    bake: BoolProperty(name="Bake", default=True,
                       description="render node subgraphs Facet cannot express (procedural "
                                   "textures, ...) from images Blender bakes over the object's "
                                   "UV map (Bake Procedural Inputs)")
    bake_resolution: IntProperty(name="Bake Resolution", default=512, min=16, max=8192,
                                 description="width and height in pixels of each baked image")


# Material.facet is generated from the model table: for every model m and parameter p, a value
# property "m__p" and a flag "m__p__set" (only parameters the user set are passed to the core:
# the core rejects parameters that the chosen options make meaningless, e.g. ior with
# fresnel = conductor, and applies its own defaults to the rest).
MODELS = []


def _parse_default(ptype, text):
    """The table's default text ("0.5", "1.657 0.880 0.521", "none", "false", "-")."""
    if text in ("-", ""):
        return None
    if ptype == "colour":
        v = [float(x) for x in text.split()]
        return v * 3 if len(v) == 1 else v
    if ptype == "number":
        return float(text)
    if ptype == "bool":
        return text == "true"
    return text


def prop_name(model, param):
    return "%s__%s" % (model, param)


def _tag_material(settings, context):
    """Editing a Facet material setting tags its material: without the tag, the evaluated copy
    that the viewport and the exporter read keeps the old settings (evaluated_depsgraph_get()
    does not see a Material.facet value set from Python; tests/blender/test_materials.py)."""
    settings.id_data.update_tag()


def _make_material_props():
    global MODELS
    MODELS = native.models()
    ann = {
        "source": EnumProperty(
            update=_tag_material, name="Source", default="NODES",
            items=[("NODES", "Shader Nodes", "convert the Cycles node tree (Diffuse, Glossy, "
                    "Principled BSDF, Emission) or the viewport colour"),
                   ("FACET", "Facet Model", "a model of Facet's core, by its own parameters")]),
        "model": EnumProperty(update=_tag_material, name="Model",
                              items=[(m["name"], m["name"], m["summary"]) for m in MODELS]),
        "emission": FloatVectorProperty(update=_tag_material, name="Emission", subtype='COLOR',
                                        size=3, min=0.0, default=(0.0, 0.0, 0.0),
                                        description="emitted radiance (W sr^-1 m^-2)"),
        "two_sided": BoolProperty(update=_tag_material, name="Two Sided", default=True,
                                  description="the back reflects like the front; off: black"),
    }
    for m in MODELS:
        for p in m["params"]:
            name = prop_name(m["name"], p["name"])
            d = _parse_default(p["type"], p["default"])
            desc = p["doc"]
            common = dict(update=_tag_material, name=p["name"], description=desc)
            if p["type"] == "colour":
                ann[name] = FloatVectorProperty(subtype='COLOR', size=3,
                                                default=d or (0.0, 0.0, 0.0), soft_min=0.0,
                                                soft_max=1.0, **common)
            elif p["type"] == "number":
                ann[name] = FloatProperty(default=d or 0.0, precision=4, **common)
            elif p["type"] == "bool":
                ann[name] = BoolProperty(default=bool(d), **common)
            else:
                ann[name] = StringProperty(default=d or "", **common)
            ann[name + "__set"] = BoolProperty(
                update=_tag_material, name="Set %s" % p["name"], default=False,
                description="pass %s to the core (unset: the core's default)" % p["name"])
    return type("FacetMaterialSettings", (bpy.types.PropertyGroup,), {"__annotations__": ann})


def material_params(mat_settings):
    """Material.facet -> (model, {param: value}) with only the parameters that are set."""
    model = mat_settings.model
    params = {}
    for m in MODELS:
        if m["name"] != model:
            continue
        for p in m["params"]:
            name = prop_name(model, p["name"])
            if getattr(mat_settings, name + "__set"):
                v = getattr(mat_settings, name)
                params[p["name"]] = [float(c) for c in v] if p["type"] == "colour" else v
    return model, params


def set_material_params(mat_settings, model, params):
    """The inverse of material_params (JSON import)."""
    mat_settings.source = 'FACET'
    mat_settings.model = model
    for m in MODELS:
        if m["name"] != model:
            continue
        for p in m["params"]:
            if p["name"] in params:
                v = params[p["name"]]
                if isinstance(v, dict):
                    continue  # a texture: kept in the material's "facet_material" JSON
                if p["type"] == "colour" and isinstance(v, (int, float)):
                    v = [float(v)] * 3
                setattr(mat_settings, prop_name(model, p["name"]), v)
                setattr(mat_settings, prop_name(model, p["name"]) + "__set", True)


def _requery_passes(self, context):
    """The compositor's Render Layers node re-reads the engine's passes (Blender does this by
    itself for its own pass toggles)."""
    vl = getattr(context, "view_layer", None)
    if vl is not None and hasattr(vl, "update_render_passes"):
        vl.update_render_passes()


class FacetViewLayerSettings(bpy.types.PropertyGroup):
    use_pass_albedo: BoolProperty(
        name="Albedo", default=False, update=_requery_passes,
        description="Albedo pass: the directional albedo of the material seen by the camera "
                    "(the fraction of light from the viewer's direction it sends back)")


_classes = []


def register():
    mat_cls = _make_material_props()
    _classes[:] = [FacetRenderSettings, FacetViewLayerSettings, mat_cls]
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.facet = PointerProperty(type=FacetRenderSettings)
    bpy.types.Material.facet = PointerProperty(type=mat_cls)
    bpy.types.ViewLayer.facet = PointerProperty(type=FacetViewLayerSettings)


def unregister():
    del bpy.types.ViewLayer.facet
    del bpy.types.Material.facet
    del bpy.types.Scene.facet
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
    _classes.clear()
