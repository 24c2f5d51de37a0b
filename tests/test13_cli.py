"""The command line: python -m gridwalk {demo, render, validate, info}, run in subprocesses."""
import dataclasses
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from gridwalk import RenderSettings
from gridwalk.validate import compare

SPD_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "scenes" / "spd"
needs_spd = pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")


def gridwalk(*args, timeout=60):
    return subprocess.run([sys.executable, "-m", "gridwalk", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout)


def assert_non_trivial_png(path, size):
    image = np.asarray(Image.open(path).convert("RGB"))
    assert image.shape == (size[1], size[0], 3)
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 50, "the image is (nearly) one colour"


def write_ply(path, n=6):
    """An ASCII PLY of a bumpy n x n height field (2 (n-1)^2 triangles)."""
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
    z = 0.3 * np.sin(3 * x) * np.cos(2 * y)
    quads = [(r * n + c, r * n + c + 1, (r + 1) * n + c + 1, (r + 1) * n + c)
             for r in range(n - 1) for c in range(n - 1)]
    lines = ["ply", "format ascii 1.0", f"element vertex {n * n}", "property float x", "property float y",
             "property float z", f"element face {len(quads)}", "property list uchar int vertex_indices",
             "end_header"]
    lines += [f"{a} {b} {c}" for a, b, c in zip(x.ravel(), y.ravel(), z.ravel())]
    lines += ["4 " + " ".join(map(str, q)) for q in quads]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_demo_quick_writes_a_png_and_a_one_line_summary(tmp_path):
    out = tmp_path / "demo.png"
    run = gridwalk("demo", "-o", out, "--quick")
    assert run.returncode == 0, run.stderr
    assert_non_trivial_png(out, (256, 256))
    summary = run.stdout.strip().splitlines()
    assert len(summary) == 1 and "Mrays/s" in summary[0] and " s," in summary[0]
    assert "%" in run.stderr                      # the progress bar


@needs_spd
def test_render_nff_writes_png_npy_and_the_statistics_summary(tmp_path):
    png, npy = tmp_path / "balls.png", tmp_path / "balls.npy"
    run = gridwalk("render", SPD_DIR / "balls_s2.nff", "-o", png, "--npy", npy, "--width", 96, "--height", 64)
    assert run.returncode == 0, run.stderr
    assert_non_trivial_png(png, (96, 64))
    rgba = np.load(npy)
    assert rgba.shape == (64, 96, 4) and rgba.dtype == np.float32
    for expected in ("primary 6.14 k", "shadow", "secondary", "Mrays/s", "intersection tests", "cells",
                     "grid", "refs", "KiB", "built in"):
        assert expected in run.stdout, expected
    assert "100%" in run.stderr


def test_an_upper_case_npy_suffix_is_written_under_the_name_given(tmp_path):
    out = tmp_path / "image.NPY"
    run = gridwalk("demo", "-o", out, "--resolution", 16)
    assert run.returncode == 0, run.stderr
    assert out.is_file() and not (tmp_path / "image.NPY.npy").exists()
    assert np.load(out).shape[2] == 4


@needs_spd
def test_validate_refuses_more_rays_than_memory_holds():
    run = gridwalk("validate", SPD_DIR / "balls_s2.nff", "--rays", 10 ** 13)
    assert run.returncode == 2
    assert "--rays 10000000000000 needs an estimated" in run.stderr and "physical memory" in run.stderr
    assert "Traceback" not in run.stderr


def test_render_has_an_option_for_every_render_setting():
    run = gridwalk("render", "--help")
    assert run.returncode == 0
    for field in dataclasses.fields(RenderSettings):
        assert "--" + field.name.replace("_", "-") in run.stdout, field.name
    assert "{center,jittered,random,adaptive,sobol}" in run.stdout


@needs_spd
def test_render_settings_options_reach_the_renderer(tmp_path):
    out = tmp_path / "a.png"
    run = gridwalk("render", SPD_DIR / "balls_s1.nff", "-o", out, "--width", 20, "--height", 10,
                   "--aa", "jittered", "--aa-samples", 3, "--no-mailboxes", "--accel", "none", "--alpha")
    assert run.returncode == 0, run.stderr
    assert "primary 1.8 k" in run.stdout          # 3 x 3 samples for each of 200 pixels
    assert "grid " not in run.stdout               # accel none: no grid was built
    assert Image.open(out).mode == "RGBA"


def test_render_ply_frames_the_mesh(tmp_path):
    out = tmp_path / "mesh.png"
    run = gridwalk("render", write_ply(tmp_path / "mesh.ply"), "-o", out, "--width", 64, "--height", 64)
    assert run.returncode == 0, run.stderr
    rgb = np.asarray(Image.open(out).convert("RGB")).reshape(-1, 3)
    background = np.all(rgb == rgb[0], axis=1)     # the corner pixel is sky
    assert 0.1 < 1 - background.mean() < 0.95      # the mesh covers part of the view


def test_render_nff_with_a_cylinder(tmp_path):
    scene = tmp_path / "cyl.nff"
    scene.write_text("v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 32 32\n"
                     "b 0 0 0\nl 2 -4 3\nf 1 0.2 0.2 0.8 0 10 0 1\nc\n0 0 -1 0.4\n0 0 1 0.4\n")
    out = tmp_path / "cyl.npy"
    assert gridwalk("render", scene, "-o", out, "--quiet").returncode == 0
    alpha = np.load(out)[..., 3]
    assert alpha[16, 16] == 1 and alpha[16, 2] == 0 and alpha[16, 29] == 0


@pytest.mark.parametrize("case, content, message", [
    ("missing", None, "no such file"),
    ("malformed", "s 0 0\n", "scene.nff:1: 's' needs 4 numbers (x y z radius), but the file ends after 2"),
    ("unknown type", "solid\n", "expected .nff or .ply"),
])
def test_bad_scene_files_give_a_one_line_error_and_exit_2(tmp_path, case, content, message):
    path = tmp_path / ("scene.stl" if case == "unknown type" else "scene.nff")
    if content is not None:
        path.write_text(content)
    for command in (["render", path, "-o", tmp_path / "x.png"], ["info", path], ["validate", path]):
        run = gridwalk(*command)
        assert run.returncode == 2, (command, run.stderr)
        assert run.stderr.startswith("gridwalk: error: ") and message in run.stderr, run.stderr
        assert "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1


def test_a_device_given_as_the_scene_file_is_named_as_such():
    run = gridwalk("info", "/dev/null")
    assert run.returncode == 2 and run.stderr.strip() == (
        "gridwalk: error: /dev/null: not a regular file (a device or a pipe); give a scene file")


@needs_spd
@pytest.mark.parametrize("options, message", [
    (["--aa-samples", "0"], "aa_samples"),
    (["--grid-density", "-1"], "grid_density"),
    (["--width", "0"], "--width must be at least 1, got 0"),
    (["--width", "-3"], "--width must be at least 1, got -3"),    # (was "width must be >= 0", then 0 refused)
    (["--height", "0"], "--height must be at least 1, got 0"),
    (["-o", "out.jpg"], "must end in .png or .npy"),
    (["--npy", "also.png"], "also.png: output must end in .npy"),     # (was written as a PNG)
])
def test_bad_settings_give_a_one_line_error_and_exit_2(tmp_path, options, message):
    run = gridwalk("render", SPD_DIR / "balls_s1.nff", "-o", tmp_path / "x.png", *options)
    assert run.returncode == 2 and run.stderr.startswith("gridwalk: error: "), run.stderr
    assert message in run.stderr and "Traceback" not in run.stderr


def test_an_unwritable_output_is_refused_before_rendering(tmp_path):
    # It was found only after the whole render, which was lost.
    started = time.perf_counter()
    run = gridwalk("demo", "--resolution", "512", "-o", "/proc/self/demo.png")
    assert run.returncode == 2 and run.stderr.strip() == (
        "gridwalk: error: /proc/self/demo.png: cannot be written (No such file or directory)"), run.stderr
    assert "rendering" not in run.stderr and time.perf_counter() - started < 20
    existing = tmp_path / "kept.png"
    existing.write_bytes(b"old")                        # the check leaves an existing file as it was
    from gridwalk.cli import check_output
    check_output(existing)
    assert existing.read_bytes() == b"old"
    check_output(tmp_path / "new.png")
    assert not (tmp_path / "new.png").exists()


def test_an_image_beyond_the_memory_limit_is_refused_before_anything_is_built():
    # 16384 x 16384 passes the pixel limit and needed about 30 GB; nothing checked it
    from gridwalk.cli import check_memory, demo_scene
    from gridwalk.memory import SceneTooLarge
    with pytest.raises(SceneTooLarge, match=r"Rendering 16384x16384 needs an estimated 28(\.\d)? GiB of memory "
                                            r"\(.*images 28(\.\d)? GiB\), more than the limit of 1 GiB"):
        check_memory(demo_scene(1, 16384), RenderSettings(), limit=1 << 30)
    check_memory(demo_scene(1, 512), RenderSettings(), limit=1 << 30)


def test_the_farm_offers_no_region_option():
    # It was offered, and refused when given (the farm renders the whole image in tiles)
    run = gridwalk("farm", "--help")
    assert run.returncode == 0 and "--aa-samples" in run.stdout and "--region" not in run.stdout


def test_triangles_of_zero_area_are_named(tmp_path):
    """A PLY whose faces have zero area renders (nothing of them shows: no ray hits them) with a
    warning naming how many, as Blender's export names them; it rendered blank without a word."""
    flat = tmp_path / "flat.ply"
    lines = ["ply", "format ascii 1.0", "element vertex 4", "property float x", "property float y",
             "property float z", "element face 2", "property list uchar int vertex_indices", "end_header",
             "0 0 0", "1 0 0", "2 0 0", "0 1 0", "3 0 1 2", "3 0 1 3"]   # the first collinear, the second not
    flat.write_text("\n".join(lines) + "\n")
    run = gridwalk("render", flat, "-o", tmp_path / "flat.png", "--width", 16, "--height", 16, "--quiet")
    assert run.returncode == 0, run.stderr
    assert f"gridwalk: warning: {flat}: 1 of 2 triangles have zero area and are invisible" in run.stderr
    run = gridwalk("render", write_ply(tmp_path / "mesh.ply"), "-o", tmp_path / "mesh.png", "--width", 16,
                   "--height", 16, "--quiet")
    assert run.returncode == 0 and "zero area" not in run.stderr


def test_a_polygon_with_a_corner_on_a_side_gives_no_zero_area_triangle(tmp_path):
    # A 2 x 2 square with a corner in the middle of its first side: fanned from corner 0, its
    # first triangle had no area and the warning named it invisible, though the square rendered
    # whole. Fanned from the corner on the side, all three triangles have area.
    square = tmp_path / "square.ply"
    lines = ["ply", "format ascii 1.0", "element vertex 5", "property float x", "property float y",
             "property float z", "element face 1", "property list uchar int vertex_indices", "end_header",
             "0 0 0", "1 0 0", "2 0 0", "2 2 0", "0 2 0", "5 0 1 2 3 4"]
    square.write_text("\n".join(lines) + "\n")
    run = gridwalk("render", square, "-o", tmp_path / "square.png", "--width", 16, "--height", 16, "--quiet")
    assert run.returncode == 0 and "zero area" not in run.stderr, run.stderr
    from gridwalk.io import load_ply_mesh
    mesh = load_ply_mesh(square)
    p = mesh.vertices.astype(np.float64)[mesh.triangles]
    area = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2] / 2
    assert len(area) == 3 and np.all(area > 0.1) and area.sum() == pytest.approx(4.0)


