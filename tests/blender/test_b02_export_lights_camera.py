"""Lights (every type, watts converted) and the camera (fov, shift, depth of field)."""
import math

import numpy as np
import pytest

POINT = 1 / (4 * math.pi ** 2)
AREA = 1 / math.pi ** 2
SUN = 1 / math.pi


def _by_position(out):
    return {tuple(np.round(light["position"], 3)): light for light in out.lights}


def test_every_light_type_is_exported(export, any_blender):
    out = export("lights")
    lights = _by_position(out)
    exp = out.expected["lights"]

    def get(name):
        return lights[tuple(np.round(exp[name]["position"], 3))]

    point = get("Point")
    assert point["kind"] == "point"
    assert [get(name)["casts_shadows"] for name in ("Point", "Sun", "Spot", "Disk", "Ellipse")] == \
        [True, True, True, True, False]           # the ellipse's Cast Shadow is off
    np.testing.assert_allclose(point["color"], np.array([1, 0.5, 0.25]) * 100 * POINT, rtol=1e-5)
    sphere = get("Sphere")
    assert sphere["kind"] == "sphere" and sphere["radius"] == pytest.approx(0.5)
    np.testing.assert_allclose(sphere["color"], [50 * POINT] * 3, rtol=1e-5)
    sun = get("Sun")
    assert sun["kind"] == "sun" and sun["angle"] == pytest.approx(math.radians(10))
    np.testing.assert_allclose(sun["direction"], exp["Sun"]["down"], atol=1e-6)
    # (Blender 3.4's Cycles gives a facing surface 2 cos h / (1 + cos h) of a sun's Strength, h half
    # its angle of 10 degrees: test_b57)
    h = math.radians(5.0)
    spread = 2 * math.cos(h) / (1 + math.cos(h)) if any_blender == "blender34" else 1.0
    np.testing.assert_allclose(sun["color"], [3 * SUN * spread] * 3, rtol=1e-5)
    spot = get("Spot")
    assert spot["kind"] == "spot"
    assert spot["spot_size"] == pytest.approx(math.radians(60))
    assert spot["spot_blend"] == pytest.approx(0.25)
    np.testing.assert_allclose(spot["direction"], exp["Spot"]["down"], atol=1e-6)
    np.testing.assert_allclose(spot["color"], [200 * POINT] * 3, rtol=1e-5)
    # Soft Falloff: on for the sphere (the default), off for the spot (4.0+; before, always on)
    assert sphere["soft_falloff"] and spot["soft_falloff"] == (any_blender == "blender34")
    square = get("Square")
    assert square["kind"] == "rect"
    np.testing.assert_allclose(square["size"], [2.0, 2.0], rtol=1e-5)
    # (Blender before 4.0 converts an area light's power to radiance with 4 where 4.0 has pi)
    area = AREA * (math.pi / 4 if any_blender == "blender34" else 1)
    np.testing.assert_allclose(square["color"], [80 * area] * 3, rtol=1e-5)
    np.testing.assert_allclose(np.cross(square["axis_u"], square["axis_v"]), exp["Square"]["down"], atol=1e-6)
    np.testing.assert_allclose(square["direction"], exp["Square"]["down"], atol=1e-6)
    rect = get("Rect")
    assert rect["kind"] == "rect"
    np.testing.assert_allclose(rect["size"], [3.0, 1.0], rtol=1e-5)   # object scale (1.5, 2)
    disk = get("Disk")
    assert disk["kind"] == "disk" and disk["radius"] == pytest.approx(0.5)
    ellipse = get("Ellipse")   # size 2, size_y 0.5: its own shape (it was a disk of equal area)
    assert ellipse["kind"] == "ellipse"
    np.testing.assert_allclose(ellipse["size"], [2.0, 0.5], rtol=1e-5)
    np.testing.assert_allclose(ellipse["color"], [40 * area] * 3, rtol=1e-5)
    oval = get("Oval")         # a disk of size 1 scaled (1, 2)
    assert oval["kind"] == "ellipse"
    np.testing.assert_allclose(oval["size"], [1.0, 2.0], rtol=1e-5)
    np.testing.assert_allclose(oval["color"], [40 * area] * 3, rtol=1e-5)
    assert len(out.lights) == 9


def test_a_light_dimmed_by_its_nodes_is_dimmed_and_other_light_nodes_are_named(export):
    out = export("lights", nodes=True)
    lights = _by_position(out)
    point = lights[tuple(np.round(out.expected["lights"]["Point"]["position"], 3))]
    # Cycles multiplies the light by its Emission node's Color x Strength (measured: 4x darker at 0.25)
    np.testing.assert_allclose(point["color"], np.array([1, 0.5, 0.125]) * 0.25 * 100 * POINT, rtol=1e-5)
    assert ("Light 'Sphere': its nodes are not read (only an Emission node with unlinked Color and Strength "
            "into the Light Output is): it gives the light's own colour and power") in out.warnings
    assert not any("Light 'Point'" in w for w in out.warnings)


def test_a_portal_gives_no_light_and_a_lights_ray_visibility_is_exported(export):
    out = export("lights", portal=True)
    lights = _by_position(out)
    exp = out.expected["lights"]
    assert tuple(np.round(exp["Square"]["position"], 3)) not in lights     # (a portal only guides Cycles' world sampling)
    assert tuple(np.round(exp["Disk"]["position"], 3)) in lights
    assert len(lights) == len(exp) - 1
    disk = lights[tuple(np.round(exp["Disk"]["position"], 3))]
    assert (disk["visible_diffuse"], disk["visible_glossy"], disk["visible_transmission"]) == (False, False, True)
    assert all(light["visible_diffuse"] and light["visible_glossy"] for key, light in lights.items()
               if key != tuple(np.round(exp["Disk"]["position"], 3)))
    assert not any("Light 'Square'" in w or "Light 'Disk'" in w for w in out.warnings), out.warnings


