"""Blender texture subgraphs -> Facet textures (scenes/FORMAT.md, Textures), exactly as Cycles
3.4 evaluates them where Facet can express it; pure Python over bpy data (no bpy.ops).

A BSDF input (or an Emission's Color) fed by one of these converts to a texture dict of the
scene format (`{"texture": file, ...}` or `{"checker": {...}, ...}`):

- Image Texture, Color or Alpha output: the image's file (a packed, generated or missing file
  is written to the cache directory as a float EXR of Blender's pixels, with the image's colour
  space), colour space sRGB -> "srgb", Linear / Non-Color / Raw -> "linear" (others reported,
  "linear" used); interpolation Linear -> "linear", Closest -> "closest" (Cubic and Smart
  reported, "linear" used); extension Repeat -> "repeat", Extend -> "clamp", Mirror ->
  "mirror" (Clip reported, "clamp" used: Cycles gives transparent black outside [0, 1]);
  projection Flat (Box, Sphere, Tube are not converted). Cycles interpolates an 8-bit sRGB
  image's encoded values and decodes after; Facet decodes the texels, then interpolates:
  reported (measured on an 8 x 6 texture of strongly different neighbours magnified 4x per
  texel: mean difference 0.06; a float image agrees to 0.001). Alpha -> channel "a" (an image
  without alpha: the constant 1, as Cycles). A colour output into a number input: channel
  "luminance" (Facet's Rec. 709 weights 0.2126, 0.7152, 0.0722 against Cycles' 0.2126729,
  0.7151522, 0.0721750: reported, under 1e-4 relative).
- Channels (_separate, _combine, _math): Separate Color (RGB) / RGB / XYZ of an Image Texture's
  Color -> channel r, g, b (a grey image: luminance); Separate of a Combine -> the Combine's
  input; Combine of the three channels of one texture in order -> the texture; Math Multiply
  of a number texture by a constant c >= 0 (no Clamp) -> "scale" c (c = 0: the constant 0).
- Checker Texture, Color or Fac output, with constant Color1, Color2 and Scale: Cycles'
  svm_checker on p = Scale x the vector: the cell (floor x, floor y, floor z) is Color1 when
  (|floor x| mod 2 == |floor y| mod 2) != (|floor z| mod 2), else Color2. On UVs (z = 0) the
  cell at the origin is Color2: "colors": [Color2, Color1], "scale": Scale (Fac: [0, 1]); a
  constant z with an odd cell swaps them. Cycles nudges p by (p + 1e-6) 0.999999 against
  precision issues on integer coordinates; Facet does not (cell edges move by ~1e-6 cells).
- The vector: an Image Texture's unlinked Vector is the render UV map (Cycles' default); a
  Checker's unlinked Vector is Generated coordinates (not converted). Texture Coordinate's UV
  output and UV Map nodes are a mesh's UV map (UV Map names it; the mesh exports that layer),
  then any chain of Mapping nodes of type Point, Texture or Vector with constant Location,
  Rotation and Scale (Cycles' svm_mapping: Point R (v s) + l, Texture R^T (v - l) / s, Vector
  R (v s), R = Rz Ry Rx), Separate / Combine XYZ, Math Add, Subtract, Multiply and Multiply
  Add by constants, Divide by a constant (no Clamp), Vector Math Add, Subtract, Multiply,
  Scale, the Mix node's Vector mode with a constant factor (_affine). The chain acts on
  (u, v, 0) as an affine map; it is exact when its (x, y) part is R(theta) diag(su, sv)
  (u, v) + (ou, ov) -- "uv_rotation" theta in degrees,
  "uv_scale", "uv_offset" -- i.e. its 2 x 2 matrix has orthogonal columns (a rotation about Z
  with any scale, or any rotation with a uniform scale in the UV plane), and, for the
  checker, its z is constant. Anything else raises Unsupported.
- Color Attribute (Vertex Color) node -> `{"vertex_color": true}` (FORMAT.md, "Vertex
  colours"): the mesh exports the attribute the node names (empty: the mesh's default colour
  attribute, Cycles' ATTR_STD_VERTEX_COLOR) as its `colors` (export.py). Color output: the
  colour (into a number input: channel "luminance", as for images); Alpha: channel "a".
  Cycles interpolates linear values per corner (byte colours are decoded per corner first),
  as the core does.
- Hair Info node, Random, Intercept or Is Strand output -> `{"hair_info": {"output": ...}}`
  (FORMAT.md, "Textures"): the strand's random value (Cycles 3.4's hash of its index), its
  position along the strand, 1 on curves; 0 elsewhere, as Cycles. Length, Thickness and
  Tangent Normal raise Unsupported.
- Light Path node, any output but Is Shadow Ray and Transparent Depth ->
  `{"light_path": {"output": ...}}` (FORMAT.md, "Light Path outputs"): the kind, length and
  bounce counts of the ray that reached the hit, as Cycles 3.4 gives them to a surface shader.
  Only BSDF inputs and Mix Shader factors read it (materials.py reports it in an emission, an
  Alpha, a Normal Map or a Bump).

Every approximation is returned as a note (the caller reports it); everything else raises
Unsupported(out, reason) naming the node that stops the conversion.
"""
import math
import os
import tempfile

from . import nodegraph

CACHE_DIR = os.path.join(tempfile.gettempdir(), "facet_blender_cache")

# Blender 3.4's colour spaces whose values Facet reads exactly.
_COLORSPACES = {"sRGB": "srgb", "Linear": "linear", "Non-Color": "linear", "Raw": "linear"}
# Cycles' Linear is bilinear on the full-resolution image at every sample (no MIP maps on the
# CPU): Facet's `linear`, named explicitly since the core's default is `mipmap`, which in
# minification differs from Cycles (TextureTransformTest with Extend: +7.3% image mean, up to
# +33% per 8 x 8 block; linear: +0.4%; docs/realscenes.md).
_FILTERS = {'Linear': "linear", 'Closest': "closest"}
_WRAPS = {'REPEAT': None, 'EXTEND': "clamp", 'MIRROR': "mirror"}
# Cycles' rgb_to_y (nodegraph.RGB_TO_Y) against Facet's luminance channel.
LUMINANCE_NOTE = ("a colour into a number input: Facet's luminance (0.2126, 0.7152, 0.0722) "
                  "instead of Cycles' (0.2126729, 0.7151522, 0.0721750), under 1e-4 relative")


class Unsupported(Exception):
    """`out` (nodegraph.Out) stops the conversion, for `reason` (None: `out` is no texture
    node at all)."""

    def __init__(self, out, reason):
        super().__init__(reason or "not a texture")
        self.out = out
        self.reason = reason


class Result:
    """A converted texture: `data` (scene-format texture dict), `uv_map` (the Blender UV layer
    name it reads, "" for the render UV map), `notes` (approximations to report)."""

    def __init__(self, data, uv_map="", notes=(), const=1.0, color_attribute=None):
        self.data = data
        self.uv_map = uv_map
        self.notes = list(notes)
        self.const = const  # the value when data is None (an opaque image's Alpha: 1)
        # A vertex colour texture: the colour attribute the mesh exports ("" the default
        # one; None: not a vertex colour texture, and then uv_map is the UV layer read).
        self.color_attribute = color_attribute
        # A composite's (math, mix_rgb, color_ramp): what its input textures read besides
        # uv_map / color_attribute, and whether one reads Generated coordinates.
        self.more_uv_maps = set()
        self.more_color_attributes = set()
        self.generated = False

    def reads(self):
        """(UV maps, colour attributes, reads Generated coordinates) of the texture."""
        uvs, cas = set(self.more_uv_maps), set(self.more_color_attributes)
        if self.data is not None:
            if self.color_attribute is not None:
                cas.add(self.color_attribute)
            elif self.uv_map is not None:
                uvs.add(self.uv_map)
        gen = self.generated or (self.data is not None
                                 and self.data.get("coordinates") == "generated")
        return uvs, cas, gen


