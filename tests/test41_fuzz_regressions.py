"""Every crash the fuzzers (tests/fuzz) found, kept as a regression test.

Each input file under tests/fuzz/regressions/ goes through the fuzz target
(tests/fuzz/harness.py: load, build the Scene, render 8 x 8) and must end in
a clean refusal (SceneFileError / ValueError) or an image. The core-level
cause of each crash is also tested directly through the Scene API.

Every case runs in its own Python process, so that a crash in the native core
fails that one test instead of killing the test session; the child inherits
the environment, so under the sanitizer run of test83 it uses the ASan core.
"""
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

FUZZ = Path(__file__).resolve().parent / "fuzz"
REGRESSIONS = sorted(p for p in (FUZZ / "regressions").iterdir() if p.suffix in (".nff", ".ply"))
API_REGRESSIONS = sorted((FUZZ / "regressions").glob("api_*.bin"))
SANITIZER_MARKS = ("runtime error:", "AddressSanitizer", "LeakSanitizer")


def run_isolated(code: str, timeout=120):
    """Run `code` in a fresh interpreter with tests/fuzz on sys.path; fail on a
    non-zero exit (a signal shows as a negative code) or a sanitizer report."""
    proc = subprocess.run([sys.executable, "-W", "ignore", "-c", code], capture_output=True, text=True,
                          timeout=timeout, env={**os.environ, "PYTHONFAULTHANDLER": "1"},
                          cwd=str(FUZZ))
    output = (proc.stdout + proc.stderr)[-4000:]
    assert proc.returncode == 0, f"exit code {proc.returncode}:\n{output}"
    assert not any(m in output for m in SANITIZER_MARKS), output
    return proc.stdout


def test_there_are_regression_inputs():
    assert REGRESSIONS, "tests/fuzz/regressions/ is empty"


# What each regression input must give: "refused" (a clean SceneFileError or
# ValueError) or "rendered" (an image). A new regression file states its outcome here.
EXPECTED = {
    "grid_overflowing_extent.nff": "refused",    # a sphere spanning 6e38: beyond the core's +-1e30
    "grid_subnormal_extent.nff": "rendered",     # a point sphere is a valid scene
    # a PLY header line holding only 0x1e: str.split() took it for whitespace (IndexError)
    "ply_header_line_of_a_record_separator.ply": "refused",
}


def test_every_regression_input_states_its_expected_outcome():
    assert {p.name for p in REGRESSIONS} == set(EXPECTED)


# Inputs of the API fuzzer (tests/fuzz/api_harness.py) that found a wrong
# answer: the structure and brute force disagreed. Replayed, every ray query
# in them must agree with brute force again (the harness raises WrongResult
# otherwise), with no crash. Each states what must happen to it, so that an
# input that stops reaching the comparison (refused earlier) is noticed:
# "compared" (at least one ray query agreed with brute force) or "scene
# refused" (the Scene that gave the wrong answer is refused with a clean error).
API_EXPECTED = {
    # rays from 1e30 whose float t cannot order the scene's hits (now misses for every structure)
    "api_ray_from_1e30_unresolved_t.bin": "compared",
    # a 1e-45-high cone whose quadratic reported a hit 4 units away (now refused)
    "api_cone_flatter_than_its_radii.bin": "scene refused",
    # a ray from 1e30 passing 180 units beside the scene, "hit" by brute
    # force's quadratic (rays that miss the scene's box are now misses before any test)
    "api_ray_missing_the_box_from_1e30.bin": "compared",
    # complex instance_matrices, which raised a TypeError (now refused with a ValueError)
    "api_complex_instance_matrices.bin": "scene refused",
}


def test_every_api_regression_input_states_its_expected_outcome():
    assert {p.name for p in API_REGRESSIONS} == set(API_EXPECTED)


@pytest.mark.parametrize("path", API_REGRESSIONS, ids=[p.name for p in API_REGRESSIONS])
def test_api_fuzz_regression_agrees_with_brute_force(path):
    out = run_isolated(textwrap.dedent(f"""
        import json
        import api_harness
        from pathlib import Path
        api_harness.run_bytes(Path({str(path)!r}).read_bytes())
        print(json.dumps(api_harness.COUNTS))
    """))
    counts = json.loads(out.strip().splitlines()[-1])
    compared = counts.get("ray queries that agreed with brute force", 0)
    if API_EXPECTED.get(path.name) == "compared":
        assert compared >= 1, counts
    else:
        assert API_EXPECTED.get(path.name) == "scene refused"
        assert counts.get("Scene() with Camera/Light/Material: refused", 0) >= 1, counts


def test_there_are_api_regression_inputs():
    assert len(API_REGRESSIONS) >= 3


@pytest.mark.parametrize("path", REGRESSIONS, ids=[p.name for p in REGRESSIONS])
def test_fuzz_regression_input_gives_its_expected_outcome(path):
    out = run_isolated(textwrap.dedent(f"""
        import harness
        image = harness.run_file({str(path)!r}, {path.suffix!r})
        print("refused" if image is None else "rendered")
    """))
    assert out.strip().splitlines()[-1] == EXPECTED.get(path.name)


# The core-level causes, through the public API (found by the NFF fuzzer seeds).
SCENE_CASES = {
    # A scene whose whole extent is zero or subnormal: the grid's padding
    # underflows, 1 / cell size is inf and cell indices become int(NaN).
    "point_sphere_at_origin": "dict(sphere_centers=[[0, 0, 0]], sphere_radii=[0.0])",
    "subnormal_sphere": "dict(sphere_centers=[[1e-40, -1e-40, 1e-40]], sphere_radii=[1e-45])",
    "subnormal_triangle": "dict(vertices=[[0, 0, 0], [1e-45, 0, 0], [0, 1e-45, 0]], triangles=[[0, 1, 2]])",
    # A scene whose extent overflows float32 although every value is finite.
    "huge_sphere": "dict(sphere_centers=[[0, 0, 0]], sphere_radii=[3e38])",
    "huge_triangle": "dict(vertices=[[-3e38, 0, 0], [3e38, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]])",
    "huge_cone": "dict(cylinder_base=[[0, 0, 0]], cylinder_apex=[[0, 0, 1]], cylinder_base_radius=[3e38], "
                 "cylinder_apex_radius=[1.0])",
}
# A point (or subnormal speck) is a valid scene and must render; a scene whose
# bounding box is not representable may instead be refused with ValueError.
MUST_BUILD = {"point_sphere_at_origin", "subnormal_sphere", "subnormal_triangle"}


@pytest.mark.parametrize("name", sorted(SCENE_CASES))
def test_grid_build_on_degenerate_extents_does_not_crash(name):
    out = run_isolated(textwrap.dedent(f"""
        import numpy as np
        import gridwalk as gw
        try:
            scene = gw.Scene(**{SCENE_CASES[name]}, camera=gw.Camera(width=8, height=8))
        except ValueError as err:
            print("refused:", err)
        else:
            info = scene.grid_info()
            assert info["cells"] >= 1, info
            image = gw.render(scene, gw.RenderSettings(threads=1))
            o = np.array([[0, -10, 0], [0, 0, -10], [1, 2, 3]], np.float32)
            d = np.array([[0, 1, 0], [0, 0, 1], [-1, -2, -3]], np.float32)
            g, n = scene.intersect(o, d), scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
            assert np.array_equal(g.t, n.t), (g.t, n.t)
            print("rendered", image.shape)
    """))
    if name in MUST_BUILD:
        assert "rendered" in out, out
