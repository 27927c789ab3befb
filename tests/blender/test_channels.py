"""Image channels, Principled Alpha and Emission textures, Clearcoat Normal
(facet_blender/textures.py, materials.py, normals.py) in headless Blender:

1. Exported data: Separate Color (RGB) / Separate RGB / Separate XYZ of an Image Texture's Color
   into a number input -> the texture's "channel" r / g / b (a grey image: "luminance"); a
   Separate of a Combine -> the Combine's input; a Combine of the three channels of one image in
   order -> the image; Math Multiply by a constant -> "scale" (by 0: the constant 0); what does
   not convert (Separate Color in HSV mode, a permuted Combine) is reported. Principled Alpha
   -> "opacity" (an image's Alpha: channel "a"; a constant), not on an emitting Principled
   (reported); an image into Principled Emission -> the emission texture with "scale" =
   Emission Strength. Clearcoat Normal: the same map as Normal, or Clearcoat 0, is exact (no
   line); a map of its own is ignored (Normal's, or none, shades every lobe) and reported.
2. Renders against Cycles (16 spp both, box filter 1 px, black world, max depth 1): a strip of
   quads seen from above by an orthographic camera, each pixel a function of one texture
   (no shading): Emission Color from Separate Color Green, from Separate RGB Blue, from
   Separate XYZ X (each a grey emission of that channel); an image into Principled Emission
   with Strength 2 (black base, Specular 0: the principled reflects nothing of the black
   world); a black Principled whose Alpha is an image's alpha above an emissive quad of
   radiance 1 (a pixel shows 1 - alpha). Tolerance: mean |Facet - Cycles| per quad < 0.01 and
   99th percentile < 0.15, as the texture strip of test_textures.py (sampling noise where a
   pixel straddles a texel edge: sd up to 0.14 for the difference). A wrong channel changes
   the pixels by 0.25 to 0.38 on average (the test image's channels are different ramps: R
   along x, G along y, B a 3-periodic pattern; measured between the quads' images), the
   Principled emission without its Strength by half its mean (0.65).
   The cut-out is stochastic per pixel in both renderers, so its 8 x 8-block means are
   checked against the analytic 1 - alpha (bound and why: render_strip).
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 16
new_material = bt.new_material


def test_image(outdir, name, w=8, h=6, grey=False, alpha=False):
    """A float EXR (so that Cycles and Facet interpolate the same values) of distinct
    channels: R = (x + 0.5) / w, G = (y + 0.5) / h, B = ((x + 2y) mod 3) / 2, with `alpha`
    0.2 + 0.6 (x + y) / (w + h - 2) (else opaque); a grey image has R = G = B = the R ramp."""
    path = os.path.join(outdir, name + ".exr")
    img = bpy.data.images.new(name + "_src", w, h, alpha=alpha, float_buffer=True)
    y, x = np.mgrid[0:h, 0:w]
    px = np.ones((h, w, 4), np.float32)
    px[..., 0] = (x + 0.5) / w
    px[..., 1] = (y + 0.5) / h if not grey else px[..., 0]
    px[..., 2] = ((x + 2 * y) % 3) / 2.0 if not grey else px[..., 0]
    if alpha:
        px[..., 3] = 0.2 + 0.6 * (x + y) / (w + h - 2)
    img.pixels.foreach_set(px.ravel())
    img.filepath_raw = path
    img.file_format = 'OPEN_EXR'
    img.save()
    bpy.data.images.remove(img)
    out = bpy.data.images.load(path, check_existing=False)
    out.colorspace_settings.name = 'Non-Color'
    return out


def image_node(nt, img):
    t = nt.nodes.new("ShaderNodeTexImage")
    t.image = img
    t.interpolation = 'Closest'
    t.extension = 'EXTEND'
    return t


def separate(nt, idname, sock, mode=None):
    s = nt.nodes.new(idname)
    if mode is not None:
        s.mode = mode
    nt.links.new(sock, s.inputs[0])
    return s


def principled(nt, out, **inputs):
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    for k, v in inputs.items():
        p.inputs[k.replace("_", " ")].default_value = v
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    return p


def exported(outdir):
    from facet_blender import materials
    img = test_image(outdir, "facet_channels")
    grey = test_image(outdir, "facet_channels_grey", grey=True)
    img_a = test_image(outdir, "facet_channels_alpha", alpha=True)
    path = os.path.normpath(img.filepath)

    # Separate * -> channel, into Roughness (a number input).
    for idname, mode, out_name, ch in (
            ("ShaderNodeSeparateColor", 'RGB', "Green", "g"),
            ("ShaderNodeSeparateRGB", None, "B", "b"),
            ("ShaderNodeSeparateXYZ", None, "X", "r")):
        mat, nt, out = new_material("sep_" + ch)
        p = principled(nt, out)
        s = separate(nt, idname, image_node(nt, img).outputs["Color"], mode)
        nt.links.new(s.outputs[out_name], p.inputs["Roughness"])
        c = materials.convert(mat)
        r = c.data["roughness"]
        bt.check(isinstance(r, dict) and r["texture"] == path and r.get("channel") == ch
                 and r.get("scale", 1.0) == 1.0 and c.problems == [],
                 "%s %s -> channel %s: %s %s" % (idname, out_name, ch, r, c.problems))

    # A grey image: every channel is its luminance.
    mat, nt, out = new_material("sep_grey")
    p = principled(nt, out)
    s = separate(nt, "ShaderNodeSeparateColor", image_node(nt, grey).outputs["Color"], 'RGB')
    nt.links.new(s.outputs["Blue"], p.inputs["Metallic"])
    c = materials.convert(mat)
    bt.check(c.data["metallic"].get("channel") == "luminance" and c.problems == [],
             "a grey image's Blue -> luminance: %s %s" % (c.data["metallic"], c.problems))

    # HSV mode: not one channel; reported (no bake without an object), the input's value used.
    mat, nt, out = new_material("sep_hsv")
    p = principled(nt, out, Roughness=0.25)
    s = separate(nt, "ShaderNodeSeparateColor", image_node(nt, img).outputs["Color"], 'HSV')
    nt.links.new(s.outputs["Red"], p.inputs["Roughness"])
    c = materials.convert(mat)
    bt.check(c.data["roughness"] == 0.25 and len(c.problems) == 1
             and "Separate Color" in c.problems[0] and "HSV" in c.problems[0],
             "Separate Color HSV: reported: %s %s" % (c.data["roughness"], c.problems))

    # Math Multiply of a channel: scale; by 0 the constant 0 (the glTF importer's
    # metallicFactor 0 x the metallic-roughness texture's B).
    for factor in (0.5, 0.0):
        mat, nt, out = new_material("mul")
        p = principled(nt, out, Metallic=0.75)
        s = separate(nt, "ShaderNodeSeparateColor", image_node(nt, img).outputs["Color"], 'RGB')
        m = nt.nodes.new("ShaderNodeMath")
        m.operation = 'MULTIPLY'
        m.inputs[1].default_value = factor
        nt.links.new(s.outputs["Blue"], m.inputs[0])
        nt.links.new(m.outputs[0], p.inputs["Metallic"])
        c = materials.convert(mat)
        v = c.data["metallic"]
        ok = v == 0.0 if factor == 0.0 else (v.get("channel") == "b" and v.get("scale") == 0.5)
        bt.check(ok and c.problems == [], "Separate Blue x %g: %s %s" % (factor, v, c.problems))

    # Combine(Separate R, G, B of one image) into Base Color: the image; permuted: reported.
    for order in (("Red", "Green", "Blue"), ("Green", "Red", "Blue")):
        mat, nt, out = new_material("combine")
        p = principled(nt, out)
        s = separate(nt, "ShaderNodeSeparateColor", image_node(nt, img).outputs["Color"], 'RGB')
        cmb = nt.nodes.new("ShaderNodeCombineColor")
        for o, i in zip(order, ("Red", "Green", "Blue")):
            nt.links.new(s.outputs[o], cmb.inputs[i])
        nt.links.new(cmb.outputs[0], p.inputs["Base Color"])
        # Separate(Combine).Green -> the Combine's Green input: the image's (order[1]) channel.
        s2 = separate(nt, "ShaderNodeSeparateColor", cmb.outputs[0], 'RGB')
        nt.links.new(s2.outputs["Green"], p.inputs["Roughness"])
        c = materials.convert(mat)
        b, r = c.data["base_color"], c.data["roughness"]
        rch = r.get("channel") if isinstance(r, dict) else None
        if order[0] == "Red":
            bt.check(isinstance(b, dict) and "channel" not in b and b["texture"] == path
                     and rch == "g" and c.problems == [],
                     "Combine of R, G, B: the image; Separate of it: %s %s %s" % (b, r, c.problems))
        else:
            bt.check(not isinstance(b, dict) and rch == "r" and len(c.problems) == 1
                     and "Combine Color" in c.problems[0],
                     "a permuted Combine is reported; Separate Green of it is R: %s %s %s"
                     % (b, r, c.problems))

    # Principled Alpha: an image's Alpha -> opacity channel "a"; a constant; with an emission:
    # reported, opaque.
    mat, nt, out = new_material("alpha")
    p = principled(nt, out)
    t = image_node(nt, img_a)
    nt.links.new(t.outputs["Color"], p.inputs["Base Color"])
    nt.links.new(t.outputs["Alpha"], p.inputs["Alpha"])
    c = materials.convert(mat)
    o = c.data.get("opacity")
    bt.check(isinstance(o, dict) and o.get("channel") == "a"
             and o["texture"] == os.path.normpath(img_a.filepath)
             and c.problems == [], "image Alpha -> opacity: %s %s" % (o, c.problems))
    # A packed image (the glTF importer packs every image): its file's bytes, alpha included,
    # not an EXR of Blender's RGB pixels (which made ClearCoatTest's cut-out opaque).
    png = os.path.join(outdir, "facet_channels_alpha.png")
    src = bpy.data.images.new("alpha_png_src", 8, 6, alpha=True)
    px = np.ones((6, 8, 4), np.float32)
    px[..., 3] = np.linspace(0.0, 1.0, 48).reshape(6, 8)
    src.pixels.foreach_set(px.ravel())
    src.filepath_raw = png
    src.file_format = 'PNG'
    src.save()
    bpy.data.images.remove(src)
    packed = bpy.data.images.load(png, check_existing=False)
    packed.pack()
    mat, nt, out = new_material("alpha_packed")
    p = principled(nt, out)
    nt.links.new(image_node(nt, packed).outputs["Alpha"], p.inputs["Alpha"])
    c = materials.convert(mat)
    o = c.data.get("opacity")
    same = False
    if isinstance(o, dict) and o["texture"].endswith(".png"):
        with open(png, "rb") as f, open(o["texture"], "rb") as g:
            same = f.read() == g.read()
    bt.check(same and o.get("channel") == "a" and c.problems == [],
             "a packed PNG's Alpha -> opacity from the packed bytes: %s %s" % (o, c.problems))
    mat, nt, out = new_material("alpha_const")
    principled(nt, out, Alpha=0.3)
    c = materials.convert(mat)
    bt.check(abs(c.data.get("opacity", 1.0) - 0.3) < 1e-6 and c.problems == [],
             "Alpha 0.3 -> opacity 0.3: %s %s" % (c.data.get("opacity"), c.problems))
    mat, nt, out = new_material("alpha_emit")
    principled(nt, out, Alpha=0.3, Emission=(1, 1, 1, 1), Emission_Strength=1.0)
    c = materials.convert(mat)
    bt.check("opacity" not in c.data and len(c.problems) == 1 and "Alpha" in c.problems[0]
             and "emission" in c.problems[0],
             "Alpha with an emission: reported, opaque: %s %s" % (c.data, c.problems))

    # Image into Principled Emission, Strength 2: the texture, scale 2.
    mat, nt, out = new_material("emit")
    p = principled(nt, out, Emission_Strength=2.0)
    nt.links.new(image_node(nt, img).outputs["Color"], p.inputs["Emission"])
    c = materials.convert(mat)
    e = c.emission
    bt.check(isinstance(e, dict) and e["texture"] == path and e.get("scale") == 2.0
             and c.problems == [], "image -> Principled Emission x 2: %s %s" % (e, c.problems))

    # Clearcoat Normal.
    def coat_material(name, clearcoat, base_map, coat_map):
        mat, nt, out = new_material(name)
        p = principled(nt, out, Clearcoat=clearcoat)
        for target, im in (("Normal", base_map), ("Clearcoat Normal", coat_map)):
            if im is not None:
                nm = nt.nodes.new("ShaderNodeNormalMap")
                nt.links.new(image_node(nt, im).outputs["Color"], nm.inputs["Color"])
                nt.links.new(nm.outputs[0], p.inputs[target])
        return materials.convert(mat)
    c = coat_material("coat_shared", 1.0, img, img)
    bt.check(c.data.get("normal_map", {}).get("texture") == path and c.problems == [],
             "the same map into Normal and Clearcoat Normal: exact: %s" % c.problems)
    c = coat_material("coat_none", 0.0, None, grey)
    bt.check("normal_map" not in c.data and c.problems == [],
             "Clearcoat 0: its normal shades nothing: %s %s" % (c.data, c.problems))
    c = coat_material("coat_own", 1.0, None, grey)
    bt.check("normal_map" not in c.data and len(c.problems) == 1
             and "Clearcoat Normal is ignored" in c.problems[0]
             and "the shading normal" in c.problems[0],
             "a Clearcoat Normal of its own: ignored, reported: %s %s" % (c.data, c.problems))
    c = coat_material("coat_both", 1.0, img, grey)
    bt.check(c.data.get("normal_map", {}).get("texture") == path and len(c.problems) == 1
             and "Clearcoat Normal is ignored" in c.problems[0] and "Normal's" in c.problems[0],
             "Normal and a different Clearcoat Normal: the Normal's kept, reported: %s"
             % c.problems)


# --- render against Cycles -----------------------------------------------------------------

def _quad(me_verts, faces, x0, z=0.0):
    n = len(me_verts)
    me_verts += [(x0, 0, z), (x0 + 1, 0, z), (x0 + 1, 1, z), (x0, 1, z)]
    faces.append((n, n + 1, n + 2, n + 3))


def render_strip(outdir):
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    img = test_image(outdir, "facet_channels_r")
    img_a = test_image(outdir, "facet_channels_ra", alpha=True)
    n = 5
    verts, faces = [], []
    for i in range(n):
        _quad(verts, faces, i)
    _quad(verts, faces, n - 1, 0.5)  # the cut-out quad, above the last one
    me = bpy.data.meshes.new("strip")
    me.from_pydata(verts, [], faces)
    uv = me.uv_layers.new(name="UVMap")
    for i in range(len(me.loops)):
        uv.data[i].uv = [(0, 0), (1, 0), (1, 1), (0, 1)][i % 4]
    ob = bpy.data.objects.new("strip", me)
    scene.collection.objects.link(ob)
    bt.ortho_camera(scene, n, (n / 2.0, 0.5, 5.0))
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0

    def emission(nt, out, sock):
        e = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(sock, e.inputs["Color"])
        nt.links.new(e.outputs[0], out.inputs["Surface"])

    def sep_color(nt, out):
        s = separate(nt, "ShaderNodeSeparateColor", image_node(nt, img).outputs["Color"], 'RGB')
        emission(nt, out, s.outputs["Green"])

    def sep_rgb(nt, out):
        s = separate(nt, "ShaderNodeSeparateRGB", image_node(nt, img).outputs["Color"])
        emission(nt, out, s.outputs["B"])

    def sep_xyz(nt, out):
        s = separate(nt, "ShaderNodeSeparateXYZ", image_node(nt, img).outputs["Color"])
        emission(nt, out, s.outputs["X"])

    flat = bpy.data.images.new("flat_normal", 2, 2, float_buffer=True)
    flat.pixels.foreach_set(np.tile([0.5, 0.5, 1.0, 1.0], 4).astype(np.float32))
    flat.filepath_raw = os.path.join(outdir, "facet_flat_normal.exr")
    flat.file_format = 'OPEN_EXR'
    flat.save()
    flat.colorspace_settings.name = 'Non-Color'

    def principled_emission(nt, out):
        p = principled(nt, out, Base_Color=(0, 0, 0, 1), Specular=0.0, Emission_Strength=2.0)
        nt.links.new(image_node(nt, img).outputs["Color"], p.inputs["Emission"])
        # A (flat) Normal Map naming the render UV map, as the glTF importer writes them: the
        # same map as the textures' default one (no "several UV maps" line; export.py).
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.uv_map = "UVMap"
        nt.links.new(image_node(nt, flat).outputs["Color"], nm.inputs["Color"])
        nt.links.new(nm.outputs[0], p.inputs["Normal"])

    def lit(nt, out):  # under the cut-out quad: radiance 1
        e = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(e.outputs[0], out.inputs["Surface"])

    def cutout(nt, out):
        p = principled(nt, out, Base_Color=(0, 0, 0, 1), Specular=0.0)
        nt.links.new(image_node(nt, img_a).outputs["Alpha"], p.inputs["Alpha"])

    builders = [sep_color, sep_rgb, sep_xyz, principled_emission, lit, cutout]
    for i, build in enumerate(builders):
        mat, nt, out = new_material("chan%d" % i)
        build(nt, out)
        me.materials.append(mat)
        me.polygons[i].material_index = i
    scene.render.resolution_x, scene.render.resolution_y = 32 * n, 32
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    # Cycles' transparent bounces: enough to pass the cut-out (max_depth 1 leaves 0).
    scene.cycles.transparent_max_bounces = 8
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, "channels_facet.exr"), seed=1)
    from facet_blender import hooks
    problems = list(hooks.last_problems)
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "channels_cycles.exr"), seed=1)
    bt.check(problems == [], "the strip converts without a report (a Normal Map naming the "
             "render UV map is that map): %s" % problems)
    d = np.abs(a - b)
    for i, name in enumerate(("Separate Color Green", "Separate RGB Blue", "Separate XYZ X",
                              "Principled Emission x 2")):
        sl = slice(32 * i, 32 * (i + 1))
        di = d[:, sl]
        print("%s: means Facet %.4f, Cycles %.4f" % (name, a[:, sl].mean(), b[:, sl].mean()))
        bt.check(b[:, sl].mean() > 0.05, "Cycles sees quad %d (%.3f)" % (i, b[:, sl].mean()))
        bt.check(di.mean() < 0.01 and np.percentile(di, 99) < 0.15,
                 "%s: mean |Facet - Cycles| %.4f < 0.01, 99th pct %.4f < 0.15"
                 % (name, di.mean(), np.percentile(di, 99)))
    # The cut-out: each renderer's pixel is a mean of 16 stochastic pass-or-stop choices, so
    # pixels differ by up to 0.25 (sd 0.5 / 4), and the 8 x 8-block means are compared with
    # the analytic 1 - alpha, averaged over each pixel (64 subpixels; Closest texels): a block
    # averages 1024 choices, sd <= 0.5 / 32 = 0.016, bound 0.065 (4 sd). An opacity of
    # 1 - alpha instead (the image's mean is the same) is off by up to 0.47 in a block.
    sub = (np.arange(32 * 8) + 0.5) / (32 * 8)
    u, v = np.meshgrid(sub, 1.0 - sub)
    tx, ty = np.minimum((u * 8).astype(int), 7), np.minimum((v * 6).astype(int), 5)
    alpha = 0.2 + 0.6 * (tx + ty) / 12.0
    expected = (1.0 - alpha).reshape(32, 8, 32, 8).mean(axis=(1, 3))
    sl = slice(32 * 4, 32 * 5)

    def blocks(img):
        return img[:, sl].mean(axis=2).reshape(4, 8, 4, 8).mean(axis=(1, 3))
    eb = expected.reshape(4, 8, 4, 8).mean(axis=(1, 3))
    wrong = np.abs(1.0 - eb - eb).max()
    for who, img in (("Facet", a), ("Cycles", b)):
        err = np.abs(blocks(img) - eb).max()
        bt.check(err < 0.065, "cut-out (1 - alpha): %s's 8 x 8 blocks within %.4f < 0.065 of "
                 "the analytic value (an opacity of 1 - alpha would be off by %.3f)"
                 % (who, err, wrong))


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    exported(outdir)
    render_strip(outdir)


bt.run(main)