def convert(walker, src, number):
    """The texture for the Out `src` feeding a number (`number` True) or colour input, or
    Unsupported. The link conversions on the way (src.convs) are applied: colour -> number is
    the luminance channel; number -> colour a grey texture."""
    node = src.node
    types = (src.socket.type,) + src.convs
    # Vectors pass between colours unchanged (Cycles' colour <-> vector links copy the
    # components, a number -> vector link repeats it): a colour texture into a Mix node's
    # vector input, and that Mix's (or a Vector Math's) vector result into a colour input. A
    # vector -> number link
    # (the components' mean) and any other vector output do not convert.
    vector_ok = (not any(a == 'VECTOR' and b in ('VALUE', 'INT', 'BOOLEAN')
                         for a, b in zip(types, types[1:]))
                 and (src.socket.type != 'VECTOR' or (node.bl_idname == 'ShaderNodeMix'
                                                      and src.socket.identifier ==
                                                      'Result_Vector')
                      or node.bl_idname == 'ShaderNodeVectorMath'))
    if ('VECTOR' in types and not vector_ok) or 'SHADER' in types:
        raise Unsupported(src, "a vector output used as a colour or number")
    to_number = any(a == 'RGBA' and b in ('VALUE', 'INT', 'BOOLEAN')
                    for a, b in zip(types, types[1:])) or (number and types[-1] == 'RGBA')
    if node.bl_idname == 'ShaderNodeTexImage':
        return _image(walker, src, to_number)
    if node.bl_idname == 'ShaderNodeTexChecker':
        return _checker(walker, src, to_number)
    if node.bl_idname == 'ShaderNodeVertexColor':
        return _color_attribute(src, to_number)
    if node.bl_idname == 'ShaderNodeHairInfo':
        return _hair_info(src)
    if node.bl_idname == 'ShaderNodeLightPath':
        return _light_path(src)
    if node.bl_idname in PROCEDURAL:
        return _procedural(walker, src, to_number)
    if node.bl_idname in SEPARATE:
        return _separate(walker, src)
    if node.bl_idname in COMBINE and not to_number:
        return _combine(walker, src)
    if node.bl_idname == 'ShaderNodeMath':
        return _math(walker, src, 'RGBA' in types)
    if node.bl_idname == 'ShaderNodeVectorMath':
        return _vector_math_node(walker, src)
    if node.bl_idname == 'ShaderNodeValToRGB':
        return _color_ramp(walker, src, to_number)
    if node.bl_idname in ('ShaderNodeMixRGB', 'ShaderNodeMix'):
        return _mix(walker, src, to_number)
    raise Unsupported(src, None)  # not a texture node: the caller reports the folding


# --- channels ---------------------------------------------------------------------------------
#
# Separate Color (mode RGB), Separate RGB and Separate XYZ of an Image Texture's Color: one
# channel of the image, the core texture's "channel" r, g or b (Cycles' separate nodes copy the
# component, and a colour <-> vector link keeps the components). Separate of a Combine (RGB
# mode) is the Combine's input of that channel, and a Combine of the three Separate channels of
# one texture, in order, is that texture (pass-throughs). Math Multiply of a number texture by a
# constant c >= 0 (no Clamp) scales it ("scale" c); by 0 it is the constant 0.

# bl_idname -> (input, {output identifier: channel}, the node's mode that converts or None).
SEPARATE = {
    'ShaderNodeSeparateColor': ('Color', {'Red': "r", 'Green': "g", 'Blue': "b"}, 'RGB'),
    'ShaderNodeSeparateRGB': ('Image', {'R': "r", 'G': "g", 'B': "b"}, None),
    'ShaderNodeSeparateXYZ': ('Vector', {'X': "r", 'Y': "g", 'Z': "b"}, None),
}
COMBINE = {
    'ShaderNodeCombineColor': (('Red', 'Green', 'Blue'), 'RGB'),
    'ShaderNodeCombineRGB': (('R', 'G', 'B'), None),
    'ShaderNodeCombineXYZ': (('X', 'Y', 'Z'), None),
}
_CHANNELS = ("r", "g", "b")


def _mode_ok(node, mode):
    return mode is None or getattr(node, "mode", mode) == mode


def _separate(walker, src):
    node = src.node
    inp, outs, mode = SEPARATE[node.bl_idname]
    if not _mode_ok(node, mode):
        raise Unsupported(src, "mode %s of a texture (only RGB converts: one channel)"
                          % node.mode)
    channel = outs[src.socket.identifier]
    up = walker.input(node, inp, src.path)
    if isinstance(up, nodegraph.Const):
        raise Unsupported(src, None)  # constant: the folding decides
    if up.node.bl_idname in COMBINE and _mode_ok(up.node, COMBINE[up.node.bl_idname][1]):
        # Separate(Combine(a, b, c)).channel is the Combine's input of that channel.
        names = COMBINE[up.node.bl_idname][0]
        return convert(walker, _number_src(walker, up, names[_CHANNELS.index(channel)]),
                       number=True)
    if up.node.bl_idname != 'ShaderNodeTexImage' or up.socket.identifier != 'Color':
        raise Unsupported(src, "a channel of something other than an Image Texture's Color "
                          "(only an image's channels convert)")
    res = _image(walker, up, to_number=False)
    if res.data is not None:
        # A grey image (r = g = b at every pixel; its file may have one channel only): every
        # channel is its luminance (Facet's weights sum to 1).
        res.data["channel"] = "luminance" if _grey(up.node.image) else channel
    return res


def _number_src(walker, combine_out, name):
    """The value feeding input `name` of the Combine node of `combine_out` (an Out), or
    Unsupported when it is a constant (a constant channel of a texture is no texture)."""
    v = walker.input(combine_out.node, name, combine_out.path)
    if isinstance(v, nodegraph.Const):
        raise Unsupported(combine_out, "a constant channel of a combined texture")
    return v


def _combine(walker, src):
    """Combine(Separate r, g, b of one texture X), in that order: X itself."""
    node = src.node
    names, mode = COMBINE[node.bl_idname]
    if not _mode_ok(node, mode):
        raise Unsupported(src, "mode %s of textures (only RGB converts)" % node.mode)
    ups = [walker.input(node, n, src.path) for n in names]
    first = None
    for ch, up in zip(_CHANNELS, ups):
        if isinstance(up, nodegraph.Const) or up.node.bl_idname not in SEPARATE or up.convs:
            raise Unsupported(src, "combines other than the three channels of one texture in "
                              "order are not converted")
        inp, outs, smode = SEPARATE[up.node.bl_idname]
        if outs[up.socket.identifier] != ch or not _mode_ok(up.node, smode):
            raise Unsupported(src, "combines other than the three channels of one texture in "
                              "order are not converted")
        x = walker.input(up.node, inp, up.path)
        if isinstance(x, nodegraph.Const):
            raise Unsupported(src, None)
        key = (x.key, x.socket.identifier, x.convs)
        if first is None:
            first = (key, x)
        elif key != first[0]:
            raise Unsupported(src, "combines channels of different textures (not converted)")
    return convert(walker, first[1], number=False)


