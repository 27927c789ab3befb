"""A Cycles version of a Facet scene imported into Blender, for comparisons against Cycles.

Use inside Blender (`blender -b --factory-startup --python your_script.py`), after
`bpy.ops.import_scene.facet(filepath=...)` (the addon's importer):

    sys.path.insert(0, "<repo>/tests/support/python")
    from facet_testsupport import cycles_scene as cs
    notes = cs.convert(bpy.context.scene, exact=True)   # materials, emitters, geometry, lights
    cs.cycles_settings(bpy.context.scene, samples=256, seed=1)
    img, seconds = cs.render(bpy.context.scene, 'CYCLES', "/tmp/c.exr")  # or 'FACET'
    z = cs.block_z(facet_pair, cycles_pair, block=16)[0]  # noise-derived comparison
    # analytic references: cs.camera_rays(facet camera dict), cs.polygon_form_factor(p, n, quad)
    # time-budget runs: scene.cycles.time_limit / scene.facet.time_budget after cycles_settings

`convert` changes only what Cycles reads: every material gets an equivalent Cycles node tree,
emissive shapes get an Emission shader, analytic shapes get a fine mesh. Facet keeps rendering
the imported description exactly (the exporter reads the stored shapes, the materials' Facet
settings and the stored lights), so Facet and Cycles render the same Blender scene.
It returns a list of notes, one per approximation (tessellated analytic shapes, and with
exact=False the inexact models below); with exact=True a material or light without an exact
Cycles 3.4 equivalent raises NoEquivalent naming it. one_sided_emission=False gives Cycles'
emitters their default two-sided emission (for experiments; not Facet's semantics).

Measured with it (tests/blender/test_cycles_*.py): light units and one-sided mesh emission
agree with the analytic irradiance in both renderers to 1e-5; white furnaces agree; Cycles
3.4's direct light from the Cornell box's ceiling quad is ~1% dark on the back wall against
the analytic form factor (Facet: exact), see test_cycles_cornell.py; Cycles 3.4's spot light
has an extra cos(angle from the axis) (units.py).

Facet model -> Cycles 3.4 nodes (exact = the same function, up to floating point):
- lambert -> Diffuse BSDF (Roughness 0, i.e. Lambert; Color = reflectance): exact.
- mirror, fresnel none -> Glossy BSDF Sharp, Color = reflectance: exact.
- mirror, fresnel dielectric -> Glossy Sharp whose Color = reflectance x Fresnel node (IOR):
  exact (a mirror's microfacet normal is the shading normal, where the Fresnel node evaluates
  the unpolarised dielectric Fresnel).
- mirror, fresnel schlick -> Glossy Sharp, Color = reflectance x (f0 + (1 - f0) Facing^5),
  Facing = Layer Weight's 1 - |N.I| (blend 0.5): exact.
- mirror, fresnel conductor: no equivalent (no conductor Fresnel node in 3.4).
- ggx / beckmann, isotropic, fresnel none -> Glossy BSDF GGX / Beckmann, Roughness =
  sqrt(alpha) (Cycles squares it), Color = reflectance: NOT exact. Cycles 3.4 uses the
  separable Smith term G1(i) G1(o) (Beckmann's G1 with Walter et al.'s rational approximation),
  Facet the exact height-correlated 1 / (1 + L(i) + L(o)); the difference is
  L(i) L(o) / ((1 + L(i))(1 + L(o))(1 + L(i) + L(o))) relative, small at low alpha and away
  from grazing. exact=False converts with a note. energy_compensation -> Multiscatter GGX
  (a different compensation: note). alpha < 1e-4 is the mirror (exact, as in the core).
- ggx / beckmann with a Fresnel term, anisotropic lobes, blinn (no Blinn D in Cycles),
  composite (Principled's diffuse is Disney's and its Fresnel is not any of Facet's): none.
- shape emission L -> Emission shader, Color L, Strength 1 on the front side only (Strength =
  1 - Backfacing: Facet's emitters are one-sided, Cycles' mesh lights two-sided): exact.
- two_sided false -> a black back (Mix Shader on Backfacing): exact.
- point, directional: the imported Blender lights (radius/angle 0) in Cycles' units (units.py):
  exact. spot: none (measured: Cycles 3.4's cone intensity is P/(4 pi) cos(angle from the
  axis), Facet's constant; and for inner < outer Cycles fades with smoothstep, Facet linearly
  in cos): a note, or NoEquivalent with exact=True. environment: the world colour, as imported.
- shapes: mesh, quad and box are the imported meshes (exact; mesh normals from the file's
  normals as custom split normals); sphere, disc, plane, icosphere and grid get a fine mesh
  (a note each; the sphere is a smooth UV sphere of 256 x 128 segments).
- render: max bounces = Facet's max_depth - 1 (Facet's depth counts the camera ray's vertex:
  max_depth 1 is direct lighting, Cycles' max_bounces 0); the "direct" integrator: none.
"""
import json
import math
import os
import time

