"""Every kind of Blender camera renders as Cycles renders it (issue 12).

Final renders in bpy 4.5 and 5.0, and in Debian's blender 3.4 (`blender -b`,
where the panorama's settings are Cycles' camera settings), of cubes, a sphere and a ground pad seen by
a perspective camera with a vertical sensor fit and lens shift, portrait
images with the automatic and the horizontal sensor fit (and shift), an
orthographic camera with shift, an equirectangular panorama with
asymmetric ranges, a mirrored camera (scale -1), 2:1 pixels, near and far
clipping through the scene, and a camera 1e7 from the origin. Coverage
(alpha, film transparent) must agree with Cycles' at IoU >= 0.98; both
sample pixel centres, so the masks compare the cameras' geometry. A
panorama's objects and the opaque pixels it leaves without a ray (a
fisheye's corners, at the miss depth) are compared apart.

The exported camera (from lens, sensor and shift settings) must also give
the rays of the camera rebuilt from Blender's own matrices
(calc_matrix_camera), as the viewport rebuilds its view.
"""
import json

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output

PANORAMAS = ("fisheye_equidistant", "fisheye_equisolid", "fisheye_polynomial", "mirror_ball", "cubemap_face",
             "central_cylindrical")
# A mirrored camera (scale -1) flips each panorama's image as it flips a perspective one.
MIRRORED = ("mirrored_panoramic", "mirrored_fisheye_equisolid", "mirrored_mirror_ball")
KINDS = ("perspective", "orthographic", "panoramic", "mirrored", "pixel_aspect", "clipped", "far", "portrait_auto",
         "portrait_horizontal") + PANORAMAS + MIRRORED


@pytest.fixture(scope="module", params=list(ALL_BLENDERS))
def renders(request, tmp_path_factory):
    return script_output(request.param, tmp_path_factory, "camera_kinds.py", *KINDS, timeout=600)


def coverage(out, kind, engine):
    """Where the image is opaque: the objects, and a panorama's pixels without a ray."""
    objects, none = masks(out, kind, engine)
    return objects | none


def masks(out, kind, engine):
    """(objects, no ray): a panorama's opaque pixels at Blender's miss depth (1e10) got no ray
    (a fisheye's corners: opaque black in Cycles); every other kind has none."""
    channels = exr.read_exr(out / f"{kind}_{engine}.exr")
    if "A" in channels:
        return channels["A"] > 0.5, np.zeros(channels["A"].shape, bool)
    opaque, far = channels["ViewLayer.Combined.A"] > 0.5, channels["ViewLayer.Depth.Z"] >= 1e9
    return opaque & ~far, opaque & far


objects_and_none = masks    # (a test below names its dict of masks `masks`)


def iou(a, b):
    return (a & b).sum() / (a | b).sum()


def rendered(renders, kind):
    """Skips a kind this Blender has no camera for (Central Cylindrical came in 4.3)."""
    info = json.loads((renders / "kinds.json").read_text())
    if kind not in info["rendered"]:
        assert kind == "central_cylindrical" and tuple(info["blender"][:2]) < (4, 3), info
        pytest.skip(f"Blender {info['blender'][:2]} has no {kind} panorama (4.3 added it)")


@pytest.mark.parametrize("kind", KINDS)
def test_coverage_matches_cycles(renders, kind):
    rendered(renders, kind)
    (ours, ours_none), (cycles, cycles_none) = masks(renders, kind, "gridwalk"), masks(renders, kind, "cycles")
    assert 0.02 < cycles.mean() < 0.9, "the scene must be partly covered for the comparison to mean something"
    assert iou(ours, cycles) >= 0.98, f"{kind}: objects' IoU {iou(ours, cycles):.4f} with Cycles"
    base = kind.removeprefix("mirrored_")
    if base.startswith("fisheye") or base == "mirror_ball":     # (cut at a circle, or at an angle)
        assert cycles_none.mean() > 0.05
        assert iou(ours_none, cycles_none) >= 0.99, f"{kind}: no-ray pixels' IoU {iou(ours_none, cycles_none):.4f}"
    else:
        assert not ours_none.any() and not cycles_none.any()


def test_kinds_differ_from_each_other(renders):
    """Each camera option changed the image (a setting silently ignored would not)."""
    done = json.loads((renders / "kinds.json").read_text())["rendered"]
    masks = {kind: coverage(renders, kind, "cycles") for kind in done if kind != "far"}
    plain = masks.pop("perspective")
    for kind, mask in masks.items():
        if mask.shape == plain.shape:
            assert (mask != plain).mean() > 0.02, kind
    for kind in MIRRORED:                       # a mirrored panorama's objects differ from its panorama's
        if kind in done:
            objects = [objects_and_none(renders, k, "cycles")[0] for k in (kind, kind.removeprefix("mirrored_"))]
            assert iou(*objects) < 0.9, kind                  # (a fisheye's objects are small: IoU, not pixels)


def test_exported_camera_equals_the_camera_rebuilt_from_blenders_matrices(renders):
    distances = json.loads((renders / "rays.json").read_text())
    assert set(distances) == set(KINDS) - {"panoramic", *PANORAMAS, *MIRRORED}
    for kind, worst in distances.items():
        # relative: directions, and the clipped segments' ends (Blender's float32
        # projection matrix holds the far clip to about 1e-3 of its distance)
        assert worst < 1e-3, (kind, worst)
