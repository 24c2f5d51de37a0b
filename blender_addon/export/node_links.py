"""Following a node input to what feeds it, as Cycles reads a node tree:
through reroutes, muted nodes and node groups, to the node and output linked
into it, or to the value the input takes when nothing the export reads feeds it.

Node groups are read as Cycles reads them, as if their nodes stood in the
material's tree: a group node's output leads to what feeds the matching input
of the group's active Group Output inside it, and a Group Input node's output
back to what feeds the matching input of the group node that holds it. A node
found inside a group comes wrapped (InGroup): the node itself for every
attribute, its inputs and outputs wrapped too, so that following one of its
inputs to a Group Input leaves through the right group node (a group used twice
is two places in the tree).
"""
from __future__ import annotations


def _socket(node, *names):
    for name in names:
        socket = node.inputs.get(name)
        if socket is not None:
            return socket
    return None


def _through(node, out):
    """The input socket a muted node passes to its output `out` (reroutes
    pass their one input), or None when nothing reaches `out`."""
    if node.type == "REROUTE":
        return node.inputs[0]
    for internal in node.internal_links:
        if internal.to_socket.identifier == out.identifier and not internal.is_muted:
            return internal.from_socket
    return None


CONSTANT_NODES = ("RGB", "VALUE")   # nodes whose output is a value set on it
MAX_GROUP_DEPTH = 32                # group nodes nested deeper are read as unlinked (a group cannot hold itself)


class InGroup:
    """A node or socket inside node groups: `item` (the Blender node or socket; every other
    attribute is its own) and `groups`, the group nodes it sits in, outermost first."""
    __slots__ = ("item", "groups")

    def __init__(self, item, groups):
        self.item, self.groups = item, groups

    def __getattr__(self, name):
        value = getattr(self.item, name)
        if name in ("inputs", "outputs"):
            return _Sockets(value, self.groups)
        if name == "node":
            return _wrap(value, self.groups)
        return value

    def __eq__(self, other):
        return isinstance(other, InGroup) and self.item == other.item and self.groups == other.groups

    def __hash__(self):
        return hash(self.item.as_pointer())


class _Sockets:
    """A wrapped node's inputs or outputs: each socket wrapped (InGroup)."""
    __slots__ = ("sockets", "groups")

    def __init__(self, sockets, groups):
        self.sockets, self.groups = sockets, groups

    def __getitem__(self, key):
        found = self.sockets[key]
        return [_wrap(s, self.groups) for s in found] if isinstance(key, slice) else _wrap(found, self.groups)

    def get(self, name, default=None):
        found = self.sockets.get(name)
        return default if found is None else _wrap(found, self.groups)

    def __contains__(self, name):
        return name in self.sockets

    def keys(self):
        return self.sockets.keys()

    def find(self, name):
        return self.sockets.find(name)

    def __iter__(self):
        return (_wrap(s, self.groups) for s in self.sockets)

    def __len__(self):
        return len(self.sockets)


def tree_nodes(tree):
    """Every node of `tree` and of the node groups it uses, however deep (each group's tree once)."""
    seen, todo = {tree.as_pointer()}, [tree]
    while todo:
        for node in todo.pop().nodes:
            yield node
            inner = getattr(node, "node_tree", None) if node.type == "GROUP" else None
            if inner is not None and inner.as_pointer() not in seen:
                seen.add(inner.as_pointer())
                todo.append(inner)


def _wrap(item, groups):
    return InGroup(item, groups) if groups else item


def _unwrap(item):
    return (item.item, item.groups) if isinstance(item, InGroup) else (item, ())


def _group_output_input(group, out):
    """The input of the active Group Output inside `group` (a group node) that its output
    `out` gives, or None (no tree, no such output)."""
    tree = getattr(group, "node_tree", None)
    if tree is None:
        return None
    outputs = [n for n in tree.nodes if n.type == "GROUP_OUTPUT"]
    node = next((n for n in outputs if getattr(n, "is_active_output", False)), outputs[0] if outputs else None)
    if node is None:
        return None
    return next((s for s in node.inputs if s.identifier == out.identifier), None)


class _Computed:
    """A value a node computes from constant inputs, held as a socket holds its own."""

    def __init__(self, value):
        self.default_value = value


def _constant_ramp(node, out):
    """A Color Ramp whose Fac nothing the export reads feeds (unlinked, a Value or RGB
    node, another such ramp): its output's value there, as Blender evaluates the ramp;
    else None."""
    fac = node.inputs["Fac"]
    if _follow(fac)[0] is not None:
        return None
    rgba = tuple(float(c) for c in node.color_ramp.evaluate(input_value(fac)))
    return _Computed(rgba if out.name == "Color" else rgba[3])