import bmesh
import bpy
import numpy as np

from facet_testsupport import blender_harness as _bt

SPHERE_SEGMENTS = (256, 128)
DISC_SEGMENTS = 1024
PLANE_HALF_SIZE_FACTOR = 1000.0  # x the camera's distance to the plane
CYCLES_ONLY = "facet_cycles_only"  # materials Facet's exporter ignores (export.py)
FLOAT_FLOOR = 1e-6  # block_z's relative precision floor (float32)


class NoEquivalent(RuntimeError):
    """A material, shape, light or setting with no exact Cycles equivalent (names it)."""


# --- materials -------------------------------------------------------------------------------

def _rgb(v):
    v = [float(v)] * 3 if isinstance(v, (int, float)) else [float(c) for c in v]
    return (v[0], v[1], v[2], 1.0)


def _facet_description(mat):
    if "facet_material" in mat:
        return json.loads(mat["facet_material"])
    from facet_blender import materials
    model, params = materials.material_params(mat.facet)
    data = {"model": model}
    data.update(params)
    return data


def _new_tree(mat):
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    out.target = 'ALL'
    return nt, out


def schlick_colour(nt, f0, refl):
    """A colour socket of node tree `nt`: refl x (f0 + (1 - f0) (1 - |N.I|)^5), Schlick's
    Fresnel from Layer Weight's Facing output (f0, refl: RGB or RGBA sequences)."""
    lw = nt.nodes.new("ShaderNodeLayerWeight")
    lw.inputs['Blend'].default_value = 0.5
    pw = nt.nodes.new("ShaderNodeMath")
    pw.operation = 'POWER'
    nt.links.new(lw.outputs['Facing'], pw.inputs[0])
    pw.inputs[1].default_value = 5.0
    mix = nt.nodes.new("ShaderNodeMixRGB")
    mix.blend_type = 'MIX'
    nt.links.new(pw.outputs[0], mix.inputs['Fac'])
    mix.inputs['Color1'].default_value = (f0[0], f0[1], f0[2], 1.0)
    mix.inputs['Color2'].default_value = (1.0, 1.0, 1.0, 1.0)
    mul = nt.nodes.new("ShaderNodeMixRGB")
    mul.blend_type = 'MULTIPLY'
    mul.inputs['Fac'].default_value = 1.0
    mul.inputs['Color1'].default_value = (refl[0], refl[1], refl[2], 1.0)
    nt.links.new(mix.outputs['Color'], mul.inputs['Color2'])
    return mul.outputs['Color']


def _colour_times(nt, colour, factor_socket):
    """A Mix RGB node giving colour x factor (factor: a float socket)."""
    mul = nt.nodes.new("ShaderNodeMixRGB")
    mul.blend_type = 'MULTIPLY'
    mul.inputs['Fac'].default_value = 1.0
    mul.inputs['Color1'].default_value = colour
    nt.links.new(factor_socket, mul.inputs['Color2'])
    return mul.outputs['Color']


