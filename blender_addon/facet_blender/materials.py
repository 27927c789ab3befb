"""Blender material -> Facet material (model + parameters of the core's table), emission and
sidedness.

A material's Facet panel chooses the source: a Facet model by its own parameters, or the
conversion of the Cycles node tree below. Conversions and their approximations (each one a
difference from Cycles 3.4 that the user may see):

- Diffuse BSDF: lambert, reflectance = Color. Roughness > 0 (Oren-Nayar in Cycles) is ignored.
- Glossy BSDF: Cycles' glossy has no Fresnel term (F = 1, tinted by Color) and
  alpha = Roughness^2. GGX -> ggx, Beckmann -> beckmann, Sharp -> mirror (all fresnel none,
  reflectance = Color). Multiscatter GGX -> ggx with energy_compensation (Kulla & Conty 2017
  instead of Cycles' random walk: same energy, slightly different lobe shape).
  Ashikhmin-Shirley has no Facet equivalent: reported, converted as GGX.
- Anisotropic BSDF: anisotropy a (clamped to [-0.99, 0.99] as Cycles does) gives
  alpha_u = alpha (1 - a), alpha_v = alpha / (1 - a) for a >= 0 and alpha_u = alpha / (1 + a),
  alpha_v = alpha (1 + a) for a < 0 (Cycles 3.4's SVM closure setup for this node).
  Principled Anisotropic uses Disney's aspect instead: alpha_u = alpha / aspect, alpha_v =
  alpha * aspect, aspect = sqrt(1 - 0.9 anisotropic). Rotation and tangents are ignored
  (Facet meshes have no tangent field).
- Principled BSDF (3.4's Disney-based model) -> composite: diffuse_reflectance =
  Base Color (1 - Metallic); a GGX glossy lobe with alpha = Roughness^2 and Schlick Fresnel with
  f0 = mix(0.08 Specular mix(1, tint, Specular Tint), Base Color, Metallic) (Disney's Cspec0).
  Approximations: Principled's diffuse is Disney's (retro-reflection at grazing angles), not
  Lambert; Facet's composite weights the diffuse lobe by what the specular lobe leaves
  (energy conserving) where Principled adds them; Subsurface, Sheen, Clearcoat, Transmission
  and Alpha are not converted (reported when not at their defaults); Emission is converted.
- Emission: the shape's emission = Color x Strength (radiance), black material.
- Any linked input (a texture or another node) is reported and its default value used; a Mix
  or Add Shader or any other node at the output is reported and the material becomes grey
  lambert (reflectance 0.8).
- No node tree: lambert with the viewport Diffuse Color.
"""
import json
import math

from . import units
from .properties import material_params

DEFAULT_MATERIAL = {"model": "lambert", "reflectance": 0.8}


class Converted:
    """A converted material: data (FORMAT.md material dict), emission, two_sided, problems."""

    def __init__(self, data, emission=None, two_sided=True, problems=()):
        self.data = data
        self.emission = emission or [0.0, 0.0, 0.0]
        self.two_sided = two_sided
        self.problems = list(problems)


def convert(mat):
    """Blender material (or None) -> Converted. Never raises for a bad node tree: what cannot
    be converted is listed in problems, each naming the material and the input or node."""
    if mat is None:
        return Converted(dict(DEFAULT_MATERIAL))
    fs = getattr(mat, "facet", None)
    if fs is not None and fs.source == 'FACET':
        if "facet_material" in mat and mat.get("facet_state") == material_state(mat):
            # Unchanged since the JSON import: the parameters as read (double precision).
            data = json.loads(mat["facet_material"])
        else:
            model, params = material_params(fs)
            data = {"model": model}
            data.update(params)
        return Converted(data, list(fs.emission), fs.two_sided)
    two_sided = True if fs is None else fs.two_sided
    if not mat.use_nodes or mat.node_tree is None:
        return Converted({"model": "lambert", "reflectance": list(mat.diffuse_color)[:3]},
                         two_sided=two_sided)
    problems = []
    node = _output_surface(mat, problems)
    if node is None:
        return Converted(dict(DEFAULT_MATERIAL), two_sided=two_sided, problems=problems)
    conv = _NODE_CONVERTERS.get(node.bl_idname)
    if conv is None:
        problems.append("material '%s': node '%s' (%s) is not supported by Facet; using grey "
                        "lambert" % (mat.name, node.name, node.bl_idname))
        return Converted(dict(DEFAULT_MATERIAL), two_sided=two_sided, problems=problems)
    data, emission = conv(mat, node, problems)
    return Converted(data, emission, two_sided, problems)


def material_state(mat):
    """A snapshot of a material's Facet settings (to tell whether it changed since import)."""
    fs = mat.facet
    return repr((fs.source, material_params(fs), tuple(fs.emission), fs.two_sided))


def _output_surface(mat, problems):
    nodes = mat.node_tree.nodes
    outs = [n for n in nodes if n.bl_idname == 'ShaderNodeOutputMaterial']
    out = next((n for n in outs if n.is_active_output and n.target in ('ALL', 'CYCLES')), None)
    out = out or next((n for n in outs if n.target in ('ALL', 'CYCLES')), None)
    if out is None:
        problems.append("material '%s': no Material Output node; using grey lambert" % mat.name)
        return None
    links = out.inputs['Surface'].links
    if not links:
        problems.append("material '%s': nothing connected to the output's Surface; using grey "
                        "lambert" % mat.name)
        return None
    node = links[0].from_node
    while node.bl_idname == 'NodeReroute' and node.inputs[0].links:
        node = node.inputs[0].links[0].from_node
    return node


