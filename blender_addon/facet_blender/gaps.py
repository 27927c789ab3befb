"""What the addon does not convert exactly yet, in one place: every entry is a report line the
user sees (never a silent drop), and the entry to delete when Facet's core gains the feature.

- NODES: shader nodes the node-graph walker meets that are not converted, by bl_idname, with
  why (node_reason() adds the families: any other texture, any other shader).
- INPUTS: inputs of converted BSDF nodes that are converted only at one value, by (bl_idname,
  input name): (the value converted exactly, what Facet does otherwise). Inputs a converter
  does not read at all (Normal, Tangent, ...) are reported when linked (materials.py).
- LIGHTS: lamp settings the exporter ignores or approximates, by lamp type (LIGHTS_ALL: every
  type): (attribute, Blender's label, the value converted exactly, what Facet does otherwise).
- OBJECT_TYPES: what becomes of each Blender object type that the exporter does not turn into
  Facet shapes or lights.
- SETTINGS, OBJECT_FLAGS, LAMP_FLAGS, COLLECTION_FLAGS: scene, render, Cycles, view layer and
  world settings and per-object (per-lamp, per-collection) flags that change Cycles' image and
  are not converted: (path, Blender's label, the quiet values, what Facet does). Away from
  every quiet value (Blender's factory value, and the value Facet renders as Cycles does when
  there is one) the setting gives a report line.
- CONVERTED and UNCHANGED (UNCHANGED_PREFIXES): the other settings of the same structs, each
  with where it is converted or why it does not change the image;
  tests/blender/test_silent_drops.py walks Blender's properties and fails on one in none of
  these tables (classify()).
- CLIP_START, CLIP_END: the scene camera's clipping when it cuts an exported object off
  (export.ClipCheck).
"""

# Any other node, or a node nodevalues.py could not evaluate (an unknown mode, a math domain
# error).
UNKNOWN = "Facet does not convert this node yet"

# Converted textures (textures.py) feed colour inputs of Diffuse, Glossy, Glass, Refraction,
# Emission and Principled Base Color straight (or through reroutes and groups); on any other
# input (one the conversion computes with, such as Roughness -> alpha = Roughness^2), or
# through other nodes, they are reported with this reason.
TEXTURE_HERE = ("a texture converts only straight into a colour input of Diffuse, Glossy, "
                "Glass, Refraction, Emission or Principled Base Color")

VOLUME_ON_SURFACE = ("a volume shader converts only on a Material or World Output's Volume "
                     "(a homogeneous medium)")

NODES = {
    'ShaderNodeTexImage': TEXTURE_HERE,
    'ShaderNodeTexChecker': TEXTURE_HERE,
    'ShaderNodeTexEnvironment': "environment textures convert only as the world's "
                                "Background colour",
    # The Nishita type converts as the World's Background colour (sync_world.py, _world_sky);
    # node_reason names the other types.
    'ShaderNodeTexSky': "a Nishita Sky Texture converts only straight into the World's "
                        "Background (or Emission) Color, through Mapping rotations, with a "
                        "constant Strength",
    'ShaderNodeNormalMap': "a Normal Map converts only into a BSDF's Normal input (or a "
                           "Bump's Normal)",
    'ShaderNodeBump': "a Bump converts only into a BSDF's Normal input",
    'ShaderNodeDisplacement': "displacement is not converted; the mesh is rendered undisplaced",
    'ShaderNodeVectorDisplacement': "displacement is not converted; the mesh is rendered "
                                    "undisplaced",
    'ShaderNodeMixShader': "a shader converts only into a shader input",
    'ShaderNodeAddShader': "a shader converts only into a shader input",
    'ShaderNodeBsdfToon': "the toon BSDF is not in Facet's core",
    # Converted on a Volume output (materials.NodeContext.volume); on a Surface nothing
    # converts them.
    'ShaderNodeVolumeAbsorption': VOLUME_ON_SURFACE,
    'ShaderNodeVolumeScatter': VOLUME_ON_SURFACE,
    'ShaderNodeVolumePrincipled': VOLUME_ON_SURFACE,
    'ShaderNodeRGBCurve': "RGB Curves is not converted yet",
    'ShaderNodeMapping': "Mapping converts only between a UV map and a texture",
    'ShaderNodeTexCoord': "Texture Coordinate converts only as a texture's vector (or the "
                          "world's Generated)",
    'ShaderNodeUVMap': "UV Map converts only as a texture's vector",
    'ShaderNodeVertexColor': "a Color Attribute converts only as a texture (into a colour "
                             "or number input of a BSDF or an Emission, or a Mix Shader's "
                             "Fac)",
    'ShaderNodeAttribute': "attributes are not converted yet",
    'ShaderNodeFresnel': "the Fresnel node is not converted (Facet's Fresnel is a model "
                         "parameter)",
    'ShaderNodeLayerWeight': "Layer Weight is not converted",
    'ShaderNodeLightPath': "Light Path converts in a material's BSDF inputs and Mix Shader "
                           "factors (Is Shadow Ray only as a Mix Shader's Fac straight from "
                           "it); Transparent Depth, and uses in emissions, Alpha, normals or "
                           "the world, are not converted",
}

INPUTS = {
    ('ShaderNodeBsdfAnisotropic', 'Rotation'): (0.0, "tangent rotation is not converted; "
                                                     "ignored"),
    ('ShaderNodeVolumePrincipled', 'Blackbody Intensity'): (
        0.0, "blackbody emission (Temperature, Blackbody Tint) is not converted; the medium "
             "emits only Emission Strength x Emission Color"),
}