def _bsdf(nt, name, d, exact, notes):
    """The BSDF node output for Facet description d of material `name`."""
    model = d["model"]
    fresnel = d.get("fresnel", "none")
    aniso = "alpha_u" in d or "alpha_v" in d
    if model == "lambert":
        n = nt.nodes.new("ShaderNodeBsdfDiffuse")
        n.inputs['Color'].default_value = _rgb(d.get("reflectance", 0.5))
        n.inputs['Roughness'].default_value = 0.0
        return n.outputs[0]
    alpha = float(d.get("alpha", 0.2))
    if model == "mirror" or (model in ("ggx", "beckmann") and not aniso and alpha < 1e-4):
        if fresnel == "conductor":
            raise NoEquivalent("material '%s': mirror with fresnel conductor has no Cycles 3.4 "
                               "equivalent (no conductor Fresnel node)" % name)
        n = nt.nodes.new("ShaderNodeBsdfGlossy")
        n.distribution = 'SHARP'
        refl = _rgb(d.get("reflectance", 1.0))
        if fresnel == "none":
            n.inputs['Color'].default_value = refl
        elif fresnel == "dielectric":
            fr = nt.nodes.new("ShaderNodeFresnel")
            fr.inputs['IOR'].default_value = float(d.get("ior", 1.5))
            nt.links.new(_colour_times(nt, refl, fr.outputs['Fac']), n.inputs['Color'])
        elif fresnel == "schlick":
            nt.links.new(schlick_colour(nt, _rgb(d.get("f0", 0.04)), refl), n.inputs['Color'])
        else:
            raise NoEquivalent("material '%s': unknown fresnel '%s'" % (name, fresnel))
        return n.outputs[0]
    if model in ("ggx", "beckmann"):
        if fresnel != "none":
            raise NoEquivalent("material '%s': %s with fresnel %s has no Cycles 3.4 equivalent "
                               "(Glossy BSDF has no Fresnel; Principled's is not Facet's)"
                               % (name, model, fresnel))
        if aniso:
            raise NoEquivalent("material '%s': anisotropic %s has no exact Cycles equivalent "
                               "(tangent conventions and Smith term differ)" % (name, model))
        why = ("material '%s': %s alpha %g -> Glossy %s roughness %g: Cycles 3.4's Smith term "
               "is separable G1(i) G1(o)%s, Facet's height-correlated"
               % (name, model, alpha, model.upper(), math.sqrt(alpha),
                  " (rational G1 approximation)" if model == "beckmann" else ""))
        dist = 'GGX' if model == "ggx" else 'BECKMANN'
        if d.get("energy_compensation", False):
            if model != "ggx":
                raise NoEquivalent("material '%s': beckmann with energy compensation has no "
                                   "Cycles equivalent" % name)
            dist = 'MULTI_GGX'
            why += "; energy compensation -> Multiscatter GGX (a different method)"
        if exact:
            raise NoEquivalent(why + " (not exact; convert(exact=False) approximates)")
        notes.append(why)
        n = nt.nodes.new("ShaderNodeBsdfGlossy")
        n.distribution = dist
        n.inputs['Color'].default_value = _rgb(d.get("reflectance", 1.0))
        n.inputs['Roughness'].default_value = math.sqrt(alpha)
        return n.outputs[0]
    raise NoEquivalent("material '%s': model '%s' has no Cycles 3.4 equivalent%s" % (
        name, model, {"blinn": " (no Blinn distribution in Cycles)",
                      "composite": " (Principled's diffuse is Disney's, its Fresnel not "
                                   "Facet's)"}.get(model, "")))


def _black(nt):
    n = nt.nodes.new("ShaderNodeBsdfDiffuse")
    n.inputs['Color'].default_value = (0.0, 0.0, 0.0, 1.0)
    return n.outputs[0]


def _surface(mat, d, emission, two_sided, exact, notes, one_sided_emission=True):
    """Builds mat's node tree: BSDF (or black) [front-only if not two_sided] + emission."""
    nt, out = _new_tree(mat)
    bsdf = _bsdf(nt, mat.name, d, exact, notes) if d is not None else None
    geo = None
    if bsdf is not None and not two_sided:
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geo.outputs['Backfacing'], mix.inputs['Fac'])
        nt.links.new(bsdf, mix.inputs[1])
        nt.links.new(_black(nt), mix.inputs[2])
        bsdf = mix.outputs[0]
    if emission is not None and any(c > 0.0 for c in emission):
        geo = geo or nt.nodes.new("ShaderNodeNewGeometry")
        front = nt.nodes.new("ShaderNodeMath")
        front.operation = 'SUBTRACT'
        front.inputs[0].default_value = 1.0
        nt.links.new(geo.outputs['Backfacing'], front.inputs[1])
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs['Color'].default_value = _rgb(emission)
        if one_sided_emission:
            nt.links.new(front.outputs[0], em.inputs['Strength'])
        else:
            em.inputs['Strength'].default_value = 1.0
        if bsdf is not None:
            add = nt.nodes.new("ShaderNodeAddShader")
            nt.links.new(em.outputs[0], add.inputs[0])
            nt.links.new(bsdf, add.inputs[1])
            bsdf = add.outputs[0]
        else:
            bsdf = em.outputs[0]
    nt.links.new(bsdf if bsdf is not None else _black(nt), out.inputs['Surface'])


