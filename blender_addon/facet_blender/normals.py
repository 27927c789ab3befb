"""A BSDF's Normal input -> the material's `normal_map` and `bump` (scenes/FORMAT.md, "Normal
maps" and "Bump maps"), exactly as Cycles 3.4 evaluates them where the core can express it.

- Nothing linked: the shading normal ({}).
- Normal Map node (Cycles' svm_node_normal_map), space Tangent: `normal_map` = the texture
  feeding its Color (textures.py: an Image Texture, or Blender's bake of any other subgraph,
  bake.py) read as its colour space says (Non-Color: linear), with `strength` = max(Strength,
  0); its UV Map (empty: the render UV map) is the map whose MikkTSpace tangents the mesh
  exports (export.py, Blender's own calc_tangents()). The colour texture reading another UV
  map than the node's is reported (the core has one UV map per mesh). A constant Color of
  (0.5, 0.5, 1) is no map; any other constant is reported. Spaces Object, World, Blender
  Object and Blender World are reported (the core's maps are tangent space only).
- Bump node (Cycles' svm_node_set_bump): `bump` = the texture of its Height (a number
  texture: an image's luminance, a checker, or the bake) with `distance` = Distance, negated
  when Invert is on (Cycles negates the distance), and `strength` = max(Strength, 0) (0: no
  bump). A constant Height is no bump (its gradient is zero). Its Normal input may be a Normal Map node (the core applies
  the normal map, then the bump, as Cycles chains them); another Bump (a chain of bumps) is
  reported and only the outer one converted.
- Anything else into a Normal input (Geometry, Texture Coordinate, a vector Math...) is
  reported, and the shading normal used.
- Principled's Clearcoat Normal: clearcoat() (the core's principled has one shading normal).
"""
from . import gaps, nodegraph, textures

# The tangent-space normal of a texel that leaves the normal unchanged.
FLAT = (0.5, 0.5, 1.0)


def convert(ctx, node, path):
    """The material keys for what feeds `node`'s Normal input (ctx: materials.NodeContext):
    {} or {"normal_map": texture dict + strength, "bump": texture dict + distance}. Needs
    tangents when "normal_map" is there (the caller's ctx.tangents is set)."""
    sock = next(s for s in node.inputs if s.identifier == 'Normal')
    feeds = "%s '%s' input 'Normal'" % (nodegraph.node_type_label(node), node.name)
    out = {}
    _normal(ctx, ctx.walker.input(node, sock, path), feeds, out, outer=True)
    return out


def _normal(ctx, src, feeds, out, outer):
    if isinstance(src, nodegraph.Const):
        return  # unlinked: the shading normal
    idname = src.node.bl_idname
    if src.socket.type == 'VECTOR' and idname == 'ShaderNodeNormalMap' and not src.convs:
        _normal_map(ctx, src, feeds, out)
    elif src.socket.type == 'VECTOR' and idname == 'ShaderNodeBump' and not src.convs:
        if outer:
            _bump(ctx, src, feeds, out)
        else:
            ctx.gap(src, "a Bump feeding another Bump (a chain of bumps): the core has one "
                    "bump per material", "feeds %s; only the outer Bump is converted" % feeds)
    else:
        ctx.gap(src, gaps.node_reason(src.node) or "only a Normal Map or a Bump node converts "
                "into a Normal input", "feeds %s; the shading normal is used" % feeds)


def _normal_map(ctx, src, feeds, out):
    node, path = src.node, src.path
    used = "feeds %s; the shading normal is used" % feeds
    if node.space != 'TANGENT':
        ctx.gap(src, "space %s (the core's normal maps are tangent space)"
                % node.space.replace('_', ' ').title(), used)
        return
    strength = max(0.0, float(ctx.value(node, 'Strength', path)))
    color = ctx.param(node, 'Color', path, ray=False)
    if not isinstance(color, dict):
        if any(abs(float(c) - f) > 0.0 for c, f in zip(color, FLAT)) and strength > 0.0:
            ctx.gap(src, "a constant Color %s (a uniformly tilted normal)"
                    % (tuple(round(float(c), 4) for c in color),), used)
        return  # (0.5, 0.5, 1): no map, exactly
    if strength == 0.0:
        return  # no map, exactly
    if color.get("vertex_color"):
        ctx.gap(src, "a Color Attribute into its Color (the core's normal maps are images)",
                used)
        return
    if not textures.reads_uv_only(color):
        ctx.gap(src, "a texture that reads %s into its Color (the core's normal maps read UVs "
                "only)" % _point_read(color), used)
        return
    nm = dict(color)
    if nm.pop("scale", 1.0) != 1.0:
        ctx.gap(src, "a scaled colour into its Color", used)
        return
    if "channel" in nm:
        ctx.gap(src, "a single channel into its Color", used)
        return
    if strength != 1.0:
        nm["strength"] = strength
    out["normal_map"] = nm
    # The node's UV map gives the tangents (the texture's may differ: export.py reports an
    # object whose materials read several UV maps).
    ctx.uv_maps.add(node.uv_map or "")
    ctx.tangents = True