# With Lamp Model "Physical" (Scene.facet.lamp_model); with "Cycles 3.4", the default, both are
# converted exactly to the core's Cycles 3.4 models (radius_model, angle_model: no line).
RADIUS_NOTE = ("converted to a sphere of uniform radiance and the same power (Lamp Model "
               "Physical: Cycles 4, pbrt); Cycles 3.4 renders a disc facing each shaded point "
               "instead, d^2/(d^2+R^2) as bright at distance d (Lamp Model Cycles 3.4)")
SUN_ANGLE_NOTE = ("converted to a cone of uniform radiance with the irradiance kept (Lamp Model "
                  "Physical); Cycles 3.4's sun loses irradiance as the angle grows (x0.982 at "
                  "30 deg, x0.828 at 90 deg; Lamp Model Cycles 3.4)")
# The settings Lamp Model "Cycles 3.4" converts exactly.
LAMP_MODEL_ATTRS = ("shadow_soft_size", "angle")
# (attribute path, Blender's UI label, the value converted exactly, shown in degrees, what
# Facet does otherwise); Cycles' own light settings are under light.cycles.
LIGHTS = {
    # Radius (point, spot) and the Sun's Angle are converted (sync_light.py, _light_data) to
    # the core's Cycles 3.4 models; with Lamp Model "Physical" to the sphere light and the sun
    # cone, which differ from Cycles 3.4 (docs/blender.md): a non-zero value is then reported.
    'POINT': (("shadow_soft_size", "Radius", 0.0, False, RADIUS_NOTE),),
    'SPOT': (("shadow_soft_size", "Radius", 0.0, False, RADIUS_NOTE),),
    'SUN': (("angle", "Angle", 0.0, True, SUN_ANGLE_NOTE),),
    'AREA': (("spread", "Spread", 3.141592653589793, True,
              "ignored: the light emits into the full hemisphere (180 degrees)"),
             ("cycles.is_portal", "Portal", False, False,
              "portals are not in Facet's core: the lamp is exported as an emitter")),
}
# Every lamp type.
LIGHTS_ALL = (("cycles.cast_shadow", "Cast Shadow", True, False,
               "not in Facet's core: the light casts shadows"),
              ("cycles.max_bounces", "Max Bounces", 1024, False,
               "not in Facet's core: the scene's max depth applies"),
              ("use_nodes", "Use Nodes", False, False,
               "light node trees are not converted: Color x Power is used"))


def node_reason(node):
    """Why a node met by the walker is not converted (None: it has no entry)."""
    idname = node.bl_idname
    if idname == 'ShaderNodeTexSky' and getattr(node, "sky_type", 'NISHITA') != 'NISHITA':
        name = {'PREETHAM': "Preetham", 'HOSEK_WILKIE': "Hosek-Wilkie"}.get(node.sky_type,
                                                                           node.sky_type)
        return "the %s sky model is not in Facet's core (only Nishita converts)" % name
    if idname in NODES:
        return NODES[idname]
    if idname.startswith('ShaderNodeTex'):
        return "procedural textures are not in Facet's core yet"
    if idname.startswith(('ShaderNodeBsdf', 'ShaderNodeVolume')) or idname.startswith(
            'ShaderNodeEeveeSpecular'):
        return "this shader is not in Facet's core"
    return None


def volume_bounce_line(scene):
    """A line when the scene's media scatter and Cycles' Volume bounces are at their factory 0
    (single scattering in Cycles) while Facet's Max Bounces - 1 is not 0 (Facet counts a
    scattering event as a bounce: max_depth 1 is single scattering); other values are the
    SETTINGS row's. None otherwise."""
    c = getattr(scene, "cycles", None)
    if c is None or getattr(c, "volume_bounces", None) != 0 or _facet_bounces(scene, 0):
        return None
    return ("render: Light Paths > Max Bounces > Volume = 0: Cycles scatters once in a volume "
            "(single scattering); Facet's Max Bounces (%d) applies to media"
            % scene.facet.max_depth)


def volume_reason(node):
    """Why a node feeding a Volume output gives no medium."""
    idname = node.bl_idname
    if idname.startswith(('ShaderNodeBsdf', 'ShaderNodeSubsurface', 'ShaderNodeHoldout')) or \
            idname in ('ShaderNodeBackground', 'ShaderNodeEeveeSpecular'):
        return "a surface shader on a Volume output (Cycles makes no volume of it)"
    return node_reason(node) or UNKNOWN


def lamp_model_line(lights):
    """The report line (INFO) that says which lamp model the exported `lights` (the scene
    description's) use for a Radius or a Sun's Angle, or None when no lamp has a size: Cycles
    3.4's disc and sun sampling (Lamp Model "Cycles 3.4") or the physical sphere and cone
    ("Physical")."""
    sized = [lt for lt in lights if lt.get("radius", 0.0) > 0.0 or lt.get("angle", 0.0) > 0.0]
    if not sized:
        return None
    cycles34 = sum(1 for lt in sized if lt.get("radius_model") == "cycles34_disc" or
                   lt.get("angle_model") == "cycles34")
    physical = len(sized) - cycles34
    parts = []
    if cycles34:
        parts.append("%d as Cycles 3.4 renders them (a disc facing each shaded point; the sun's "
                     "angle as Cycles 3.4 samples it)" % cycles34)
    if physical:
        parts.append("%d as the physical sphere or cone (Cycles 4, pbrt)" % physical)
    return ("Lamp Model: of the lamps with a Radius or an Angle, " + "; ".join(parts) +
            " (Render Properties > Facet > Lamp Model)")