def _kind(socket) -> str:
    """"number", "shader" or "value" (a colour or vector: several numbers) of a socket's type."""
    kind = socket.type
    return "number" if kind in ("VALUE", "INT", "BOOLEAN") else "shader" if kind == "SHADER" else "value"


def node_key(node) -> tuple:
    """What tells a node apart where it stands: its address and the group nodes it sits in."""
    real, groups = _unwrap(node)
    return (real.as_pointer(),) + tuple(g.as_pointer() for g in groups)


def _follow(socket):
    """(node, output socket, value) for the input `socket`: the node and output
    linked into it, through reroutes, muted nodes and node groups as Blender
    passes them (InGroup-wrapped inside a group); else node None, and `value`
    the socket whose value the input takes:
      - the input itself when it is unlinked, when its link or what reaches
        it is muted, or when a muted node passes nothing to that output;
      - a group node's input, or a Group Output's, where the chain ends there unlinked;
      - the output of an RGB or Value node linked to it (not a shader or
        vector input: a constant texture coordinate is not read), or of a
        Color Ramp whose Fac is such a constant (its colour there);
      - None (the value 0, as Cycles reads it) when the chain ends at an
        unlinked input of a reroute or muted node, not that input's value."""
    socket, groups = _unwrap(socket)
    first, holder, seen = socket, socket, set()
    crossed, narrowed = None, False   # the first group node the chain crosses, and its output; a number socket crossed
    while socket is not None and socket.is_linked:
        link = socket.links[0]
        key = (socket.as_pointer(), tuple(g.as_pointer() for g in groups))
        if link.is_muted or not link.is_valid or key in seen:   # (invalid: red; a reroute loop)
            break
        seen.add(key)
        node, out = link.from_node, link.from_socket
        lossy = narrowed and _kind(out) != "number" and _kind(first) != "number"
        if lossy and (node.type in CONSTANT_NODES or (node.type not in ("GROUP", "GROUP_INPUT", "REROUTE")
                                                      and not node.mute)):
            # (a colour or vector made a number at a group's socket, and a colour again: Cycles'
            # conversions there are not followed; the group is named as before)
            return crossed[0], crossed[1], None
        if node.type in CONSTANT_NODES and not node.mute and first.type not in ("SHADER", "VECTOR"):
            return None, None, out
        if node.type == "VALTORGB" and not node.mute and first.type not in ("SHADER", "VECTOR"):
            computed = _constant_ramp(_wrap(node, groups), out)
            if computed is not None:
                return None, None, computed
        if node.type == "GROUP" and not node.mute:          # into the group, at its output
            inner = _group_output_input(node, out) if len(groups) < MAX_GROUP_DEPTH else None
            if inner is None:
                return None, None, None
            crossed = crossed or (_wrap(node, groups), _wrap(out, groups))
            narrowed = narrowed or _kind(out) == "number"
            groups, socket = groups + (node,), inner
            holder = socket
            continue
        if node.type == "GROUP_INPUT":                      # out of the group, at the group node's input
            outer = next((s for s in groups[-1].inputs if s.identifier == out.identifier), None) if groups else None
            if outer is None:             # (no group node around it, or none of its inputs matches: the input's own)
                return None, None, socket
            crossed = crossed or (_wrap(node, groups), _wrap(out, groups))
            narrowed = narrowed or _kind(out) == "number"
            groups, socket = groups[:-1], outer
            holder = socket
            continue
        if node.type != "REROUTE" and not node.mute:
            return _wrap(node, groups), _wrap(out, groups), None
        fed, socket = socket, _through(node, out)
        if socket is None:                 # a muted node passing nothing: the input it fed
            socket = fed                   # stays unlinked (a reroute's gives 0)
            break
        holder = None
    return None, None, holder if socket is holder else None


def _source(socket):
    """(node, output socket) linked into `socket` (see _follow), or (None, None)."""
    node, out, _ = _follow(socket)
    return node, out


def input_value(socket):
    """The value Cycles gives an input that no node feeds (see _follow), as a
    float or a tuple like the input's own: its own value, an RGB or Value
    node's (converted as Blender converts: a float to grey, a colour to its
    Rec. 709 luminance), or 0."""
    own = socket.default_value
    node, _, value = _follow(socket)
    if node is not None:                   # a node the export does not read: the input's own value
        value = socket
    value = 0.0 if value is None else value.default_value
    if hasattr(own, "__len__"):
        if hasattr(value, "__len__"):
            return tuple(float(c) for c in value)
        return tuple(float(value) for _ in own)
    if hasattr(value, "__len__"):
        return 0.2126 * float(value[0]) + 0.7152 * float(value[1]) + 0.0722 * float(value[2])
    return float(value)