def _math(walker, src, as_color=False):
    """Math Multiply of a number texture by a constant >= 0: its "scale"; any other Math node
    of textures: the core's `math` kind (_math_node)."""
    node = src.node
    if node.operation != 'MULTIPLY' or node.use_clamp or as_color:
        return _math_node(walker, src)
    a = walker.input(node, node.inputs[0], src.path)
    b = walker.input(node, node.inputs[1], src.path)
    va, _ = walker.fold(a)
    vb, _ = walker.fold(b)
    if (va is None) == (vb is None):
        return _math_node(walker, src)  # both textures (both constant: the folding's)
    c, tex = (va, b) if va is not None else (vb, a)
    if not isinstance(c, float) or not math.isfinite(c) or c < 0.0:
        return _math_node(walker, src)
    if c == 0.0:
        return Result(None, const=0.0)  # 0 x a finite texture
    res = convert(walker, tex, number=True)
    if res.data is not None:
        res.data["scale"] = res.data.get("scale", 1.0) * c
    else:
        res.const *= c
    return res


def _color_attribute(src, to_number):
    """The Color Attribute node: the mesh's colours at the hit (no UVs, no filtering)."""
    data = {"vertex_color": True}
    notes = []
    if src.socket.identifier == 'Alpha':
        data["channel"] = "a"
    elif to_number:
        data["channel"] = "luminance"
        notes.append("%s: %s" % (src.label(), LUMINANCE_NOTE))
    return Result(data, None, notes, color_attribute=src.node.layer_name)


# Light Path outputs -> the light_path texture's outputs (Is Shadow Ray: the shape's switches
# only, materials.py light_path_switches; Transparent Depth: not tracked).
_LIGHT_PATH = {'Is Camera Ray': "is_camera_ray", 'Is Diffuse Ray': "is_diffuse_ray",
               'Is Glossy Ray': "is_glossy_ray", 'Is Singular Ray': "is_singular_ray",
               'Is Reflection Ray': "is_reflection_ray",
               'Is Transmission Ray': "is_transmission_ray", 'Ray Length': "ray_length",
               'Ray Depth': "ray_depth", 'Diffuse Depth': "diffuse_depth",
               'Glossy Depth': "glossy_depth", 'Transmission Depth': "transmission_depth"}


def _light_path(src):
    """The Light Path node -> `{"light_path": {"output": ...}}` (FORMAT.md "Light Path
    outputs"): the ray's kind, length and bounce counts at the hit, as Cycles 3.4 gives them to
    a surface shader. Is Shadow Ray (shading never runs for shadow rays in Facet; a Mix Shader's
    Fac straight from it is the shape's switch) and Transparent Depth raise Unsupported."""
    output = _LIGHT_PATH.get(src.socket.identifier)
    if output is None:
        raise Unsupported(src, "output '%s' is not converted as a value (Facet reads Is Shadow "
                          "Ray only as a Mix Shader's Fac, and does not count transparent "
                          "bounces)" % src.socket.name)
    return Result({"light_path": {"output": output}}, None, [])


def reads_ray(tex, output=None):
    """Whether a texture dict (or any value: a material's data) reads the ray's Light Path
    state (`output`: that output of it)."""
    if isinstance(tex, dict):
        lp = tex.get("light_path")
        if isinstance(lp, dict) and (output is None or lp.get("output") == output):
            return True
        return any(reads_ray(v, output) for v in tex.values())
    if isinstance(tex, (list, tuple)):
        return any(reads_ray(v, output) for v in tex)
    return False


def reads_uv_only(tex):
    """Whether a texture dict reads the hit's UVs and nothing else of the point (what the
    core's opacity, normal and bump maps accept): no procedural texture in Generated, Object
    or view coordinates, no Hair Info, no Light Path."""
    if isinstance(tex, dict):
        if "light_path" in tex or "hair_info" in tex:
            return False
        if tex.get("coordinates", "uv") != "uv":
            return False
        return all(reads_uv_only(v) for v in tex.values())
    if isinstance(tex, (list, tuple)):
        return all(reads_uv_only(v) for v in tex)
    return True


# Hair Info outputs -> the hair_info texture's outputs.
_HAIR_INFO = {'Random': "random", 'Intercept': "intercept", 'Is Strand': "is_strand"}


def _hair_info(src):
    """The Hair Info node: Random, Intercept, Is Strand -> `{"hair_info": {"output": ...}}`
    (0 off curves, as Cycles). Intercept is noted: Facet's position along the strand is uniform
    in each segment's curve parameter, Cycles' the keys' share of the strand's length."""
    output = _HAIR_INFO.get(src.socket.identifier)
    if output is None:
        raise Unsupported(src, "output '%s' (Facet has Random, Intercept and Is Strand)"
                          % src.socket.name)
    notes = []
    if output == "intercept":
        notes.append("%s: Intercept is the position along the strand uniform in each segment "
                      "(Cycles: the keys' share of the strand's length; equal where the "
                      "segments are of equal length)" % src.label())
    return Result({"hair_info": {"output": output}}, None, notes)


# --- images ---------------------------------------------------------------------------------

def _image(walker, src, to_number):
    node = src.node
    img = node.image
    if img is None:
        raise Unsupported(src, "no image (Cycles renders it magenta)")
    if node.projection != 'FLAT':
        raise Unsupported(src, "projection '%s' (only Flat converts)" % node.projection.title())
    notes = []
    label = src.label()
    try:
        path, colorspace, note = image_file(img)
    except ValueError as e:
        raise Unsupported(src, str(e)) from e
    if note:
        notes.append("%s: %s" % (label, note))
    data = {"texture": path, "colorspace": colorspace}
    if colorspace == "srgb" and not img.is_float and node.interpolation != 'Closest' \
            and src.socket.identifier != 'Alpha':  # alpha is stored linear
        notes.append("%s: Cycles interpolates an 8-bit sRGB image before decoding it, Facet "
                     "after (they differ between strongly different texels when magnified)"
                     % label)
    filt = _FILTERS.get(node.interpolation)
    if filt is None:
        notes.append("%s: interpolation %s converted as Linear" % (label, node.interpolation))
        filt = "linear"
    data["filter"] = filt
    wrap = _WRAPS.get(node.extension, "")
    if wrap == "":
        notes.append("%s: extension %s converted as Extend (Cycles is transparent black "
                     "outside the image)" % (label, node.extension.title()))
        data["wrap"] = "clamp"
    elif wrap:
        data["wrap"] = wrap
    if src.socket.identifier == 'Alpha':
        if not has_alpha(img):
            return Result(None, notes=notes)  # Cycles' alpha of an opaque image: 1
        data["channel"] = "a"
    else:
        if has_alpha(img) and img.alpha_mode not in ('NONE', 'CHANNEL_PACKED') \
                and not _linked(node.outputs['Alpha']) and _transparent(img):
            notes.append("%s: Cycles premultiplies the colour by the image's alpha when the "
                         "Alpha output is unused; Facet reads the colour as stored" % label)
        if to_number:
            data["channel"] = "luminance"
            if img.channels >= 3 and not _grey(img):
                notes.append("%s: %s" % (label, LUMINANCE_NOTE))
    uv_map, _, mirrored = _vector(walker, src, data, checker=False)
    if mirrored:
        # Math Ping-Pong (scale 1) on a coordinate is a mirrored repeat of it (the glTF
        # importer's MIRRORED_REPEAT); Facet's wrap is one for both axes.
        data["wrap"] = "mirror"
        if mirrored != {0, 1} or node.extension not in ('EXTEND', 'MIRROR'):
            notes.append("%s: mirrored on %s, extension %s on the other: converted as Mirror on "
                         "both (they differ where that coordinate leaves [0, 1])"
                         % (label, "U" if 0 in mirrored else "V", node.extension.title()))
    return Result(data, uv_map, notes)


def _linked(sock):
    return any(not l.is_muted for l in sock.links)


def has_alpha(img):
    """Whether the image's file has an alpha channel (Blender's depth in bits per pixel: 32 or
    64 for RGBA bytes / halves, 128 for RGBA floats)."""
    return img.depth in (32, 64, 128) or (img.depth == 16 and img.channels == 2)