def light_gaps(light, lamp_model="cycles34"):
    """[(Blender's label, the value as shown, what Facet does)] for a Blender light's settings
    that are not converted exactly (Radius and Angle only with lamp_model "physical")."""
    out = []
    for attr, label, exact, degrees, what in LIGHTS.get(light.type, ()) + LIGHTS_ALL:
        if lamp_model == "cycles34" and attr in LAMP_MODEL_ATTRS:
            continue
        obj = light
        for part in attr.split(".")[:-1]:
            obj = getattr(obj, part, None)
        v = getattr(obj, attr.split(".")[-1], exact) if obj is not None else exact
        if isinstance(exact, bool) or isinstance(exact, int):
            if v != exact:
                out.append((label, str(v), what))
        elif abs(float(v) - exact) > 1e-6 * max(1.0, exact):
            shown = ("%.4g deg" % (float(v) * 57.29577951308232) if degrees
                     else "%.4g" % float(v))
            out.append((label, shown, what))
    return out


def _subject(line):
    """The subject a report line starts with ("material 'Wood'", "object 'Rock'", "light
    'Sun'", "world 'World'", "camera ...", "collection 'Props'", "view layer 'ViewLayer'"), or
    "scene" for the core's build warnings and the render settings."""
    head = line.split(": ", 1)[0]
    for kind in ("material", "object", "light", "world", "camera", "collection", "view layer"):
        if head.startswith(kind + " "):
            return head
    if head.startswith("blender") and "/materials/" in line:
        # the core's warning about a material: "blender: /materials/<name>: ..."
        name = line.split("/materials/", 1)[1].split(":", 1)[0].split("/", 1)[0]
        return "material '%s'" % name.replace("~1", "/").replace("~0", "~")
    return "scene"


def grouped(lines, users=None):
    """One render's report, grouped: [(subject, [lines])] in order of first appearance, each
    line once (a material converted for several objects, or an instanced object, says it
    once). A material's subject names the objects using it (`users`: material name -> object
    names) and counts them, e.g. "material 'Wood' (3 objects: Chair, Desk, Shelf)"."""
    groups, seen = {}, set()
    for line in lines:
        if line in seen:
            continue
        seen.add(line)
        groups.setdefault(_subject(line), []).append(line)
    out = []
    for subject, ls in groups.items():
        label = subject
        if subject.startswith("material '") and users:
            objs = sorted(users.get(subject[len("material '"):-1], ()))
            if objs:
                shown = ", ".join(objs[:5]) + (", ..." if len(objs) > 5 else "")
                label = "%s (%d object%s: %s)" % (subject, len(objs),
                                                 "" if len(objs) == 1 else "s", shown)
        out.append((label, ls))
    return out


def summary(groups):
    """A one-line count of a grouped report: "7 notes: material 'Wood' (3 objects: ...) 2,
    object 'Rock' 1, ..."."""
    n = sum(len(ls) for _, ls in groups)
    return "%d conversion note%s: %s" % (n, "" if n == 1 else "s",
                                         ", ".join("%s %d" % (s, len(ls)) for s, ls in groups))


# --- object types, settings and flags (export.py: scene_lines, object_lines) -----------------

# Object types the exporter does not turn into shapes or lights (export.GEOMETRY_TYPES, LIGHT)
# -> the report line, or None: Cycles renders nothing of it either (or Blender draws it
# itself), so there is nothing to convert.
OBJECT_TYPES = {
    # Converted by sync_hair.py (curves shapes); what is not, it reports.
    'CURVES': None,
    'POINTCLOUD': "point clouds are not in Facet's core yet; not rendered",
    # Converted by sync_volume.py (a grid medium in a null box); what is not, it reports.
    'VOLUME': None,
    # Blender draws grease pencil over any render engine's final result, Facet's as Cycles'
    # (source/blender/render/intern/engine.cc: DRW_render_gpencil after the engine's render).
    'GPENCIL': None,
    'EMPTY': None, 'ARMATURE': None, 'LATTICE': None, 'LIGHT_PROBE': None, 'SPEAKER': None,
    'CAMERA': None,
}
# A type that is in none of the tables (a newer Blender's).
UNKNOWN_TYPE = "object type %s is not known to Facet's exporter; not rendered"


MOTION = "motion blur (sync_motion.py: shutter, position, curve, motion steps)"
VOLUME_STEPS = ("Cycles' ray marching of heterogeneous volumes (grids; textured inputs are "
                "reported): its step's bias; Facet tracks grids without bias, and homogeneous "
                "media render alike in both")
ONLY_FAST_GI = "only with Fast GI Approximation, which is reported"
ONLY_ADAPTIVE = "only with an object's Adaptive Subdivision, which is reported"
NOISE = ("Cycles' sampling and noise: Facet's own samples, seed and time limit "
         "(Render Properties > Facet) apply")
DEVICE = "Cycles' device, memory and speed: not the image"
OUTPUT = "saving and stamping the result (Blender): not the rendered image"
BAKE = "baking (Render > Bake), not rendering"
PASS = "a render pass, not the Combined image (Facet's passes: docs/blender.md)"
EEVEE = "Eevee's and Workbench's setting; Cycles does not read it"
POST = "post-processing Blender applies to any engine's result"


