"""Blender material -> Facet material (model + parameters of the core's table), emission and
sidedness.

A material's Facet panel chooses the source: a Facet model by its own parameters, or the
conversion of the Cycles node tree below. Conversions and their approximations (each one a
difference from Cycles 3.4 that the user may see):

The node tree is read through nodegraph.py (the tree as Cycles flattens it: reroutes, nested
groups, muted nodes, link conversions) from the Material Output Cycles renders (target Cycles
before All, then the active one).
Every BSDF input is folded to a constant when its subgraph is made of nodes nodevalues.py
evaluates (Math, Mix, Invert, Gamma, Hue/Saturation/Value, Combine/Separate, Map Range, Vector
Math, ColorRamp, RGB, Value, ...); that is exact. Anything else is reported through gaps.py, one
line per material and node, naming the input it feeds and what Facet used instead (the input's
own value, grey lambert, ...). Colour inputs the conversions pass on unchanged (Diffuse, Glossy
and Glass Color, Emission Color x Strength, Principled Base Color with Metallic and Specular
Tint 0) also take textures (textures.py: Image and Checker Textures through UV Map and Mapping
nodes, the procedural textures, and Math, Mix RGB / Mix and ColorRamp nodes of textures as the
core's composite kinds, evaluated per hit) and, for any other subgraph, the image Blender bakes
of it (bake.py). Inherent model
differences of the conversions below are documented here and in docs/blender.md, not reported
per material (they would fire on every default material).

- Diffuse BSDF: lambert, reflectance = Color. Roughness > 0 (Oren-Nayar): the core's
  oren_nayar (sigma = Roughness, clamped to 1 as Cycles does).
- Translucent BSDF -> translucent (transmittance = Color); Velvet BSDF -> velvet (Color, Sigma).
- Principled Hair BSDF -> principled_hair (every parametrization and input by its own name,
  constants; _principled_hair says what is reported); Hair BSDF -> hair (Component, Color,
  Offset, RoughnessU, RoughnessV). Both take the fibre direction from the surface's dp/du.
- Transparent BSDF -> the material's opacity (resolve_transparent, _mix_transparent).
- Glossy BSDF: Cycles' glossy has no Fresnel term (F = 1, tinted by Color) and
  alpha = Roughness^2. GGX -> ggx, Beckmann -> beckmann, Sharp -> mirror (all fresnel none,
  reflectance = Color). Multiscatter GGX -> ggx with energy_compensation (Kulla & Conty 2017
  instead of Cycles' random walk: same energy, slightly different lobe shape).
  Ashikhmin-Shirley has no Facet equivalent: reported, converted as GGX.
- Anisotropic BSDF: anisotropy a (clamped to [-0.99, 0.99] as Cycles does) gives
  alpha_u = alpha (1 - a), alpha_v = alpha / (1 - a) for a >= 0 and alpha_u = alpha / (1 + a),
  alpha_v = alpha (1 + a) for a < 0 (Cycles 3.4's SVM closure setup for this node).
  Principled Anisotropic uses Disney's aspect instead: alpha_u = alpha / aspect, alpha_v =
  alpha * aspect, aspect = sqrt(1 - 0.9 anisotropic). Rotation and tangents are not converted
  (Facet meshes have no tangent field): a non-zero Rotation is reported.
- Principled BSDF -> principled (the core's model of Cycles 3.4's Principled BSDF, lobe by lobe:
  docs/principled.md), every input by its own name: Base Color, Subsurface, Subsurface Color,
  Metallic, Specular, Specular Tint, Roughness, Anisotropic, Anisotropic Rotation (wrapped to
  [0, 1): the rotation is periodic), Sheen, Sheen Tint, Clearcoat, Clearcoat Roughness, IOR,
  Transmission, Transmission Roughness; factors clamped to [0, 1] as Cycles clamps them (colours
  per channel), IOR to [0.001, 100]. Emission (a colour, or an image x Emission Strength) is
  converted; Alpha -> the material's "opacity" (_principled_alpha); Clearcoat Normal as
  normals.clearcoat says. Multiscatter GGX -> distribution multi_ggx (the core's Kulla-Conty
  compensation of the specular lobe instead of Cycles' random walk: same energy,
  docs/principled.md gives the measured difference on coloured metals). Reported: Multiscatter
  GGX glass with Specular Tint > 0 (MULTI_GLASS_NOTE), Alpha < 1 on an emitting Principled;
  Tangent when linked (not read). Subsurface, Subsurface Color / Radius / IOR / Anisotropy and
  the subsurface method -> the core's random walk (_subsurface_walk: Christensen-Burley is
  converted as Random Walk (Fixed Radius), reported). The anisotropic
  tangent is Facet's surface dp/du, not Cycles' default tangent.
- Glass / Refraction BSDF: dielectric, ior = IOR, alpha = Roughness^2 (Sharp: smooth), GGX or
  Beckmann, transmittance = Color (see _glass for what is reported). Multiscatter GGX -> ggx
  with energy_compensation (the core's rough-dielectric compensation instead of Cycles' random
  walk: same energy, a white glass sphere renders the environment in both).
- Emission: the shape's emission = Color x Strength (radiance), black material. A colour or
  value linked straight into a shader socket is an Emission (Cycles' conversion).
- Mix Shader (weights 1 - t, t; t = Fac clamped to [0, 1], or a texture / bake of the Fac;
  a Fac straight from a Fresnel node or a Layer Weight node's Fresnel / Facing output with a
  constant IOR / Blend and no Normal link: the core's view-dependent `factor`, as Cycles
  evaluates it per shading point) -> the core's `mix`, Add Shader -> `add` (combine()), nested as the tree nests them; t = 0
  or 1 is that side alone, a black side only weights the other, and two BSDFs of one linear
  model (lambert, mirror, ggx, beckmann without energy compensation) differing only in
  reflectance merge into one while the reflectance stays <= 1. Emissions add with the same
  weights (a textured Fac on an emission: reported, averaged). A child's opacity (Principled
  Alpha) is reported and dropped: the core's opacity is a whole material's. The children's
  normal maps and
  bumps move to the combination (the core applies a combination's own); different ones are
  reported and the first's kept.
- A linear BSDF's constant Color above 1 (Cycles' plain factor): the `add` of ceil(max) copies
  of Color / n, exact (split_over_unity); Multiscatter GGX and colours above 8: clamped,
  reported.
- Normal inputs: Normal Map and Bump nodes -> `normal_map` / `bump` (normals.py). Inputs a
  conversion does not read (Tangent, ...) and the Material Output's Displacement are reported
  when something is linked to them.
- Volume output (NodeContext.volume) -> a homogeneous medium named as the material
  (FORMAT.md "media"), units.py's conversions: Principled Volume (the core's cycles_volume of
  Density, Color, Absorption Color; Anisotropy -> g; Emission Strength x Emission Color),
  Volume Scatter (sigma_s = Density Color), Volume Absorption (sigma_a = Density (1 - Color)),
  Emission (Color x Strength per unit length), Mix Shader (constant Fac: the sides' sigmas and
  emissions weighted) and Add Shader (summed) of them. Nothing on the Surface: the `null`
  model with the medium as its "interior" (Cycles renders the surface of a volume-only
  material as an invisible boundary); a surface rays cross (crosses(): Glass, Principled
  Transmission > 0, ...): that material with the "interior"; an opaque surface: the volume is
  unreachable, in Cycles too, reported, the surface alone. Reported: textured inputs (the
  input's value), Blackbody Intensity > 0, a Density / Color Attribute the mesh has, an Add of
  scattering volumes of different Anisotropy (the first's), a surface shader on the Volume.
  Density 0 and no emission: no medium (a transparent surface when nothing is on the
  Surface).
- No node tree: lambert with the viewport Diffuse Color.
- Worlds (export.py) use the same NodeContext: Background = Color x Strength, as an Emission.
"""
import json
import math

from . import bake, gaps, nodegraph, normals, textures, units
from .properties import material_params

DEFAULT_MATERIAL = {"model": "lambert", "reflectance": 0.8}


class Converted:
    """A converted material: data (FORMAT.md material dict; colour and number parameters may
    be texture dicts), emission (a colour or a texture dict), two_sided, problems, and uv_maps:
    the UV layers its textures read ("" the render UV map; empty: no texture)."""

    def __init__(self, data, emission=None, two_sided=True, problems=(), uv_maps=()):
        self.data = data
        self.emission = emission or [0.0, 0.0, 0.0]
        self.two_sided = two_sided
        self.problems = list(problems)
        self.uv_maps = set(uv_maps)
        self.baked = False  # an input baked over the UVs of the object it was converted for
        self.tangents = False  # a normal map: the mesh needs the tangents of its UV map
        self.color_attributes = set()  # colour attributes read by Color Attribute nodes
        self.generated = False  # a procedural texture reads Generated coordinates
        # The shape's Light Path switches (FORMAT.md "Light Path switches"), or [].
        self.light_path = []
        # The medium inside (FORMAT.md "media": a homogeneous medium dict, named as the
        # material in the scene's media and the data's "interior"), or None.
        self.medium = None

    def emits(self):
        return is_texture(self.emission) or any(c > 0.0 for c in self.emission)


def is_texture(v):
    """Whether a parameter value is a texture dict (textures.py) rather than a constant."""
    return isinstance(v, dict)


