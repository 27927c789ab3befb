"""The flattened view of a Blender shader node tree that Cycles 3.4 renders, walked from the
output node back to the inputs; pure Python over bpy data (no bpy.ops, no bpy import).

Conventions (each rule is Cycles 3.4's, intern/cycles/blender/shader.cpp, as Blender hands the
tree to Cycles):
- A link counts when it is valid, not muted, and both its sockets are enabled; any other link
  is as if absent (the input's own value is used).
- Reroute nodes and muted nodes pass their `internal_links` through (Blender computes them: a
  muted node's output takes the first input of the best-matching type). Cycles makes each such
  pair one conversion proxy of the *output's* type, so a link into the passed input converts
  straight to the output's type, and an unlinked passed input gives 0 (the proxy's own value,
  not the socket's). An output with no internal link is not connected at all: the input it
  feeds keeps its own value.
- Node groups are flattened: a Group node's output is its tree's active Group Output input
  (that socket's own value when unlinked), a Group Input output is the enclosing Group node's
  input (its own value when unlinked). Nested groups nest; `path` is the tuple of Group nodes
  from the outermost.
- A link between sockets of different types converts as Cycles' ShaderGraph::connect does:
  float -> colour/vector (f, f, f); colour -> float: luminance with Cycles' scene-linear
  coefficients (RGB_TO_Y below, measured);
  vector -> float: the mean of the components; colour <-> vector: the components; a colour
  into a shader socket is an Emission of that Color (Strength 1), a float an Emission of
  Strength f (Color 1).
- Values are floats or 3-tuples of floats (a colour's alpha is dropped, as Cycles does).

The output is the one Cycles renders (active_output: target Cycles before All, then the active
one). Walker.input() gives, for an input socket, either a Const (its value) or an Out (the output
socket feeding it, with the conversions on the way); Walker.fold() evaluates an Out to a
constant when every node of its subgraph is one nodevalues.py evaluates, and otherwise lists
the nodes that stop it.
"""
from . import nodevalues

# Scene-linear RGB -> luminance, Cycles' rgb_to_y in Blender 3.4.1's default OCIO config,
# measured by render (tests/blender/test_nodegraph.py: pure red, green and blue linked into a
# float). It differs from the Y row of the config's srgb_to_xyz.spimtx (0.2126729, 0.7151522,
# 0.0721750) in the 7th digit; how Cycles derives it from the config was not traced.
RGB_TO_Y = (0.21267297863960266, 0.7151526212692261, 0.07217544317245483)

_PASS_THROUGH = ('NodeReroute',)
_GROUPS = ('ShaderNodeGroup', 'NodeCustomGroup')


class Const:
    """A constant value: a float or a 3-tuple; `stype` is Blender's socket type of the value."""

    __slots__ = ("value", "stype")

    def __init__(self, value, stype):
        self.value = value
        self.stype = stype

    def __repr__(self):
        return "Const(%r)" % (self.value,)


class Out:
    """An output socket of a node in the flattened tree (`path`: the enclosing Group nodes) and
    the socket types its value is converted to on the way to the input asking for it."""

    __slots__ = ("node", "socket", "path", "convs")

    def __init__(self, node, socket, path, convs=()):
        self.node = node
        self.socket = socket
        self.path = path
        self.convs = tuple(convs)

    @property
    def key(self):
        """Identifies the node in the flattened tree (for one report line per node)."""
        return tuple(g.name for g in self.path) + (self.node.name,)

    def label(self):
        """"Image Texture 'Tex'" or "Bump 'Bump' in node group 'Outer' > 'Inner'" (the groups'
        node trees, outermost first)."""
        s = "%s '%s'" % (node_type_label(self.node), self.node.name)
        if self.path:
            s += " in node group " + " > ".join(
                "'%s'" % (g.node_tree.name if g.node_tree is not None else g.name)
                for g in self.path)
        return s

    def __repr__(self):
        return "Out(%s.%s)" % ("/".join(self.key), self.socket.identifier)


def node_type_label(node):
    """The node's type name as Blender's UI shows it ("Image Texture", "Mix Shader")."""
    return getattr(node, "bl_label", None) or node.bl_idname