def _facet_bounces(scene, v):
    """Whether Cycles' bounces `v` are Facet's depth: max_depth - 1 bounces (as
    tests/support/python/facet_testsupport/cycles_scene.py matches Cycles to Facet)."""
    fs = getattr(scene, "facet", None)
    return fs is not None and v == fs.max_depth - 1


def _bounces(attr, label, factory):
    return ("cycles." + attr, "Light Paths > Max Bounces > " + label, (factory, _facet_bounces),
            "Facet's own Max Bounces (Render Properties > Facet) applies to every ray")


# (path from the scene ("view_layer." from the view layer), Blender's label, the quiet values
# (a value, or a tuple of values and of callables (scene, value) -> bool), what Facet does).
SETTINGS = (
    ("cycles.film_transparent_glass", "Film > Transparent > Transparent Glass",
     (False, lambda scene, v: not scene.render.film_transparent),
     "not converted: glass and other transmission are opaque in Facet's alpha channel (the "
     "world seen through them stays in the colour)"),
    ("cycles.rolling_shutter_type", "Motion Blur > Rolling Shutter", 'NONE',
     "not converted: every row of the image is exposed over the same shutter interval"),
    ("render.use_multiview", "Stereoscopy", False,
     "not converted: every view renders the scene camera"),
    ("cycles.film_exposure", "Film > Exposure", 1.0,
     "not converted: the image is rendered at exposure 1 (Color Management > Exposure "
     "applies to Facet's image too)"),
    ("cycles.pixel_filter_type", "Film > Pixel Filter", ('BLACKMAN_HARRIS', 'BOX'),
     "Facet's pixel filter is a box of one pixel"),
    ("cycles.filter_width", "Film > Pixel Filter > Width", (1.5, 1.0),
     "Facet's pixel filter is a box of one pixel"),
    ("cycles.caustics_reflective", "Light Paths > Caustics > Reflective", True,
     "Facet renders reflective caustics"),
    ("cycles.caustics_refractive", "Light Paths > Caustics > Refractive", True,
     "Facet renders refractive caustics"),
    ("cycles.blur_glossy", "Light Paths > Caustics > Filter Glossy", (1.0, 0.0),
     "Facet does not blur glossy reflections after a diffuse or rough bounce"),
    ("cycles.sample_clamp_direct", "Light Paths > Clamping > Direct Light", 0.0,
     "Facet does not clamp samples"),
    ("cycles.sample_clamp_indirect", "Light Paths > Clamping > Indirect Light", (10.0, 0.0),
     "Facet does not clamp samples"),
    _bounces("max_bounces", "Total", 12), _bounces("diffuse_bounces", "Diffuse", 4),
    _bounces("glossy_bounces", "Glossy", 4),
    _bounces("transmission_bounces", "Transmission", 12),
    _bounces("volume_bounces", "Volume", 0),
    _bounces("transparent_max_bounces", "Transparent", 8),
    ("cycles.use_fast_gi", "Light Paths > Fast GI Approximation", False,
     "not in Facet's core: full global illumination"),
    ("cycles.texture_limit_render", "Simplify > Render > Texture Limit", 'OFF',
     "not converted: Facet reads the images at full resolution"),
    ("view_layer.use_solid", "View Layer > Filter > Surfaces", True,
     "not converted: Facet renders the surfaces"),
    ("view_layer.use_sky", "View Layer > Filter > Environment", True,
     "not converted: camera rays see the world"),
    ("view_layer.material_override", "View Layer > Material Override", None,
     "not converted: the objects' own materials are rendered"),
    ("world.cycles.max_bounces", "World > Settings > Max Bounces", 1024,
     "not in Facet's core: the scene's max depth applies"),
    ("world.cycles.is_caustics_light", "World > Settings > Shadow Caustics", False,
     "shadow caustics (MNEE) are not in Facet's core"),
    ("world.cycles_visibility.camera", "World > Ray Visibility > Camera", True,
     "per-ray visibility is not in Facet's core yet: camera rays see the world"),
    ("world.cycles_visibility.diffuse", "World > Ray Visibility > Diffuse", True,
     "per-ray visibility is not in Facet's core yet: diffuse rays see the world"),
    ("world.cycles_visibility.glossy", "World > Ray Visibility > Glossy", True,
     "per-ray visibility is not in Facet's core yet: glossy rays see the world"),
    ("world.cycles_visibility.transmission", "World > Ray Visibility > Transmission", True,
     "per-ray visibility is not in Facet's core yet: transmitted rays see the world"),
    ("world.cycles_visibility.scatter", "World > Ray Visibility > Volume Scatter", True,
     "per-ray visibility is not in Facet's core yet"),
    ("world.cycles_visibility.shadow", "World > Ray Visibility > Shadow", True,
     "per-ray visibility is not in Facet's core yet"),
)

