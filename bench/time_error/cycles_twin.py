"""Cycles twins of the benchmark scenes (used by blender_worker.py; named apart from the module it builds on), on top of
facet_testsupport.cycles_scene (tests/support/python; the exact conversions: Lambert,
emission, point lights, fine meshes for analytic shapes, Cycles settings).

The benchmark also needs materials that Cycles 3.4 cannot express exactly. They get the node
setup a Blender user would build for them, each listed as a note (and the reference check in
time_error_summary.md shows where the images then differ):
- ggx / beckmann with fresnel conductor -> Glossy BSDF (GGX / Beckmann, Roughness sqrt(alpha)),
  Color = reflectance x Schlick(F0, view angle), F0 = ((eta-1)^2 + k^2) / ((eta+1)^2 + k^2) per
  channel (the conductor's exact normal-incidence reflectance; Schlick's curve instead of the
  exact conductor Fresnel, and evaluated at the view angle instead of per microfacet);
  Cycles' separable Smith term.
- anisotropic ggx / beckmann -> Anisotropic BSDF (same Fresnel as above): Roughness =
  (alpha_u alpha_v)^(1/4), Anisotropy inverted from Cycles 3.4's Anisotropic BSDF (a >= 0:
  alpha_x = alpha (1 - a), alpha_y = alpha / (1 - a); a < 0: alpha_x = alpha / (1 + a),
  alpha_y = alpha (1 + a); not Principled's aspect formula); the tangent is Facet's (FORMAT.md): spheres
  the radial tangent about the object's z axis (the longitude), quads p1 - p0, planes, discs,
  boxes and grids the local x axis, given to the node in world space.
- composite with fresnel dielectric -> Principled BSDF (what a Blender user picks for a coated
  plastic): Base Color = diffuse_reflectance, Metallic 0, Specular = F0 / 0.08 with
  F0 = ((ior - 1) / (ior + 1))^2, Specular Tint 0, Roughness = sqrt(alpha). Principled's diffuse
  is Disney's and is added to the coat rather than given what the coat leaves.
"""
import json
import math
import os
import sys

from mathutils import Vector

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "support", "python"))
from facet_testsupport import cycles_scene as cs  # noqa: E402

ANISO_LABEL = "facet anisotropic"
_exact_bsdf = cs._bsdf


def _grey(v):
    return [float(v)] * 3 if isinstance(v, (int, float)) else [float(c) for c in v]


def _conductor_f0(d):
    eta = _grey(d.get("eta", [1.657, 0.880, 0.521]))
    k = _grey(d.get("k", [9.224, 6.270, 4.837]))
    return [((n - 1) ** 2 + kk ** 2) / ((n + 1) ** 2 + kk ** 2) for n, kk in zip(eta, k)]


def _approx_bsdf(nt, name, d, exact, notes):
    model = d["model"]
    fresnel = d.get("fresnel", "none" if model != "composite" else "dielectric")
    aniso = "alpha_u" in d or "alpha_v" in d
    if model in ("ggx", "beckmann") and (fresnel == "conductor" or aniso):
        if fresnel not in ("conductor", "none"):
            return _exact_bsdf(nt, name, d, exact, notes)
        refl = _grey(d.get("reflectance", 1.0))
        if aniso:
            au, av = float(d["alpha_u"]), float(d["alpha_v"])
            alpha = math.sqrt(au * av)
            # Cycles 3.4's Anisotropic BSDF (svm closure): alpha = Roughness^2, a >= 0:
            # alpha_x = alpha (1 - a), alpha_y = alpha / (1 - a); a < 0: alpha_x = alpha / (1 + a),
            # alpha_y = alpha (1 + a); x along the tangent.
            a = 1.0 - math.sqrt(au / av) if au <= av else math.sqrt(av / au) - 1.0
            if abs(a) > 0.99:
                raise cs.NoEquivalent("material '%s': anisotropy ratio %g beyond Cycles' clamp "
                                      "|a| <= 0.99" % (name, max(au / av, av / au)))
            n = nt.nodes.new("ShaderNodeBsdfAnisotropic")
            n.label = ANISO_LABEL
            n.inputs['Anisotropy'].default_value = a
            n.inputs['Rotation'].default_value = 0.0
            what = "Anisotropic %s roughness %.4g anisotropy %.4f" % (model.upper(),
                                                                     math.sqrt(alpha), a)
        else:
            alpha = float(d.get("alpha", 0.2))
            n = nt.nodes.new("ShaderNodeBsdfGlossy")
            what = "Glossy %s roughness %.4g" % (model.upper(), math.sqrt(alpha))
        n.distribution = 'GGX' if model == "ggx" else 'BECKMANN'
        n.inputs['Roughness'].default_value = math.sqrt(alpha)
        if fresnel == "conductor":
            f0 = _conductor_f0(d)
            nt.links.new(cs.schlick_colour(nt, f0, refl), n.inputs['Color'])
            what += ", Schlick Fresnel from the conductor's F0 (%.3f %.3f %.3f) at the view angle" \
                % tuple(f0)
        else:
            n.inputs['Color'].default_value = (refl[0], refl[1], refl[2], 1.0)
        notes.append("material '%s' (%s): approximated by %s; Cycles' separable Smith term"
                     % (name, model, what))
        return n.outputs[0]
    if model == "composite" and fresnel == "dielectric" and not aniso \
            and d.get("distribution", "ggx") == "ggx" and float(d.get("mirror_reflectance", 0)) == 0:
        ior = float(d.get("ior", 1.5))
        f0 = ((ior - 1) / (ior + 1)) ** 2
        alpha = float(d.get("alpha", 0.2))
        n = nt.nodes.new("ShaderNodeBsdfPrincipled")
        dr = _grey(d.get("diffuse_reflectance", 0.5))
        n.inputs['Base Color'].default_value = (dr[0], dr[1], dr[2], 1.0)
        n.inputs['Metallic'].default_value = 0.0
        n.inputs['Specular'].default_value = f0 / 0.08
        n.inputs['Specular Tint'].default_value = 0.0
        n.inputs['Roughness'].default_value = math.sqrt(alpha)
        n.distribution = 'GGX'
        notes.append("material '%s' (composite): approximated by Principled BSDF (Disney "
                     "diffuse added to a GGX coat, Specular %.3f = F0 %.3f / 0.08, Roughness "
                     "%.4g)" % (name, f0 / 0.08, f0, math.sqrt(alpha)))
        return n.outputs[0]
    return _exact_bsdf(nt, name, d, exact, notes)