# --- geometry --------------------------------------------------------------------------------

def _uv_sphere(name, center, radius, nu, nv, flip):
    """A smooth UV sphere mesh (outward faces unless flip) built with numpy (bmesh's
    create_uvsphere takes seconds at this size)."""
    th = np.pi * np.arange(1, nv) / nv
    ph = 2 * np.pi * np.arange(nu) / nu
    ring = np.stack([np.outer(np.sin(th), np.cos(ph)), np.outer(np.sin(th), np.sin(ph)),
                     np.repeat(np.cos(th)[:, None], nu, axis=1)], axis=-1).reshape(-1, 3)
    pos = np.concatenate([[[0, 0, 1]], ring, [[0, 0, -1]]]) * radius + np.asarray(center)
    top, bottom = 0, len(pos) - 1

    def v(i, j):  # ring i (0 .. nv-2), column j
        return 1 + i * nu + (j % nu)
    j = np.arange(nu)
    tris_top = np.stack([np.full(nu, top), v(0, j), v(0, j + 1)], axis=1)
    tris_bot = np.stack([v(nv - 2, j), np.full(nu, bottom), v(nv - 2, j + 1)], axis=1)
    i, jj = np.meshgrid(np.arange(nv - 2), j, indexing='ij')
    quads = np.stack([v(i, jj), v(i + 1, jj), v(i + 1, jj + 1), v(i, jj + 1)],
                     axis=-1).reshape(-1, 4)
    loops = np.concatenate([tris_top.ravel(), quads.ravel(), tris_bot.ravel()])
    sizes = np.concatenate([np.full(nu, 3), np.full(len(quads), 4), np.full(nu, 3)])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    if flip:
        loops = np.concatenate([loops[st:st + n][::-1] for st, n in zip(starts, sizes)])
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(pos))
    me.vertices.foreach_set("co", pos.astype(np.float32).ravel())
    me.loops.add(len(loops))
    me.loops.foreach_set("vertex_index", loops.astype(np.int32))
    me.polygons.add(len(sizes))
    me.polygons.foreach_set("loop_start", starts.astype(np.int32))
    me.polygons.foreach_set("loop_total", sizes.astype(np.int32))
    me.update(calc_edges=True)
    return me


def _fine_mesh(ob, s, scene, notes):
    """A Blender mesh (local space) for Cycles, or None to keep the imported one."""
    kind = s["type"]
    if kind == "sphere":
        u, v = SPHERE_SEGMENTS
        me = _uv_sphere(ob.data.name + " (Cycles)", s["center"], float(s["radius"]), u, v,
                        bool(s.get("flip_normals")))
        me.polygons.foreach_set("use_smooth", np.ones(len(me.polygons), bool))
        notes.append("shape '%s': sphere -> smooth UV sphere %d x %d" % (ob.name, u, v))
        return me
    bm = bmesh.new()
    try:
        if kind == "icosphere":
            bmesh.ops.create_icosphere(bm, subdivisions=int(s["subdivisions"]),
                                       radius=float(s["radius"]))
            bmesh.ops.translate(bm, vec=s["center"], verts=bm.verts)
            smooth = bool(s.get("smooth", True))
            notes.append("shape '%s': icosphere -> Blender's icosphere (vertices differ)"
                         % ob.name)
        elif kind in ("disc", "plane"):
            from mathutils import Vector
            n = Vector(s["normal"]).normalized()
            rot = n.to_track_quat('Z', 'Y').to_matrix().to_4x4()
            if kind == "disc":
                bmesh.ops.create_circle(bm, cap_ends=True, segments=DISC_SEGMENTS,
                                        radius=float(s["radius"]), matrix=rot)
                bmesh.ops.translate(bm, vec=s["center"], verts=bm.verts)
                notes.append("shape '%s': disc -> %d-gon" % (ob.name, DISC_SEGMENTS))
            else:
                cam = scene.camera.matrix_world.translation
                half = PLANE_HALF_SIZE_FACTOR * max(1e-6, abs((cam - Vector(s["point"])).dot(n)))
                bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=half, matrix=rot)
                bmesh.ops.translate(bm, vec=s["point"], verts=bm.verts)
                notes.append("shape '%s': infinite plane -> square of half size %g" % (
                    ob.name, half))
            smooth = False
        elif kind == "grid":
            nx, ny = int(s["nx"]), int(s["ny"])
            bmesh.ops.create_grid(bm, x_segments=nx + 1, y_segments=ny + 1, size=1.0)
            a, f = float(s.get("amplitude", 0.0)), float(s.get("frequency", 0.0))
            for vert in bm.verts:
                vert.co.z = a * math.sin(f * vert.co.x) * math.sin(f * vert.co.y)
            notes.append("shape '%s': grid -> Blender grid %d x %d (diagonals may differ)"
                         % (ob.name, nx, ny))
            smooth = False
        else:
            return None
        if s.get("flip_normals"):
            bmesh.ops.reverse_faces(bm, faces=bm.faces)
        me = bpy.data.meshes.new(ob.data.name + " (Cycles)")
        bm.to_mesh(me)
    finally:
        bm.free()
    me.polygons.foreach_set("use_smooth", np.full(len(me.polygons), smooth))
    return me