# Per object (any type exported as shapes): (attribute path, Blender's label, quiet, what
# Facet does). Ray Visibility is converted (the shape's "visibility", export.ray_visibility)
# except on volume objects (VOLUME_RAY_FLAGS).
RAY = "per-object ray visibility is not converted for volume objects: the volume is seen by %s"
VOLUME_RAY_FLAGS = (
    ("visible_camera", "Visibility > Ray Visibility > Camera", True, RAY % "camera rays"),
    ("visible_diffuse", "Visibility > Ray Visibility > Diffuse", True, RAY % "diffuse rays"),
    ("visible_glossy", "Visibility > Ray Visibility > Glossy", True, RAY % "glossy rays"),
    ("visible_transmission", "Visibility > Ray Visibility > Transmission", True,
     RAY % "transmitted rays"),
    ("visible_volume_scatter", "Visibility > Ray Visibility > Volume Scatter", True,
     RAY % "volume-scatter rays"),
    ("visible_shadow", "Visibility > Ray Visibility > Shadow", True,
     RAY % "shadow rays (it casts shadows)"),
)
OBJECT_FLAGS = (
    ("cycles.use_camera_cull", "Visibility > Culling > Camera Cull", False,
     "culling is not converted: Facet renders the whole object"),
    ("cycles.use_distance_cull", "Visibility > Culling > Distance Cull", False,
     "culling is not converted: Facet renders the whole object"),
    ("cycles.use_adaptive_subdivision", "Adaptive Subdivision", False,
     "not converted: the mesh is rendered as Blender evaluates it"),
    ("cycles.shadow_terminator_offset", "Shading > Shadow Terminator > Shading Offset", 0.0,
     "not in Facet's core"),
    ("cycles.shadow_terminator_geometry_offset",
     "Shading > Shadow Terminator > Geometry Offset", 0.1, "not in Facet's core"),
    ("cycles.is_caustics_caster", "Shading > Caustics > Cast Shadow Caustics", False,
     "shadow caustics (MNEE) are not in Facet's core"),
    ("cycles.is_caustics_receiver", "Shading > Caustics > Receive Shadow Caustics", False,
     "shadow caustics (MNEE) are not in Facet's core"),
)
def emitter_visibility_line(name, visibility):
    """The report line of an emitting object with Diffuse or Glossy visibility off (but not
    both, with Transmission): its light samples skip purely diffuse / glossy materials as
    Cycles' do, and light materials of both kinds whole (FORMAT.md "Ray visibility")."""
    off = [k for k in ("diffuse", "glossy") if k in visibility]
    if not off or all(k in visibility for k in ("diffuse", "glossy", "transmission")):
        return None
    return ("object '%s': an emitter with Visibility > Ray Visibility > %s off: its light "
            "samples skip purely %s materials as Cycles 3.4 does, but light materials with "
            "both diffuse and glossy closures (Principled, Mix Shaders of both) whole, where "
            "Cycles keeps only the other closures' share"
            % (name, " and ".join(k.capitalize() for k in off), " or ".join(off)))


# Per lamp object: Facet's lamps are seen by camera rays only as area lamps with Camera on
# (converted: camera_visible), and by no reflected ray (FORMAT.md); they light every surface.
LAMP = "per-lamp ray visibility is not in Facet's core yet: the lamp lights %s"
LAMP_FLAGS = (
    ("visible_camera", "Visibility > Ray Visibility > Camera", (False, lambda obj, v:
                                                              obj.data.type == 'AREA'),
     "Facet's point, spot and sun lamps are not seen by camera rays"),
    ("visible_diffuse", "Visibility > Ray Visibility > Diffuse", True,
     LAMP % "diffuse surfaces"),
    ("visible_glossy", "Visibility > Ray Visibility > Glossy", True,
     LAMP % "glossy surfaces"),
    ("visible_transmission", "Visibility > Ray Visibility > Transmission", True,
     LAMP % "through transmission"),
    ("visible_volume_scatter", "Visibility > Ray Visibility > Volume Scatter", True,
     "per-lamp ray visibility is not in Facet's core yet"),
    # Blender makes every lamp object a shadow catcher; Cycles leaves a lamp without the flag
    # out of the catcher-only light (its shadows on a catcher are not caught).
    ("is_shadow_catcher", "Visibility > Shadow Catcher", True,
     "not converted: the lamp lights Facet's shadow catchers as every lamp does (Cycles leaves "
     "it out of what a catcher would receive unshadowed, so its shadows are not caught)"),
)
# Per collection of the view layer (its layer collection's restriction toggles).
COLLECTION_FLAGS = (
    ("indirect_only", "Indirect Only", False,
     "not in Facet's core: its objects are seen by camera rays too"),
)

