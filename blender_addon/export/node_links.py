"""Following a node input to what feeds it, as Cycles reads a node tree:
through reroutes and muted nodes, to the node and output linked into it, or
to the value the input takes when nothing the export reads feeds it."""
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


def _follow(socket):
    """(node, output socket, value) for the input `socket`: the node and output
    linked into it, through reroutes and muted nodes as Blender passes them;
    else node None, and `value` the socket whose value the input takes:
      - the input itself when it is unlinked, when its link or what reaches
        it is muted, or when a muted node passes nothing to that output;
      - the output of an RGB or Value node linked to it (not a shader or
        vector input: a constant texture coordinate is not read), or of a
        Color Ramp whose Fac is such a constant (its colour there);
      - None (the value 0, as Cycles reads it) when the chain ends at an
        unlinked input of a reroute or muted node, not that input's value."""
    first, seen = socket, set()
    while socket is not None and socket.is_linked:
        link = socket.links[0]
        if link.is_muted or not link.is_valid or socket.as_pointer() in seen:   # (invalid: red; a reroute loop)
            break
        seen.add(socket.as_pointer())
        node, out = link.from_node, link.from_socket
        if node.type in CONSTANT_NODES and not node.mute and first.type not in ("SHADER", "VECTOR"):
            return None, None, out
        if node.type == "VALTORGB" and not node.mute and first.type not in ("SHADER", "VECTOR"):
            computed = _constant_ramp(node, out)
            if computed is not None:
                return None, None, computed
        if node.type != "REROUTE" and not node.mute:
            return node, out, None
        fed, socket = socket, _through(node, out)
        if socket is None:                 # a muted node passing nothing: the input it fed
            socket = fed                   # stays unlinked (a reroute's gives 0)
            break
    return None, None, first if socket is first else None


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