def socket_value(sock):
    """The unlinked value of a socket: float or 3-tuple (alpha dropped); None for a socket
    without a value (shader, custom)."""
    v = getattr(sock, "default_value", None)
    if v is None:
        return None
    try:
        vals = [float(c) for c in v]
    except TypeError:
        return float(v)
    return tuple(vals[:3]) if len(vals) >= 3 else tuple(vals)


def convert(value, from_type, to_type):
    """A value crossing a link from a `from_type` socket to a `to_type` socket (Cycles'
    ShaderGraph::connect conversions). Returns the converted value; a non-shader value into a
    shader socket becomes ("EMISSION", colour, strength)."""
    if from_type == to_type or value is None:
        return value
    scalar = not isinstance(value, tuple)
    if to_type == 'SHADER':
        if scalar:
            return ("EMISSION", (1.0, 1.0, 1.0), value)
        return ("EMISSION", value, 1.0)
    if to_type in ('VALUE', 'INT', 'BOOLEAN'):
        if scalar:
            return value
        if from_type == 'RGBA':
            return sum(c * w for c, w in zip(value, RGB_TO_Y))
        return sum(value) / 3.0
    if to_type in ('RGBA', 'VECTOR'):
        return (value, value, value) if scalar else value
    return value


def _live_link(sock):
    for link in sock.links:
        if (link.is_valid and not link.is_muted and link.from_socket.enabled
                and link.to_socket.enabled):
            return link
    return None


def active_output(tree, idname):
    """The output node Cycles renders (Blender's ntreeShaderOutputNode for target Cycles): among
    the nodes of type `idname` with target All or Cycles, a Cycles one before an All one, then
    the active one, then the first; None when there is none."""
    best = None
    for n in tree.nodes:
        if n.bl_idname != idname:
            continue
        target = getattr(n, "target", 'ALL')
        if target not in ('ALL', 'CYCLES'):
            continue
        if best is None:
            best = n
            continue
        best_target = getattr(best, "target", 'ALL')
        if target == 'CYCLES' and best_target == 'ALL':
            best = n
        elif target == best_target and n.is_active_output and not best.is_active_output:
            best = n
    return best