# Settings of the same structs that are converted (where) ...
CONVERTED = {
    "render.resolution_x": "the camera's width (export_camera)",
    "render.resolution_y": "the camera's height (export_camera)",
    "render.resolution_percentage": "the camera's width and height (export_camera)",
    "render.pixel_aspect_x": "reported by export_camera when not square",
    "render.pixel_aspect_y": "reported by export_camera when not square",
    "render.use_border": "the render region (final.py, pixels.border_rect)",
    "render.border_min_x": "the render region (final.py, pixels.border_rect)",
    "render.border_min_y": "the render region (final.py, pixels.border_rect)",
    "render.border_max_x": "the render region (final.py, pixels.border_rect)",
    "render.border_max_y": "the render region (final.py, pixels.border_rect)",
    "object.hide_render": "Blender's render depsgraph leaves the object out",
    "collection.exclude": "Blender's render depsgraph leaves the collection out",
    "lamp.visible_camera": "an area lamp's camera_visible (export.py, _area_light)",
    "render.film_transparent": "the alpha channel (export_render_settings: the scene's "
                               "render.film_transparent)",
    "object.is_holdout": "the shape's holdout (export.py, _is_holdout)",
    "object.is_shadow_catcher": "the shape's shadow_catcher (export.py, _is_shadow_catcher)",
    "object.visible_camera": "the shape's visibility (export.py, ray_visibility)",
    "object.visible_diffuse": "the shape's visibility (export.py, ray_visibility)",
    "object.visible_glossy": "the shape's visibility (export.py, ray_visibility)",
    "object.visible_transmission": "the shape's visibility (export.py, ray_visibility)",
    "object.visible_volume_scatter": "the shape's visibility (export.py, ray_visibility)",
    "object.visible_shadow": "the shape's visibility (export.py, ray_visibility)",
    "collection.holdout": "its objects' shapes are holdouts (export.py, holdout_objects)",
    "view_layer.cycles.use_pass_shadow_catcher": "the Shadow Catcher pass, and Cycles' "
                                                 "Combined pass with it (passes.py, final.py)",
    "render.use_motion_blur": MOTION, "render.motion_blur_shutter": MOTION,
    "render.motion_blur_shutter_curve": MOTION, "cycles.motion_blur_position": MOTION,
}
# ... or do not change the image (why).
UNCHANGED = {
    "render.preview_pixel_size": "the viewport's drawing resolution",
    "render.fps": "animation timing: Blender sets the frame, Facet renders it",
    "render.fps_base": "animation timing: Blender sets the frame, Facet renders it",
    "render.frame_map_old": "animation timing: Blender sets the frame, Facet renders it",
    "render.frame_map_new": "animation timing: Blender sets the frame, Facet renders it",
    "render.dither_intensity": POST,
    "render.filter_size": EEVEE,
    "render.use_freestyle": "Blender draws Freestyle strokes over any engine's result",
    "render.line_thickness_mode": "Freestyle (drawn by Blender)",
    "render.line_thickness": "Freestyle (drawn by Blender)",
    "render.threads": "the number of threads (final.py passes it on), not the image",
    "render.threads_mode": "the number of threads (final.py passes it on), not the image",
    "render.hair_type": EEVEE, "render.hair_subdiv": EEVEE,
    "render.use_high_quality_normals": EEVEE,
    "render.use_crop_to_border": "Blender crops the result to the render region",
    "render.use_placeholder": OUTPUT, "render.use_overwrite": OUTPUT,
    "render.use_file_extension": OUTPUT, "render.filepath": OUTPUT,
    "render.use_render_cache": OUTPUT, "render.use_lock_interface": "the user interface",
    "render.use_compositing": POST, "render.use_sequencer": POST,
    "render.metadata_input": OUTPUT, "render.stamp_note_text": OUTPUT,
    "render.stamp_font_size": OUTPUT, "render.stamp_foreground": OUTPUT,
    "render.stamp_background": OUTPUT,
    "render.sequencer_gl_preview": "the sequencer's preview",
    "render.use_sequencer_override_scene_strip": "the sequencer's preview",
    "render.use_single_layer": "which view layers Blender renders",
    "render.views_format": "only with Stereoscopy, which is reported",
    "render.engine": "the render engine itself",
    "render.use_simplify": "Blender's depsgraph applies it to the meshes Facet exports",
    "render.simplify_subdivision_render": "Blender's depsgraph applies it to the meshes "
                                          "Facet exports",
    "render.simplify_subdivision": "the viewport's", "render.simplify_child_particles":
    "the viewport's", "render.simplify_child_particles_render":
    "Blender's depsgraph applies it to the child hairs Facet exports",
    "render.simplify_volumes": VOLUME_STEPS,
    "render.use_persistent_data": DEVICE,
    "cycles.device": DEVICE, "cycles.feature_set": ONLY_ADAPTIVE,
    "cycles.shading_system": "Open Shading Language runs the same nodes",
    "cycles.preview_pause": "the viewport's",
    "cycles.film_transparent_roughness": "only with Transparent Glass, which is reported",
    "cycles.rolling_shutter_duration": "only with Motion Blur > Rolling Shutter, which is "
                                       "reported",
    "cycles.fast_gi_method": ONLY_FAST_GI, "cycles.ao_bounces_render": ONLY_FAST_GI,
    "cycles.ao_bounces": "the viewport's Fast GI",
    "cycles.texture_limit": "the viewport's",
    "cycles.use_camera_cull": "acts through objects' Camera Cull, reported per object",
    "cycles.use_distance_cull": "acts through objects' Distance Cull, reported per object",
    "cycles.camera_cull_margin": "acts through objects' Camera Cull, reported per object",
    "cycles.distance_cull_margin": "acts through objects' Distance Cull, reported per object",
    "cycles.dicing_rate": ONLY_ADAPTIVE, "cycles.preview_dicing_rate": ONLY_ADAPTIVE,
    "cycles.max_subdivisions": ONLY_ADAPTIVE, "cycles.dicing_camera": ONLY_ADAPTIVE,
    "cycles.offscreen_dicing_scale": ONLY_ADAPTIVE,
    "cycles.volume_step_rate": VOLUME_STEPS, "cycles.volume_preview_step_rate": VOLUME_STEPS,
    "cycles.volume_max_steps": VOLUME_STEPS,
    "cycles.bake_type": BAKE,
    "cycles_curves.shape": "only with hair, whose curves' profile it sets (sync_hair.py: "
                           "Rounded Ribbons flat, 3D Curves round)",
    "cycles_curves.subdivisions": "Cycles' own curve intersector's subdivision; Embree's "
                                  "(Cycles' on the CPU, and Facet's) traces the curves",
    "view_layer.samples": NOISE, "view_layer.pass_alpha_threshold": PASS,
    "view_layer.active_aov_index": "the user interface",
    "view_layer.active_lightgroup_index": "the user interface",
    "view_layer.active_layer_collection": "the user interface",
    "view_layer.use_ao": EEVEE,
    "view_layer.use_strand": "off, Cycles renders no hair either (then no hair is exported)",
    "view_layer.use_volumes": "off, Cycles renders no volumes either (then no volume object "
                              "is reported)",
    "view_layer.use_motion_blur": MOTION,
    "view_layer.use": "which view layers Blender renders",
    "view_layer.use_freestyle": "Freestyle (drawn by Blender)",
    "view_layer.cycles.use_denoising": NOISE,
    "view_layer.cycles.denoising_store_passes": PASS,
    "world.cycles.sampling_method": NOISE, "world.cycles.sample_map_resolution": NOISE,
    "world.cycles.homogeneous_volume": VOLUME_STEPS,
    "world.cycles.volume_sampling": VOLUME_STEPS,
    "world.cycles.volume_interpolation": VOLUME_STEPS,
    "world.cycles.volume_step_size": VOLUME_STEPS,
    "world.light_settings.use_ambient_occlusion": ONLY_FAST_GI,
    "world.light_settings.ao_factor": ONLY_FAST_GI,
    "world.light_settings.distance": ONLY_FAST_GI,
    "object.cycles.use_motion_blur": "read with Motion Blur for objects that move "
                                     "(sync_motion.py); a still object renders alike",
    "object.cycles.motion_steps": "read with Motion Blur for objects that move "
                                  "(sync_motion.py); a still object renders alike",
    "object.cycles.use_deform_motion": "read with Motion Blur for objects that deform "
                                       "(sync_motion.py); a still mesh renders alike",
    "object.cycles.dicing_rate": ONLY_ADAPTIVE,
    "object.cycles.ao_distance": ONLY_FAST_GI,
    "collection.hide_viewport": "the viewport's",
    "lamp.visible_shadow": "Cast Shadow (Light > Settings) is the lamp's own, reported there",
    "lamp.is_holdout": "Cycles applies it to geometry only (Object > Visibility shows it for "
                       "none of a lamp's)",
}
for _k in ("samples", "preview_samples", "sample_offset", "time_limit", "sampling_pattern",
           "scrambling_distance", "preview_scrambling_distance", "auto_scrambling_distance",
           "use_layer_samples", "light_sampling_threshold", "use_adaptive_sampling",
           "adaptive_threshold", "adaptive_min_samples", "use_preview_adaptive_sampling",
           "preview_adaptive_threshold", "preview_adaptive_min_samples",
           "direct_light_sampling_type", "min_light_bounces", "min_transparent_bounces",
           "seed", "use_animated_seed", "use_denoising", "denoiser", "denoising_prefilter",
           "denoising_input_passes", "use_preview_denoising", "preview_denoiser",
           "preview_denoising_prefilter", "preview_denoising_input_passes",
           "preview_denoising_start_sample", "use_guiding", "use_deterministic_guiding",
           "guiding_distribution_type", "use_surface_guiding", "surface_guiding_probability",
           "use_volume_guiding", "guiding_training_samples", "volume_guiding_probability",
           "use_guiding_direct_light", "use_guiding_mis_weights"):
    UNCHANGED["cycles." + _k] = NOISE