def test_demo_refuses_a_resolution_of_zero(tmp_path):
    # 0 read as "not given": the full 512 x 512 render ran
    run = gridwalk("demo", "--resolution", "0", "-o", tmp_path / "demo.png")
    assert run.returncode == 2 and run.stderr.startswith("gridwalk: error: "), run.stderr
    assert "--resolution must be at least 1, got 0" in run.stderr and not (tmp_path / "demo.png").exists()


@needs_spd
def test_render_says_when_the_grid_density_was_reduced(tmp_path):
    run = gridwalk("render", SPD_DIR / "mount_s4.nff", "-o", tmp_path / "m.png", "--accel", "grid",
                   "--max-cells", 100, "--width", 16, "--height", 16)
    assert run.returncode == 0, run.stderr
    assert "4x4x4 = 64 cells" in run.stdout and "note" in run.stdout and "density reduced" in run.stdout


@needs_spd
def test_ctrl_c_cancels_the_render_and_exits_130(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "gridwalk", "render", SPD_DIR / "balls_s4.nff",
                             "-o", tmp_path / "x.png", "--aa", "jittered", "--aa-samples", "8"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    seen, deadline = b"", time.monotonic() + 30
    while b"rendering" not in seen and time.monotonic() < deadline:   # wait for the progress bar
        seen += os.read(proc.stderr.fileno(), 64)
    proc.send_signal(signal.SIGINT)
    start = time.monotonic()
    _, err = proc.communicate(timeout=20)
    assert proc.returncode == 130, err
    assert time.monotonic() - start < 5 and b"cancelled" in err
    assert not (tmp_path / "x.png").exists()


@needs_spd
def test_info_reports_counts_bounds_camera_and_grid():
    run = gridwalk("info", SPD_DIR / "mount_s4.nff")
    assert run.returncode == 0, run.stderr
    assert "512 triangles" in run.stdout and "4 spheres" in run.stdout and "0 cylinders" in run.stdout
    assert "1 lights" in run.stdout
    assert "bounds" in run.stdout and "eye (-1.6, 1.6, 1.7)" in run.stdout
    assert "adaptive grid: root " in run.stdout and " grids, " in run.stdout
    uniform = gridwalk("info", SPD_DIR / "mount_s4.nff", "--accel", "grid")
    assert "uniform grid: 17x17x16 = 4624 cells" in uniform.stdout


@needs_spd
def test_validate_agrees_with_embree_on_mount():
    run = gridwalk("validate", SPD_DIR / "mount_s4.nff", "--rays", 20000)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "512 triangles only" in run.stdout and "4 spheres" in run.stdout
    for kind in ("primary", "shadow", "random"):
        row = next(line for line in run.stdout.splitlines() if line.startswith(kind)).split()
        assert float(row[2]) == 100.0 and int(row[5]) == 0, row   # hit/miss %, mismatches
    assert "PASS" in run.stdout


def _hits(t, prim):
    t = np.asarray(t, np.float32)
    return type("Hits", (), {"t": t, "prim": np.asarray(prim, np.int32)})


def test_compare_fails_on_a_primitive_mismatch_but_not_on_a_tie():
    embree = {"tfar": np.array([1.0, 2.0, 3.0, np.inf]), "primID": np.array([0, 1, 2, -1])}
    tie = compare(_hits([1.0, 2.0, 3.0 * (1 + 1e-7), np.inf], [0, 1, 7, -1]), embree)
    assert tie["passed"] and tie["ties"] == 1 and tie["mismatches"] == 0
    wrong = compare(_hits([1.0, 2.0, 2.5, np.inf], [0, 1, 7, -1]), embree)
    assert not wrong["passed"] and wrong["mismatches"] == 1 and wrong["examples"][0][0] == 2


def test_compare_fails_below_99_999_percent_hit_miss_agreement():
    n = 50_000
    embree = {"tfar": np.ones(n), "primID": np.zeros(n, np.int64)}
    t = np.ones(n)
    t[0] = np.inf                                   # one miss in 50000: 99.998%
    result = compare(_hits(t, np.where(np.isfinite(t), 0, -1)), embree)
    assert result["hit_miss_disagreements"] == 1 and not result["passed"]


def test_matte_ranks_say_that_they_have_no_effect_on_a_scene_file(tmp_path):
    """--matte-ranks (every render setting has an option) keys Cryptomatte's mattes, which NFF and PLY
    scenes cannot give: the render says so instead of silently ignoring it."""
    mesh = write_ply(tmp_path / "mesh.ply")
    run = gridwalk("render", mesh, "-o", tmp_path / "m.png", "--width", 16, "--height", 16, "--quiet",
                   "--matte-ranks", 2)
    assert run.returncode == 0, run.stderr
    assert "--matte-ranks 2 has no effect" in run.stderr
    run = gridwalk("render", mesh, "-o", tmp_path / "m.png", "--width", 16, "--height", 16, "--quiet")
    assert run.returncode == 0 and "matte" not in run.stderr


def test_an_image_write_that_fails_leaves_the_file_that_was_there(tmp_path):
    # (Ctrl-C while a large PNG was written left it truncated under the output's name). The .npy
    # write fails after the file is opened (the old write had emptied it); the PNG's before any
    # byte is written, which checks that no temporary is left behind.
    from gridwalk.cli import write_image
    for name in ("image.png", "image.npy"):
        out = tmp_path / name
        write_image(out, np.full((4, 4, 4), 0.5, np.float32))
        before = out.read_bytes()
        with pytest.raises(Exception):
            write_image(out, np.zeros((4, 4, 2), np.float32) if name.endswith(".png") else object())
        assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["image.npy", "image.png"]     # no temporary left