def convert(mat, obj=None):
    """Blender material (or None) -> Converted. Never raises for a bad node tree: what cannot
    be converted is listed in problems, each naming the material and the input or node.
    `obj` (the first object using the material) is the one a bake (bake.py) is made over."""
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
        conv = Converted(data, list(fs.emission), fs.two_sided)
        if "interior" in data and "facet_medium" in mat:  # imported with its medium
            conv.medium = json.loads(mat["facet_medium"])
        return conv
    two_sided = True if fs is None else fs.two_sided
    if not mat.use_nodes or mat.node_tree is None:
        return Converted({"model": "lambert", "reflectance": list(mat.diffuse_color)[:3]},
                         two_sided=two_sided)
    ctx = NodeContext("material", mat.name, mat.node_tree)
    ctx.material, ctx.obj = mat, obj
    out = nodegraph.active_output(mat.node_tree, 'ShaderNodeOutputMaterial')
    if out is None:
        ctx.problems.append("material '%s': no Material Output node; using grey lambert"
                            % mat.name)
        return Converted(dict(DEFAULT_MATERIAL), two_sided=two_sided, problems=ctx.problems)
    feeds = "the Material Output"
    src = ctx.walker.input(out, 'Surface')
    vol = ctx.walker.input(out, 'Volume')
    no_volume = isinstance(vol, nodegraph.Const) and vol.value is None
    ctx.ignored_input(out, 'Displacement', (), feeds)
    if isinstance(src, nodegraph.Const) and src.value is None:
        if no_volume:
            ctx.problems.append("material '%s': nothing connected to the output's Surface or "
                                "Volume; using grey lambert" % mat.name)
            return Converted(dict(DEFAULT_MATERIAL), two_sided=two_sided,
                             problems=ctx.finish())
        # A volume alone: Cycles' surface is then an invisible boundary (no surface closure),
        # the core's `null` model with the medium as its interior (FORMAT.md "media").
        medium = ctx.volume(vol, "the Material Output's Volume")
        if medium is None:  # nothing to render inside (density 0, ...): a transparent surface
            return Converted(dict(DEFAULT_MATERIAL, opacity=0.0), two_sided=two_sided,
                             problems=ctx.finish())
        conv = Converted({"model": "null", "interior": mat.name}, two_sided=two_sided,
                         problems=ctx.finish())
        conv.medium = medium
        return conv
    data, emission = ctx.shader(src, "the Material Output's Surface")
    notes = []
    data, emission, switches = light_path_switches(data, emission, notes)
    data = split_over_unity(data, notes)
    for sw in switches:
        if "material" in sw:
            sw["material"] = split_over_unity(sw["material"], notes)
    for note in notes:
        ctx.gap(src, note, "feeds the Material Output's Surface")
    if is_transparent(data):
        notes = []
        data = resolve_transparent(data, notes)
        for note in notes:
            ctx.gap(src, note, "feeds the Material Output's Surface")
    medium = None
    if not no_volume:
        if crosses(data):  # a glass of fog: the medium is the surface's interior
            medium = ctx.volume(vol, "the Material Output's Volume")
            if medium is not None:
                data = dict(data, interior=mat.name)
        else:  # rays never enter: Cycles renders no volume inside an opaque surface either
            ctx.problems.append(
                "material '%s': the output's Volume (%s) is not rendered: the Surface is "
                "opaque (model '%s'), so no ray enters the volume, in Cycles as in Facet; "
                "the surface is converted alone"
                % (mat.name, vol.label() if isinstance(vol, nodegraph.Out) else "a value",
                   data.get("model")))
    if switches and ("opacity" in data or medium is not None):
        ctx.problems.append("material '%s': its Light Path switches are not converted: the "
                            "shader other rays see is %s" % (mat.name, "a cut-out (opacity)"
                                                            if "opacity" in data else
                                                            "a medium's boundary"))
        switches = []
    conv = Converted(data, emission, two_sided, ctx.finish(), ctx.uv_maps)
    conv.light_path = switches
    conv.medium = medium
    conv.baked = ctx.baked
    conv.tangents = ctx.tangents
    conv.color_attributes = ctx.color_attributes
    conv.generated = ctx.generated
    return conv


def material_state(mat):
    """A snapshot of a material's Facet settings (to tell whether it changed since import)."""
    fs = mat.facet
    return repr((fs.source, material_params(fs), tuple(fs.emission), fs.two_sided))


def _fmt(v):
    if isinstance(v, tuple):
        return "(%s)" % ", ".join("%.4g" % c for c in v)
    return "%.4g" % v


BLACK = {"model": "lambert", "reflectance": 0.0}