for _k in ("use_auto_tile", "tile_size", "debug_bvh_type", "debug_use_spatial_splits",
           "debug_use_hair_bvh", "debug_use_compact_bvh", "debug_bvh_time_steps",
           "debug_use_cpu_avx2", "debug_use_cpu_avx", "debug_use_cpu_sse41",
           "debug_use_cpu_sse3", "debug_use_cpu_sse2", "debug_bvh_layout",
           "debug_use_cuda_adaptive_compile", "debug_use_optix_debug"):
    UNCHANGED["cycles." + _k] = DEVICE


def _resolve(root, path):
    """(the struct holding the path's last attribute, the attribute), or (None, name)."""
    parts = path.split(".")
    for part in parts[:-1]:
        root = getattr(root, part, None) if root is not None else None
    return root, parts[-1]


def quiet(value, quiets, owner):
    """Whether `value` is one of the quiet values (a value, or a tuple of values and of
    callables (owner, value) -> bool)."""
    for q in (quiets if isinstance(quiets, tuple) else (quiets,)):
        if callable(q):
            if q(owner, value):
                return True
        elif isinstance(q, float) and isinstance(value, (int, float)):
            if abs(value - q) <= 1e-6 * max(1.0, abs(q)):
                return True
        elif value == q:
            return True
    return False


def _shown(v):
    if isinstance(v, bool):
        return "on" if v else "off"
    if isinstance(v, float):
        return "%.4g" % v
    if isinstance(v, str):
        return v.replace("_", " ").title()
    if v is None:
        return "none"
    return getattr(v, "name", str(v))


def _flag_lines(owner, table, subject):
    out = []
    for path, label, quiets, what in table:
        struct, attr = _resolve(owner, path)
        if struct is None or not hasattr(struct, attr):
            continue
        v = getattr(struct, attr)
        if not quiet(v, quiets, owner):
            out.append("%s: %s = %s: %s" % (subject, label, _shown(v), what))
    return out