def _bump(ctx, src, feeds, out):
    node, path = src.node, src.path
    label = src.label()
    strength = max(0.0, float(ctx.value(node, 'Strength', path)))
    distance = float(ctx.value(node, 'Distance', path))
    if node.invert:
        distance = -distance
    # Its Normal input first: a Normal Map feeding the Bump is applied before it (the core's
    # order); the unbumped normal when the Bump does nothing.
    inner = ctx.walker.input(node, next(s for s in node.inputs if s.identifier == 'Normal'),
                             path)
    _normal(ctx, inner, "%s input 'Normal'" % label, out, outer=False)
    if strength == 0.0 or distance == 0.0:
        return  # n unchanged (Cycles: normalize(0 n' + 1 n) = n)
    height = ctx.param(node, 'Height', path, ray=False)
    if not isinstance(height, dict):
        return  # a constant height: zero gradient, the normal unchanged
    if height.get("vertex_color"):
        ctx.gap(src, "a Color Attribute as its Height (the core's bumps read images or "
                "checkers)", "feeds %s; the shading normal is used" % feeds)
        return
    if not textures.reads_uv_only(height):
        ctx.gap(src, "a texture that reads %s as its Height (the core's bumps read UVs only)"
                % _point_read(height), "feeds %s; the shading normal is used" % feeds)
        return
    bump = dict(height)
    bump["distance"] = distance
    if strength != 1.0:
        bump["strength"] = strength
    out["bump"] = bump


def _point_read(tex):
    """What of the point a texture reads besides UVs, for a report line."""
    if textures.reads_ray(tex):
        return "the ray (Light Path)"
    keys = list(_keys(tex))
    if any(k == "hair_info" for k, _ in keys):
        return "the strand (Hair Info)"
    coords = sorted({v for k, v in keys if k == "coordinates" and v != "uv"})
    return "%s coordinates" % "/".join(c.title() for c in coords)


def _keys(tex):
    """Every (key, value) of a texture dict, nested ones too."""
    if isinstance(tex, dict):
        for k, v in tex.items():
            yield k, v
            yield from _keys(v)
    elif isinstance(tex, (list, tuple)):
        for v in tex:
            yield from _keys(v)


# The keys of a material that are its shading normal (materials.NORMAL_KEYS).
_NORMAL_KEYS = ("normal_map", "bump")


def clearcoat(ctx, node, path, data):
    """Principled's Clearcoat Normal (Cycles shades the clearcoat lobe with it, every other lobe
    with Normal). The core's principled has one shading normal for all its lobes, so:
    - nothing linked, the same map as Normal (the glTF importer's shared normal texture), or no
      clearcoat (constant Clearcoat 0: the lobe is absent): exact;
    - otherwise an approximation, reported: the Clearcoat Normal is ignored and every lobe uses
      Normal's (none: the shading normal). The other choice, its map for every lobe, is
      further from Cycles: Cycles' coat lobe is weak (0.25 Clearcoat x Fresnel at IOR 1.5) and
      shows the map only in its sharp reflections, while the base lobes would show it
      everywhere (ClearCoatTest's 'CoatNorm_Coated', 96 x 72 crop at 128 spp: block RMSE 2.9x
      the Cycles noise floor ignoring the map, 8.7x with it on every lobe).
    `data` is the converted material (its normal keys already set by convert())."""
    sock = next((s for s in node.inputs if s.identifier == 'Clearcoat Normal' and s.enabled),
                None)
    if sock is None:
        return
    src = ctx.walker.input(node, sock, path)
    if isinstance(src, nodegraph.Const):
        return
    feeds = "%s '%s' input 'Clearcoat Normal'" % (nodegraph.node_type_label(node), node.name)
    coat = data.get("clearcoat")
    if not isinstance(coat, dict) and float(coat or 0.0) == 0.0:
        return  # no clearcoat lobe: its normal shades nothing
    cc = {}
    _normal(ctx, src, feeds, cc, outer=True)
    base = {k: data[k] for k in _NORMAL_KEYS if k in data}
    if cc == base:
        return  # one normal for every lobe, as in Cycles
    ctx.problems.append("%s: %s: Facet's principled shades every lobe with one normal; the "
                        "Clearcoat Normal is ignored and the coat uses %s (Cycles: its own)"
                        % (ctx.what, feeds, "Normal's" if base else "the shading normal"))