def _value(mat, node, name, problems, default_ok=None):
    """The unlinked value of an input; a linked input is reported (its default is used)."""
    sock = node.inputs[name]
    if sock.is_linked:
        problems.append("material '%s': node '%s' input '%s' is linked (textures and node "
                        "networks are not converted); using its value" % (mat.name, node.name,
                                                                          name))
    v = sock.default_value
    try:
        return [float(c) for c in v]
    except TypeError:
        return float(v)


def _rgb(v):
    return [float(c) for c in v[:3]]


def _alpha(roughness):
    """Cycles' microfacet alpha = roughness^2 (glossy, anisotropic and principled)."""
    r = max(0.0, min(1.0, float(roughness)))
    return r * r


def _aniso_bsdf(alpha, anisotropy):
    """Cycles' Anisotropic BSDF node: a >= 0 stretches alpha_x by (1 - a) and alpha_y by
    1 / (1 - a); a < 0 the other way round (a clamped to [-0.99, 0.99])."""
    a = max(-0.99, min(0.99, float(anisotropy)))
    if a >= 0.0:
        return alpha * (1.0 - a), alpha / (1.0 - a)
    return alpha / (1.0 + a), alpha * (1.0 + a)


def _aniso(alpha, anisotropy):
    """Principled (Disney): aspect = sqrt(1 - 0.9 anisotropy), alpha_x = alpha / aspect,
    alpha_y = alpha aspect."""
    a = max(-1.0, min(1.0, float(anisotropy)))
    aspect = math.sqrt(1.0 - 0.9 * a) if a >= 0.0 else 1.0 / math.sqrt(1.0 + 0.9 * a)
    return alpha / aspect, alpha * aspect


def _diffuse(mat, node, problems):
    color = _rgb(_value(mat, node, 'Color', problems))
    if _value(mat, node, 'Roughness', problems) > 0.0:
        problems.append("material '%s': Diffuse BSDF Roughness (Oren-Nayar) is not supported; "
                        "converted as Lambert" % mat.name)
    return {"model": "lambert", "reflectance": color}, None


def _glossy_model(mat, node, problems):
    dist = node.distribution
    if dist == 'SHARP':
        return "mirror", False
    if dist == 'BECKMANN':
        return "beckmann", False
    if dist == 'MULTI_GGX':
        return "ggx", True
    if dist != 'GGX':
        problems.append("material '%s': %s distribution '%s' is not supported; converted as "
                        "GGX" % (mat.name, node.name, dist))
    return "ggx", False


def _glossy(mat, node, problems):
    color = _rgb(_value(mat, node, 'Color', problems))
    model, compensate = _glossy_model(mat, node, problems)
    data = {"model": model, "reflectance": color, "fresnel": "none"}
    if model != "mirror":
        alpha = _alpha(_value(mat, node, 'Roughness', problems))
        if node.bl_idname == 'ShaderNodeBsdfAnisotropic':
            aniso = _value(mat, node, 'Anisotropy', problems)
            if aniso != 0.0:
                data["alpha_u"], data["alpha_v"] = _aniso_bsdf(alpha, aniso)
            else:
                data["alpha"] = alpha
        else:
            data["alpha"] = alpha
        if compensate:
            data["energy_compensation"] = True
    return data, None


_PRINCIPLED_UNSUPPORTED = (("Subsurface", 0.0), ("Sheen", 0.0), ("Clearcoat", 0.0),
                           ("Transmission", 0.0), ("Alpha", 1.0))


def _principled(mat, node, problems):
    base = _rgb(_value(mat, node, 'Base Color', problems))
    metallic = max(0.0, min(1.0, _value(mat, node, 'Metallic', problems)))
    specular = max(0.0, _value(mat, node, 'Specular', problems))
    tint = max(0.0, min(1.0, _value(mat, node, 'Specular Tint', problems)))
    alpha = _alpha(_value(mat, node, 'Roughness', problems))
    aniso = _value(mat, node, 'Anisotropic', problems)
    for name, default in _PRINCIPLED_UNSUPPORTED:
        if name in node.inputs and (node.inputs[name].is_linked
                                    or abs(node.inputs[name].default_value - default) > 0.0):
            problems.append("material '%s': Principled BSDF input '%s' is not supported by "
                            "Facet; ignored" % (mat.name, name))
    # Disney's tint: the base colour's hue at luminance 1.
    lum = 0.2126 * base[0] + 0.7152 * base[1] + 0.0722 * base[2]
    ctint = [c / lum for c in base] if lum > 0.0 else [1.0, 1.0, 1.0]
    f0 = [min(1.0, (1.0 - metallic) * 0.08 * specular * ((1.0 - tint) + tint * ct)
              + metallic * b) for ct, b in zip(ctint, base)]
    data = {"model": "composite", "diffuse_reflectance": [b * (1.0 - metallic) for b in base],
            "distribution": "ggx", "fresnel": "schlick", "f0": f0}
    if aniso != 0.0:
        data["alpha_u"], data["alpha_v"] = _aniso(alpha, aniso)
    else:
        data["alpha"] = alpha
    emission = units.emission_from_blender(_value(mat, node, 'Emission', problems),
                                           _value(mat, node, 'Emission Strength', problems))
    return data, emission


def _emission(mat, node, problems):
    emission = units.emission_from_blender(_value(mat, node, 'Color', problems),
                                           _value(mat, node, 'Strength', problems))
    return {"model": "lambert", "reflectance": 0.0}, emission


_NODE_CONVERTERS = {
    'ShaderNodeBsdfDiffuse': _diffuse,
    'ShaderNodeBsdfGlossy': _glossy,
    'ShaderNodeBsdfAnisotropic': _glossy,
    'ShaderNodeBsdfPrincipled': _principled,
    'ShaderNodeEmission': _emission,
}