_PIXEL_STATS = {}  # (image name, file, size) -> (min alpha, grey)


def _pixel_stats(img):
    key = (img.name, img.filepath, tuple(img.size), img.is_dirty)
    if key not in _PIXEL_STATS:
        import numpy as np
        w, h = img.size
        px = np.empty(w * h * 4, np.float32)
        img.pixels.foreach_get(px)
        px = px.reshape(-1, 4)
        grey = bool(np.all(px[:, 0] == px[:, 1]) and np.all(px[:, 1] == px[:, 2]))
        _PIXEL_STATS[key] = (float(px[:, 3].min()) if len(px) else 1.0, grey)
    return _PIXEL_STATS[key]


def _transparent(img):
    return _pixel_stats(img)[0] < 1.0


def _grey(img):
    return _pixel_stats(img)[1]


def image_file(img):
    """(absolute path Facet reads, colour space, note or None) of a Blender image. A file on
    disk is used as it is; a packed one's bytes are written to CACHE_DIR as they are
    (_write_packed); a generated, edited or missing one is written there as an EXR of
    Blender's pixels (the same values Cycles reads; RGB only)."""
    if img.source not in ('FILE', 'GENERATED'):
        raise ValueError("image '%s': source %s is not converted (a single still image only)"
                         % (img.name, img.source))
    cs_name = img.colorspace_settings.name
    colorspace = _COLORSPACES.get(cs_name)
    note = None
    if colorspace is None:
        note = "colour space '%s' converted as Linear" % cs_name
        colorspace = "linear"
    path = None
    if img.source == 'FILE' and img.packed_file is None and not img.is_dirty:
        import bpy
        p = bpy.path.abspath(img.filepath, library=img.library)
        if os.path.isfile(p):
            path = os.path.normpath(p)
    if path is None and img.source == 'FILE' and img.packed_file is not None \
            and not img.is_dirty:
        path = _write_packed(img)
    if path is None:
        path = _write_pixels(img)
        # Blender's float pixels of a byte image are its stored (encoded) values: keep the
        # colour space; a float image's pixels are scene linear already.
        if img.is_float:
            colorspace = "linear"
    return path, colorspace, note


_NONNEGATIVE = {}  # (path, mtime, size) -> (path Facet reads, note or None)


def nonnegative_radiance_file(img, path):
    """(path, note): the file of a float image used as a radiance (the World's Environment
    Texture), with its negative colour values clamped to 0. The core refuses negative radiance
    (FORMAT.md, environment); HDRIs often hold small negative values from their filtering or
    compression (every one of Blender's studio lights does, down to -0.0039), and Cycles 3.4
    renders them as they are. A file with none is used as it is (note None); otherwise a
    clamped EXR copy is written once per file version to CACHE_DIR and the note says how many
    values were clamped and by how much at most (the largest radiance difference to Cycles).
    Cached by (path, modification time, size)."""
    import hashlib
    import numpy as np
    from . import native
    st = os.stat(path)
    key = (path, st.st_mtime_ns, st.st_size)
    if key in _NONNEGATIVE:
        return _NONNEGATIVE[key]
    w, h = img.size
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    rgb = px.reshape(h, w, 4)[::-1, :, :3]  # Blender's rows run bottom-up
    neg = rgb < 0.0
    result = (path, None)
    if neg.any():
        name = hashlib.sha1(repr(key).encode()).hexdigest()[:20]
        os.makedirs(CACHE_DIR, exist_ok=True)
        out = os.path.join(CACHE_DIR, "nonnegative_%s.exr" % name)
        if not os.path.isfile(out):
            native.facet.write_image(np.maximum(rgb, 0.0), out)
        result = (out, "%d negative colour values (down to %.3g) clamped to 0: Facet refuses "
                       "negative radiance, Cycles uses them as they are"
                  % (int(neg.sum()), float(rgb.min())))
    _NONNEGATIVE[key] = result
    return result


# Packed files by their first bytes (the format Blender decoded them as), else file_format.
_MAGIC = ((b"\x89PNG", ".png"), (b"\xff\xd8", ".jpg"), (b"v/1\x01", ".exr"),
          (b"#?RADIANCE", ".hdr"), (b"#?RGBE", ".hdr"), (b"II*\x00", ".tif"), (b"MM\x00*", ".tif"),
          (b"BM", ".bmp"))
_FORMAT_EXT = {'PNG': ".png", 'JPEG': ".jpg", 'OPEN_EXR': ".exr", 'HDR': ".hdr",
               'TIFF': ".tif", 'BMP': ".bmp", 'TARGA': ".tga", 'TARGA_RAW': ".tga"}


def _write_packed(img):
    """A packed (unedited) image: its file's bytes as they were packed, written once per
    content to CACHE_DIR (the glTF importer packs every image it reads). Keeps the file's
    alpha and bit depth, which the EXR of Blender's pixels (_write_pixels: RGB) would lose.
    None when the format is not known."""
    import hashlib
    data = img.packed_file.data
    ext = next((e for magic, e in _MAGIC if data.startswith(magic)),
               _FORMAT_EXT.get(img.file_format))
    if ext is None:
        return None
    os.makedirs(CACHE_DIR, exist_ok=True)
    path = os.path.join(CACHE_DIR, "packed_%s%s" % (hashlib.sha1(data).hexdigest()[:20], ext))
    if not os.path.isfile(path):
        tmp = path + ".tmp%d" % os.getpid()
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)  # whole or absent, for a concurrent render
    return path


def _write_pixels(img):
    """Writes the image's pixels once per content: the file is named by a hash of the packed
    file's bytes (or the generated image's settings); an edited (dirty) image is written
    every time."""
    import hashlib
    import numpy as np
    from . import native
    w, h = img.size
    if w == 0 or h == 0:
        raise ValueError("image '%s' has no pixels" % img.name)
    key = hashlib.sha1(("%s|%d|%d|%s|%s|%s" % (
        img.name, w, h, img.source, getattr(img, "generated_type", ""),
        tuple(getattr(img, "generated_color", ())))).encode())
    if img.packed_file is not None:
        key.update(img.packed_file.data)
    os.makedirs(CACHE_DIR, exist_ok=True)
    path = os.path.join(CACHE_DIR, "image_%s.exr" % key.hexdigest()[:20])
    if os.path.isfile(path) and not img.is_dirty:
        return path
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    rgb = px.reshape(h, w, 4)[::-1, :, :3].copy()  # Blender's rows run bottom-up
    native.facet.write_image(rgb, path)
    return path


# --- checker --------------------------------------------------------------------------------

def _checker(walker, src, to_number):
    node = src.node
    consts = {}
    for name in ('Color1', 'Color2', 'Scale'):
        v, blockers = walker.fold(walker.input(node, name, src.path))
        if v is None:
            raise Unsupported(blockers[0] if blockers else src,
                              "feeds the Checker Texture's %s (only constants convert)" % name)
        consts[name] = v
    data = {}
    uv_map, z, mirrored = _vector(walker, src, data, checker=True)
    if mirrored:
        raise Unsupported(src, "a Ping-Pong vector on the checker is not converted")
    c1, c2 = consts['Color1'], consts['Color2']
    if src.socket.identifier == 'Fac':
        c1, c2 = 1.0, 0.0
    elif to_number:
        c1, c2 = (sum(a * b for a, b in zip(c, nodegraph.RGB_TO_Y)) for c in (c1, c2))
    colors = [c2, c1]
    if abs(math.floor(z * consts['Scale'])) % 2 == 1:
        colors.reverse()
    data["checker"] = {"colors": [_plain(c) for c in colors], "scale": consts['Scale']}
    return Result(data, uv_map)


def _plain(c):
    return [float(x) for x in c] if isinstance(c, tuple) else float(c)


