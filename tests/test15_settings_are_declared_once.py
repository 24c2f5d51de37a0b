"""Every render setting comes from the core's one table (core/src/settings.h):
RenderSettings, the core's validation and the CLI options all follow it.
(The Blender side is tests/blender/test_b00_registration.py.)"""
import math

import numpy as np
import pytest

import gridwalk as gw
from gridwalk import _core
from gridwalk.cli import build_parser
from gridwalk.settings import SCHEMA

NUMERIC = [s for s in SCHEMA if s.kind in ("int", "float")]


def test_render_settings_fields_and_defaults_are_the_tables():
    fields = gw.RenderSettings.__dataclass_fields__
    assert list(fields) == [s.name for s in SCHEMA]
    defaults = gw.RenderSettings()
    core = _core.RenderSettings()
    for s in SCHEMA:
        assert getattr(defaults, s.name) == s.default, s.name
        if s.kind == "float":
            assert getattr(core, s.name) == np.float32(s.default) or getattr(core, s.name) == s.default, s.name
        elif s.kind in ("int", "bool"):
            assert getattr(core, s.name) == s.default, s.name
    assert gw.RenderSettings().to_core() is not None


@pytest.mark.parametrize("s", NUMERIC, ids=[s.name for s in NUMERIC])
def test_the_core_accepts_each_limit_and_refuses_just_beyond_it(s):
    def at(value):
        return gw.RenderSettings(**{s.name: int(value) if s.kind == "int" else value})

    at(s.min).to_core()
    if math.isfinite(s.max):
        at(s.max).to_core()
    below = s.min - 1 if s.kind == "int" else float(np.nextafter(np.float32(s.min), np.float32(-np.inf)))
    with pytest.raises(ValueError, match=rf"RenderSettings\.{s.name} must be in \["):
        at(below).to_core()
    if math.isfinite(s.max):
        above = s.max + 1 if s.kind == "int" else float(np.nextafter(np.float32(s.max), np.float32(np.inf)))
        with pytest.raises(ValueError, match=rf"RenderSettings\.{s.name} must be in \["):
            at(above).to_core()


@pytest.mark.parametrize("name, value, message", [
    ("mailboxes", "no", "must be True or False"),
    ("aa_samples", 2.5, "must be an integer"),
    ("aa_samples", True, "must be a number"),
    ("threads", 2**31, r"must be in \[0, 1024\]"),
    ("max_cells", 2**64, r"must be in \[1, "),
    ("tile_size", 2**40, r"must be in \[1, 4096\]"),
    ("seed", -1, r"must be in \[0, "),
    ("filter_width", 1e39, "does not fit a float32"),
    ("grid_density", float("nan"), "must be in"),
    ("aa", "supersampled", "must be one of"),
    ("region", (0, 0, 2**31, 4), "x, y >= 0 and w, h >= 1"),
    ("region", (0, 0, 4), "4 integers"),
])
def test_values_are_checked_not_coerced(name, value, message):
    with pytest.raises(ValueError, match=rf"RenderSettings\.{name} .*{message}|RenderSettings\.{name} {message}"):
        gw.RenderSettings(**{name: value}).to_core()


def test_enum_choices_are_the_cores():
    for s in SCHEMA:
        if s.kind == "enum":
            core_enum = getattr(_core, s.enum_type)
            assert [getattr(core_enum, cid).name for cid in s.ids] == list(s.ids)
            assert s.default in s.ids


def test_the_cli_has_one_option_per_setting_with_the_tables_choices():
    render = build_parser()._subparsers._group_actions[0].choices["render"]
    options = {a.dest: a for a in render._actions if a.dest in {s.name for s in SCHEMA}}
    assert set(options) == {s.name for s in SCHEMA}
    for s in SCHEMA:
        assert (tuple(options[s.name].choices) if options[s.name].choices else ()) == s.ids, s.name
        assert s.help.replace("%", "%%")[:30] in options[s.name].help, s.name


def test_a_host_default_differs_only_with_a_reason():
    differing = [s for s in SCHEMA if s.host_default is not None]
    for s in differing:
        assert s.host_default != s.default and len(s.host_default_reason) > 20, s.name
        s.check(s.host_default)            # and is itself a valid value
