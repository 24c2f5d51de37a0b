"""Command line: python -m gridwalk {demo, render, farm, validate, info} ...

    python -m gridwalk demo -o demo.png                 the built-in balls scene, distribution effects on
    python -m gridwalk render SCENE.nff -o out.png      any NFF / PLY file, every RenderSettings field an option
    python -m gridwalk farm SCENE -o OUT                the same on a Dask cluster (tiles, or a .blend's frames)
    python -m gridwalk validate SCENE                   cross-check the triangles against Embree
    python -m gridwalk info SCENE                       counts, bounds, camera and the grid

Errors in the input (a missing or malformed file, bad settings) print one line,
`gridwalk: error: ...`, and exit with status 2; Ctrl-C cancels a render (130).
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

import numpy as np

from . import io, memory, scenes
from .mesh_checks import zero_area_count
from .render import RenderJob
from .scene import Scene
from .settings import BY_NAME, SCHEMA, RenderSettings

OUTPUT_TYPES = (".png", ".npy")


class CliError(Exception):
    """A user error found by the CLI itself (reported like ValueError)."""


# -- the demo scene -----------------------------------------------------------
def demo_scene(size: int = 3, resolution: int = 512) -> dict:
    """SPD balls with the distribution effects: the three lights become sphere
    lights (soft shadows), the floor a glossy mirror, and the lens is focused
    on the front of the big ball (depth of field)."""
    kwargs = scenes.balls(size)
    floor, ball = kwargs["materials"]
    kwargs["materials"] = [dataclasses.replace(floor, mirror=0.3, roughness=0.2), ball]
    kwargs["lights"] = [dataclasses.replace(l, kind="sphere", radius=0.5) for l in kwargs["lights"]]
    cam = kwargs["camera"]
    focus = float(np.linalg.norm(np.subtract(cam.eye, cam.target))) - 0.5   # the big ball's front
    kwargs["camera"] = dataclasses.replace(cam, width=resolution, height=resolution,
                                           aperture=0.05, focus_distance=focus)
    return kwargs


def demo_settings(quick: bool, threads: int) -> RenderSettings:
    n = 2 if quick else 3
    return RenderSettings(aa="jittered", aa_samples=n, shadow="area", shadow_samples=n,
                          glossy_samples=1, threads=threads)


# -- output -------------------------------------------------------------------
def check_output(path, types=OUTPUT_TYPES) -> Path:
    """Refuse an unusable output path before rendering, not after."""
    path = Path(path)
    if path.suffix.lower() not in types:
        raise CliError(f"{path}: output must end in {' or '.join(types)}")
    if not path.parent.is_dir():
        raise CliError(f"{path}: the folder {str(path.parent)!r} does not exist")
    if path.is_dir():
        raise CliError(f"{path}: is a folder, not an image file")
    target = path.resolve()              # (a symbolic link: the file it names)
    existed = target.exists()
    try:                                  # (a read-only folder or file, /proc, a full quota: now, not after the render)
        with open(path, "ab"):
            pass
    except OSError as err:
        raise CliError(f"{path}: cannot be written ({err.strerror or err})") from None
    if not existed:
        target.unlink(missing_ok=True)
    return path


def check_memory(kwargs: dict, settings: RenderSettings, limit: int | None = None) -> None:
    """Refuse a render whose estimated memory (gridwalk.memory: the scene, its
    grid and the image's buffers) exceeds `limit` (default
    memory.default_limit()), before any of it is allocated."""
    cam = kwargs["camera"]
    count = lambda key: len(kwargs.get(key, ()))
    est = memory.estimate(triangles=count("triangles"), vertices=count("vertices"), spheres=count("sphere_radii"),
                          cylinders=count("cylinder_base_radius"), width=cam.width, height=cam.height,
                          settings=settings, normals=kwargs.get("normals") is not None)
    memory.check(est, memory.default_limit() if limit is None else limit, f"Rendering {cam.width}x{cam.height}",
                 f"{memory.DEFAULT_FRACTION:.0%} of physical memory" if limit is None else "")


def to_srgb8(linear: np.ndarray) -> np.ndarray:
    """Linear values in [0, 1] (clipped; NaN -> 0) to 8-bit sRGB, converted
    in slices of rows (a large image needs no image-sized float64 copies)."""
    out = np.empty(linear.shape, np.uint8)
    rows = max(1, (1 << 20) // max(1, linear[0].size)) if linear.ndim > 1 else len(linear)
    for start in range(0, len(linear), rows):
        x = np.clip(np.nan_to_num(linear[start:start + rows].astype(np.float64), nan=0.0), 0.0, 1.0)
        srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
        out[start:start + rows] = (srgb * 255.0 + 0.5).astype(np.uint8)
    return out


def write_image(path: Path, rgba: np.ndarray, alpha: bool = False) -> None:
    """.npy: the float32 linear RGBA array; .png: 8-bit sRGB (RGBA with alpha =
    coverage when `alpha`, else RGB). Written to a temporary name beside it, then renamed:
    an interrupted write (Ctrl-C, a full disk) leaves the file that was there, not a part."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as f:
            if path.suffix.lower() == ".npy":     # (np.save given a path would add ".npy" to "image.NPY")
                np.save(f, np.asarray(rgba, np.float32))
            else:
                from PIL import Image

                rgb = to_srgb8(rgba[..., :3])
                if alpha:
                    a = (np.clip(np.nan_to_num(rgba[..., 3]), 0, 1) * 255 + 0.5).astype(np.uint8)
                    Image.fromarray(np.dstack([rgb, a]), "RGBA").save(f, format="PNG")
                else:
                    Image.fromarray(rgb, "RGB").save(f, format="PNG")
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