class NodeContext:
    """One node tree's conversion (a material's or a world's): the walker, the inputs read,
    and the report, one line per node that is not converted exactly (gaps.py), naming the
    tree, the node (and its group), the input it feeds and what Facet used instead."""

    def __init__(self, kind, name, tree):
        self.what = "%s '%s'" % (kind, name)
        self.world = kind == "world"
        self.walker = nodegraph.Walker(tree)
        self.problems = []
        self._lines = {}  # node key -> [label, reason, [feeds and what was used]]
        self.uv_maps = set()  # UV layers read by the textures converted
        self.material = self.obj = None  # set for a material: what a bake needs (bake.py)
        self.exact = set()  # (node, input) of gaps.INPUTS entries a conversion converted
        # (node name, input name) -> the value a caller converted itself (value() returns it:
        # a volume's Emission Strength read from a grid, sync_volume.py).
        self.given = {}
        self.baked = False
        self.tangents = False  # a normal map: the mesh exports its UV map's tangents
        self.color_attributes = set()  # colour attributes read ("" the default one)
        self.generated = False  # a procedural texture reads Generated coordinates

    def gap(self, src, reason, feeds):
        """Reports the node of `src` (an Out), once per node; `feeds` says which input it
        feeds and what was used."""
        line = self._lines.get(src.key)
        if line is None:
            self._lines[src.key] = [src.label(), reason, [feeds]]
        elif feeds not in line[2]:
            line[2].append(feeds)

    def finish(self):
        """The problem lines: the direct ones, then one per node not converted."""
        for label, reason, feeds in self._lines.values():
            self.problems.append("%s: %s is not converted (%s): %s"
                                 % (self.what, label, reason, "; ".join(feeds)))
        self._lines = {}
        return self.problems

    def value(self, node, name, path=()):
        """The value of a BSDF input: folded to a constant when its subgraph allows (exact),
        else the input's own value, and each node stopping the folding is reported."""
        if (node.name, name) in self.given:
            return self.given[(node.name, name)]
        sock = _input(node, name)
        src = self.walker.input(node, sock, path)
        v, blockers = self.walker.fold(src)
        if v is not None:
            return v
        own = nodegraph.socket_value(sock)
        for b in blockers:
            self.gap(b, gaps.node_reason(b.node) or gaps.UNKNOWN,
                     "feeds %s '%s' input '%s'; using the input's value %s"
                     % (nodegraph.node_type_label(node), node.name, sock.name, _fmt(own)))
        return own

    def param(self, node, name, path=(), scale=1.0, square=False, ray=True):
        """A BSDF input that Facet may texture: the folded constant (as value()), or the
        texture its subgraph converts to (textures.py; `scale` multiplies it, the texture's
        "scale"), or the image Blender bakes of it (bake.py), or, when none, the input's own
        value with the nodes reported. `square`: the caller wants clamp(v, 0, 1)^2 (a
        roughness -> alpha): a constant is returned as it is (the caller squares it), a
        subgraph is baked squared (a texture cannot square). `ray` False: an input that
        shading does not read for a ray (an emission, an Alpha, a Transparent BSDF's colour,
        a normal): a texture of a Light Path output is reported and the input's value used."""
        sock = _input(node, name)
        src = self.walker.input(node, sock, path)
        v, blockers = self.walker.fold(src)
        if v is not None:
            return v
        feeds = "%s '%s' input '%s'" % (nodegraph.node_type_label(node), node.name, sock.name)
        try:
            if square:  # no texture squares: the folding's blockers are reported
                raise textures.Unsupported(src, None)
            res = textures.convert(self.walker, src, number=sock.type != 'RGBA')
        except textures.Unsupported as e:
            used = "feeds %s; using the input's value %s" % (feeds,
                                                            _fmt(nodegraph.socket_value(sock)))
            baked = bake.request(self, node, sock, src, square) \
                if self.material is not None else None
            if baked:  # Blender's bake of the subgraph, over the object's render UV map
                self.uv_maps.add("")
                self.baked = True
                if sock.type != 'RGBA' or square:
                    baked["channel"] = "r"  # a grey bake of a number
                return _scaled(baked, scale)
            if baked is False:  # reported by bake.request
                return nodegraph.socket_value(sock)
            if e.reason is None:  # not a texture: the nodes stopping the folding
                for b in blockers:
                    self.gap(b, gaps.node_reason(b.node) or gaps.UNKNOWN, used)
            else:
                self.gap(e.out, e.reason, used)
            return nodegraph.socket_value(sock)
        if not ray and textures.reads_ray(res.data):
            self.gap(src, "a Light Path output is read by BSDF inputs and Mix Shader factors "
                     "only (emissions, Alpha, Transparent BSDF colours and normals are read "
                     "without a ray: light sampling, shadow rays)",
                     "feeds %s; using the input's value %s"
                     % (feeds, _fmt(nodegraph.socket_value(sock))))
            return nodegraph.socket_value(sock)
        for note in res.notes:
            self.problems.append("%s: %s (feeds %s)" % (self.what, note, feeds))
        if res.data is None:  # a constant: the Alpha of an opaque image (1), a texture x 0
            return res.const * scale
        # What the texture (and a composite's inputs) reads: UV layers (none for procedural
        # textures of Generated / Object), colour attributes (Color Attribute nodes: no UVs),
        # Generated coordinates (the mesh exports its texture space, export.py).
        uvs, cas, gen = res.reads()
        self.uv_maps |= uvs
        self.color_attributes |= cas
        self.generated = self.generated or gen
        tex = dict(res.data)
        if scale != 1.0:
            tex["scale"] = tex.get("scale", 1.0) * scale
        return tex

    def ignored_input(self, node, name, path, feeds_what):
        """An input the conversion does not read: a live link into it is reported (the node
        feeding it, or the nodes stopping its folding)."""
        sock = next((s for s in node.inputs if s.name == name and s.enabled), None)
        if sock is None:
            return
        src = self.walker.input(node, sock, path)
        if isinstance(src, nodegraph.Const):
            return
        v, blockers = self.walker.fold(src)
        for b in (blockers or [src]):
            self.gap(b, gaps.node_reason(b.node) or "input '%s' is not converted" % name,
                     "feeds %s input '%s'; ignored" % (feeds_what, name))

    def check_inputs(self, node, path, read):
        """After a BSDF's conversion: inputs converted only at one value (gaps.INPUTS) and
        linked inputs the conversion did not read are reported."""
        label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
        for sock in node.inputs:
            if not sock.enabled or sock.type == 'SHADER':
                continue
            entry = gaps.INPUTS.get((node.bl_idname, sock.name))
            if entry is not None and (node.name, sock.name) not in self.exact:
                v = self.value(node, sock.identifier, path)
                if isinstance(v, float) and v != entry[0]:
                    self.problems.append("%s: %s input '%s' = %s: %s"
                                         % (self.what, label, sock.name, _fmt(v), entry[1]))
            elif sock.name not in read:
                self.ignored_input(node, sock.name, path, label)

    def shader(self, src, feeds):
        """A shader socket's value -> (Facet material data, emission or None)."""
        if isinstance(src, nodegraph.Const):
            if isinstance(src.value, tuple) and src.value and src.value[0] == "EMISSION":
                # A colour or value linked into a shader socket: Cycles' Emission.
                return dict(BLACK), units.emission_from_blender(src.value[1], src.value[2])
            return dict(BLACK), None  # no closure: black
        node, path = src.node, src.path
        if src.convs:  # a colour or value output into a shader socket: an Emission
            v, blockers = self.walker.fold(src)
            if v is not None:
                return dict(BLACK), units.emission_from_blender(v[1], v[2])
            for b in blockers:
                self.gap(b, gaps.node_reason(b.node) or gaps.UNKNOWN,
                         "feeds %s as an emission; no emission" % feeds)
            return dict(BLACK), None
        conv = _NODE_CONVERTERS.get(node.bl_idname)
        if conv is None and self.world and node.bl_idname == 'ShaderNodeBackground':
            conv = _emission  # the world's radiance: Color x Strength, as an Emission's
        if conv is not None:
            read = _READS.get(node.bl_idname, ('Color', 'Strength'))
            data, emission = conv(self, node, path)
            if any(s.identifier == 'Normal' for s in node.inputs) and not self.world:
                data.update(normals.convert(self, node, path))
                read = read + ('Normal',)
            if node.bl_idname == 'ShaderNodeBsdfPrincipled':
                normals.clearcoat(self, node, path, data)
                read = read + ('Clearcoat Normal', 'Alpha')
            self.check_inputs(node, path, read)
            return data, emission
        if node.bl_idname == 'ShaderNodeMixShader':
            return self._mix_shader(src, feeds)
        if node.bl_idname == 'ShaderNodeAddShader':
            return self._add_shader(src, feeds)
        if self.world:
            self.gap(src, gaps.node_reason(node) or gaps.UNKNOWN,
                     "feeds %s; no light from it" % feeds)
            return dict(BLACK), None
        self.gap(src, gaps.node_reason(node) or gaps.UNKNOWN,
                 "feeds %s; using grey lambert" % feeds)
        return dict(DEFAULT_MATERIAL), None

    # --- volumes: the Material Output's (or the World Output's) Volume -> a medium ---------

    def volume(self, src, feeds):
        """A Volume socket's value -> the core's homogeneous medium (FORMAT.md "media":
        sigma_a, sigma_s per scene unit, g, emission), or None when nothing is there to render
        (no closure, density 0 and no emission). Constant inputs convert exactly (units.py,
        through the core's cycles_volume); textured inputs, blackbody emission and anything
        else are reported by material, node and input, with what was used."""
        part = self._volume_part(src, feeds)
        if part is None:
            return None
        sa, ss, g, em = part
        if not any(c > 0.0 for c in sa + ss + em):
            return None
        medium = {"kind": "homogeneous", "sigma_a": sa, "sigma_s": ss}
        if g is not None and g != 0.0 and any(c > 0.0 for c in ss):
            medium["g"] = g
        if any(c != 0.0 for c in em):
            medium["emission"] = em
        return medium

    def _volume_part(self, src, feeds):
        """(sigma_a, sigma_s, g or None, emission) of a Volume socket's value, or None."""
        zero = [0.0, 0.0, 0.0]
        if isinstance(src, nodegraph.Const):
            if isinstance(src.value, tuple) and src.value and src.value[0] == "EMISSION":
                # A colour or value linked into a shader socket: Cycles' Emission, here a
                # volume emission (radiance per unit length).
                return zero, zero, None, units.emission_from_blender(src.value[1],
                                                                     src.value[2])
            return None
        node, path = src.node, src.path
        if src.convs:  # a colour or value output into the socket: an emission
            v, blockers = self.walker.fold(src)
            if v is not None:
                return zero, zero, None, units.emission_from_blender(v[1], v[2])
            for b in blockers:
                self.gap(b, gaps.node_reason(b.node) or gaps.UNKNOWN,
                         "feeds %s as an emission; no emission" % feeds)
            return None
        conv = _VOLUME_CONVERTERS.get(node.bl_idname)
        if conv is not None:
            part = conv(self, node, path)
            self.check_inputs(node, path, _VOLUME_READS[node.bl_idname])
            return part
        label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
        ins = [s for s in node.inputs if s.type == 'SHADER']
        if node.bl_idname == 'ShaderNodeMixShader':
            # Cycles weights each side's closures by (1 - t, t), t = Fac clamped: densities
            # and emissions scale, and a sum of homogeneous media is one (sigmas add).
            t = self.value(node, 'Fac', path)  # a texture: reported, its own value used
            t = min(max(float(t), 0.0), 1.0)
            if t in (0.0, 1.0):
                return self._volume_part(self.walker.input(node, ins[int(t)], path), label)
            weights = (1.0 - t, t)
        elif node.bl_idname == 'ShaderNodeAddShader':
            weights = (1.0, 1.0)
        else:
            self.gap(src, gaps.volume_reason(node), "feeds %s; no medium from it" % feeds)
            return None
        parts = [(w, self._volume_part(self.walker.input(node, s, path), label))
                 for w, s in zip(weights, ins)]
        parts = [(w, p) for w, p in parts if p is not None]
        if not parts:
            return None
        sa, ss, em = ([sum(w * p[i][c] for w, p in parts) for c in range(3)]
                      for i in (0, 1, 3))
        gs = [p[2] for _, p in parts if p[2] is not None and any(c > 0.0 for c in p[1])]
        if any(g != gs[0] for g in gs):
            self.gap(src, "the medium's Henyey-Greenstein phase has one anisotropy: a sum of "
                     "scattering volumes of different Anisotropy (%s) is not one"
                     % ", ".join(_fmt(g) for g in gs),
                     "feeds %s; the first one's %s is used" % (feeds, _fmt(gs[0])))
        return sa, ss, (gs[0] if gs else None), em

    def _mix_shader(self, src, feeds):
        """Cycles mixes with weights (1 - t, t), t = Fac clamped to [0, 1]: t = 0 or 1 is one
        of the shaders exactly (Cycles skips the other); any other t, or a Fac that is a
        texture or a bake, is the core's `mix` (mix())."""
        node, path = src.node, src.path
        label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
        ins = [s for s in node.inputs if s.type == 'SHADER']
        view = self._view_factor(node, path)
        if view is not None:  # Fresnel / Layer Weight: the core's view-dependent mix weight
            sides = [self.shader(self.walker.input(node, s, path), label) for s in ins]
            return self._combined(sides, view, src, feeds)
        ray = None if self.world else self._light_path_ray(node, path)
        if ray is not None:  # Light Path: a switch by the ray's kind (light_path_switches)
            sides = [self.shader(self.walker.input(node, s, path), label) for s in ins]
            return {"model": LIGHT_PATH, "ray": ray, "sides": sides}, None
        fac = self.param(node, 'Fac', path, ray=not self.world)
        if textures.reads_ray(fac) and \
                not fac.get("light_path", {}).get("output", "").startswith("is_"):
            # Cycles clamps the Fac to [0, 1] (svm_node_mix_closure); a Light Path length or
            # depth (through Math or not) may leave it.
            fac = {"math": {"operation": "add", "a": fac, "b": 0.0, "use_clamp": True}}
        if not is_texture(fac):
            t = min(max(float(fac), 0.0), 1.0)
            if t in (0.0, 1.0):
                return self.shader(self.walker.input(node, ins[int(t)], path), label)
            fac = t
        sides = [self.shader(self.walker.input(node, s, path), label) for s in ins]
        return self._combined(sides, fac, src, feeds)

    def _view_factor(self, node, path):
        """A Mix Shader's Fac straight from a Fresnel node's Fac or a Layer Weight node's
        Fresnel or Facing output, with a constant IOR / Blend and the default normal: the
        core's mix `factor` ({"factor": ..., "ior" or "blend": ...}); else None."""
        src = self.walker.input(node, 'Fac', path)
        if not isinstance(src, nodegraph.Out) or src.convs:
            return None
        n = src.node
        kind = {('ShaderNodeFresnel', 'Fac'): ("fresnel", 'IOR', "ior"),
                ('ShaderNodeLayerWeight', 'Fresnel'): ("layer_fresnel", 'Blend', "blend"),
                ('ShaderNodeLayerWeight', 'Facing'): ("layer_facing", 'Blend', "blend")}.get(
                    (n.bl_idname, src.socket.identifier))
        if kind is None:
            return None
        factor, inp, key = kind
        value, _ = self.walker.fold(self.walker.input(n, inp, src.path))
        normal = self.walker.input(n, 'Normal', src.path)
        if value is None or isinstance(normal, nodegraph.Out):
            return None  # a textured IOR / Blend or a custom normal: reported as before
        if factor == "fresnel":
            value = max(float(value), 0.0)
        else:
            value = min(max(float(value), 0.0), 1.0)
        return {"factor": factor, key: value}

    def _light_path_ray(self, node, path):
        """A Mix Shader's Fac straight from one of a Light Path node's ray outputs: the core's
        switch output ("camera", ...; FORMAT.md "Light Path switches"); else None."""
        src = self.walker.input(node, 'Fac', path)
        if not isinstance(src, nodegraph.Out) or src.convs or \
                src.node.bl_idname != 'ShaderNodeLightPath':
            return None
        return LIGHT_PATH_OUTPUTS.get(src.socket.identifier)

    def _add_shader(self, src, feeds):
        """Both sides summed: the core's `add` (emissions added)."""
        node, path = src.node, src.path
        label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
        ins = [s for s in node.inputs if s.type == 'SHADER']
        parts = [self.shader(self.walker.input(node, s, path), label) for s in ins]
        return self._combined(parts, None, src, feeds)

    def _combined(self, parts, fac, src, feeds):
        """combine() of a Mix (fac: its weight, a number or a texture) or an Add (fac None),
        with what it could not keep exactly reported on the node."""
        data, emission, notes = combine(parts, fac)
        for note in notes:
            self.gap(src, note, "feeds %s" % feeds)
        return data, emission