def _exact_mesh_normals(ob, s):
    """Imported triangle meshes: the file's normals as custom split normals; flip_normals."""
    me = ob.data
    if s.get("flip_normals"):
        bm = bmesh.new()
        bm.from_mesh(me)
        bmesh.ops.reverse_faces(bm, faces=bm.faces)
        bm.to_mesh(me)
        bm.free()
    if "facet_normal" in me.attributes:
        nrm = np.empty(len(me.vertices) * 3, np.float32)
        me.attributes["facet_normal"].data.foreach_get("vector", nrm)
        me.use_auto_smooth = True
        me.normals_split_custom_set_from_vertices(nrm.reshape(-1, 3).tolist())


# --- the scene -------------------------------------------------------------------------------

def convert(scene=None, exact=True, one_sided_emission=True):
    """Makes the imported Facet scene renderable by Cycles (see the module's docstring).
    Returns the notes (approximations); raises NoEquivalent naming what has no equivalent."""
    scene = scene or bpy.context.scene
    notes = []
    done = {}
    for ob in list(scene.objects):
        if ob.type == 'LIGHT' and "facet_light" in ob:
            lt = json.loads(ob["facet_light"])
            if lt["type"] == "spot":
                why = ("light '%s': spot: Cycles 3.4's intensity in the cone is P/(4 pi) "
                       "cos(angle from the axis), Facet's constant (units.py)" % ob.name)
                if lt.get("inner_angle", lt.get("outer_angle")) != lt.get("outer_angle"):
                    why += "; its fade is smoothstep, Facet's linear in cos"
                if exact:
                    raise NoEquivalent(why)
                notes.append(why)
            continue
        if ob.type != 'MESH' or "facet_shape" not in ob:
            continue
        s = json.loads(ob["facet_shape"])
        if s["type"] == "mesh" and "file" in s:
            raise NoEquivalent("shape '%s': mesh file '%s' is not loaded into Blender"
                               % (ob.name, s["file"]))
        fine = _fine_mesh(ob, s, scene, notes)
        mats = list(ob.data.materials)
        if fine is not None:
            for m in mats:
                fine.materials.append(m)
            ob.data = fine
        else:
            _exact_mesh_normals(ob, s)
        emission = s.get("emission")
        emits = emission is not None and any(float(c) > 0.0 for c in (
            [emission] * 3 if isinstance(emission, (int, float)) else emission))
        two_sided = bool(s.get("two_sided", True))
        mat = mats[0] if mats else None
        key = (mat.name if mat else None, two_sided, json.dumps(emission) if emits else None)
        if key in done:
            target = done[key]
        elif mat is not None and not emits and two_sided:
            target = mat  # the shared material itself: only its node tree changes
        elif mat is not None:
            target = mat.copy()  # the same Facet settings, a per-shape Cycles tree
            target.name = "%s (Cycles, %s)" % (mat.name, ob.name)
        else:
            target = bpy.data.materials.new("%s (Cycles emitter)" % ob.name)
            target[CYCLES_ONLY] = True
        if key not in done:
            d = _facet_description(mat) if mat is not None else None
            _surface(target, d, emission if emits else None, two_sided, exact, notes,
                     one_sided_emission)
            done[key] = target
        if target is not mat:
            if ob.data.materials:
                ob.data.materials[0] = target
            else:
                ob.data.materials.append(target)
    fs = scene.facet
    if fs.integrator != "path":
        raise NoEquivalent("render: integrator '%s' has no Cycles equivalent (path only)"
                           % fs.integrator)
    if fs.max_depth < 1:
        raise NoEquivalent("render: max_depth 0 (emission only) has no Cycles equivalent")
    return notes


