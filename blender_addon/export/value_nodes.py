"""The nodes between an Image Texture and a shader input, folded into the
texture's channel, gain, bias and clamp (gridwalk.Texture).

Models exported by Blender's glTF importer, and many hand-made materials,
put a few nodes there: a Separate Color picks the green channel of a packed
occlusion-roughness-metallic image, a Math node multiplies it by the
material's roughness factor, a Mix multiplies the base colour image by a
tint, an Invert turns a gloss map into roughness. Each of these is an affine
map of the value, channel by channel, so a chain of them is one:
  Separate Color (RGB; Separate RGB in 3.x)  one channel, as grey
  Math: Multiply, Add, Subtract, Divide (by a constant), Multiply Add
  Mix (Color or Float; MixRGB in 3.x): Mix, Multiply, Add, Subtract
  Invert                                      v (1 - f) + (1 - v) f
and one Color Ramp among them, its Color output, or one Math Less Than or Greater
Than of a constant threshold in (0, 1], which is a Constant ramp (StepRamp: the glTF
importer's alpha cut-off) (the nodes after it adjust
the ramp's colour: gridwalk.Texture's ramp_* fields), with every other input of the node constant (unlinked, or an RGB or Value
node). A colour entering a float input becomes its luminance, as Blender
converts it. A node's Clamp (Math's, Mix's Clamp Result) is kept where it is
the last step (Mix's only in Color mode, as Cycles reads it); anything else
(an earlier clamp, a linked factor, another node or operation, a value
beyond float range) leaves the input at its default value, named in the
material's warning.
"""
from __future__ import annotations

import types

import numpy as np

from .node_links import _source, input_value
from .object_info import OUTPUTS as OBJECT_INFO_OUTPUTS
from .textures import PROCEDURAL_NODES

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
FLOAT_MAX = float(np.finfo(np.float32).max)   # the core keeps float32
SEPARATE = {"SEPARATE_COLOR": ("Red", "Green", "Blue"), "SEPRGB": ("R", "G", "B")}


class Value:
    """The value so far: the image's colour (or alpha: `single`), channel, gain, bias, clamp."""

    def __init__(self, alpha: bool, vector: bool = False):
        self.single = alpha                # one number (alpha, a channel, a luminance) broadcast to RGB
        self.vector = vector               # a vector (a Voronoi's Position): a number is its average
        self.channel = -1
        self.gain, self.bias = np.ones(3), np.zeros(3)
        self.clamp = False

    def affine(self, gain, bias, what):
        if self.clamp:
            raise Unread(f"{what} after a clamp")
        self.gain, self.bias = self.gain * gain, self.bias * gain + bias

    def to_float(self, what):
        """A colour entering a float input: its luminance (a vector: its average, as Cycles converts it)."""
        if self.single:
            if self.clamp and np.ptp(self.gain) + np.ptp(self.bias) > 0:
                raise Unread(f"{what} of a clamped colour")
            self.gain, self.bias = np.full(3, LUMINANCE @ self.gain), np.full(3, LUMINANCE @ self.bias)
            return
        if self.clamp or np.ptp(self.gain) > 0 or np.ptp(self.bias) > 0:
            raise Unread(f"{what} of a tinted colour")
        self.channel, self.single = 4 if self.vector else 3, True

    def pick(self, k):
        if not self.single:
            self.channel, self.single = k, True
        self.gain, self.bias = np.full(3, self.gain[k]), np.full(3, self.bias[k])

    def fields(self) -> dict:
        if not np.all(np.abs(np.concatenate([self.gain, self.bias])) <= FLOAT_MAX):   # (NaN fails too)
            raise Unread("a gain or offset beyond float range")
        return {"channel": self.channel, "gain": tuple(float(x) for x in self.gain),
                "bias": tuple(float(x) for x in self.bias), "clamp": self.clamp}


class Unread(Exception):
    """A step the fold cannot take: the message names it. quiet: nothing to add
    to the warning when it is the first node (one the fold does not read, or
    a calculation that no image feeds)."""

    def __init__(self, message, quiet=False):
        super().__init__(message)
        self.quiet = quiet


def _linked(socket) -> bool:
    return _source(socket)[0] is not None


def _enabled(node, *identifiers):
    return [next(s for s in node.inputs if s.identifier == i) for i in identifiers]


def mix_inputs(node):
    """(factor, A, B) input sockets of a Mix node mixing colours or floats (MixRGB in 3.x), or None."""
    if node.type == "MIX":
        suffix = {"RGBA": "Color", "FLOAT": "Float"}.get(node.data_type)
        return None if suffix is None else _enabled(node, "Factor_Float", f"A_{suffix}", f"B_{suffix}")
    if node.type == "MIX_RGB":
        return node.inputs["Fac"], node.inputs["Color1"], node.inputs["Color2"]
    return None