# --- texture coordinates ----------------------------------------------------------------------

def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _euler(rx, ry, rz):
    """Cycles' euler_to_transform: R = Rz Ry Rx, as a 4 x 4 affine matrix."""
    cx, cy, cz = math.cos(rx), math.cos(ry), math.cos(rz)
    sx, sy, sz = math.sin(rx), math.sin(ry), math.sin(rz)
    return [[cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz, 0.0],
            [cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz, 0.0],
            [-sy, cy * sx, cy * cx, 0.0],
            [0.0, 0.0, 0.0, 1.0]]


def _transposed3(m):
    return [[m[j][i] for j in range(3)] + [0.0] for i in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def _diag(s):
    return [[s[0], 0, 0, 0], [0, s[1], 0, 0], [0, 0, s[2], 0], [0, 0, 0, 1.0]]


def _translate(t):
    return [[1, 0, 0, t[0]], [0, 1, 0, t[1]], [0, 0, 1, t[2]], [0, 0, 0, 1.0]]


def mapping_matrix(vector_type, loc, rot, scale):
    """Cycles' svm_mapping as a 4 x 4 affine matrix (None for Normal, not affine)."""
    r = _euler(*rot)
    if vector_type == 'POINT':
        return _matmul(_translate(loc), _matmul(r, _diag(scale)))
    if vector_type == 'VECTOR':
        return _matmul(r, _diag(scale))
    if vector_type == 'TEXTURE':
        inv = [1.0 / s if s != 0.0 else 0.0 for s in scale]  # Cycles' safe_divide
        return _matmul(_diag(inv), _matmul(_transposed3(r), _translate([-x for x in loc])))
    return None


def _vector(walker, src, data, checker):
    """Follows the texture's Vector input back to a UV map (_affine); sets uv_scale /
    uv_offset / uv_rotation in `data`. Returns (the UV map's name, "" the render one; the
    constant z, for the checker; the set of axes (0: x, 1: y) mirrored by a Ping-Pong)."""
    cur = walker.input(src.node, 'Vector', src.path)
    if isinstance(cur, nodegraph.Const):
        if checker:
            raise Unsupported(src, "its vector is Generated coordinates, not a UV map")
        cur = None  # an Image Texture's unlinked Vector: the render UV map
    state = {"uv": None, "mirror": set()}
    rows = _affine(walker, cur, state) if cur is not None else _IDENTITY
    if state.get("coords") not in (None, "uv"):
        raise Unsupported(src, "its vector is %s coordinates, not a UV map (only procedural "
                          "textures read them)" % state["coords"].title())
    uv_map = state["uv"] or ""
    if cur is not None and state["uv"] is None:
        raise Unsupported(src, "its vector is a constant, not a UV map")
    m = rows
    # (x, y) = A (u, v) + b with z = 0 in: A = [[a, b], [c, d]] = R(theta) diag(su, sv).
    a, b, c, d = m[0][0], m[0][1], m[1][0], m[1][1]
    su = math.hypot(a, c)
    theta = math.atan2(c, a) if su > 0.0 else 0.0
    sv = -b * math.sin(theta) + d * math.cos(theta)
    resid = abs(b + sv * math.sin(theta)) + abs(d - sv * math.cos(theta))
    if su == 0.0 or resid > 1e-6 * max(1.0, abs(su), abs(sv)):
        raise Unsupported(src, "its vector is not a rotation and scale of the UV plane "
                          "(only rotation about Z, or a uniform scale, converts exactly)")
    if theta != 0.0:
        data["uv_rotation"] = math.degrees(theta)
    if (su, sv) != (1.0, 1.0):
        data["uv_scale"] = [su, sv]
    if (m[0][3], m[1][3]) != (0.0, 0.0):
        data["uv_offset"] = [m[0][3], m[1][3]]
    if checker:
        if abs(m[2][0]) + abs(m[2][1]) > 1e-9:
            raise Unsupported(src, "its vector turns the UV plane out of z = 0 (the 3D "
                              "checker is not a 2D one there)")
        return uv_map, m[2][3], state["mirror"]
    return uv_map, 0.0, state["mirror"]


# --- affine texture coordinates ---------------------------------------------------------------
#
# A texture's vector as an affine function of the UV map's (u, v, 0): rows [a_u, a_v, a_z, b]
# (3 for a vector, 1 for a number), through the nodes below, each exactly as Cycles evaluates
# it; anything else raises Unsupported. The glTF importer's V flip (Separate XYZ, Math
# 1 - y, Combine XYZ) is such a chain.

_IDENTITY = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]

# Texture Coordinate outputs procedural textures read as the core's "coordinates" (the
# output's name in lower case; UV is a UV map's, handled with the UV Map node).
_POINT_COORDINATES = ('Generated', 'Object', 'Normal', 'Reflection', 'Camera', 'Window')


def _is_const(row):
    return row[0] == 0.0 and row[1] == 0.0 and row[2] == 0.0


def _lin(a, ra, b=0.0, rb=None):
    """a ra + b rb (rows), rb None: a ra."""
    if rb is None:
        return [a * x for x in ra]
    return [a * x + b * y for x, y in zip(ra, rb)]


def _times(ra, rb, at):
    """ra rb when one of them is constant, else Unsupported."""
    if _is_const(ra):
        return _lin(ra[3], rb)
    if _is_const(rb):
        return _lin(rb[3], ra)
    raise Unsupported(at, "a product of two texture coordinates is not affine")


def _rows_in(walker, node, ident, path, state):
    sock = next((s for s in node.inputs if s.identifier == ident), None)
    if sock is None or not sock.enabled:
        return None
    return _affine(walker, walker.input(node, sock, path), state)