def cycles_settings(scene, samples=None, seed=None, max_depth=None):
    """Cycles render settings for a comparison: box filter 1 px, no clamping, no denoising,
    adaptive sampling off, light threshold 0, fixed seed, max bounces matched to Facet's
    max_depth (Cycles bounces = max_depth - 1), 32-bit float EXR output."""
    fs = scene.facet
    c = scene.cycles
    c.device = 'CPU'
    c.samples = int(samples if samples is not None else fs.spp)
    c.seed = int(seed if seed is not None else fs.seed) & 0x7fffffff
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.time_limit = 0.0
    bounces = int(max_depth if max_depth is not None else fs.max_depth) - 1
    if bounces < 0:
        raise NoEquivalent("render: max_depth 0 has no Cycles equivalent")
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = bounces
    c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = bounces
    c.min_light_bounces = c.min_transparent_bounces = 0
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.use_fast_gi = False
    c.auto_scrambling_distance = False
    c.scrambling_distance = 1.0
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    c.film_exposure = 1.0
    scene.render.film_transparent = False
    scene.render.use_motion_blur = False
    _exr(scene)



def luminance(img):
    """Rec. 709 luminance of an (h, w, 3+) image."""
    return img[..., 0] * 0.2126 + img[..., 1] * 0.7152 + img[..., 2] * 0.0722


def block_rmse(a, b, block=8):
    """RMS difference of the luminance's block x block means of two images (the real-scene
    suite's measure: mean within 2%, block RMSE within 3x the seed-to-seed floor)."""
    def means(x):
        h, w = x.shape
        return x[:h - h % block, :w - w % block].reshape(
            h // block, block, w // block, block).mean(axis=(1, 3))
    return float(np.sqrt(np.mean((means(luminance(a)) - means(luminance(b))) ** 2)))


def compare_to_cycles(name, f, c1, c2, block=8):
    """Facet's image `f` against Cycles' seeds `c1`, `c2` (the bounds the Cycles comparisons
    assert): returns (mean luminance of f over the two seeds' mean, block RMSE of f against c1
    over the noise floor: the same between c1 and c2), and prints both with the floor."""
    floor = block_rmse(c1, c2, block)
    ratio = luminance(f).mean() / (0.5 * (luminance(c1).mean() + luminance(c2).mean()))
    rel = block_rmse(f, c1, block) / max(floor, 1e-12)
    print("%-16s mean ratio Facet / Cycles %.4f, block RMSE %.2f x floor (%.5f)"
          % (name, ratio, rel, floor))
    return ratio, rel


def add_fur(obj, count=300, material=2):
    """A hair particle system on the mesh object `obj`: `count` hairs 0.6 long, 9 keys at
    render step 3, radius 0.02 at the root and 0.01 at the tip (shape 0, no Close Tip), in
    material slot `material`. Hairs grow from vertices taken in index order, not from random
    points on faces: Blender 3.4's face distribution places them differently in every
    process (measured: a new set of roots each run even with the system's seed set), which
    would make each Cycles comparison a different scene."""
    mod = obj.modifiers.new("Fur", 'PARTICLE_SYSTEM')
    st = mod.particle_system.settings
    st.type = 'HAIR'
    st.count = count
    st.emit_from = 'VERT'
    st.use_emit_random = False
    st.hair_length = 0.6
    st.material = material
    st.radius_scale = 0.04  # root radius 0.02
    st.root_radius = 1.0
    st.tip_radius = 0.5
    st.shape = 0.0
    st.use_close_tip = False
    st.display_step = st.render_step = 3
    return mod


def new_scene(res, world_color=(1.0, 1.0, 1.0, 1.0), world_strength=1.0, world_name="world"):
    """An empty scene (factory data gone) rendering res x res pixels at 100%, lit by a
    constant world of `world_color` x `world_strength`."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = res
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new(world_name)
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = world_color
    bg.inputs["Strength"].default_value = world_strength
    scene.world = world
    return scene


def ortho_camera_down(scene, height, scale):
    """The scene's camera: orthographic, `scale` wide, at (0, 0, height) looking down -z."""
    cd = bpy.data.cameras.new("cam")
    cd.type = 'ORTHO'
    cd.ortho_scale = scale
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, 0.0, height)
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def add_light(scene, kind, energy, location, rotation=(0.0, 0.0, 0.0), visible_camera=True,
              **props):
    """A lamp object of Blender type `kind` ('POINT', 'SUN', 'SPOT', 'AREA') linked into
    `scene`, with `energy` (W, or W/m^2 for a sun) and the light data's other `props`."""
    ld = bpy.data.lights.new(kind, kind)
    ld.energy = energy
    for k, v in props.items():
        setattr(ld, k, v)
    ob = bpy.data.objects.new(kind, ld)
    ob.location = location
    ob.rotation_euler = rotation
    ob.visible_camera = visible_camera
    scene.collection.objects.link(ob)
    return ob