# Facet models whose BSDF is linear in "reflectance" (f = reflectance x a lobe independent of
# it): a weighted sum of two of them that differ only in reflectance is one of them, and a
# weight scales the reflectance. Energy compensation (Kulla-Conty) is left out.
_LINEAR_MODELS = ("lambert", "mirror", "ggx", "beckmann")
# The keys of a material that are its shading normal (FORMAT.md "Normal maps", "Bump maps"):
# the core applies a combination's own, not its children's.
NORMAL_KEYS = ("normal_map", "bump")


def _add_emission(e1, e2, w1, w2):
    """w1 e1 + w2 e2 (None: no emission), or None when that is no single texture or colour
    (a texture plus another emission). A texture plus nothing is the weighted texture."""
    if e1 is None and e2 is None:
        return None
    if is_texture(e1) or is_texture(e2):
        if not (_black(e1) or _black(e2)):
            raise ValueError("a texture plus another emission")
        return _scaled(e1, w1) if is_texture(e1) else _scaled(e2, w2)
    e1, e2 = e1 or [0.0] * 3, e2 or [0.0] * 3
    return [w1 * a + w2 * b for a, b in zip(e1, e2)]


def _black(e):
    return e is None or (not is_texture(e) and not any(e))


def _linear_sum(bsdfs):
    """sum w d over [(data, weight)] as one BSDF when they are the same linear model with the
    same parameters but reflectance, constant, and the sum stays <= 1; else None."""
    model = bsdfs[0][0].get("model")
    if model not in _LINEAR_MODELS or any(d.get("energy_compensation") for d, _ in bsdfs):
        return None
    if any(is_texture(v) for d, _ in bsdfs for v in d.values()):
        return None  # a weighted sum of textured BSDFs is not one BSDF
    rest = [{k: v for k, v in d.items() if k != "reflectance"} for d, _ in bsdfs]
    if any(r != rest[0] for r in rest):
        return None
    refl = [0.0] * 3
    for d, w in bsdfs:
        refl = [a + w * b for a, b in zip(refl, units.rgb3(d.get("reflectance", 1.0)))]
    if max(refl) > 1.0:
        return None
    data = dict(rest[0])
    data["reflectance"] = refl
    return data


# Models whose BSDF is linear in one colour parameter with range [0, 1]: the core's reflectance
# or transmittance, where Cycles takes a BSDF's Color as a plain factor (a Glossy BSDF of
# Color 1.25 reflects 1.25 times what one of Color 1 does).
_LINEAR_COLOUR = {"lambert": "reflectance", "mirror": "reflectance", "ggx": "reflectance",
                  "beckmann": "reflectance", "oren_nayar": "reflectance",
                  "translucent": "transmittance"}
_MAX_SPLIT = 8  # copies: a colour above 8 is clamped (reported)


def split_over_unity(data, notes):
    """A material tree whose linear BSDFs (_LINEAR_COLOUR) have a constant colour above 1 ->
    the same f in the core's ranges: each such BSDF becomes the `add` of n = ceil(max) copies
    of colour / n (exact: f is linear in it; the copies' normal map or bump moves to the
    combination, which the core shades with). Energy-compensated lobes (Multiscatter GGX: not
    linear in the colour) and colours above _MAX_SPLIT are clamped to 1 with a note; textured
    colours are left to the core's range check."""
    if not isinstance(data, dict):
        return data
    if data.get("model") in ("mix", "add"):
        return dict(data, materials=[split_over_unity(d, notes) for d in data["materials"]])
    key = _LINEAR_COLOUR.get(data.get("model"))
    if key is None or key not in data or is_texture(data[key]):
        return data
    colour = units.rgb3(data[key])
    top = max(colour)
    if top <= 1.0:
        return data
    n = math.ceil(top)
    if data.get("energy_compensation") or n > _MAX_SPLIT:
        notes.append("its %s's Color %s is above 1 (Cycles' factor); Facet's %s is at most 1"
                     "%s: clamped" % (data["model"], _fmt(tuple(colour)), key,
                                      " with energy compensation" if n <= _MAX_SPLIT else
                                      " and is split into at most %d copies" % _MAX_SPLIT))
        return dict(data, **{key: [min(c, 1.0) for c in colour]})
    normal = {k: data[k] for k in NORMAL_KEYS if k in data}
    part = {k: v for k, v in data.items() if k not in NORMAL_KEYS}
    part[key] = [c / n for c in colour]
    out = dict(part)
    for _ in range(n - 1):
        out = {"model": "add", "materials": [dict(part), out]}
    out.update(normal)
    return out


def _hoist_normals(children, notes):
    """The core shades a combination with its own normal_map / bump and ignores its
    children's: the children's (of those that reflect) move to the combination when they are
    the same; different ones keep the first's (a note)."""
    own = [{k: d[k] for k in NORMAL_KEYS if k in d} for d in children if d != BLACK]
    out = [{k: v for k, v in d.items() if k not in NORMAL_KEYS} for d in children]
    if own and any(o != own[0] for o in own):
        notes.append("its shaders have different normals (Normal Map / Bump); Facet shades a "
                     "combination with one normal: the first shader's")
    return out, (own[0] if own else {})


# A Mix Shader whose Fac is a Light Path output inside the walker: a marker with the output and
# both sides, turned into the shape's Light Path switches at the Surface (light_path_switches);
# inside another Mix or Add Shader it is its first side (reported by combine()).
LIGHT_PATH = "(light path)"
LIGHT_PATH_OUTPUTS = {"Is Camera Ray": "camera", "Is Shadow Ray": "shadow",
                      "Is Diffuse Ray": "diffuse", "Is Glossy Ray": "glossy",
                      "Is Singular Ray": "singular", "Is Reflection Ray": "reflection",
                      "Is Transmission Ray": "transmission"}


def is_light_path(d):
    return d.get("model") == LIGHT_PATH


def _light_path_default(part, notes):
    """A shader that may be a Light Path marker inside another Mix or Add Shader -> the
    core's `mix` of its sides weighted by a light_path texture of its output (FORMAT.md "Light
    Path outputs"; combine()). Is Shadow Ray has no such texture (shading never runs for
    shadow rays): its first side, with a note when the second one's shadow differs."""
    data, emission = part
    if not is_light_path(data):
        return data, emission
    if data["ray"] != "shadow":
        fac = {"light_path": {"output": "is_%s_ray" % data["ray"]}}
        data, emission, sub = combine(data["sides"], fac)
        notes.extend(sub)
        return data, emission
    (d1, e1), (d2, e2) = (_light_path_default(p, notes) for p in data["sides"])
    if is_transparent(d1) != is_transparent(d2):
        notes.append("a Mix Shader by Is Shadow Ray inside another Mix or Add Shader is not "
                     "converted (the core switches shadow rays for a whole surface); its first "
                     "shader is used, for shadow rays too")
    return d1, e1


def _entry_material(data, emission, notes):
    """A switch's material and emission -> the entry's (material dict or None, emission) or
    None when it cannot be one (a note says why)."""
    if is_light_path(data):
        notes.append("a Light Path Mix Shader on the second side of another is not converted; "
                     "its first shader is used there")
        data, emission = _light_path_default((data, emission), [])
    if is_transparent(data):
        sub = []
        if _transparent_grey(data, sub) < 1.0 or sub or not _black(emission):
            notes.append("a switch to a grey, coloured or emitting Transparent BSDF is not "
                         "converted (the core passes a switch's `null` surface whole); the "
                         "switch is left out")
            return None
        return {"model": "null"}, None
    if any(is_texture(v) for v in data.values()) or is_texture(emission) or \
            any(k in data for k in ("opacity",) + NORMAL_KEYS):
        notes.append("a switch to a textured shader (or one with Alpha, a Normal Map or Bump) "
                     "is not converted; the switch is left out")
        return None
    return data, emission