def _chain_input(node):
    """(the node's input the chain comes through, its other inputs by role) or Unread."""
    kind = node.type
    if kind in SEPARATE:
        return node.inputs[0], {}
    if kind == "INVERT":
        if _linked(node.inputs["Fac"]):
            raise Unread(f"{node.name!r} with a linked factor")
        return node.inputs["Color"], {"fac": node.inputs["Fac"]}
    if kind == "MATH":
        used = node.inputs[:3] if node.operation == "MULTIPLY_ADD" else node.inputs[:2]
    elif kind in ("MIX", "MIX_RGB"):
        sockets = mix_inputs(node)
        if sockets is None:
            raise Unread(f"{node.name!r} mixing {node.data_type.lower()}s")
        fac, *used = sockets
    else:
        raise Unread(f"{node.name!r} ({node.bl_idname})", quiet=True)
    linked = [s for s in used if _linked(s)]
    if len(linked) != 1:
        raise Unread(f"{node.name!r} with {len(linked)} linked inputs", quiet=not linked)
    others = {"slot": used.index(linked[0]), "used": used}
    if kind in ("MIX", "MIX_RGB"):
        if _linked(fac):
            raise Unread(f"{node.name!r} with a linked factor")
        others["fac"] = fac
    return linked[0], others


def _apply(value: Value, node, out, others):
    kind, what = node.type, repr(node.name)
    if kind in SEPARATE:
        if kind == "SEPARATE_COLOR" and node.mode != "RGB":
            raise Unread(f"{what} in {node.mode} mode")
        value.pick(SEPARATE[kind].index(out.name))
        return
    if kind == "INVERT":
        f = float(input_value(others["fac"]))
        value.affine(np.full(3, 1.0 - 2.0 * f), np.full(3, f), what)
        value.vector = False     # (a vector into a colour input is a colour: a number of it, its luminance)
        return
    slot, used = others["slot"], others["used"]
    consts = [None if i == slot else input_value(s) for i, s in enumerate(used)]
    if kind == "MATH" or (kind == "MIX" and node.data_type == "FLOAT"):
        value.to_float(what)
    if kind == "MATH":
        gain, bias = _math(node.operation, slot, consts, what)
        value.affine(np.full(3, gain), np.full(3, bias), what)
        if node.use_clamp:
            value.clamp = True
        return
    f = float(input_value(others["fac"]))
    if kind == "MIX_RGB" or getattr(node, "clamp_factor", True):
        f = min(max(f, 0.0), 1.0)
    k = np.broadcast_to(np.asarray(consts[1 - slot], np.float64).reshape(-1)[:3], 3)
    floats = kind == "MIX" and node.data_type == "FLOAT"     # (no blend modes; Clamp Result is Color's)
    gain, bias = _mix("MIX" if floats else node.blend_type, slot, f, k, what)
    value.affine(gain, bias, what)
    value.vector = value.vector and floats
    if (kind == "MIX" and not floats and node.clamp_result) or (kind == "MIX_RGB" and node.use_clamp):
        value.clamp = True


def _math(operation, slot, consts, what):
    """(gain, bias) of a Math node on its input `slot`, the others constant."""
    other = [float(c) for c in consts if c is not None]
    if operation == "MULTIPLY":
        return other[0], 0.0
    if operation == "ADD":
        return 1.0, other[0]
    if operation == "SUBTRACT":
        return (1.0, -other[0]) if slot == 0 else (-1.0, other[0])
    if operation == "DIVIDE" and slot == 0:
        return (1.0 / other[0], 0.0) if other[0] != 0 else (0.0, 0.0)   # (Blender's safe divide: 0)
    if operation == "MULTIPLY_ADD":
        return (other[0], other[1]) if slot < 2 else (1.0, other[0] * other[1])
    raise Unread(f"{what} ({operation.replace('_', ' ').title()})")


def _mix(blend, slot, f, k, what):
    """(gain, bias) per channel of a Mix on its input A (slot 0) or B (slot 1), the other K."""
    if blend == "MIX":
        return (np.full(3, 1.0 - f), k * f) if slot == 0 else (np.full(3, f), k * (1.0 - f))
    if blend == "MULTIPLY":
        return (1.0 - f + f * k, np.zeros(3)) if slot == 0 else (k * f, k * (1.0 - f))
    if blend == "ADD":
        return (np.ones(3), k * f) if slot == 0 else (np.full(3, f), k)
    if blend == "SUBTRACT":
        return (np.ones(3), -k * f) if slot == 0 else (np.full(3, -f), k)
    raise Unread(f"{what} ({blend.replace('_', ' ').title()})")


TEXTURE_NODES = ("TEX_IMAGE", "ATTRIBUTE", "OBJECT_INFO") + PROCEDURAL_NODES   # the nodes gridwalk.Texture models
# The outputs that are one number (the texture's alpha, Texture.use_alpha), by node type;
# 5.0 names a Fac output Factor.
SINGLE_OUTPUTS = {"TEX_IMAGE": ("Alpha",), "TEX_NOISE": ("Fac", "Factor"), "TEX_VORONOI": ("Distance", "W", "Radius"),
                  "TEX_WAVE": ("Fac", "Factor"), "TEX_MAGIC": ("Fac", "Factor"), "TEX_BRICK": ("Fac", "Factor"),
                  "TEX_WHITE_NOISE": ("Value",), "TEX_MUSGRAVE": ("Fac",), "ATTRIBUTE": ("Fac", "Factor"),
                  "OBJECT_INFO": ("Random", "Alpha", "Object Index")}