def _exr(scene):
    s = scene.render.image_settings
    s.file_format = 'OPEN_EXR'
    s.color_depth = '32'
    s.color_mode = 'RGB'
    s.exr_codec = 'ZIP'


def render(scene, engine, path, seed=None, problems_are_errors=True):
    """F12 with `engine` ('CYCLES' or 'FACET'), written to the EXR `path`; returns (image
    float64 (h, w, 3) top row first, seconds). `seed` sets the engine's seed first. With
    problems_are_errors, a Facet report line containing "error" raises (for scenes whose names
    cannot contain the word; real assets can: a glTF sample names a material 'Error')."""
    scene.render.engine = engine
    if seed is not None:
        if engine == 'CYCLES':
            scene.cycles.seed = int(seed) & 0x7fffffff
        else:
            scene.facet.seed = int(seed)
    scene.render.filepath = path
    _exr(scene)
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    dt = time.perf_counter() - t0
    if engine == 'FACET' and problems_are_errors:
        from facet_blender import hooks
        if hooks.last_problems and any("error" in p.lower() for p in hooks.last_problems):
            raise RuntimeError("; ".join(hooks.last_problems))
    if not os.path.exists(path):
        raise RuntimeError("%s wrote no image to %s" % (engine, path))
    return load_exr(path).astype(np.float64), dt



def load_rgba(path):
    """An RGBA EXR through Blender's loader -> float64 (h, w, 4), top row first."""
    im = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = im.size
        px = np.empty(w * h * im.channels, np.float32)
        im.pixels.foreach_get(px)
        img = px.reshape(h, w, im.channels)[::-1].astype(np.float64)
    finally:
        bpy.data.images.remove(im)
    if img.shape[2] != 4:
        raise RuntimeError("%s: %d channels, expected RGBA" % (path, img.shape[2]))
    return img


def render_rgba(scene, engine, path, seed):
    """F12 with `engine` and its seed, saved as a 32-bit RGBA EXR: the Combined pass with its
    alpha (1 everywhere over an opaque film), float64 (h, w, 4)."""
    scene.render.engine = engine
    if engine == 'CYCLES':
        scene.cycles.seed = seed
    else:
        scene.facet.seed = seed
    bpy.ops.render.render()
    s = scene.render.image_settings
    s.file_format = 'OPEN_EXR'
    s.color_depth = '32'
    s.color_mode = 'RGBA'
    s.exr_codec = 'ZIP'
    bpy.data.images["Render Result"].save_render(path, scene=scene)
    return load_rgba(path)

# One EXR loader for every Blender test and benchmark (blender_harness.load_exr).
load_exr = _bt.load_exr


def facet_description(scene=None):
    """What Facet's exporter makes of the scene, as JSON text (to check that convert leaves
    Facet's render unchanged)."""
    from facet_blender import export
    scene = scene or bpy.context.scene
    data, _ = export.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})

    def conv(v):
        if isinstance(v, np.ndarray):
            return v.tolist()
        raise TypeError(type(v))
    return json.dumps(data, default=conv, sort_keys=True)


# --- analytic references -----------------------------------------------------------------

def camera_rays(cam, sub=4, region=None):
    """FORMAT.md's pinhole: (origin (3,), directions (h, w, sub*sub, 3) unit) of sub x sub
    stratified points per pixel, for a Facet camera description `cam` (dict); region
    (x0, y0, x1, y1) restricts it to those pixels (directions (y1-y0, x1-x0, sub*sub, 3))."""
    pos = np.asarray(cam["position"], float)
    f = np.asarray(cam["look_at"], float) - pos
    f /= np.linalg.norm(f)
    r = np.cross(f, np.asarray(cam.get("up", [0, 1, 0]), float))
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    w, h = int(cam["width"]), int(cam["height"])
    tan_y = math.tan(math.radians(cam["fov"]) / 2)
    tan_x = tan_y * w / h
    x0, y0, x1, y1 = region or (0, 0, w, h)
    t = (np.arange(sub) + 0.5) / sub
    xs = (np.arange(x0, x1)[:, None] + t[None, :]).ravel()  # ((x1-x0)*sub,)
    ys = (np.arange(y0, y1)[:, None] + t[None, :]).ravel()
    sx = (2 * xs / w - 1) * tan_x
    sy = (1 - 2 * ys / h) * tan_y
    d = (f[None, None, :] + sx[None, :, None] * r[None, None, :]
         + sy[:, None, None] * u[None, None, :])
    d /= np.linalg.norm(d, axis=2, keepdims=True)
    d = d.reshape(y1 - y0, sub, x1 - x0, sub, 3).transpose(0, 2, 1, 3, 4).reshape(
        y1 - y0, x1 - x0, sub * sub, 3)
    return pos, d