def light_path_switches(data, emission, notes):
    """A Surface that may be a Light Path marker -> (data, emission, switches): the shader that
    rays no switch matches see, and the shape's "light_path" list (FORMAT.md "Light Path
    switches"), outermost Mix Shader first (Cycles picks its second side when its output is
    1, else looks inside the first)."""
    switches = []
    while is_light_path(data):
        (d1, e1), (d2, e2) = data["sides"]
        entry = _entry_material(d2, e2, notes)
        if entry is not None:
            sw = {"ray": data["ray"]}
            if entry[0] != BLACK:
                sw["material"] = entry[0]
            if not _black(entry[1]):
                sw["emission"] = list(entry[1])
            switches.append(sw)
        data, emission = d1, e1
    return data, emission, switches


def combine(parts, fac):
    """A Mix Shader (fac: the weight t of the second side, a number in (0, 1) or a texture) or
    an Add Shader (fac None) of parts [(data, emission)] -> (data, emission, notes): the
    core's `mix` / `add` of the two BSDFs (FORMAT.md "Combinations": mix f = (1 - t) f_a +
    t f_b, add f = f_a + f_b) and the weighted sum of the emissions. Simpler forms where they
    are exact: a black side (emission only, or nothing) only weights the other; two BSDFs of
    the same linear model and parameters but reflectance merge into one (while <= 1). `notes`
    lists what is not exact (reported by the caller)."""
    notes = []
    (d1, e1), (d2, e2) = (_light_path_default(p, notes) for p in parts)
    view = isinstance(fac, dict) and "factor" in fac  # a weight from the view (Fresnel, ...)
    if is_transparent(d1) or is_transparent(d2):
        # (An opacity is decided without a ray: no Light Path weight.)
        if fac is not None and not view and not textures.reads_ray(fac) and _black(e1) and \
                _black(e2):
            data = _mix_transparent(d1, d2, fac, notes)
            if data is not None:
                return data, None, notes
        notes.append("a Transparent BSDF converts only as a Mix Shader's side with a BSDF and "
                     "no emission (the core's opacity), a textured Fac only with a white "
                     "Transparent first (or second with a Checker), not by a Light Path output "
                     "inside another Mix; here it is opaque black")
        d1, d2 = (dict(BLACK) if is_transparent(d) else d for d in (d1, d2))
    if any("opacity" in d for d in (d1, d2)):
        d1, d2 = ({k: v for k, v in d.items() if k != "opacity"} for d in (d1, d2))
        notes.append("the Alpha of a shader inside a Mix or Add Shader is not converted (the "
                     "core's opacity is a whole material's); opaque")
    textured = is_texture(fac) or view
    w1, w2 = (1.0, 1.0) if fac is None else (None, None) if textured else (1.0 - fac, fac)
    if textured:
        emission = None
        if not (_black(e1) and _black(e2)):  # (1 - w) e1 + w e2, w a texture: no texture
            emission = next((e for e in (e1, e2) if is_texture(e)), None) or \
                _add_emission(e1, e2, 0.5, 0.5)
            notes.append("an emission weighted by a textured or view-dependent Fac is not "
                         "converted; the "
                         "emissions are averaged (weight 0.5)")
    else:
        try:
            emission = _add_emission(e1, e2, w1, w2)
        except ValueError:
            emission = e1 if is_texture(e1) else e2
            notes.append("a textured emission plus another emission is not one texture; only "
                         "the textured one is kept")
    if d1 == BLACK and d2 == BLACK:
        return dict(BLACK), emission, notes
    if not textured:
        bsdfs = [(d, w) for d, w in ((d1, w1), (d2, w2)) if d != BLACK]
        if len(bsdfs) == 1 and bsdfs[0][1] == 1.0:
            return dict(bsdfs[0][0]), emission, notes  # one BSDF at weight 1: itself
        merged = _linear_sum(bsdfs)
        if merged is not None:
            return merged, emission, notes
    children, normal = _hoist_normals([d1, d2], notes)
    data = {"model": "add" if fac is None else "mix", "materials": children}
    if view:
        data.update(fac)
    elif fac is not None:
        data["weight"] = fac
    data.update(normal)
    return data, emission, notes


def _input(node, name):
    for s in node.inputs:
        if s.identifier == name:
            return s
    return next(s for s in node.inputs if s.name == name and s.enabled)


def _rgb(v):
    """A colour parameter: [r, g, b], or a texture dict as it is."""
    if is_texture(v):
        return v
    return [float(c) for c in v[:3]]


def _scaled(tex, w):
    if w == 1.0:
        return tex
    out = dict(tex)
    out["scale"] = out.get("scale", 1.0) * w
    return out


def _alpha(roughness):
    """Cycles' microfacet alpha = roughness^2 (glossy, anisotropic and principled)."""
    r = max(0.0, min(1.0, float(roughness)))
    return r * r


def _alpha_param(ctx, node, path):
    """alpha = clamp(Roughness, 0, 1)^2: a number, or a texture of it baked squared."""
    r = ctx.param(node, 'Roughness', path, square=True)
    return r if is_texture(r) else _alpha(r)


def _aniso_bsdf(alpha, anisotropy):
    """Cycles' Anisotropic BSDF node: a >= 0 stretches alpha_x by (1 - a) and alpha_y by
    1 / (1 - a); a < 0 the other way round (a clamped to [-0.99, 0.99])."""
    a = max(-0.99, min(0.99, float(anisotropy)))
    su, sv = ((1.0 - a), 1.0 / (1.0 - a)) if a >= 0.0 else (1.0 / (1.0 + a), (1.0 + a))
    if is_texture(alpha):
        return _scaled(alpha, su), _scaled(alpha, sv)
    return alpha * su, alpha * sv


def _aniso(alpha, anisotropy):
    """Principled (Disney): aspect = sqrt(1 - 0.9 anisotropy), alpha_x = alpha / aspect,
    alpha_y = alpha aspect (a texture of alpha: scaled)."""
    a = max(-1.0, min(1.0, float(anisotropy)))
    aspect = math.sqrt(1.0 - 0.9 * a) if a >= 0.0 else 1.0 / math.sqrt(1.0 + 0.9 * a)
    if is_texture(alpha):
        return _scaled(alpha, 1.0 / aspect), _scaled(alpha, aspect)
    return alpha / aspect, alpha * aspect


def _diffuse(ctx, node, path):
    """Lambert; with Roughness > 0, the core's `oren_nayar` with sigma = Roughness, clamped to 1
    (Cycles 3.4's Diffuse BSDF: Oren-Nayar with sigma = saturate(Roughness), Lambert at 0)."""
    color = _rgb(ctx.param(node, 'Color', path))
    rough = ctx.value(node, 'Roughness', path)
    if isinstance(rough, float) and rough > 0.0:
        return {"model": "oren_nayar", "reflectance": color,
                "sigma": min(rough, 1.0)}, None
    return {"model": "lambert", "reflectance": color}, None


# A Transparent BSDF inside the walker: a marker with its Color, resolved into the core's
# opacity (FORMAT.md "Opacity") by combine() and at the Surface (resolve_transparent); it never
# reaches the core.
TRANSPARENT = "(transparent)"


def _transparent(ctx, node, path):
    return {"model": TRANSPARENT, "color": _rgb(ctx.param(node, 'Color', path, ray=False))}, None


def is_transparent(d):
    return d.get("model") == TRANSPARENT


def _transparent_grey(d, notes):
    """The pass-through fraction g of a Transparent marker: its grey Color; a coloured or
    textured one is reported and read as its luminance (or white)."""
    c = d["color"]
    if is_texture(c):
        notes.append("a textured Transparent Color is not converted (the core's opacity is "
                     "grey); fully transparent")
        return 1.0
    if max(c) - min(c) > 1e-6:
        notes.append("a coloured Transparent BSDF is not converted (the core's opacity is "
                     "grey); its luminance is used")
        return sum(w * v for w, v in zip(nodegraph.RGB_TO_Y, c))
    return min(max(c[0], 0.0), 1.0)


def resolve_transparent(data, notes):
    """A Transparent BSDF alone at the Surface: passes g of the light, reflects nothing, which
    is the core's opacity 1 - g on a black surface (opacity 0 on grey lambert when g = 1, as a
    surface with nothing connected)."""
    if not is_transparent(data):
        return data
    g = _transparent_grey(data, notes)
    if g >= 1.0:
        return dict(DEFAULT_MATERIAL, opacity=0.0)
    return dict(BLACK, opacity=1.0 - g)


def _mix_transparent(d1, d2, fac, notes):
    """A Mix Shader with a Transparent BSDF on one side (weight w_t) and a BSDF X on the other
    (weight w_x = 1 - w_t): Cycles passes w_t g of the light and reflects w_x X. The core's
    opacity a with material M passes 1 - a and reflects a M, so a = 1 - w_t g and
    M = mix(black, X, w_x / a) (X itself when g = 1). A textured Fac converts when g = 1 and the
    Transparent is the first input (a = Fac), or the second with a Checker Fac (a = 1 - Fac,
    its colours inverted); otherwise None (the caller reports it)."""
    first = is_transparent(d1)
    tr, x = (d1, d2) if first else (d2, d1)
    if is_transparent(x) or "opacity" in x:
        return None
    g = _transparent_grey(tr, notes)
    if is_texture(fac):
        if g < 1.0:
            return None
        if first:
            return dict(x, opacity=fac)
        if ("checker" in fac and "scale" not in fac
                and all(isinstance(c, float) for c in fac["checker"]["colors"])):
            inv = dict(fac)
            inv["checker"] = dict(fac["checker"])
            inv["checker"]["colors"] = [1.0 - c for c in fac["checker"]["colors"]]
            return dict(x, opacity=inv)
        return None
    w_t = (1.0 - fac) if first else fac
    alpha = 1.0 - w_t * g
    if alpha <= 0.0:
        return dict(DEFAULT_MATERIAL, opacity=0.0)
    w = (1.0 - w_t) / alpha
    data = dict(x) if w >= 1.0 - 1e-9 else {"model": "mix", "materials": [dict(BLACK), dict(x)],
                                             "weight": w}
    data["opacity"] = alpha
    return data