def _tangents(scene, notes):
    """Links Facet's tangent (FORMAT.md) into every anisotropic node."""
    owner = {}
    for ob in scene.objects:
        if ob.type != 'MESH' or "facet_shape" not in ob:
            continue
        for mat in ob.data.materials:
            if mat is None or not mat.use_nodes:
                continue
            nodes = [n for n in mat.node_tree.nodes if n.label == ANISO_LABEL]
            if not nodes:
                continue
            if mat.name in owner and owner[mat.name] is not ob:
                raise cs.NoEquivalent("material '%s': anisotropic on two shapes; the tangent is "
                                      "per shape" % mat.name)
            owner[mat.name] = ob
            s = json.loads(ob["facet_shape"])
            nt = mat.node_tree
            if s["type"] == "sphere":
                t = nt.nodes.new("ShaderNodeTangent")
                t.direction_type = 'RADIAL'
                t.axis = 'Z'
                sock = t.outputs['Tangent']
                what = "radial about the object's z axis"
            else:
                if s["type"] == "quad":
                    p = [Vector(v) for v in s["vertices"]]
                    local = p[1] - p[0]
                elif s["type"] in ("plane", "disc", "box", "grid"):
                    local = Vector((1.0, 0.0, 0.0))
                else:
                    raise cs.NoEquivalent("shape '%s': %s has no tangent in Facet" % (ob.name,
                                                                                    s["type"]))
                world = (ob.matrix_world.to_3x3() @ local).normalized()
                c = nt.nodes.new("ShaderNodeCombineXYZ")
                c.inputs[0].default_value, c.inputs[1].default_value, \
                    c.inputs[2].default_value = world
                sock = c.outputs[0]
                what = "constant (%.3f, %.3f, %.3f) in world space" % tuple(world)
            for n in nodes:
                nt.links.new(sock, n.inputs['Tangent'])
            notes.append("shape '%s': anisotropic tangent %s" % (ob.name, what))


def build(scene, data, threads):
    """Converts the imported scene for Cycles (exact where facet_testsupport.cycles_scene is,
    approximated as above otherwise) and applies the comparison settings. Returns the notes."""
    integrator = scene.facet.integrator
    scene.facet.integrator = "path"   # Cycles is a path tracer; point_plane's path = direct
    cs._bsdf = _approx_bsdf
    try:
        notes = cs.convert(scene, exact=False)
    finally:
        cs._bsdf = _exact_bsdf
        scene.facet.integrator = integrator
    _tangents(scene, notes)
    cs.cycles_settings(scene, samples=16, seed=1,
                       max_depth=int(data.get("render", {}).get("max_depth", 8)))
    c = scene.cycles
    c.use_auto_tile = False
    scene.render.threads_mode = 'FIXED'
    scene.render.threads = threads
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    return notes