def polygon_form_factor(p, n, verts):
    """Form factor from differential areas at points p (..., 3) with unit normals n (..., 3)
    to the polygon `verts` (k, 3), when the whole polygon is above every point's tangent plane
    and unoccluded (Lambert's contour formula: F = |sum_i beta_i n . g_i| / (2 pi), g_i the unit
    normal of the plane through p and edge i, beta_i the angle the edge subtends). Irradiance
    from a Lambertian emitter of radiance L is pi L F; a Lambertian surface of reflectance rho
    then has radiance rho L F."""
    total = 0.0
    verts = np.asarray(verts, float)
    for i in range(len(verts)):
        a = verts[i] - p
        b = verts[(i + 1) % len(verts)] - p
        a = a / np.linalg.norm(a, axis=-1, keepdims=True)
        b = b / np.linalg.norm(b, axis=-1, keepdims=True)
        c = np.cross(a, b)
        cn = np.linalg.norm(c, axis=-1, keepdims=True)
        beta = np.arctan2(cn[..., 0], np.sum(a * b, axis=-1))
        total = total + beta * np.sum(n * c / np.maximum(cn, 1e-300), axis=-1)
    return np.abs(total) / (2 * math.pi)


# --- comparison ------------------------------------------------------------------------------

def block_z(pair_a, pair_b, block, keep=None, expected_diff=None, min_pixels=8):
    """Noise-derived comparison of two renderers, each rendered twice with different seeds
    (pair_x = (image seed 1, image seed 2), float (h, w, c)). The variance of one render per
    pixel is estimated as (x1 - x2)^2 / 2; the mean of each pair is compared over blocks of
    block x block pixels per channel: z = (mean_a - mean_b - expected) / sqrt(var_a + var_b),
    var the block-mean variances. keep: optional (h, w) bool mask of the pixels to use;
    expected_diff: optional (h, w, c) predicted a - b. A block whose variance rests on fewer
    than min_pixels kept non-black pixels gets z = 0 (a variance estimated from one or two
    pixels' seed pairs can be arbitrarily small: chi-square with that many degrees of freedom).
    Returns (z (h/block, w/block, c), block means a, block means b, kept pixels per block)."""
    a1, a2 = pair_a
    b1, b2 = pair_b
    h, w, c = a1.shape
    k = np.ones((h, w, 1)) if keep is None else keep[..., None].astype(np.float64)
    k = np.broadcast_to(k, (h, w, c))

    def bsum(x):
        return (x * k).reshape(h // block, block, w // block, block, c).sum(axis=(1, 3))
    n = bsum(np.ones((h, w, c)))
    nn = np.maximum(n, 1.0)
    active = bsum(((a1 != 0) | (a2 != 0) | (b1 != 0) | (b2 != 0)).astype(np.float64))
    var = (bsum(0.25 * (a1 - a2) ** 2) + bsum(0.25 * (b1 - b2) ** 2)) / nn ** 2
    ma, mb = bsum(0.5 * (a1 + a2)) / nn, bsum(0.5 * (b1 + b2)) / nn
    # Floor: float32 rendering and storage (24-bit mantissa; 1e-6 relative is ~16 ulps), so
    # noiseless blocks (background, sun-lit Lambert) compare at float precision, not exactly.
    var = var + (FLOAT_FLOOR * np.maximum(np.abs(ma), np.abs(mb))) ** 2
    diff = ma - mb
    if expected_diff is not None:
        diff = diff - bsum(expected_diff) / nn
    z = np.where(active >= min_pixels, diff / np.sqrt(np.maximum(var, 1e-30)), 0.0)
    return z, ma, mb, n