def _affine(walker, src, state):
    """Rows of `src` (Const or Out) as an affine function of (u, v, 0)."""
    if isinstance(src, nodegraph.Const):
        v = src.value
        vals = v if isinstance(v, tuple) else (v,)
        return [[0.0, 0.0, 0.0, float(c)] for c in vals]
    n, ident, path = src.node, src.socket.identifier, src.path
    idname = n.bl_idname
    if idname == 'ShaderNodeTexCoord' and ident in _POINT_COORDINATES:
        # Procedural textures only (_procedural): the hit's generated / object coordinates, or
        # the view-dependent ones (the core evaluates them per hit as Cycles 3.4's
        # svm_node_tex_coord: Normal in object space, Reflection in world space, Camera,
        # Window).
        if ident == 'Object' and n.object is not None:
            raise Unsupported(src, "Object coordinates of another object are not converted")
        if n.from_instancer:
            raise Unsupported(src, "coordinates from the instancer are not converted")
        coords = ident.lower()
        if state.get("coords") not in (None, coords) or state["uv"] is not None:
            raise Unsupported(src, "two kinds of texture coordinates in one texture's vector")
        state["coords"] = coords
        rows = [list(r) for r in _IDENTITY]
    elif idname in ('ShaderNodeTexCoord', 'ShaderNodeUVMap'):
        if idname == 'ShaderNodeTexCoord' and ident != 'UV':
            raise Unsupported(src, "the Texture Coordinate output %s is not converted"
                              % src.socket.name)
        if n.from_instancer:
            raise Unsupported(src, "UVs from the instancer are not converted")
        name = n.uv_map if idname == 'ShaderNodeUVMap' else ""
        if state["uv"] not in (None, name) or state.get("coords") not in (None, "uv"):
            raise Unsupported(src, "two UV maps (or kinds of coordinates) in one texture's "
                              "vector")
        state["uv"] = name
        state["coords"] = "uv"
        rows = [list(r) for r in _IDENTITY]
    elif idname == 'ShaderNodeMapping':
        vals = []
        for name in ('Location', 'Rotation', 'Scale'):
            sock = next((s for s in n.inputs if s.name == name and s.enabled), None)
            if sock is None:
                vals.append((0.0, 0.0, 0.0) if name != 'Scale' else (1.0, 1.0, 1.0))
                continue
            v, blockers = walker.fold(walker.input(n, sock, path))
            if v is None:
                raise Unsupported(blockers[0] if blockers else src,
                                  "feeds the Mapping's %s (only constants convert)" % name)
            vals.append(v)
        mm = mapping_matrix(n.vector_type, *vals)
        if mm is None:
            raise Unsupported(src, "Mapping of type Normal is not a UV transform")
        inner = _rows_in(walker, n, 'Vector', path, state)
        rows = [[sum(mm[i][k] * inner[k][j] for k in range(3)) + (mm[i][3] if j == 3 else 0.0)
                 for j in range(4)] for i in range(3)]
    elif idname == 'ShaderNodeMix' and n.data_type == 'VECTOR' and ident == 'Result_Vector':
        # Cycles' svm_node_mix_vector (uniform) / _non_uniform: a (1 - t) + b t, t clamped to
        # [0, 1] with Clamp Factor, per component with a Non-Uniform factor; affine when the
        # factor is a constant.
        uniform = n.factor_mode == 'UNIFORM'
        fsock = next(s for s in n.inputs if s.identifier ==
                     ('Factor_Float' if uniform else 'Factor_Vector'))
        t, blockers = walker.fold(walker.input(n, fsock, path))
        if t is None:
            raise Unsupported(blockers[0] if blockers else src,
                              "feeds the Mix's Factor on texture coordinates (only constants "
                              "convert)")
        ts = [float(t)] * 3 if uniform else [float(c) for c in t[:3]]
        if n.clamp_factor:
            ts = [min(max(x, 0.0), 1.0) for x in ts]
        a = _rows_in(walker, n, 'A_Vector', path, state)
        b = _rows_in(walker, n, 'B_Vector', path, state)
        rows = [_lin(1.0 - x, ra, x, rb) for x, ra, rb in zip(ts, a, b)]
    elif idname == 'ShaderNodeSeparateXYZ':
        inner = _rows_in(walker, n, 'Vector', path, state)
        rows = [inner["XYZ".index(ident)]]
    elif idname == 'ShaderNodeCombineXYZ':
        rows = []
        for axis, k in enumerate(("X", "Y", "Z")):
            inner = walker.input(n, k, path)
            pp = inner if isinstance(inner, nodegraph.Out) and not inner.convs and \
                inner.node.bl_idname == 'ShaderNodeMath' and \
                inner.node.operation == 'PINGPONG' and not inner.node.use_clamp else None
            if pp is not None and axis < 2 and \
                    walker.fold(walker.input(pp.node, 'Value_001', pp.path))[0] == 1.0:
                state["mirror"].add(axis)  # Ping-Pong(x, 1) = x mirrored with period 2
                rows.append(_rows_in(walker, pp.node, 'Value', pp.path, state)[0])
            else:
                rows.append(_affine(walker, inner, state)[0])
    elif idname == 'ShaderNodeMath' and not n.use_clamp:
        a = _rows_in(walker, n, 'Value', path, state)[0]
        b = (_rows_in(walker, n, 'Value_001', path, state) or [[0.0] * 4])[0]
        op = n.operation
        if op == 'ADD':
            rows = [_lin(1.0, a, 1.0, b)]
        elif op == 'SUBTRACT':
            rows = [_lin(1.0, a, -1.0, b)]
        elif op == 'MULTIPLY':
            rows = [_times(a, b, src)]
        elif op == 'DIVIDE' and _is_const(b) and b[3] != 0.0:
            rows = [_lin(1.0 / b[3], a)]
        elif op == 'MULTIPLY_ADD':
            c = _rows_in(walker, n, 'Value_002', path, state)[0]
            rows = [_lin(1.0, _times(a, b, src), 1.0, c)]
        else:
            raise Unsupported(src, "Math %s on texture coordinates is not affine" % op.title())
    elif idname == 'ShaderNodeVectorMath' and ident == 'Vector':
        a = _rows_in(walker, n, 'Vector', path, state)
        b = _rows_in(walker, n, 'Vector_001', path, state)
        op = n.operation
        if op == 'ADD':
            rows = [_lin(1.0, x, 1.0, y) for x, y in zip(a, b)]
        elif op == 'SUBTRACT':
            rows = [_lin(1.0, x, -1.0, y) for x, y in zip(a, b)]
        elif op == 'MULTIPLY':
            rows = [_times(x, y, src) for x, y in zip(a, b)]
        elif op == 'SCALE':
            s = _rows_in(walker, n, 'Scale', path, state)[0]
            rows = [_times(x, s, src) for x in a]
        else:
            raise Unsupported(src, "Vector Math %s on texture coordinates is not affine"
                              % op.title())
    else:
        raise Unsupported(src, "texture coordinates other than UV maps are not converted")
    # The link conversions on the way (nodegraph.convert): vector -> number the mean,
    # number -> vector the row three times.
    for to in src.convs:
        if to in ('VALUE', 'INT', 'BOOLEAN') and len(rows) == 3:
            rows = [_lin(1.0 / 3.0, _lin(1.0, rows[0], 1.0, _lin(1.0, rows[1], 1.0, rows[2])))]
        elif to in ('VECTOR', 'RGBA') and len(rows) == 1:
            rows = [list(rows[0]) for _ in range(3)]
    return rows


# --- procedural textures ----------------------------------------------------------------------
#
# Noise, White Noise, Gradient, Voronoi, Wave, Magic, Brick and Musgrave (Ridged Multifractal:
# the one type whose values are never negative) Texture nodes with constant inputs -> the core's
# procedural kinds (FORMAT.md, "Procedural textures"), which evaluate Cycles 3.4's algorithms
# per hit: no bake. Their vector: unlinked, Generated coordinates (Cycles' default for these
# nodes); linked, Texture Coordinate Generated / Object (this object) / Normal / Reflection /
# Camera / Window / UV or a UV Map node
# through any affine chain (_affine: Mapping of type Point, Texture or Vector, Math and Vector
# Math by constants, Separate / Combine XYZ), written as the texture's "mapping" matrix.
# Outputs: Noise Fac / Color, White Noise Value / Color, Gradient Fac / Color (grey), Voronoi
# Distance / Color / Radius, Wave, Magic and Brick Fac / Color, Musgrave Fac. A colour output
# into a number input is Cycles' luminance of the colour: the texture's "channel" luminance
# (Facet's weights, reported as for images; the Gradient's and the Wave's colours are grey).