def is_vector(node, output: str) -> bool:
    """Whether the texture node's output is a vector (Cycles reads it as a number by its average)."""
    return (node.type == "TEX_VORONOI" and output == "Position") or (node.type == "ATTRIBUTE" and output == "Vector") \
        or (node.type == "OBJECT_INFO" and output == "Location")


class StepRamp:
    """A Math node's Less Than or Greater Than of the value and a constant threshold in (0, 1], as
    the Color Ramp it equals (Constant, grey 1 on the side the comparison holds, 0 on the other):
    the glTF importer's alpha cut-off (Alpha Mode Mask: 1 - (alpha < cutoff)). It reads like a
    Color Ramp node (color_ramp.ramp_stops); the value at the threshold itself falls as the
    comparison puts it (the stop above it lies one float step up), but a value within the ramp
    table's 1/255 of it may land on the other side than Cycles' exact comparison puts it."""

    def __init__(self, node, slot: int, threshold: float):
        below = (node.operation == "LESS_THAN") == (slot == 0)      # 1 below the threshold
        low, high = (1.0, 0.0) if below else (0.0, 1.0)
        if not below:   # (1 only above it: the value at the threshold itself reads the stop below)
            threshold = float(np.nextafter(np.float32(threshold), np.float32(np.inf)))
        element = lambda position, v: types.SimpleNamespace(position=position, color=(v, v, v, 1.0))
        self.name = node.name
        self.color_ramp = types.SimpleNamespace(elements=[element(0.0, low), element(threshold, high)],
                                                interpolation="CONSTANT", color_mode="RGB")


THRESHOLDS = ("LESS_THAN", "GREATER_THAN")


def _step(node, steps, ramp):
    """(StepRamp, the input the chain comes through) of a Math threshold node, or Unread."""
    if ramp is not None:
        raise Unread(f"{node.name!r} after a Color Ramp or another threshold")
    chain, others = _chain_input(node)
    threshold = input_value(others["used"][1 - others["slot"]])
    threshold = float(threshold if not isinstance(threshold, tuple) else LUMINANCE @ np.asarray(threshold[:3]))
    if not 0.0 < threshold <= 1.0:      # (the ramp clamps its input to [0, 1]; at 0 it would differ on 0 itself)
        raise Unread(f"{node.name!r} (a threshold of {threshold:g}, outside (0, 1])")
    return StepRamp(node, others["slot"], threshold), chain


def image_through_nodes(socket):
    """(image or procedural texture node (TEXTURE_NODES), its output's name, Texture fields, Color Ramp
    node or None) for an input fed by a texture through the nodes above, and through at most one
    Color Ramp's Color output, with such nodes before and after it (those after it become the
    Texture's ramp_* fields); (None, None, why not, None) for any other chain."""
    steps, after, ramp, fed = [], None, None, socket    # fed: the input the steps before the ramp lead to
    try:
        node, out = _source(socket)
        while node is not None and node.type not in TEXTURE_NODES:
            if node.type == "VALTORGB":
                if ramp is not None or out.name != "Color":
                    raise Unread(f"{node.name!r} after another Color Ramp" if ramp is not None
                                 else f"the {out.name} output of {node.name!r}")
                ramp, after, steps, fed = node, steps, [], node.inputs["Fac"]
                node, out = _source(fed)
                continue
            if node.type == "MATH" and node.operation in THRESHOLDS:     # (a Constant ramp: StepRamp)
                ramp, fed = _step(node, steps, ramp)
                after, steps = steps, []
                node, out = _source(fed)
                continue
            chain, others = _chain_input(node)
            steps.append((node, out, others))
            node, out = _source(chain)
        if node is None:
            last = steps[-1][0].name if steps else ramp.name if ramp is not None else None
            raise Unread(f"{last!r} fed by no image" if last else "no node")
        if node.type == "OBJECT_INFO" and out.name not in OBJECT_INFO_OUTPUTS:
            raise Unread(f"the {out.name} output of {node.name!r} (Object Info's "
                         f"{', '.join(OBJECT_INFO_OUTPUTS)} are read)")
        value = Value(out.name in SINGLE_OUTPUTS.get(node.type, ()), vector=is_vector(node, out.name))
        for step in reversed(steps):
            _apply(value, *step)
        if value.vector and not value.single and fed.type == "VALUE":   # (a vector into a number)
            value.to_float("a vector")
        fields = value.fields()
        if after:
            coloured = Value(False)              # (the ramp's colour)
            for step in reversed(after):
                _apply(coloured, *step)
            fields.update({f"ramp_{k}": v for k, v in coloured.fields().items()})
        return node, out.name, fields, ramp
    except Unread as problem:
        return None, None, "" if problem.quiet and not steps and ramp is None else str(problem), None