def _holdout(ctx, node, path):
    """Cycles' Holdout: the core's `holdout` (alpha 0 and colour 0 where camera rays see it;
    inside a Mix Shader its share)."""
    return {"model": "holdout"}, None


def _translucent(ctx, node, path):
    """Cycles' Translucent BSDF: the core's `translucent` (Lambertian transmission, f = Color/pi
    on the far side)."""
    return {"model": "translucent", "transmittance": _rgb(ctx.param(node, 'Color', path))}, None


def _velvet(ctx, node, path):
    """Cycles' Velvet BSDF: the core's `velvet` (Ashikhmin velvet, Sigma as Cycles reads it)."""
    return {"model": "velvet", "reflectance": _rgb(ctx.param(node, 'Color', path)),
            "sigma": ctx.param(node, 'Sigma', path)}, None


_HAIR_PARAMETRIZATIONS = {'COLOR': "color", 'MELANIN': "melanin", 'ABSORPTION': "absorption"}


def _hair_number(ctx, node, name, path, lo, hi, label=None):
    """A hair input as a number in [lo, hi] (the core's range): a value outside is reported
    and clamped."""
    v = ctx.value(node, name, path)
    c = min(max(float(v), lo), hi)
    if c != v:
        ctx.problems.append("%s: %s '%s' input '%s' = %s is outside the converted range [%s, %s]"
                            "; %s used" % (ctx.what, nodegraph.node_type_label(node), node.name,
                                           label or name, _fmt(v), _fmt(lo), _fmt(hi), _fmt(c)))
    return c


def _hair_color(ctx, node, name, path, lo=0.0, hi=1.0):
    """A hair colour input as [r, g, b] in [lo, hi] per channel (reported and clamped
    outside)."""
    v = [float(c) for c in ctx.value(node, name, path)[:3]]
    c = [min(max(x, lo), hi) for x in v]
    if c != v:
        ctx.problems.append("%s: %s '%s' input '%s' = %s is outside the converted range [%s, %s]"
                            "; %s used" % (ctx.what, nodegraph.node_type_label(node), node.name,
                                           name, _fmt(tuple(v)), _fmt(lo), _fmt(hi),
                                           _fmt(tuple(c))))
    return c


def _hair_texture(ctx, node, name, path):
    """A hair input fed by a texture subgraph (Hair Info, a Color Ramp of it, ...): the texture
    clamped to [0, 1] (the core's range of Color and Random; Cycles does not clamp, values
    outside are rare), or None when the input folds to a constant or does not convert (then
    value() reports it)."""
    sock = _input(node, name)
    src = ctx.walker.input(node, sock, path)
    if isinstance(src, nodegraph.Const) or ctx.walker.fold(src)[0] is not None:
        return None
    try:
        res = textures.convert(ctx.walker, src, number=sock.type != 'RGBA')
    except textures.Unsupported:
        return None
    if res.data is None:
        return None
    feeds = "%s '%s' input '%s'" % (nodegraph.node_type_label(node), node.name, sock.name)
    for note in res.notes:
        ctx.problems.append("%s: %s (feeds %s)" % (ctx.what, note, feeds))
    uvs, cas, gen = res.reads()
    ctx.uv_maps |= uvs
    ctx.color_attributes |= cas
    ctx.generated = ctx.generated or gen
    tex = dict(res.data)
    if "hair_info" in tex:
        return tex  # in [0, 1]
    if sock.type == 'RGBA':
        return {"mix_rgb": {"blend_type": "mix", "fac": 0.0, "color1": tex, "use_clamp": True}}
    return {"math": {"operation": "add", "a": tex, "b": 0.0, "use_clamp": True}}


def _principled_hair(ctx, node, path):
    """Cycles' Principled Hair BSDF: the core's `principled_hair` (Cycles 3.4's closure, Chiang
    et al. 2016) with the node's parametrization (Direct Coloring -> color, Melanin
    Concentration -> melanin with Tint and Random Color, Absorption Coefficient -> absorption),
    Roughness, Radial Roughness, Coat, IOR, Offset (radians), Random Roughness and Random, each
    a constant (a linked input that does not fold is reported by value()). Reported: values
    outside the core's ranges (clamped; IOR below 1, where Cycles' formulas take the square
    root of a negative number), and an unlinked Random when it matters (Random Roughness > 0,
    or Random Color > 0 under Melanin): on hair Cycles reads each strand's own random value
    there: the strand's random value (a hair_info texture), as Cycles. Color (Direct Coloring)
    and Random fed by a texture subgraph that converts (Hair Info, a Color Ramp or Math of it:
    textures.py) are textures, clamped to [0, 1]. On a mesh Cycles reads an unlinked Random's
    value, Facet's hair_info 0 there (reported when the value is not 0)."""
    kind = _HAIR_PARAMETRIZATIONS[node.parametrization]
    data = {"model": "principled_hair", "parametrization": kind}
    if kind == "color":
        data["color"] = _hair_texture(ctx, node, 'Color', path) or \
            _hair_color(ctx, node, 'Color', path)
    elif kind == "melanin":
        data["melanin"] = _hair_number(ctx, node, 'Melanin', path, 0.0, 1.0)
        data["melanin_redness"] = _hair_number(ctx, node, 'Melanin Redness', path, 0.0, 1.0)
        data["tint"] = _hair_color(ctx, node, 'Tint', path)
        # Cycles clamps Random Color to [0, 1]: exact.
        data["random_color"] = min(max(float(ctx.value(node, 'Random Color', path)), 0.0), 1.0)
    else:
        data["absorption_coefficient"] = _hair_color(ctx, node, 'Absorption Coefficient', path,
                                                     0.0, 1000.0)
    data["roughness"] = _hair_number(ctx, node, 'Roughness', path, 0.0, 1.0)
    data["radial_roughness"] = _hair_number(ctx, node, 'Radial Roughness', path, 0.0, 1.0)
    # Cycles clamps Coat to [0, 1]: exact.
    data["coat"] = min(max(float(ctx.value(node, 'Coat', path)), 0.0), 1.0)
    data["ior"] = _hair_number(ctx, node, 'IOR', path, 1.0, 1000.0)
    data["offset"] = _hair_number(ctx, node, 'Offset', path, -math.pi / 2, math.pi / 2)
    data["random_roughness"] = _hair_number(ctx, node, 'Random Roughness', path, 0.0, 1.0)
    sock = _input(node, 'Random')
    random_used = data["random_roughness"] > 0.0 or data.get("random_color", 0.0) > 0.0
    if random_used and isinstance(ctx.walker.input(node, sock, path), nodegraph.Const):
        # Cycles' attribute Random of the curve (svm_node_closure: unlinked Random reads
        # ATTR_STD_CURVE_RANDOM, the socket's value where there is none).
        data["random"] = {"hair_info": {"output": "random"}}
        if float(sock.default_value) != 0.0:
            ctx.problems.append("%s: %s '%s' input 'Random' is unlinked: each strand's random "
                                "value is used, as Cycles; on a mesh Cycles uses its value %s, "
                                "Facet 0" % (ctx.what, nodegraph.node_type_label(node),
                                             node.name, _fmt(float(sock.default_value))))
    else:
        data["random"] = _hair_texture(ctx, node, 'Random', path) if random_used else None
        if data["random"] is None:
            data["random"] = _hair_number(ctx, node, 'Random', path, 0.0, 1.0)
    return data, None


def _hair(ctx, node, path):
    """Cycles' Hair BSDF: the core's `hair` (Cycles 3.4's hair reflection / transmission
    closure) with Component, Color, Offset (radians), RoughnessU and RoughnessV; values outside
    the core's ranges are reported and clamped (Cycles clamps the roughnesses to [0.001, 1]
    itself). The fibre is the surface's dp/du (a curve's tangent); a linked Tangent is reported
    (not read). On meshes Cycles uses dp/dv and no Offset instead (docs/blender.md)."""
    return {"model": "hair",
            "component": "transmission" if node.component == 'Transmission' else "reflection",
            "color": _hair_color(ctx, node, 'Color', path),
            "offset": _hair_number(ctx, node, 'Offset', path, -math.pi / 2, math.pi / 2),
            # Cycles clamps both to [0.001, 1], the core to [0.001, 1] as well: exact.
            "roughness_u": min(max(float(ctx.value(node, 'RoughnessU', path)), 0.0), 1.0),
            "roughness_v": min(max(float(ctx.value(node, 'RoughnessV', path)), 0.0), 1.0)}, None


def _glossy_model(ctx, node):
    dist = node.distribution
    if dist == 'SHARP':
        return "mirror", False
    if dist == 'BECKMANN':
        return "beckmann", False
    if dist == 'MULTI_GGX':
        return "ggx", True
    if dist != 'GGX':
        ctx.problems.append("%s: %s distribution '%s' is not supported; converted as GGX"
                            % (ctx.what, node.name, dist))
    return "ggx", False