def scene_lines(scene, view_layer):
    """Report lines for the scene's render, Cycles, view layer and world settings (SETTINGS)
    away from their quiet values, and for its collections' flags (COLLECTION_FLAGS)."""
    lines = []
    for path, label, quiets, what in SETTINGS:
        if path.startswith("view_layer."):
            struct, attr = _resolve(view_layer, path[len("view_layer."):])
        else:
            struct, attr = _resolve(scene, path)
        if struct is None or not hasattr(struct, attr):
            continue
        v = getattr(struct, attr)
        if not quiet(v, quiets, scene):
            subject = ("world '%s'" % scene.world.name if path.startswith("world.")
                       else "view layer '%s'" % view_layer.name
                       if path.startswith("view_layer.") else "render")
            lines.append("%s: %s = %s: %s" % (subject, label, _shown(v), what))

    def walk(lc):
        for child in lc.children:
            if not child.exclude:
                lines.extend(_flag_lines(child, COLLECTION_FLAGS,
                                         "collection '%s'" % child.name))
                walk(child)
    walk(view_layer.layer_collection)
    return lines


def object_lines(obj, view_layer):
    """Report lines for one object (the original): its type when not exported
    (OBJECT_TYPES), its flags (OBJECT_FLAGS, LAMP_FLAGS) away from their quiet values and its
    particle hair (converted by sync_hair.py, which reports what is not)."""
    subject = "object '%s'" % obj.name
    if obj.type == 'LIGHT':
        return _flag_lines(obj, LAMP_FLAGS, "light '%s'" % obj.name)
    lines = []
    flags = OBJECT_FLAGS
    if obj.type == 'VOLUME':  # converted (sync_volume.py): its flags as a mesh's
        if not view_layer.use_volumes:
            return lines
        # Not exported without Camera, Diffuse, Glossy and Shadow (export.py).
        if (obj.visible_camera or obj.visible_diffuse or obj.visible_glossy
                or obj.visible_shadow):
            flags = VOLUME_RAY_FLAGS + OBJECT_FLAGS
        elif obj.visible_transmission or obj.visible_volume_scatter:
            lines.append("%s: a volume seen only by transmission or volume-scatter rays: not "
                         "exported (Cycles shows it through glass and in volumes)" % subject)
    elif obj.type not in ('MESH', 'CURVE', 'SURFACE', 'META', 'FONT', 'CURVES'):  # exported
        if obj.type in OBJECT_TYPES:
            what = OBJECT_TYPES[obj.type]
        else:
            what = UNKNOWN_TYPE % obj.type
        if what is None:
            return lines
        if obj.type == 'CURVES' and not view_layer.use_strand:
            return lines
        lines.append("%s: %s" % (subject, what))
    lines.extend(_flag_lines(obj, flags, subject))
    return lines


def component_lines(obj, view_layer):
    """Report lines for an evaluated geometry component whose type differs from its object's
    (a point cloud or volume made by geometry nodes from a mesh, ...): OBJECT_TYPES' line for
    its type, naming the object."""
    what = OBJECT_TYPES.get(obj.type, UNKNOWN_TYPE % obj.type) \
        if obj.type not in ('MESH', 'CURVE', 'SURFACE', 'META', 'FONT', 'LIGHT') else None
    if what is None or obj.type == 'CURVES' or (
            obj.type == 'VOLUME' and not view_layer.use_volumes):
        return []
    return ["object '%s': its evaluated geometry has a %s component (geometry nodes): %s"
            % (obj.original.name, obj.type.lower().replace("pointcloud", "point cloud"), what)]


# The scene camera's clipping (export.py, ClipCheck): Facet's camera clips nothing. A line when
# an exported object's bounding box reaches past Clip End, or nearer than a Clip Start raised
# above Blender's factory 0.1, along the view axis (where Cycles' clipping planes are).
CLIP_START_FACTORY = 0.1
CLIP_END = ("Clip End", "Cycles cuts off what lies farther; Facet's camera does not clip")
CLIP_START = ("Clip Start", "Cycles cuts off what lies nearer; Facet's camera does not clip")


# Whole families of the same structs that do not change the image, by path prefix.
UNCHANGED_PREFIXES = {
    "render.use_stamp": OUTPUT, "render.bake_": BAKE, "render.use_bake_": BAKE,
    "render.simplify_gpencil": "grease pencil (drawn by Blender)",
    "view_layer.use_pass_": PASS, "view_layer.pass_cryptomatte_": PASS,
    "view_layer.cycles.use_pass_": PASS, "view_layer.cycles.pass_": PASS,
    # Colour management: Blender maps the linear Combined pass of any engine for display and
    # for saving.
    "view_settings.": POST, "display_settings.": POST,
}


def classify(path):
    """What becomes of a setting or flag, by its path in these tables ("object.", "lamp." and
    "collection." for OBJECT_FLAGS, LAMP_FLAGS, COLLECTION_FLAGS): a list of ("reported",
    label) / ("converted", where) / ("unchanged", why); empty when it is in no table."""
    out = []
    for prefix, table in (("", SETTINGS), ("object.", OBJECT_FLAGS), ("lamp.", LAMP_FLAGS),
                          ("collection.", COLLECTION_FLAGS)):
        out.extend(("reported", label) for p, label, _, _ in table if prefix + p == path)
    if path in CONVERTED:
        out.append(("converted", CONVERTED[path]))
    if path in UNCHANGED:
        out.append(("unchanged", UNCHANGED[path]))
    out.extend(("unchanged", why) for prefix, why in UNCHANGED_PREFIXES.items()
               if path.startswith(prefix))
    return out
