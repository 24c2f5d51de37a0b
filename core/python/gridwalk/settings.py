"""Render settings, derived from the one declaration in the core.

Every setting is declared once, as a row of GW_RENDER_SETTINGS in
core/src/settings.h: name, type, default, limits, group, label, help and (for
enums) the choices. This module turns that table (`_core.settings_schema()`)
into `SCHEMA`, a tuple of `Setting`, and into the `RenderSettings` dataclass;
the CLI options (cli.py) and the Blender properties and panels
(blender_addon/properties.py, ui.py) are built from `SCHEMA` as well.

Values are checked, never coerced: a setting takes values of its own kind
(`mailboxes="no"` is an error, not True), integers must fit the core's type,
floats are rounded to the core's precision *before* the core checks their
limits, so a value the core stores is a value it accepts.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import struct
from dataclasses import asdict, dataclass, fields

import numpy as np

from . import _core

# Ranges of the core's integer types (the core's checked limits lie within).
_INT_RANGES = {"int32": (-2**31, 2**31 - 1), "uint32": (0, 2**32 - 1), "uint64": (0, 2**64 - 1)}


@dataclass(frozen=True)
class Setting:
    """One row of the core's settings table."""
    name: str
    ctype: str           # bool, int32, uint32, uint64, float32, float64, enum, region
    default: object
    min: float
    max: float
    group: str           # acceleration, performance, sampling, lights, lens, host
    when: str            # "aa=adaptive", "shadow!=hard", or "" (always relevant)
    label: str
    help: str
    choices: tuple = ()  # enums: ((id, label, help), ...)
    enum_type: str = ""  # enums: the core's enum (gridwalk._core.<enum_type>)
    host_default: object = None       # a host's (Blender's) default where it differs ...
    host_default_reason: str = ""     # ... and why

    @functools.cached_property
    def kind(self) -> str:
        """The Python kind: bool, int, float, enum or region."""
        if self.ctype.startswith(("int", "uint")):
            return "int"
        if self.ctype.startswith("float"):
            return "float"
        return self.ctype

    @functools.cached_property
    def ids(self) -> tuple:
        return tuple(c[0] for c in self.choices)

    def relevant(self, values) -> bool:
        """Whether this setting matters, given the other settings (`values[name]`)."""
        if not self.when:
            return True
        negate = "!=" in self.when
        other, want = self.when.replace("!=", "=").split("=")
        return (values[other] == want) != negate

    def describe(self) -> str:
        """Help with the limits and (for dependent settings) when it applies."""
        text = self.help
        if self.kind in ("int", "float"):
            hi = "inf" if math.isinf(self.max) else f"{self.max:g}"
            text += f"; [{self.min:g}, {hi}]"
        if self.when:
            text += f"; used when {self.when}"
        return text

    def check(self, value):
        """`value` as the core stores it (an int, float rounded to the core's
        precision, enum id, or 4-tuple), or ValueError naming the setting."""
        kind = self.kind
        if kind == "bool":
            if value is True or value is False:
                return value
            if not isinstance(value, np.bool_):
                raise ValueError(f"RenderSettings.{self.name} must be True or False, got {value!r}")
            return bool(value)
        if kind == "enum":
            if value not in self.ids:
                raise ValueError(f"RenderSettings.{self.name} must be one of {list(self.ids)}, got {value!r}")
            return value
        if kind == "region":
            return _check_region(f"RenderSettings.{self.name}", value)
        if type(value) is not int and type(value) is not float and (
                isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real)):
            raise ValueError(f"RenderSettings.{self.name} must be a number, got {value!r}")
        if kind == "int":
            if type(value) is not int:
                if not isinstance(value, numbers.Integral):
                    raise ValueError(f"RenderSettings.{self.name} must be an integer, got {value!r}")
                value = int(value)
            lo, hi = _INT_RANGES[self.ctype]
            if not lo <= value <= hi:
                raise ValueError(f"RenderSettings.{self.name} must be in [{self.min:g}, {self.max:g}], got {value}")
            return value
        value = float(value)
        if self.ctype != "float32":
            return value
        stored = _FLOAT32.unpack(_FLOAT32.pack(value))[0]   # rounded to the nearest float32, as the core stores it
        if math.isinf(stored) and math.isfinite(value):
            raise ValueError(f"RenderSettings.{self.name} = {value!r} does not fit a float32")
        return stored


_FLOAT32 = struct.Struct("f")


def _check_region(where, value):
    if value is None:
        return (0, 0, 0, 0)
    try:
        r = tuple(value)
    except TypeError:
        raise ValueError(f"{where} must be (x, y, w, h) or None, got {value!r}") from None
    if len(r) != 4 or not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in r):
        raise ValueError(f"{where} must be 4 integers (x, y, w, h), got {value!r}")
    r = tuple(int(v) for v in r)
    if min(r) < 0 or r[2] < 1 or r[3] < 1 or max(r) > 2**31 - 1:
        raise ValueError(f"{where} must be (x, y, w, h) with x, y >= 0 and w, h >= 1, got {value!r}")
    return r


def _host_value(row, text):
    if text is None:
        return None
    if row["ctype"] == "bool":
        return {"true": True, "false": False}[text]
    return int(text) if row["ctype"].startswith(("int", "uint")) else \
        float(text) if row["ctype"].startswith("float") else text


def _schema() -> tuple:
    host = _core.host_defaults()
    rows = []
    for row in _core.settings_schema():
        row = dict(row)
        if row["ctype"] == "float32":   # the shortest decimal of the core's float32 default
            row["default"] = float(str(np.float32(row["default"])))
        choices = tuple(tuple(c) for c in row.pop("choices", ()))
        value, reason = host.get(row["name"], (None, ""))
        rows.append(Setting(choices=choices, host_default=_host_value(row, value), host_default_reason=reason,
                            **row))
    return tuple(rows)


SCHEMA = _schema()
BY_NAME = {s.name: s for s in SCHEMA}


def _docstring() -> str:
    lines = ["Every setting of a render (declared once, in core/src/settings.h).", ""]
    for s in SCHEMA:
        line = f"{s.name}: {s.describe()}."
        if s.choices:
            line += " " + "; ".join(f'"{cid}": {chelp}' for cid, _, chelp in s.choices) + "."
        lines.append(line)
    return "\n".join(lines)


def _replace(self, **changes) -> "RenderSettings":
    unknown = set(changes) - {f.name for f in fields(self)}
    if unknown:
        raise ValueError(f"unknown render settings: {sorted(unknown)}")
    return RenderSettings(**{**asdict(self), **changes})


# Per setting: its name, its check, and the core's enum type (None for other kinds).
_CONVERSIONS = tuple((s.name, s.check, getattr(_core, s.enum_type) if s.enum_type else None) for s in SCHEMA)


def _to_core(self) -> "_core.RenderSettings":
    """The core's struct, every value checked (ValueError names the setting)."""
    core = _core.RenderSettings()
    for name, check, enum in _CONVERSIONS:
        value = check(getattr(self, name))
        setattr(core, name, getattr(enum, value) if enum is not None else value)
    core.validate()
    return core


RenderSettings = dataclasses.make_dataclass(
    "RenderSettings",
    [(s.name, {"bool": bool, "int": int, "float": float, "enum": str, "region": "tuple | None"}[s.kind],
      dataclasses.field(default=s.default)) for s in SCHEMA],
    namespace={"replace": _replace, "to_core": _to_core, "__doc__": _docstring(), "__module__": __name__},
)
