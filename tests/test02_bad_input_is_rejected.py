"""Bad input raises ValueError naming the array and the first bad index; it never crashes."""
import numpy as np
import pytest

import gridwalk as gw

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
F = np.array([[0, 1, 2], [1, 3, 2]], np.int32)


def make(**kw):
    base = dict(vertices=V, triangles=F)
    base.update(kw)
    return gw.Scene(**base)


@pytest.mark.parametrize("kw, pattern", [
    (dict(vertices=V[:, :2]), r"vertices must have shape \(N, 3\)"),
    (dict(triangles=F.reshape(-1)), r"triangles must have shape \(N, 3\)"),
    (dict(triangles=F.astype(np.float32)), "triangles must be an integer array"),
    (dict(vertices=np.array(["a", "b", "c"])), "vertices must be a numeric array"),
    (dict(sphere_centers=np.zeros((2, 3)), sphere_radii=np.ones(3)), "sphere_centers"),
    (dict(normals=np.zeros((3, 3), np.float32)), "normals must have the same shape as vertices"),
    (dict(triangle_materials=[0]), "triangle_materials must have one entry per triangle"),
])
def test_wrong_shapes_and_dtypes(kw, pattern):
    with pytest.raises(ValueError, match=pattern):
        make(**kw)


def test_out_of_range_index_names_first_bad_triangle():
    bad = F.copy(); bad[1, 2] = 4
    with pytest.raises(ValueError, match=r"triangles\[1\] = 4 is out of range"):
        make(triangles=bad)
    bad[0, 0] = -1
    with pytest.raises(ValueError, match=r"triangles\[0\] = -1"):
        make(triangles=bad)


def test_material_index_out_of_range():
    with pytest.raises(ValueError, match=r"triangle_materials\[1\] = 3"):
        make(triangle_materials=[0, 3])


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinates(value):
    bad = V.copy(); bad[2, 1] = value
    with pytest.raises(ValueError, match=r"vertices\[2\] has a non-finite value"):
        make(vertices=bad)
    with pytest.raises(ValueError, match=r"sphere_centers\[1\]"):
        gw.Scene(sphere_centers=[[0, 0, 0], [0, value, 0]], sphere_radii=[1, 1])


def test_float64_overflow_becomes_inf_and_is_rejected():
    bad = V.astype(np.float64); bad[3, 0] = 1e300
    with pytest.raises(ValueError, match=r"vertices\[3\]"):
        make(vertices=bad)


def test_negative_radius():
    with pytest.raises(ValueError, match=r"sphere_radii\[1\] is negative"):
        gw.Scene(sphere_centers=np.zeros((2, 3)), sphere_radii=[1.0, -0.5])


def test_empty_scene():
    with pytest.raises(ValueError, match="empty"):
        gw.Scene()
    with pytest.raises(ValueError, match="empty"):
        gw.Scene(vertices=V, triangles=np.zeros((0, 3), np.int32))


def test_bad_records():
    with pytest.raises(ValueError, match="Camera.target coincides with Camera.eye"):
        make(camera=gw.Camera(eye=(0, 0, 0), target=(0, 0, 0)))
    with pytest.raises(ValueError, match="Camera.up is parallel"):
        make(camera=gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 0, 1)))
    with pytest.raises(ValueError, match="Light.kind"):
        make(lights=[gw.Light(kind="laser")])
    with pytest.raises(ValueError, match=r"materials\[0\]\.ior must be > 0"):
        make(materials=[gw.Material(ior=0.0)])
    with pytest.raises(ValueError, match=r"lights\[0\] must be a gridwalk.Light"):
        make(lights=[(1, 2, 3)])


@pytest.mark.parametrize("kind", ["point", "sphere", "rect", "sun"])
def test_a_light_of_negative_colour_is_rejected(kind):
    # It was taken and added nothing: a silently wrong image (an NFF 'l' with a negative colour too)
    with pytest.raises(ValueError, match=r"lights\[0\]\.color must have no negative component"):
        make(lights=[gw.Light(kind=kind, color=(1.0, -0.5, 1.0), radius=0.5, direction=(0, 0, -1))])


@pytest.mark.parametrize("field, value", [("color", (-1.0, 0.5, 0.5)), ("kd", -0.5), ("ks", -0.1),
                                          ("mirror", -1.0), ("transmittance", -0.2), ("emission", -1.0),
                                          ("emission_color", (0.0, -2.0, 0.0))])
def test_negative_light_in_a_material_is_rejected(field, value):
    # A negative colour gave negative pixels (clipped to black in a PNG, kept in .npy)
    with pytest.raises(ValueError, match=rf"materials\[0\]\.{field} must "):
        make(materials=[gw.Material(**{field: value})])


@pytest.mark.parametrize("value", [-0.1, 1.5, float("nan")])
def test_a_metallic_weight_outside_0_1_is_rejected(value):
    with pytest.raises(ValueError, match=r"materials\[0\]\.metallic must"):
        make(materials=[gw.Material(metallic=value)])


def test_degenerate_cylinder_is_rejected():
    with pytest.raises(ValueError, match=r"cylinder_apex\[0\] coincides"):
        gw.Scene(cylinder_base=[[0, 0, 0]], cylinder_apex=[[0, 0, 0]], cylinder_base_radius=[1],
                 cylinder_apex_radius=[1])


