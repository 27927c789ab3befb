"""What the addon does not convert exactly yet, in one place: every entry is a report line the
user sees (never a silent drop), and the entry to delete when Facet's core gains the feature.

- NODES: shader nodes the node-graph walker meets that are not converted, by bl_idname, with
  why (node_reason() adds the families: any other texture, any other shader).
- INPUTS: inputs of converted BSDF nodes that are converted only at one value, by (bl_idname,
  input name): (the value converted exactly, what Facet does otherwise). Inputs a converter
  does not read at all (Normal, Tangent, ...) are reported when linked (materials.py).
- LIGHTS: lamp settings the exporter ignores or approximates, by lamp type (LIGHTS_ALL: every
  type): (attribute, Blender's label, the value converted exactly, what Facet does otherwise).
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

NODES = {
    'ShaderNodeTexImage': TEXTURE_HERE,
    'ShaderNodeTexChecker': TEXTURE_HERE,
    'ShaderNodeTexEnvironment': "environment textures convert only as the world's "
                                "Background colour",
    'ShaderNodeTexSky': "sky textures are not in Facet's core yet",
    'ShaderNodeNormalMap': "a Normal Map converts only into a BSDF's Normal input (or a "
                           "Bump's Normal)",
    'ShaderNodeBump': "a Bump converts only into a BSDF's Normal input",
    'ShaderNodeDisplacement': "displacement is not converted; the mesh is rendered undisplaced",
    'ShaderNodeVectorDisplacement': "displacement is not converted; the mesh is rendered "
                                    "undisplaced",
    'ShaderNodeMixShader': "a shader converts only into a shader input",
    'ShaderNodeAddShader': "a shader converts only into a shader input",
    'ShaderNodeBsdfTransparent': "transparency is not in Facet's core yet",
    'ShaderNodeBsdfTranslucent': "translucency is not in Facet's core yet",
    'ShaderNodeSubsurfaceScattering': "subsurface scattering is not in Facet's core yet",
    'ShaderNodeBsdfVelvet': "the velvet (sheen) BSDF is not in Facet's core yet",
    'ShaderNodeBsdfToon': "the toon BSDF is not in Facet's core",
    'ShaderNodeBsdfHair': "hair BSDFs are not in Facet's core",
    'ShaderNodeBsdfHairPrincipled': "hair BSDFs are not in Facet's core",
    'ShaderNodeHoldout': "holdout is not in Facet's core",
    'ShaderNodeVolumeAbsorption': "volumes are not in Facet's core",
    'ShaderNodeVolumeScatter': "volumes are not in Facet's core",
    'ShaderNodeVolumePrincipled': "volumes are not in Facet's core",
    'ShaderNodeRGBCurve': "RGB Curves is not converted yet",
    'ShaderNodeMapping': "Mapping converts only between a UV map and a texture",
    'ShaderNodeTexCoord': "Texture Coordinate converts only as a texture's UV (or the "
                          "world's Generated)",
    'ShaderNodeUVMap': "UV Map converts only as a texture's vector",
    'ShaderNodeVertexColor': "a Color Attribute converts only as a texture (into a colour "
                             "or number input of a BSDF or an Emission, or a Mix Shader's "
                             "Fac)",
    'ShaderNodeAttribute': "attributes are not converted yet",
    'ShaderNodeFresnel': "the Fresnel node is not converted (Facet's Fresnel is a model "
                         "parameter)",
    'ShaderNodeLayerWeight': "Layer Weight is not converted",
    'ShaderNodeLightPath': "Light Path is not converted (Facet has no ray-type switches)",
}

INPUTS = {
    ('ShaderNodeBsdfPrincipled', 'Subsurface'): (0.0, "subsurface scattering is not in "
                                                      "Facet's core; Cycles' diffuse fallback "
                                                      "(base colour mixed with Subsurface "
                                                      "Color) is used"),
    ('ShaderNodeBsdfAnisotropic', 'Rotation'): (0.0, "tangent rotation is not converted; "
                                                     "ignored"),
}

RADIUS_NOTE = ("converted to a sphere of uniform radiance and the same power (Cycles 4, pbrt); "
               "Cycles 3.4 renders a disc facing each shaded point instead, d^2/(d^2+R^2) as "
               "bright at distance d (measured 0.7995 at d = 2R)")
SUN_ANGLE_NOTE = ("converted to a cone of uniform radiance with the irradiance kept; Cycles 3.4's "
                  "sun loses irradiance as the angle grows (measured x0.983 at 30 deg, x0.829 "
                  "at 90 deg)")
# (attribute path, Blender's UI label, the value converted exactly, shown in degrees, what
# Facet does otherwise); Cycles' own light settings are under light.cycles.
LIGHTS = {
    # Radius (point, spot) and the Sun's Angle are converted (export.py, _light_data) to the
    # core's sphere light and sun cone; Cycles 3.4's own models of them differ, measured
    # (docs/blender.md), so a non-zero value is reported with the difference.
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
    if idname in NODES:
        return NODES[idname]
    if idname.startswith('ShaderNodeTex'):
        return "procedural textures are not in Facet's core yet"
    if idname.startswith(('ShaderNodeBsdf', 'ShaderNodeVolume')) or idname.startswith(
            'ShaderNodeEeveeSpecular'):
        return "this shader is not in Facet's core"
    return None


def light_gaps(light):
    """[(Blender's label, the value as shown, what Facet does)] for a Blender light's settings
    that are not converted exactly."""
    out = []
    for attr, label, exact, degrees, what in LIGHTS.get(light.type, ()) + LIGHTS_ALL:
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
    'Sun'", "world 'World'", "camera ..."), or "scene" for the core's build warnings."""
    head = line.split(": ", 1)[0]
    for kind in ("material", "object", "light", "world", "camera"):
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