def test_lights_fall_off_with_distance_squared(export):
    out = export("lights")
    local = [light for light in out.lights if light["kind"] != "sun"]
    assert all(light.get("inverse_square") for light in local), \
        "Blender lights need inverse-square falloff (gridwalk.model.Light.inverse_square)"


@pytest.mark.parametrize("fit, resolution", [("AUTO", (640, 480)), ("AUTO", (480, 640)),
                                              ("HORIZONTAL", (480, 640)), ("VERTICAL", (640, 480))])
def test_camera_vertical_fov_follows_sensor_fit(export, fit, resolution):
    out = export("camera", fit=fit, resolution=list(resolution), dof=False)
    w, h = resolution
    if fit == "VERTICAL":
        expected = 2 * math.atan(24 / (2 * 50))
    elif fit == "HORIZONTAL" or w >= h:
        expected = 2 * math.atan(36 / (2 * 50) * h / w)
    else:
        expected = 2 * math.atan(36 / (2 * 50))
    cam = out.camera
    assert cam["fov"] == pytest.approx(math.degrees(expected), rel=1e-6)
    assert (cam["width"], cam["height"]) == (w, h)
    np.testing.assert_allclose(cam["eye"], [0, -10, 0], atol=1e-6)
    forward = np.subtract(cam["target"], cam["eye"])
    np.testing.assert_allclose(forward / np.linalg.norm(forward), [0, 1, 0], atol=1e-6)
    np.testing.assert_allclose(cam["up"], [0, 0, 1], atol=1e-6)
    assert cam["aperture"] == 0.0


def test_camera_shift_is_in_units_of_the_larger_side(export):
    out = export("camera", fit="VERTICAL", resolution=[640, 480], dof=False)
    np.testing.assert_allclose(out.camera["shift"], [0.1 * 480 / 640, -0.05 * 480 / 640], rtol=1e-6)


def test_camera_depth_of_field(export):
    out = export("camera", dof=True)
    assert out.camera["aperture"] == pytest.approx(0.050 / (2 * 2.8), rel=1e-6)
    # Cycles' aperture does not depend on the Unit Scale (EEVEE's does)
    out = export("camera", dof=True, unit_scale=0.1)
    assert out.camera["aperture"] == pytest.approx(0.050 / (2 * 2.8), rel=1e-6)
    assert out.camera["focus_distance"] == pytest.approx(7.5, rel=1e-6)
    out = export("camera", dof=True, focus_object=True)
    assert out.camera["focus_distance"] == pytest.approx(14.0, rel=1e-5)
    out = export("camera", dof=True, focus_bone=True)      # the bone's head, not the armature's origin (12)
    assert out.camera["focus_distance"] == pytest.approx(18.0, rel=1e-5)
    # orthographic: Cycles' aperture is 1 / (2 f-stop), not (lens / 1000) / (2 f-stop)
    out = export("camera", dof=True, ortho=True)
    assert out.camera["aperture"] == pytest.approx(1.0 / (2 * 2.8), rel=1e-6)


@pytest.mark.parametrize("stand_in, lens", [("EMPTY", 50.0), ("SPOT", 16.0 / math.tan(math.radians(30.0))),
                                             ("POINT", 16.0 / math.tan(math.radians(22.5)))])
def test_an_empty_or_a_spot_light_as_the_camera_takes_cycles_default_lens(export, stand_in, lens):
    # (Cycles renders from the object with its default lens; a light's spot cone sets the lens,
    # 45 degrees for a light that is no spot)
    out = export("camera", dof=True, stand_in=stand_in)
    cam = out.camera
    assert cam["fov"] == pytest.approx(math.degrees(2 * math.atan(36.0 / (2 * lens) * 480 / 640)), rel=1e-6)
    assert tuple(cam["shift"]) == (0.0, 0.0) and cam["aperture"] == 0.0
    np.testing.assert_allclose(cam["eye"], out.expected["eye"], atol=1e-6)


@pytest.mark.parametrize("scale, sheared", [((1.0, 3.0, 1.0), True), ((2.0, 2.0, 2.0), False)])
def test_a_sheared_camera_is_named_in_the_warnings(export, scale, sheared):
    # (Cycles renders a camera under a rotated, unevenly scaled parent skewed; Gridwalk renders the
    # view along its -Z with its Y up, and says so)
    out = export("camera", dof=False, parent_scale=list(scale))
    named = [w for w in out.warnings if "sheared transform" in w and "'Camera'" in w]
    assert bool(named) == sheared, out.warnings


def test_no_camera_is_a_clear_error(export):
    out = export("no_camera")
    assert "no active camera" in out.error


def test_lights_scattered_from_a_hidden_source_light_the_scene(export):
    # (Geometry Nodes scatter 50 copies of a point light hidden in renders, as Cycles renders
    # them; they were left out: the scene had only its sun)
    out = export("carrier", variant="light", count=50)
    points = [light for light in out.lights if light["kind"] != "sun"]     # (a point, or a sphere of its radius)
    assert len(points) == 50 and len(out.lights) == 51
    positions = np.array([light["position"] for light in points])
    assert len(np.unique(np.round(positions, 4), axis=0)) == 50              # each at its own point
    np.testing.assert_allclose(positions[:, 2], 0.0, atol=1e-5)              # the carrier's Mesh Line lies at z = 0