def test_cone_too_flat_for_its_radii_is_rejected_and_a_flat_cylinder_is_not():
    """Found by the API fuzzer: a cone 1e-45 high with radii 0.3 and 0.1 has a
    slope of 2e44, and its quadratic reported a hit 4 units from the cone."""
    with pytest.raises(ValueError, match=r"cylinder_apex\[0\] coincides with cylinder_base within 1.4013e-45, "
                                         r"too close for radii 0.3 and 0.1"):
        gw.Scene(cylinder_base=[[0, -2, 0]], cylinder_apex=[[0, -2, -1e-45]], cylinder_base_radius=[0.3],
                 cylinder_apex_radius=[0.1])
    ring = gw.Scene(cylinder_base=[[0, 0, 0]], cylinder_apex=[[0, 0, 1e-6]], cylinder_base_radius=[0.3],
                    cylinder_apex_radius=[0.3])           # equal radii: no slope, any height
    h = ring.intersect([[1, 0, 5e-7]], [[-1, 0, 0]])
    assert h.t[0] == pytest.approx(0.7) and h.kind[0] == 3


def test_bad_rays_are_rejected_not_crashing():
    sc = make()
    with pytest.raises(ValueError, match="directions must have the shape of origins"):
        sc.intersect(np.zeros((3, 3)), np.zeros((2, 3)))


def test_coordinates_beyond_1e30_are_refused():
    with pytest.raises(ValueError, match=r"sphere_radii\[1\]: the primitive extends beyond \+-1e30"):
        gw.Scene(sphere_centers=np.zeros((2, 3)), sphere_radii=[1.0, 3e38])
    with pytest.raises(ValueError, match=r"triangles\[0\]"):
        gw.Scene(vertices=[[-2e30, 0, 0], [0, 1, 0], [0, 0, 1]], triangles=[[0, 1, 2]])


def test_rect_disk_and_ellipse_lights_need_a_direction():
    for kind in ("rect", "disk", "ellipse"):
        with pytest.raises(ValueError, match="direction must be non-zero"):
            make(lights=[gw.Light(kind=kind, direction=(0, 0, 0), radius=1.0)])


def test_the_private_module_checks_shapes_and_settings_itself():
    """A caller that skips the Python layer gets errors, not a crash."""
    sc = make()
    acc = sc.accel()
    one = np.zeros(1, np.float32)
    o = np.zeros((1, 3), np.float32)
    d = np.array([[0, 0, 1]], np.float32)
    with pytest.raises(ValueError, match="origins must have shape"):
        gw._core.spawn_origins(acc, np.zeros((3, 1), np.float32), d, one, np.zeros(1, np.int32), one, one, d)
    core = gw._core.RenderSettings()
    core.threads = 5000
    with pytest.raises(ValueError, match=r"RenderSettings.threads must be in \[0, 1024\], got 5000"):
        gw._core.intersect(acc, o, d, one, one, core, False)
    core.threads, core.aa_samples = 0, -1
    with pytest.raises(ValueError, match="RenderSettings.aa_samples"):
        gw._core.occluded(acc, o, d, one, one, core, False)


def test_a_negative_instance_move_index_is_refused_by_name():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], np.float32)
    sc = gw.Scene(vertices=V, triangles=np.array([[0, 1, 2], [3, 4, 5]], np.int32))
    for field in ("vertex_start", "triangle_start", "triangle_count"):
        fields = dict(vertex_start=3, triangle_start=1, triangle_count=1, positions=V[3:], matrix=np.eye(4))
        fields[field] = -1
        with pytest.raises(ValueError, match=rf"moves\[0\]\.{field} must be a non-negative integer, got -1"):
            sc.moved([gw.InstanceMove(**fields)])


def test_a_column_major_instance_matrix_is_refused_not_ignored():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1]], np.float32)
    sc = gw.Scene(vertices=V, triangles=np.array([[0, 1, 2], [3, 4, 5]], np.int32))
    moved = np.eye(4)
    moved[:3, 3] = (2.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"moves\[0\]\.matrix must be affine.*transpose"):
        sc.moved([gw.InstanceMove(3, 1, 1, V[3:], moved.T)])
    sc.moved([gw.InstanceMove(3, 1, 1, V[3:], moved)])          # (the row-major one is taken)


def test_settings_of_another_type_and_a_short_lens_sample_are_named():
    sc = gw.Scene(vertices=np.eye(3, dtype=np.float32), triangles=np.array([[0, 1, 2]]))
    for settings in ({"threads": 1}, "fast"):
        with pytest.raises(ValueError, match="settings must be a gridwalk.RenderSettings"):
            gw.RenderJob(sc, settings)
        with pytest.raises(ValueError, match="settings must be a gridwalk.RenderSettings"):
            gw.render(sc, settings)
    with pytest.raises(ValueError, match="lens must be two numbers"):
        sc.camera.rays([0.5], [0.5], lens=(0.5,))


def test_an_image_wider_than_the_core_counts_says_so():
    wide = np.zeros((1, 2 ** 31, 1), np.uint8)   # (2 GiB of untouched zero pages)
    with pytest.raises(ValueError, match="has 2147483648 columns: at most 2147483647"):
        gw.Image(wide)