# bl_idname -> (kind, {output identifier: core output}, {input name: core parameter},
#               {node property: (core parameter, {Blender value: core value} or None)})
PROCEDURAL = {
    'ShaderNodeTexNoise': (
        "noise", {'Fac': "fac", 'Color': "color"},
        {'Scale': "scale", 'Detail': "detail", 'Roughness': "roughness",
         'Distortion': "distortion", 'W': "w"},
        {'noise_dimensions': ("dimensions", None)}),
    'ShaderNodeTexWhiteNoise': (
        "white_noise", {'Value': "value", 'Color': "color"}, {'W': "w"},
        {'noise_dimensions': ("dimensions", None)}),
    'ShaderNodeTexMusgrave': (
        "musgrave", {'Fac': None},
        {'Scale': "scale", 'Detail': "detail", 'Dimension': "dimension",
         'Lacunarity': "lacunarity", 'Offset': "offset", 'Gain': "gain", 'W': "w"},
        {'musgrave_dimensions': ("dimensions", None), 'musgrave_type': ("type", None)}),
    'ShaderNodeTexWave': (
        "wave", {'Fac': "fac", 'Color': "color"},
        {'Scale': "scale", 'Distortion': "distortion", 'Detail': "detail",
         'Detail Scale': "detail_scale", 'Detail Roughness': "detail_roughness",
         'Phase Offset': "phase"},
        {'wave_type': ("type", None), 'bands_direction': ("bands_direction", None),
         'rings_direction': ("rings_direction", None), 'wave_profile': ("profile", None)}),
    'ShaderNodeTexMagic': (
        "magic", {'Fac': "fac", 'Color': "color"},
        {'Scale': "scale", 'Distortion': "distortion"},
        {'turbulence_depth': ("depth", None)}),
    'ShaderNodeTexGradient': (
        "gradient", {'Fac': "fac", 'Color': "color"}, {},
        {'gradient_type': ("type", None)}),
    'ShaderNodeTexBrick': (
        "brick", {'Fac': "fac", 'Color': "color"},
        {'Scale': "scale", 'Mortar Size': "mortar_size", 'Mortar Smooth': "mortar_smooth",
         'Bias': "bias", 'Brick Width': "brick_width", 'Row Height': "row_height",
         'Color1': "color1", 'Color2': "color2", 'Mortar': "mortar"},
        {'offset': ("offset", None), 'offset_frequency': ("offset_frequency", None),
         'squash': ("squash", None), 'squash_frequency': ("squash_frequency", None)}),
    'ShaderNodeTexVoronoi': (
        "voronoi", {'Distance': "distance", 'Color': "color", 'Radius': "radius"},
        {'Scale': "scale", 'Smoothness': "smoothness", 'Exponent': "exponent",
         'Randomness': "randomness", 'W': "w"},
        {'voronoi_dimensions': ("dimensions", None), 'feature': ("feature", None),
         'distance': ("distance", None)}),
}


def _procedural(walker, src, to_number):
    node = src.node
    kind, outputs, inputs, props = PROCEDURAL[node.bl_idname]
    if src.socket.identifier not in outputs:
        raise Unsupported(src, "the %s output of %s is not converted"
                          % (src.socket.name, node.bl_idname[10:]))
    out = outputs[src.socket.identifier]
    if kind == "musgrave" and node.musgrave_type != 'RIDGED_MULTIFRACTAL':
        raise Unsupported(src, "a Musgrave Texture of type %s can be negative (only Ridged "
                          "Multifractal converts)" % node.musgrave_type.replace("_", " ").title())
    luminance = to_number and out == "color" and kind not in ("gradient", "wave")
    params = {}
    # Brick's colours: constants or textures evaluated at the same hit (the core's brick
    # inputs); the Fac output reads none of them.
    textured = _Inputs(walker, src) if kind == "brick" else None
    brick_colours = {'Color1', 'Color2', 'Mortar'}
    for prop, (key, _) in props.items():
        v = getattr(node, prop)
        params[key] = (int(v[0]) if key == "dimensions" else int(v) if isinstance(v, int)
                       else float(v) if isinstance(v, float) else str(v).lower())
    for name, key in inputs.items():
        sock = next((x for x in node.inputs if x.name == name and x.enabled), None)
        if sock is None:
            continue
        if textured is not None and name in brick_colours:
            if out == "color":
                params[key] = textured.get(sock.identifier, False)
            continue
        v, blockers = walker.fold(walker.input(node, sock, src.path))
        if v is None:
            raise Unsupported(blockers[0] if blockers else src,
                              "feeds the %s's %s (only constants convert)"
                              % (node.bl_idname[10:], name))
        params[key] = [float(c) for c in v[:3]] if isinstance(v, tuple) else float(v)
    if kind in ("gradient", "wave") and out == "color":
        out = "fac"  # the same grey value
    if out is not None:  # (Musgrave: Fac only)
        params["output"] = out
    data = {kind: params}
    uv_map = None
    dims = params.get("dimensions", 3)
    vsock = next((x for x in node.inputs if x.name == "Vector" and x.enabled), None)
    cur = walker.input(node, vsock, src.path) if vsock is not None and dims != 1 else None
    if cur is None or isinstance(cur, nodegraph.Const):
        # Unlinked: Cycles' default vector of these nodes is Generated coordinates.
        data["coordinates"] = "generated"
    else:
        state = {"uv": None, "mirror": set()}
        rows = _affine(walker, cur, state)
        if state["mirror"]:
            raise Unsupported(src, "a Ping-Pong vector is not converted")
        coords = state.get("coords")
        if coords is None:
            raise Unsupported(src, "its vector is a constant, not texture coordinates")
        data["coordinates"] = coords
        if coords == "uv":
            uv_map = state["uv"] or ""
        if rows != _IDENTITY:
            data["mapping"] = {"matrix": [[float(x) for x in r] for r in rows]}
    res = Result(data, uv_map)
    for r in (textured.parts if textured is not None else ()):
        res.notes += r.notes
        uvs, cas, gen = r.reads()
        res.more_uv_maps |= uvs
        res.more_color_attributes |= cas
        res.generated = res.generated or gen
    if luminance:  # a colour output into a number input: its luminance
        _luminance(res, src)
    return res


def _luminance(res, src):
    """A colour texture read by a number input: its "channel" luminance (Cycles' colour ->
    number conversion, with Facet's weights: reported as for images)."""
    res.data["channel"] = "luminance"
    res.notes.append("%s: %s" % (src.label(), LUMINANCE_NOTE))
    return res


# --- nodes between textures: the core's composite kinds ---------------------------------------
#
# Math (every operation), Vector Math (every operation), Mix RGB and the Mix node (Color mode:
# every blend type; Float mode: Mix of numbers) and ColorRamp nodes whose inputs are textures
# (or constants) -> the core's `math`, `vector_math`, `mix_rgb` and `color_ramp` kinds
# (FORMAT.md, "Composite kinds"), evaluated per hit as Cycles 3.4 evaluates the nodes: no
# bake. Each input is its folded constant or, recursively, its texture (anything convert()
# converts, including other composites); a constant colour
# into a number input is Cycles' luminance of it (nodegraph.RGB_TO_Y, folded exactly). A
# ColorRamp in RGB mode is its stops and interpolation; in HSV or HSL mode Cycles' own table
# (Blender's ColorRamp.evaluate at i / 255, i = 0..255) as 256 stops, linear (constant when
# the ramp is Constant): the core tabulates them at the same points, so the table is the same.
# A colour output (a procedural's Color, Mix, a ColorRamp's Color with non-grey stops) into a
# number input is its luminance (the texture's "channel" luminance: Facet's weights, reported
# as for images, LUMINANCE_NOTE). The Mix node's Vector mode is the mix blend of its vectors
# as colours (a Non-Uniform factor: mix_rgb's fac_color, a factor per component). Vector
# Math's Vector output feeds colour inputs (colours pass through vector sockets unchanged),
# its Value output (Dot Product, Distance, Length) number or colour inputs; a vector into a
# number input (Cycles' mean of the components) stays reported.

# Blender's Math operations the core's kind takes (all of 3.4's, lower case).
_MATH_OPS = {'ADD', 'SUBTRACT', 'MULTIPLY', 'DIVIDE', 'MULTIPLY_ADD', 'POWER', 'LOGARITHM',
             'SQRT', 'INVERSE_SQRT', 'ABSOLUTE', 'EXPONENT', 'MINIMUM', 'MAXIMUM', 'LESS_THAN',
             'GREATER_THAN', 'SIGN', 'COMPARE', 'SMOOTH_MIN', 'SMOOTH_MAX', 'ROUND', 'FLOOR',
             'CEIL', 'TRUNC', 'FRACT', 'MODULO', 'WRAP', 'SNAP', 'PINGPONG', 'SINE', 'COSINE',
             'TANGENT', 'SINH', 'COSH', 'TANH', 'ARCSINE', 'ARCCOSINE', 'ARCTANGENT', 'ARCTAN2',
             'RADIANS', 'DEGREES'}