class Walker:
    """Walks one node tree (a material's or a world's)."""

    def __init__(self, tree):
        self.tree = tree

    # --- structure ----------------------------------------------------------------------------

    def input(self, node, name, path=()):
        """The value feeding input `name` (name or identifier; a socket also works) of `node`
        at `path`: Const or Out."""
        sock = name if not isinstance(name, str) else _find(node.inputs, name)
        return self._resolve_input(sock, path, sock.type, ())

    def _resolve_input(self, sock, path, want_type, convs):
        """Follows the link into `sock` (whose value arrives as `want_type`, then goes through
        the conversions `convs`)."""
        link = _live_link(sock)
        if link is None:
            return _const(socket_value(sock), sock.type, convs)
        return self._resolve_output(link.from_socket, link.from_node, path, want_type,
                                    (socket_value(sock), sock.type), convs)

    def _resolve_output(self, out, node, path, want_type, dest, convs, depth=0):
        """The value of output `out` of `node` arriving as `want_type`; `dest` is the (value,
        type) the destination keeps when nothing is connected."""
        if depth > 1000:
            raise ValueError("node tree too deep or cyclic at '%s'" % node.name)
        after = ((want_type,) if out.type != want_type else ()) + convs
        if node.mute or node.bl_idname in _PASS_THROUGH:
            passed = next((il.from_socket for il in node.internal_links
                           if il.to_socket == out), None)
            if passed is None and not node.mute:  # a reroute whose links are not updated yet
                passed = node.inputs[0]
            if passed is None:
                # Not connected in Cycles: the destination keeps its own value.
                return _const(dest[0], dest[1], convs)
            # A proxy of the output's type; unlinked, its own value 0.
            zero = (0.0, 0.0, 0.0) if out.type in ('RGBA', 'VECTOR') else 0.0
            return self._follow(passed, path, out.type, (zero, out.type), after, depth)
        if node.bl_idname in _GROUPS:
            tree = node.node_tree
            gout = None
            if tree is not None:
                gouts = [n for n in tree.nodes if n.bl_idname == 'NodeGroupOutput']
                gout = next((n for n in gouts if n.is_active_output),
                            gouts[0] if gouts else None)
            sock = _by_identifier(gout.inputs, out.identifier) if gout is not None else None
            if sock is None:
                return _const(dest[0], dest[1], convs)
            return self._follow(sock, path + (node,), out.type,
                                (socket_value(sock), sock.type), after, depth)
        if node.bl_idname == 'NodeGroupInput':
            sock = _by_identifier(path[-1].inputs, out.identifier) if path else None
            if sock is None:  # nothing feeds a Group Input outside a group
                return _const(dest[0], dest[1], convs)
            return self._follow(sock, path[:-1], out.type, (socket_value(sock), sock.type),
                                after, depth)
        return Out(node, out, path, after)

    def _follow(self, sock, path, proxy_type, own, convs, depth):
        """Through a proxy of `proxy_type` (a pass-through or a group boundary) whose input is
        `sock`; `own` is the proxy's (value, type) when `sock` is unlinked."""
        link = _live_link(sock)
        if link is None:
            return _const(convert(own[0], own[1], proxy_type), proxy_type, convs)
        return self._resolve_output(link.from_socket, link.from_node, path, proxy_type,
                                    (convert(own[0], own[1], proxy_type), proxy_type), convs,
                                    depth + 1)

    def inputs(self, node, path=()):
        """{input name: Const or Out} for every enabled input of `node` (a BSDF's inputs, each
        a constant or the subgraph feeding it)."""
        return {s.name: self.input(node, s, path) for s in node.inputs if s.enabled}

    def subgraph(self, src):
        """The nodes upstream of `src` (an Out, itself first) in the flattened tree, each once,
        as Outs: what a conversion of the input it feeds depends on."""
        seen, order, todo = set(), [], [src] if isinstance(src, Out) else []
        while todo:
            o = todo.pop()
            if o.key in seen:
                continue
            seen.add(o.key)
            order.append(o)
            for sock in o.node.inputs:
                if sock.enabled:
                    up = self._resolve_input(sock, o.path, sock.type, ())
                    if isinstance(up, Out):
                        todo.append(up)
        return order

    # --- values ---------------------------------------------------------------------------------

    def fold(self, src, _memo=None):
        """Const or Out -> (value, blockers): the constant value of src (converted along its
        links), or (None, [Out of every node that stops it]). Nodes nodevalues.py evaluates
        are folded when all their inputs are constant."""
        if isinstance(src, Const):
            return src.value, []
        memo = {} if _memo is None else _memo
        key = (src.key, src.socket.identifier)
        if key not in memo:
            memo[key] = self._fold_node(src, memo)
        value, blockers = memo[key]
        if value is None:
            return None, blockers
        t = src.socket.type
        for to in src.convs:
            value, t = convert(value, t, to), to
        return value, []

    def _fold_node(self, src, memo):
        node = src.node
        fn = nodevalues.EVALUATORS.get(node.bl_idname)
        if fn is None:
            return None, [src]
        values, blockers = {}, []
        for sock in node.inputs:
            if not sock.enabled:
                continue
            v, b = self.fold(self._resolve_input(sock, src.path, sock.type, ()), memo)
            values[sock.identifier] = v
            blockers.extend(x for x in b if x.key not in {y.key for y in blockers})
        if blockers:
            return None, blockers
        try:
            return fn(node, values, src.socket.identifier), []
        except (KeyError, ValueError, ArithmeticError):  # an unknown mode, a math domain error
            return None, [src]


def _const(value, vtype, convs):
    for to in convs:
        value, vtype = convert(value, vtype, to), to
    return Const(value, vtype)


def _find(sockets, name):
    """A socket by identifier first (unique), else by the first enabled one with that name."""
    for s in sockets:
        if s.identifier == name:
            return s
    for s in sockets:
        if s.name == name and s.enabled:
            return s
    raise KeyError(name)


def _by_identifier(sockets, ident):
    return next((s for s in sockets if s.identifier == ident), None)