def _glossy(ctx, node, path):
    color = _rgb(ctx.param(node, 'Color', path))
    model, compensate = _glossy_model(ctx, node)
    data = {"model": model, "reflectance": color, "fresnel": "none"}
    if model != "mirror":
        alpha = _alpha_param(ctx, node, path)
        if node.bl_idname == 'ShaderNodeBsdfAnisotropic':
            aniso = ctx.value(node, 'Anisotropy', path)
            if aniso != 0.0:
                data["alpha_u"], data["alpha_v"] = _aniso_bsdf(alpha, aniso)
            else:
                data["alpha"] = alpha
        else:
            data["alpha"] = alpha
        if compensate:
            data["energy_compensation"] = True
    return data, None


# Above this Roughness Cycles 3.4 makes one random-walk glass closure for a Multiscatter GGX
# Principled with Transmission, and Facet's principled its compensated dielectric (not tinted
# by Specular Tint: docs/principled.md).
_MULTI_GLASS_MIN_ROUGHNESS = 0.05
MULTI_GLASS_NOTE = ("%s: %s Multiscatter GGX with Transmission and Specular Tint: Facet's "
                    "multiscatter glass reflection is not tinted (Cycles tints it by "
                    "mix(1, Base Color, Specular Tint))")

MULTI_ANISO_NOTE = ("%s: %s Multiscatter GGX with Anisotropic: Facet compensates the "
                    "anisotropic lobe as an isotropic one of the same sqrt(alpha_u alpha_v) "
                    "(a white metal reflects 0.82 .. 1.04 instead of 1)")

# Principled BSDF input -> the principled model's parameter (factors in [0, 1]).
_PRINCIPLED_FACTORS = (
    ('Subsurface', "subsurface"), ('Metallic', "metallic"), ('Specular', "specular"),
    ('Specular Tint', "specular_tint"), ('Roughness', "roughness"),
    ('Anisotropic', "anisotropic"), ('Sheen', "sheen"), ('Sheen Tint', "sheen_tint"),
    ('Clearcoat', "clearcoat"), ('Clearcoat Roughness', "clearcoat_roughness"),
    ('Transmission', "transmission"), ('Transmission Roughness', "transmission_roughness"))
_PRINCIPLED_COLOURS = (('Base Color', "base_color"), ('Subsurface Color', "subsurface_color"))


# Cycles' subsurface methods -> the core's; Christensen-Burley (Cycles' disk method, which
# scales the radius by 1 / (4 pi) as Fixed Radius does) is converted as Fixed Radius, reported.
_SSS_METHODS = {'RANDOM_WALK': "random_walk", 'RANDOM_WALK_FIXED_RADIUS': "random_walk_fixed_radius",
                'BURLEY': "random_walk_fixed_radius"}
# Cycles clamps a BSSRDF's IOR to [1.01, 3.8] and its anisotropy to [0, 0.9] (the core's ranges).
_SSS_IOR = (1.01, 3.8)
_SSS_ANISOTROPY = (0.0, 0.9)


def _subsurface_walk(ctx, node, path, data, prefix, names, method, scale):
    """A random walk's Radius, IOR, Anisotropy (names) and method into data (keys prefixed):
    clamped as Cycles clamps them (exact). Reported: Christensen-Burley (converted as Random
    Walk (Fixed Radius)); a radius channel of 0 beside walked channels (Cycles makes that
    channel diffuse; Facet walks it at a radius of 1e-4 of the largest, which looks diffuse)."""
    label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
    radius = [max(0.0, float(c)) for c in ctx.value(node, names[0], path)[:3]]
    ior = float(ctx.value(node, names[1], path))
    g = float(ctx.value(node, names[2], path))
    data[prefix + "ior"] = min(max(ior, _SSS_IOR[0]), _SSS_IOR[1])
    data[prefix + "anisotropy"] = min(max(g, _SSS_ANISOTROPY[0]), _SSS_ANISOTROPY[1])
    data[prefix + "method"] = _SSS_METHODS.get(method, "random_walk")
    if method == 'BURLEY':
        ctx.problems.append("%s: %s Christensen-Burley is not in Facet; converted as Random "
                            "Walk (Fixed Radius)" % (ctx.what, label))
    elif method not in _SSS_METHODS:
        ctx.problems.append("%s: %s subsurface method '%s' is not in Facet; converted as "
                            "Random Walk" % (ctx.what, label, method))
    top = max(radius)
    walked = is_texture(scale) or scale > 0.0
    if walked and top > 0.0 and min(radius) * (1.0 if is_texture(scale) else scale) < 1e-8:
        ctx.problems.append("%s: %s %s %s has a channel of 0 beside walked ones: Cycles makes "
                            "that channel diffuse, Facet walks it at a radius of 1e-4 of the "
                            "largest" % (ctx.what, label, names[0], _fmt(tuple(radius))))
        radius = [max(c, 1e-4 * top) for c in radius]
    data[prefix + "radius"] = radius


def _subsurface(ctx, node, path):
    """Subsurface Scattering node -> subsurface: Color, Scale, Radius, IOR, Anisotropy and the
    falloff (the core's random walk as Cycles 3.4's, docs/subsurface.md)."""
    data = {"model": "subsurface"}
    color = _rgb(ctx.param(node, 'Color', path))
    data["color"] = color if is_texture(color) else [max(0.0, min(1.0, c)) for c in color]
    scale = max(0.0, float(ctx.value(node, 'Scale', path)))
    data["scale"] = scale
    _subsurface_walk(ctx, node, path, data, "", ('Radius', 'IOR', 'Anisotropy'), node.falloff,
                     scale)
    return data, None


def _principled(ctx, node, path):
    def val(name):
        return ctx.value(node, name, path)

    def unit(x):
        return max(0.0, min(1.0, float(x)))

    data = {"model": "principled"}
    # Each input a constant (clamped as Cycles clamps it) or a texture value: an image or
    # checker (textures.py) or Blender's bake of its subgraph (bake.py).
    for name, key in _PRINCIPLED_COLOURS:
        v = _rgb(ctx.param(node, name, path))
        data[key] = v if is_texture(v) else [unit(c) for c in v]
    for name, key in _PRINCIPLED_FACTORS:
        v = ctx.param(node, name, path)
        data[key] = v if is_texture(v) else unit(v)
    _subsurface_walk(ctx, node, path, data, "subsurface_",
                     ('Subsurface Radius', 'Subsurface IOR', 'Subsurface Anisotropy'),
                     node.subsurface_method, data["subsurface"])
    rotation = float(val('Anisotropic Rotation'))
    data["anisotropic_rotation"] = rotation - math.floor(rotation)  # periodic (2 pi x rotation)
    data["ior"] = max(1e-3, min(100.0, float(val('IOR'))))
    if node.distribution == 'MULTI_GGX':
        data["distribution"] = "multi_ggx"
        def above(key, threshold):
            return is_texture(data[key]) or data[key] > threshold

        if (above("transmission", 1e-5) and above("roughness", _MULTI_GLASS_MIN_ROUGHNESS)
                and above("specular_tint", 0.0)
                and (is_texture(data["metallic"]) or data["metallic"] < 1.0)):
            ctx.problems.append(MULTI_GLASS_NOTE % (ctx.what, node.name))
        if above("anisotropic", 0.0):
            ctx.problems.append(MULTI_ANISO_NOTE % (ctx.what, node.name))
    elif node.distribution != 'GGX':
        ctx.problems.append("%s: %s distribution '%s' is not in Facet's principled; exported as "
                            "GGX (single scattering)" % (ctx.what, node.name, node.distribution))
    emission = _emission_of(ctx, node, path, 'Emission', 'Emission Strength')
    _principled_alpha(ctx, node, path, data, emission)
    return data, emission


def _emission_of(ctx, node, path, color_name, strength_name):
    """Color x Strength of an emission: None (Strength 0: nothing emitted, whatever feeds the
    colour), a colour, or a texture of the colour with "scale" Strength (an image into the
    colour: Cycles' emission is the texture's value x Strength)."""
    strength = ctx.value(node, strength_name, path)
    if strength == 0.0:
        return None
    color = ctx.param(node, color_name, path, scale=strength, ray=False)
    if is_texture(color):
        return color
    return units.emission_from_blender(color, strength)


def _principled_alpha(ctx, node, path, data, emission):
    """Principled Alpha a: Cycles mixes the BSDF with a Transparent BSDF, a x principled +
    (1 - a) x transparent, shadows included; the core's "opacity" a is that in expectation
    (FORMAT.md "Opacity": a surface that a fraction a of the rays meet). A number or a number
    texture (an image's Alpha output: channel "a"; its Color into Alpha: luminance). The core
    refuses opacity on an emitting surface (next-event estimation would count its light in
    full): reported, opaque."""
    alpha = ctx.param(node, 'Alpha', path, ray=False)
    if not is_texture(alpha):
        alpha = max(0.0, min(1.0, float(alpha)))
        if alpha == 1.0:
            return
    if emission is not None and (is_texture(emission) or any(c > 0.0 for c in emission)):
        ctx.problems.append("%s: %s '%s' input 'Alpha' %s with an emission: Facet's opacity "
                            "does not take emitting surfaces; opaque"
                            % (ctx.what, nodegraph.node_type_label(node), node.name,
                               "(a texture)" if is_texture(alpha) else "= " + _fmt(alpha)))
        return
    data["opacity"] = alpha


def _emission(ctx, node, path):
    # radiance = Color x Strength (a texture's scale), nothing for Strength 0
    return dict(BLACK), _emission_of(ctx, node, path, 'Color', 'Strength')