class _Inputs:
    """The inputs of one composite node: each a constant or a texture dict; the converted
    textures' Results kept for what they read and their notes."""

    def __init__(self, walker, src):
        self.walker, self.src, self.parts = walker, src, []

    def get(self, ident, number):
        node, walker = self.src.node, self.walker
        sock = next((x for x in node.inputs if x.identifier == ident), None)
        if sock is None:
            raise Unsupported(self.src, "no input %s" % ident)
        up = walker.input(node, sock, self.src.path)
        v, blockers = walker.fold(up)
        if v is not None:
            if isinstance(v, tuple):
                c = [float(x) for x in v[:3]]
                if number:  # Cycles' colour -> float: luminance
                    return sum(w * x for w, x in zip(nodegraph.RGB_TO_Y, c))
                return c
            if isinstance(v, bool):
                v = float(v)
            if not isinstance(v, (int, float)):
                raise Unsupported(self.src, "input %s is %r" % (sock.name, v))
            return float(v)
        if isinstance(up, nodegraph.Const):
            raise Unsupported(blockers[0] if blockers else self.src, None)
        res = convert(walker, up, number)
        self.parts.append(res)
        if res.data is None:
            return res.const
        return res.data

    def result(self, data):
        out = Result(data, None)
        for r in self.parts:
            out.notes += r.notes
            uvs, cas, gen = r.reads()
            out.more_uv_maps |= uvs
            out.more_color_attributes |= cas
            out.generated = out.generated or gen
        return out


def _math_node(walker, src):
    node = src.node
    if node.operation not in _MATH_OPS:
        raise Unsupported(src, "Math %s is not converted" % node.operation.title())
    ins = _Inputs(walker, src)
    params = {"operation": node.operation.lower()}
    if node.use_clamp:
        params["use_clamp"] = True
    for key, ident in (("a", "Value"), ("b", "Value_001"), ("c", "Value_002")):
        params[key] = ins.get(ident, True)
    return ins.result({"math": params})


# Blender's Vector Math operations and the inputs each reads (a: Vector, b: Vector_001, c:
# Vector_002, s: Scale): all of 3.4's; dot_product, distance and length give the Value output.
_VECTOR_MATH_OPS = {
    'ADD': "ab", 'SUBTRACT': "ab", 'MULTIPLY': "ab", 'DIVIDE': "ab", 'MULTIPLY_ADD': "abc",
    'CROSS_PRODUCT': "ab", 'PROJECT': "ab", 'REFLECT': "ab", 'REFRACT': "abs",
    'FACEFORWARD': "abc", 'DOT_PRODUCT': "ab", 'DISTANCE': "ab", 'LENGTH': "a", 'SCALE': "as",
    'NORMALIZE': "a", 'SNAP': "ab", 'FLOOR': "a", 'CEIL': "a", 'MODULO': "ab", 'WRAP': "abc",
    'FRACTION': "a", 'ABSOLUTE': "a", 'MINIMUM': "ab", 'MAXIMUM': "ab", 'SINE': "a",
    'COSINE': "a", 'TANGENT': "a"}
_VECTOR_MATH_VALUE = {'DOT_PRODUCT', 'DISTANCE', 'LENGTH'}


def _vector_math_node(walker, src):
    """Vector Math of textures -> vector_math: its Vector output into a colour input (convert()
    refuses a vector into a number input: Cycles' mean of the components), its Value output
    (dot_product, distance, length) into a number or, grey, a colour input."""
    node = src.node
    op = node.operation
    uses = _VECTOR_MATH_OPS.get(op)
    if uses is None:
        raise Unsupported(src, "Vector Math %s is not converted" % op.title())
    value = src.socket.identifier == 'Value'
    if value != (op in _VECTOR_MATH_VALUE):
        raise Unsupported(src, "the %s output of Vector Math %s (always 0 in Cycles) is not "
                          "converted" % (src.socket.name, op.replace("_", " ").title()))
    ins = _Inputs(walker, src)
    params = {"operation": op.lower()}
    if value:
        params["output"] = "value"
    for key, ident in (("a", "Vector"), ("b", "Vector_001"), ("c", "Vector_002")):
        if key in uses:
            params[key] = ins.get(ident, False)
    if "s" in uses:
        params["scale"] = ins.get('Scale', True)
    return ins.result({"vector_math": params})


def _mix(walker, src, to_number):
    """Mix RGB, and the Mix node in Color, Float or Vector mode -> mix_rgb."""
    node = src.node
    ins = _Inputs(walker, src)
    if node.bl_idname == 'ShaderNodeMixRGB':
        params = {"blend_type": node.blend_type.lower(), "fac": ins.get('Fac', True),
                  "color1": ins.get('Color1', False), "color2": ins.get('Color2', False)}
        if node.use_clamp:
            params["use_clamp"] = True
        res = ins.result({"mix_rgb": params})
        return _luminance(res, src) if to_number else res
    dt = node.data_type
    if dt == 'RGBA':
        params = {"blend_type": node.blend_type.lower(), "fac": ins.get('Factor_Float', True),
                  "color1": ins.get('A_Color', False), "color2": ins.get('B_Color', False)}
        if node.clamp_result:
            params["use_clamp"] = True
    elif dt == 'FLOAT':  # a (1 - t) + b t: the mix blend of numbers
        params = {"blend_type": "mix", "fac": ins.get('Factor_Float', True),
                  "color1": ins.get('A_Float', True), "color2": ins.get('B_Float', True)}
    elif dt == 'VECTOR':
        # Cycles' svm_node_mix_vector: a (1 - t) + b t per component, the mix blend of colours;
        # a Non-Uniform factor is mix_rgb's fac_color (one factor per component).
        if node.factor_mode == 'UNIFORM':
            fac = ("fac", ins.get('Factor_Float', True))
        else:
            fac = ("fac_color", ins.get('Factor_Vector', False))
        params = {"blend_type": "mix", fac[0]: fac[1],
                  "color1": ins.get('A_Vector', False), "color2": ins.get('B_Vector', False)}
    else:
        raise Unsupported(src, "the Mix node's %s mode is not converted" % dt.title())
    if not node.clamp_factor:
        params["clamp_factor"] = False
    res = ins.result({"mix_rgb": params})
    return _luminance(res, src) if to_number and dt == 'RGBA' else res


RAMP_TABLE_SIZE = 256  # Cycles' RAMP_TABLE_SIZE


def _color_ramp(walker, src, to_number):
    node = src.node
    ramp = node.color_ramp
    alpha = src.socket.identifier == 'Alpha'
    if ramp.color_mode == 'RGB':
        stops = [{"position": float(e.position), "color": [float(c) for c in e.color]}
                 for e in ramp.elements]
        interp = ramp.interpolation.lower()
    else:  # Cycles' table of Blender's evaluation, as stops at the table's points
        n = RAMP_TABLE_SIZE - 1
        stops = [{"position": i / n, "color": [float(c) for c in ramp.evaluate(i / n)]}
                 for i in range(RAMP_TABLE_SIZE)]
        interp = "constant" if ramp.interpolation == 'CONSTANT' else "linear"
    luminance = to_number and not alpha and any(
        st["color"][0] != st["color"][1] or st["color"][0] != st["color"][2] for st in stops)
    ins = _Inputs(walker, src)
    params = {"fac": ins.get('Fac', True), "interpolation": interp, "stops": stops}
    if alpha:
        params["output"] = "alpha"
    res = ins.result({"color_ramp": params})
    return _luminance(res, src) if luminance else res