# -- rendering with progress --------------------------------------------------
def run_job(job: RenderJob, quiet: bool = False) -> np.ndarray:
    """Start `job`, draw a progress bar on stderr until it finishes, return the
    image. Ctrl-C cancels the job (the workers stop) and re-raises."""
    start, shown = time.perf_counter(), None

    def draw():
        nonlocal shown
        percent = int(100 * job.progress)
        if not quiet and percent != shown:
            shown = percent
            bar = "#" * (percent * 30 // 100)
            sys.stderr.write(f"\rrendering [{bar:<30}] {percent:3d}%  {time.perf_counter() - start:6.1f} s")
            sys.stderr.flush()

    job.start()
    try:
        while not job.finished:
            job.wait_for(0.05)
            draw()
        image = job.wait()
        draw()   # the last tiles may finish after the loop's last look: the bar ends at 100%
    except KeyboardInterrupt:
        job.cancel()
        raise
    finally:
        if not quiet and shown is not None:
            sys.stderr.write("\n")
    return image


def _si(n: float) -> str:
    for div, unit in ((1e9, " G"), (1e6, " M"), (1e3, " k")):
        if abs(n) >= div:
            return f"{n / div:.3g}{unit}"
    return f"{n:.3g}"


def grid_line(grid: dict) -> str:
    nx, ny, nz = grid["resolution"]
    root = f"{nx}x{ny}x{nz} = {nx * ny * nz} cells" if grid["grids"] == 1 else \
        f"root {nx}x{ny}x{nz}, {grid['grids']} grids, {grid['cells']} cells"
    line = (f"{grid['kind']}: {root}, {grid['refs']} refs, {grid['bytes'] / 1024:.1f} KiB, "
            f"built in {grid['build_seconds'] * 1e3:.2f} ms"
            + (f" on {grid['build_threads']} threads" if grid.get("build_threads", 1) > 1 else ""))
    if grid["kind"] == "uniform grid":
        line += f" (density {grid['density_used']:g})"
    return line + (f"\n  note      {grid['note']}" if grid.get("note") else "")


def stats_summary(stats: dict) -> str:
    lines = [f"  rays      {_si(stats['rays'])}: primary {_si(stats['primary_rays'])}, "
             f"shadow {_si(stats['shadow_rays'])}, secondary {_si(stats['secondary_rays'])}; "
             f"{stats['mrays_per_second']:.2f} Mrays/s",
             f"  per ray   {stats['tests_per_ray']:.2f} intersection tests, {stats['cells_per_ray']:.2f} cells "
             f"(mailboxes skipped {_si(stats['mailbox_skips'])} tests)"]
    if stats.get("grid"):
        lines.append("  grid      " + grid_line(stats["grid"]))
    return "\n".join(lines)


# -- subcommands --------------------------------------------------------------
def cmd_demo(args) -> int:
    out = check_output(args.output)
    check_pixels(resolution=args.resolution)
    resolution = args.resolution if args.resolution is not None else (256 if args.quick else 512)
    s = demo_settings(args.quick, args.threads)
    kwargs = demo_scene(args.size, resolution)
    check_memory(kwargs, s)
    scene = Scene(**kwargs)
    job = RenderJob(scene, s)
    image = run_job(job, args.quiet)
    write_image(out, image)
    st = job.stats
    print(f"gridwalk demo: balls size {args.size} ({scene.num_spheres} spheres), {resolution}x{resolution}, "
          f"{s.aa_samples}x{s.aa_samples} jittered AA, {s.shadow_samples}x{s.shadow_samples} area lights, "
          f"glossy floor, depth of field: {st['seconds']:.2f} s, {_si(st['rays'])} rays, "
          f"{st['mrays_per_second']:.2f} Mrays/s -> {out}")
    return 0


def check_pixels(**sizes):
    """Each given image size (an option's value, None when not given) is at least 1: the
    memory estimate would otherwise name a negative one first, and 0 only afterwards."""
    for option, value in sizes.items():
        if value is not None and value < 1:
            raise CliError(f"--{option} must be at least 1, got {value}")


def warn_zero_area(path, kwargs):
    """Names the scene's triangles of zero area, which no ray hits (as Blender's export names them)."""
    triangles = kwargs.get("triangles")
    if triangles is None or not len(triangles):
        return
    zero = zero_area_count(kwargs["vertices"], triangles)
    if zero:
        print(f"gridwalk: warning: {path}: {zero} of {len(triangles)} triangles have zero area and are invisible",
              file=sys.stderr)


def load(path, width: int | None = None, height: int | None = None) -> dict:
    """io.load_scene's keywords, the image size replaced where given."""
    check_pixels(width=width, height=height)
    path = Path(path)
    if path.is_dir():
        raise CliError(f"{path}: is a folder, not a scene file")
    if not path.exists():
        raise CliError(f"{path}: no such file")
    if not path.is_file():
        raise CliError(f"{path}: not a regular file (a device or a pipe); give a scene file")
    return io.load_scene(path, width, height)


def cmd_render(args) -> int:
    out = check_output(args.output)
    npy = check_output(args.npy, (".npy",)) if args.npy else None
    s = settings_from_args(args)
    kwargs = load(args.scene, args.width, args.height)
    warn_zero_area(args.scene, kwargs)
    if s.matte_ranks and kwargs.get("matte_keys") is None:
        print(f"gridwalk: warning: --matte-ranks {s.matte_ranks} has no effect: {args.scene} names no objects or "
              "materials to key (Cryptomatte's mattes come from Blender scenes), and this command writes no "
              "matte passes", file=sys.stderr)
    check_memory(kwargs, s)
    job = RenderJob(Scene(**kwargs), s)
    image = run_job(job, args.quiet)
    write_image(out, image, args.alpha)
    if npy:
        write_image(npy, image)
    c = kwargs["camera"]
    print(f"gridwalk: rendered {args.scene} ({c.width}x{c.height}) in {job.stats['seconds']:.2f} s -> "
          f"{out}{' and ' + str(npy) if npy else ''}")
    print(stats_summary(job.stats))
    return 0


def _vec(v) -> str:
    return "(" + ", ".join(f"{x:.4g}" for x in v) + ")"


def cmd_info(args) -> int:
    kwargs = load(args.scene)
    scene = Scene(**kwargs)
    lo, hi = scene.bounds
    c = scene.camera
    smooth = ", smooth normals" if kwargs.get("normals") is not None else ""
    print(f"scene      {args.scene}")
    print(f"primitives {scene.num_triangles} triangles{smooth}, {scene.num_spheres} spheres, "
          f"{scene.num_cylinders} cylinders; {len(scene.lights)} lights, {len(scene.materials)} materials")
    print(f"bounds     {_vec(lo)} .. {_vec(hi)}")
    lens = {"perspective": f"fov {c.fov:.4g} deg", "orthographic": f"ortho height {c.ortho_height:.4g}"}
    print(f"camera     eye {_vec(c.eye)}, target {_vec(c.target)}, up {_vec(c.up)}, "
          f"{lens.get(c.projection, c.projection.replace('_', ' '))}, {c.width}x{c.height}, aperture {c.aperture:g}")
    print(f"grid       {grid_line(scene.grid_info(settings_from_args(args)))}")
    return 0


def cmd_validate(args) -> int:
    from . import validate

    if args.rays < 1:
        raise CliError(f"--rays must be >= 1, got {args.rays}")
    need, limit = args.rays * validate.BYTES_PER_RAY, memory.default_limit()
    if limit is not None and need > limit:
        raise CliError(f"--rays {args.rays} needs an estimated {memory.format_bytes(need)} of memory for its ray "
                       f"sets and both engines' hits, more than the limit of {memory.format_bytes(limit)} "
                       f"({round(memory.DEFAULT_FRACTION * 100)}% of physical memory)")
    kwargs = load(args.scene)
    left_out = {k: len(kwargs[a]) for k, a in (("spheres", "sphere_radii"), ("cylinders", "cylinder_base_radius"))}
    results = validate.cross_check(kwargs, args.rays, args.seed, args.threads)
    dropped = ", ".join(f"{n} {k}" for k, n in left_out.items() if n) or "none"
    print(f"Embree cross-check of {args.scene}: {len(kwargs['triangles'])} triangles only "
          f"(spheres and cylinders are not in Embree; left out: {dropped})")
    print(f"seed {args.seed}; gridwalk grid on {args.threads or 'all'} thread(s), embreex (robust) on 1; tmin = 0")
    print(validate.format_table(results))
    passed = all(r["passed"] for r in results.values())
    return 0 if passed else 1


# -- argument parsing ---------------------------------------------------------
def add_settings_options(parser: argparse.ArgumentParser, groups=None, leave_out=()) -> None:
    """One option per setting of the core's settings table (gridwalk.settings.SCHEMA),
    so no setting can be forgotten; `groups` limits them to those groups, and
    the settings named in `leave_out` get none (the farm's tiles are its regions)."""
    group = parser.add_argument_group("render settings (gridwalk.RenderSettings)")
    for setting in SCHEMA:
        if (groups is not None and setting.group not in groups) or setting.name in leave_out:
            continue
        flag = "--" + setting.name.replace("_", "-")
        help_text = f"{setting.describe()} (default: {setting.default})".replace("%", "%%")
        if setting.kind == "bool":
            group.add_argument(flag, dest=setting.name, action=argparse.BooleanOptionalAction, default=None,
                               help=help_text)
        elif setting.kind == "region":
            group.add_argument(flag, dest=setting.name, type=_numbers, default=None, metavar="X,Y,W,H",
                               help=help_text)
        else:
            kind = {"int": int, "float": float, "enum": str}[setting.kind]
            group.add_argument(flag, dest=setting.name, type=kind, default=None, choices=setting.ids or None,
                               help=help_text)


def settings_from_args(args) -> RenderSettings:
    """The RenderSettings the options ask for (defaults where not given), checked."""
    changes = {name: getattr(args, name) for name in BY_NAME if getattr(args, name, None) is not None}
    s = RenderSettings().replace(**changes)
    s.to_core()                                   # bad settings fail here, before any scene is built
    return s


def _numbers(text: str) -> tuple:
    """'0,0,64,32' -> (0, 0, 64, 32); floats where a number is not whole."""
    try:
        values = [float(x) for x in text.replace(" ", "").split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None
    return tuple(int(v) if v.is_integer() else v for v in values)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="gridwalk", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("demo", help="render the built-in balls scene with the distribution effects")
    p.add_argument("-o", "--output", default="demo.png", help="output .png or .npy (default: demo.png)")
    p.add_argument("--size", type=int, default=3, choices=range(1, 5), help="sphereflake size factor (default: 3)")
    p.add_argument("--resolution", type=int, default=None, help="image width and height (default: 512)")
    p.add_argument("--quick", action="store_true", help="256x256 and 2x2 samples: a fast preview")
    p.add_argument("--threads", type=int, default=0, help="worker threads, 0 = all cores")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_demo)

    p = sub.add_parser("render", help="render an NFF or PLY scene")
    p.add_argument("scene", help="scene file (.nff or .ply)")
    p.add_argument("-o", "--output", required=True, help="output image: .png (8-bit sRGB) or .npy (float32 linear)")
    p.add_argument("--npy", default=None, help="also write the float32 linear RGBA array to this .npy file")
    p.add_argument("--alpha", action="store_true", help="PNG with an alpha channel (pixel coverage)")
    p.add_argument("--width", type=int, default=None, help="image width (default: the scene's)")
    p.add_argument("--height", type=int, default=None, help="image height (default: the scene's)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_settings_options(p)
    p.set_defaults(func=cmd_render)

    from .renderfarm.cli import add_parser as add_farm_parser
    add_farm_parser(sub, add_settings_options, settings_from_args)

    p = sub.add_parser("validate", help="cross-check the scene's triangle intersections against Embree")
    p.add_argument("scene", help="scene file (.nff or .ply)")
    p.add_argument("--rays", type=int, default=100_000, help="rays per set (default: 100000)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    p.add_argument("--threads", type=int, default=1, help="gridwalk threads, 0 = all (default: 1, like embreex)")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("info", help="primitive counts, bounds, camera and the grid that would be built")
    p.add_argument("scene", help="scene file (.nff or .ply)")
    add_settings_options(p, groups=("acceleration",))
    p.set_defaults(func=cmd_info)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("\ngridwalk: cancelled", file=sys.stderr)
        return 130
    except (CliError, ValueError, memory.SceneTooLarge) as err:   # SceneFileError is a ValueError
        print("gridwalk: error: " + " ".join(str(err).split()), file=sys.stderr)   # one line
        return 2
    except OSError as err:
        where = f"{err.filename}: " if err.filename else ""
        print(f"gridwalk: error: {where}{err.strerror or err}", file=sys.stderr)
        return 2