def _glass(ctx, node, path):
    """Glass and Refraction BSDF -> dielectric: ior = IOR (eta = n_inside / n_outside, the
    outside the side the normal points to, as Cycles' backfacing test), alpha = Roughness^2 as
    Cycles squares it (Sharp: 0), GGX -> ggx, Beckmann -> beckmann, Color -> transmittance.
    Approximations, reported: Cycles' Glass tints its reflection by Color too (Facet only the
    transmission); Cycles' Refraction BSDF has no reflection (Facet's dielectric reflects the
    Fresnel fraction). Multiscatter GGX -> energy_compensation (the core's rough-dielectric
    compensation: same energy as Cycles' random walk, docs/blender.md)."""
    label = "%s '%s'" % (nodegraph.node_type_label(node), node.name)
    ior = ctx.value(node, 'IOR', path)
    data = {"model": "dielectric", "ior": min(max(float(ior), 1e-3), 100.0)}
    if data["ior"] != ior:
        ctx.problems.append("%s: %s IOR %s clamped to Facet's range [0.001, 100]"
                            % (ctx.what, label, _fmt(ior)))
    color = _rgb(ctx.param(node, 'Color', path))
    if is_texture(color) or color != [1.0, 1.0, 1.0]:
        data["transmittance"] = color
        if node.bl_idname == 'ShaderNodeBsdfGlass':
            ctx.problems.append("%s: %s Color tints the reflection too in Cycles; Facet tints "
                                "only the transmission" % (ctx.what, label))
    if node.bl_idname == 'ShaderNodeBsdfRefraction':
        ctx.problems.append("%s: %s has no reflection in Cycles; Facet's dielectric reflects "
                            "the Fresnel fraction" % (ctx.what, label))
    dist = node.distribution
    if dist != 'SHARP':
        alpha = _alpha_param(ctx, node, path)
        if is_texture(alpha) or alpha > 0.0:
            data["alpha"] = alpha
            if dist == 'BECKMANN':
                data["distribution"] = "beckmann"
            elif dist == 'MULTI_GGX':
                data["energy_compensation"] = True
    return data, None


# --- volume shaders -> (sigma_a, sigma_s, g, emission) (NodeContext.volume) ----------------

# Cycles' Henyey-Greenstein anisotropy (volume_henyey_greenstein_setup clamps |g| to 1 - 1e-3,
# the core's range).
_G_MAX = 0.999


def _anisotropy(ctx, node, path):
    return min(max(float(ctx.value(node, 'Anisotropy', path)), -_G_MAX), _G_MAX)


def _principled_volume(ctx, node, path):
    """Cycles' Principled Volume: the core's cycles_volume of Density, Color, Absorption Color;
    g = Anisotropy; emission = Emission Strength x Emission Color (not scaled by the density,
    as in Cycles; nothing for a Strength <= 0). Blackbody Intensity > 0 is reported
    (gaps.INPUTS); a Density or Color Attribute naming an attribute of the mesh is reported
    (Cycles multiplies by it; a mesh without it leaves the input as it is, as here)."""
    density = ctx.value(node, 'Density', path)
    color = ctx.value(node, 'Color', path)
    absorption = ctx.value(node, 'Absorption Color', path)
    sa, ss = units.principled_volume_from_blender(density, color, absorption)
    strength = float(ctx.value(node, 'Emission Strength', path))
    em = units.emission_from_blender(ctx.value(node, 'Emission Color', path), strength) \
        if strength > 0.0 else [0.0, 0.0, 0.0]
    attrs = getattr(getattr(ctx.obj, "data", None), "attributes", None)
    for name in ('Density Attribute', 'Color Attribute'):
        sock = next((s for s in node.inputs if s.name == name), None)
        want = getattr(sock, "default_value", "") if sock is not None else ""
        if want and attrs is not None and want in attrs:
            ctx.problems.append("%s: %s '%s' input '%s' = '%s': the mesh's attribute is not "
                                "read (Facet's media are homogeneous); the constant is used"
                                % (ctx.what, nodegraph.node_type_label(node), node.name, name,
                                   want))
    return sa, ss, _anisotropy(ctx, node, path), em


def _volume_scatter(ctx, node, path):
    """Cycles' Volume Scatter: sigma_s = Density x Color, no absorption; g = Anisotropy."""
    sa, ss = units.volume_scatter_from_blender(ctx.value(node, 'Density', path),
                                               ctx.value(node, 'Color', path))
    return sa, ss, _anisotropy(ctx, node, path), [0.0, 0.0, 0.0]


def _volume_absorption(ctx, node, path):
    """Cycles' Volume Absorption: sigma_a = Density x (1 - Color)."""
    sa = units.volume_absorption_from_blender(ctx.value(node, 'Density', path),
                                              ctx.value(node, 'Color', path))
    return sa, [0.0, 0.0, 0.0], None, [0.0, 0.0, 0.0]


def _volume_emission(ctx, node, path):
    """An Emission (or the world's Background) on a Volume output: emission = Color x Strength
    per unit length, Cycles' volume emission."""
    strength = float(ctx.value(node, 'Strength', path))
    z = [0.0, 0.0, 0.0]
    return z, z, None, units.emission_from_blender(ctx.value(node, 'Color', path), strength)


_VOLUME_CONVERTERS = {
    'ShaderNodeVolumePrincipled': _principled_volume,
    'ShaderNodeVolumeScatter': _volume_scatter,
    'ShaderNodeVolumeAbsorption': _volume_absorption,
    'ShaderNodeEmission': _volume_emission,
}
_VOLUME_READS = {
    # Blackbody Tint and Temperature act only with Blackbody Intensity > 0 (reported); the
    # attribute names are checked by _principled_volume.
    'ShaderNodeVolumePrincipled': ('Color', 'Density', 'Anisotropy', 'Absorption Color',
                                   'Emission Strength', 'Emission Color', 'Blackbody Tint',
                                   'Temperature', 'Color Attribute', 'Density Attribute',
                                   'Temperature Attribute'),
    'ShaderNodeVolumeScatter': ('Color', 'Density', 'Anisotropy'),
    'ShaderNodeVolumeAbsorption': ('Color', 'Density'),
    'ShaderNodeEmission': ('Color', 'Strength'),
}

# Models rays cross (the core's transmissive models, FORMAT.md "media"): only these bound a
# medium; a combination does when a child does.
_CROSSED_MODELS = ("dielectric", "thin_dielectric", "translucent", "null", "principled_hair")


def crosses(data):
    """Whether rays cross a converted surface (so a volume behind it is reachable): a
    transmissive model, a principled with Transmission > 0 (or textured), or a mix / add with
    such a child."""
    model = data.get("model")
    if model in _CROSSED_MODELS:
        return True
    if model == "hair":
        return data.get("component") == "transmission"
    if model == "principled":
        t = data.get("transmission", 0.0)
        return is_texture(t) or t > 0.0
    if model in ("mix", "add"):
        return any(isinstance(c, dict) and crosses(c) for c in data.get("materials", ()))
    return False


# bl_idname -> conversion(ctx, node, path) -> (data, emission or None); _READS: the inputs it
# reads (every other input is checked by NodeContext.check_inputs: gaps.INPUTS or reported
# when linked).
_NODE_CONVERTERS = {
    'ShaderNodeBsdfDiffuse': _diffuse,
    'ShaderNodeBsdfGlossy': _glossy,
    'ShaderNodeBsdfAnisotropic': _glossy,
    'ShaderNodeBsdfPrincipled': _principled,
    'ShaderNodeEmission': _emission,
    'ShaderNodeBsdfGlass': _glass,
    'ShaderNodeBsdfRefraction': _glass,
    'ShaderNodeBsdfTranslucent': _translucent,
    'ShaderNodeBsdfVelvet': _velvet,
    'ShaderNodeBsdfHairPrincipled': _principled_hair,
    'ShaderNodeBsdfHair': _hair,
    'ShaderNodeBsdfTransparent': _transparent,
    'ShaderNodeHoldout': _holdout,
    'ShaderNodeSubsurfaceScattering': _subsurface,
}
_READS = {
    'ShaderNodeBsdfDiffuse': ('Color', 'Roughness'),
    'ShaderNodeBsdfGlossy': ('Color', 'Roughness'),
    'ShaderNodeBsdfAnisotropic': ('Color', 'Roughness', 'Anisotropy'),
    'ShaderNodeBsdfPrincipled': tuple(n for n, _ in _PRINCIPLED_COLOURS + _PRINCIPLED_FACTORS)
    + ('Anisotropic Rotation', 'IOR', 'Emission', 'Emission Strength', 'Subsurface Radius',
       'Subsurface IOR', 'Subsurface Anisotropy'),
    'ShaderNodeEmission': ('Color', 'Strength'),
    'ShaderNodeBsdfGlass': ('Color', 'Roughness', 'IOR'),
    'ShaderNodeBsdfRefraction': ('Color', 'Roughness', 'IOR'),
    'ShaderNodeBsdfTranslucent': ('Color',),
    'ShaderNodeBsdfVelvet': ('Color', 'Sigma'),
    'ShaderNodeBsdfHairPrincipled': ('Color', 'Melanin', 'Melanin Redness', 'Tint',
                                     'Absorption Coefficient', 'Roughness', 'Radial Roughness',
                                     'Coat', 'IOR', 'Offset', 'Random Color', 'Random Roughness',
                                     'Random'),
    'ShaderNodeBsdfHair': ('Color', 'Offset', 'RoughnessU', 'RoughnessV'),
    'ShaderNodeBsdfTransparent': ('Color',),
    'ShaderNodeHoldout': (),
    'ShaderNodeSubsurfaceScattering': ('Color', 'Scale', 'Radius', 'IOR', 'Anisotropy'),
}
