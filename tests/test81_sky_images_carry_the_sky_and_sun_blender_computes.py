"""gridwalk.sky_image bakes Blender's Sky Texture into an environment image.

The core's float table (core/src/sky.cpp) agrees with a double-precision numpy transcription of
Nishita's single scattering (sky_reference.py) along scattered directions and for changed
densities and altitudes; the sun's disc carries the same light at any image width, lies where
the node's elevation and rotation put it, and is left out without its disc; the sky is symmetric
about the sun's plane; below the horizon the single-scattering sky fades to black by z = -0.4
(Blender 3.x-4.x) where the multiple-scattering one keeps the light scattered before the ground;
Blender 3.6 and later fold an elevation past 90 degrees back, 3.4 does not. The Preetham sky
takes its sun direction's length as Blender does (normalised; a zero vector is black), peaks at
that direction, and stays finite with its sun below the horizon. Bad settings raise ValueError. Cycles' own renders of the same skies: tests/blender/test_b42."""
import math

import numpy as np
import pytest

import sky_reference as ref
from gridwalk import _core
from gridwalk.sky import RADIANCE_LIMIT, XYZ_TO_REC709, _texel_solid_angles, sky_image

RNG = np.random.default_rng(3)


def _views(n, below=False):
    v = RNG.normal(size=(n, 3))
    v[:, 2] = np.abs(v[:, 2]) * (-1 if below else 1)
    return v / np.linalg.norm(v, axis=1)[:, None]


@pytest.mark.parametrize("elevation, altitude, densities", [
    (0.26, 1.0, (1, 1, 1)), (1.2, 3000.0, (2.0, 0.5, 3.0)), (0.02, 40000.0, (1, 4, 0)), (-0.1, 1.0, (1, 1, 1))])
def test_the_cores_single_scattering_matches_the_numpy_transcription(elevation, altitude, densities):
    views = _views(300)
    expected = ref.single_scattering(views, ref.direction(elevation, 0.0), altitude, densities)
    got = _core.sky_table("single", views.astype(np.float32), elevation, altitude, *densities)
    assert expected.max() > 0
    assert np.abs(got - expected).max() < 2e-3 * np.abs(expected).max()
    assert np.median(np.abs(got - expected) / np.maximum(np.abs(expected), 1e-12)) < 1e-4


def test_the_cores_sun_matches_the_numpy_transcription():
    for elevation in (0.0, 0.3, 1.4):
        expected = ref.sun_radiance(elevation, 0.0095, 1.0, (1.0, 2.0, 1.0))
        solid = 2 * math.pi * (1 - math.cos(0.0095 / 2))
        got = np.array(_core.sky_sun("single", elevation, solid, 1.0, 1.0, 2.0, 1.0))
        assert np.allclose(got, expected, rtol=2e-3)        # (float, as Cycles computes it)
    low, high = (np.array(_core.sky_sun("single", e, 1e-4, 1.0, 1, 1, 1)) for e in (0.01, 1.0))
    assert low[2] / low[0] < 0.5 * high[2] / high[0]            # through more air at the horizon: redder


def _flux(image):
    """The image's irradiance on every side at once: radiance x solid angle, summed."""
    h, w = image.shape[:2]
    el = (0.5 - (np.arange(h) + 0.5) / h) * np.pi
    return (image * np.cos(el)[:, None, None]).sum((0, 1)) * (np.pi / h) * (2 * np.pi / w)


@pytest.mark.parametrize("model, version", [("single", (4, 5)), ("single", (3, 4)), ("multiple", (5, 0)),
                                            ("single", (5, 0))])
def test_the_suns_light_is_the_same_at_any_width_and_in_its_place(model, version):
    kw = dict(blender_version=version, sun_elevation=math.radians(35), sun_rotation=math.radians(50), altitude=100.0)
    sun = {}
    for width in (256, 1024):
        on, off = (sky_image(model, width=width, sun_disc=disc, **kw) for disc in (True, False))
        assert np.isfinite(on).all() and on.min() >= 0
        sun[width] = _flux(on) - _flux(off)
        if width == 1024:
            r, c = np.unravel_index(np.argmax(on.sum(-1)), on.shape[:2])
            el = (0.5 - (r + 0.5) / 512) * math.pi
            azimuth = (0.5 - (c + 0.5) / 1024) * 2 * math.pi
            # the node's rotation r turns the sun from +Y towards +X: azimuth 90 degrees - r
            assert abs(el - math.radians(35)) < 0.006 and abs(azimuth - math.radians(40)) < 0.008
    # the disc's light, analytically: the mean of its two edge radiances x limb darkening x solid angle
    h = math.radians(0.545) / 2
    bottom, top = (np.array(_core.sky_sun(model, math.radians(35) + s * h, 2 * math.pi * (1 - math.cos(h)),
                                          0.1 if model == "multiple" else 100.0, 1, 1, 1)) for s in (-1, 1))
    limb = 1 - 0.6 * (1 - 2 / 3)                  # (the mean of 1 - 0.6 (1 - sqrt(1 - r^2)) over the disc)
    expected = np.maximum(XYZ_TO_REC709 @ ((bottom + top) / 2), 0) * limb * 2 * math.pi * (1 - math.cos(h))
    assert np.allclose(sun[256], sun[1024], rtol=0.01)
    replaced = version < (5, 0)                   # (before 5.0 the disc replaces the sky it covers)
    assert np.allclose(sun[1024], expected, rtol=0.03 if replaced else 0.01, atol=0.002 * expected.max())


def test_the_sky_is_symmetric_about_the_suns_plane():
    image = sky_image("single", width=256, sun_rotation=math.radians(90), sun_disc=False)
    # rotation 90 degrees: the sun towards +X, the image's centre; its halves mirror each other
    assert np.allclose(image, image[:, ::-1], rtol=1e-3, atol=1e-6 * image.max())
    low = image[48:64]                                  # (0-22 degrees up: the haze around the sun)
    assert low[:, 64:192].mean() > 1.5 * np.concatenate([low[:, :64], low[:, 192:]], 1).mean()
    turned = sky_image("single", width=256, sun_rotation=0.0, sun_disc=False)
    assert np.abs(turned - image).max() > 0.1 * image.max()


def test_below_the_horizon_single_scattering_fades_and_multiple_scattering_does_not():
    old = sky_image("single", width=256, blender_version=(4, 5))
    new_single = sky_image("single", width=256, blender_version=(5, 0))
    multiple = sky_image("multiple", width=256, blender_version=(5, 0), altitude=100.0)
    rows = 128
    z = np.sin((0.5 - (np.arange(rows) + 0.5) / rows) * np.pi)
    for image in (old, new_single):
        assert image[z < -0.41].max() == 0                     # black past z = -0.4
        assert image[(z < -0.05) & (z > -0.3)].min() > 0
    assert multiple[z < -0.41].min() > 0
    horizon = np.argmin(np.abs(z - 0.01))
    assert old[horizon].mean() > 5 * old[np.argmin(np.abs(z + 0.3))].mean()


def test_blender_3_6_and_later_fold_an_elevation_past_the_zenith():
    past = dict(sun_elevation=math.radians(120), sun_rotation=0.0, width=256)
    folded = dict(sun_elevation=math.radians(60), sun_rotation=math.radians(180), width=256)
    assert np.allclose(sky_image(blender_version=(4, 5), **past), sky_image(blender_version=(4, 5), **folded))
    assert not np.allclose(sky_image(blender_version=(3, 4), **past), sky_image(blender_version=(3, 4), **folded),
                           rtol=0.05)


@pytest.mark.parametrize("kwargs", [dict(model="hosek"), dict(sun_elevation=float("nan")),
                                    dict(altitude=float("inf")), dict(width=7), dict(width=4),
                                    dict(model="preetham", sun_direction=(0, float("nan"), 1)),
                                    dict(model="preetham", turbidity=float("inf"))])
def test_bad_settings_raise_value_error(kwargs):
    with pytest.raises(ValueError):
        sky_image(**kwargs)


def test_extreme_settings_give_finite_non_negative_skies():
    for kwargs in (dict(air_density=0, dust_density=0, ozone_density=0, sun_size=0.0),
                   dict(air_density=1000, dust_density=1000, sun_size=math.pi / 2, sun_intensity=1e30),
                   dict(altitude=1e9, sun_elevation=-math.pi / 2), dict(sun_elevation=1e6, sun_rotation=-1e6)):
        for model, version in (("single", (3, 4)), ("single", (5, 0)), ("multiple", (5, 0))):
            image = sky_image(model, blender_version=version, width=64, **kwargs)
            assert np.isfinite(image).all() and image.min() >= 0, (kwargs, model)


def test_the_preetham_sky_follows_its_sun_direction():
    a = sky_image("preetham", sun_direction=(0.3, -0.6, 0.5), turbidity=3.0, width=256)
    assert np.array_equal(a, sky_image("preetham", sun_direction=(0.6, -1.2, 1.0), turbidity=3.0, width=256))
    r, c = np.unravel_index(np.argmax(a.sum(-1)), a.shape[:2])
    d = np.array([0.3, -0.6, 0.5]) / np.linalg.norm([0.3, -0.6, 0.5])
    el, az = (0.5 - (r + 0.5) / 128) * np.pi, (0.5 - (c + 0.5) / 256) * 2 * np.pi
    assert abs(el - np.arcsin(d[2])) < 0.05 and abs(az - np.arctan2(d[1], d[0])) < 0.05
    assert not np.allclose(a, sky_image("preetham", sun_direction=(0.3, -0.6, 0.5), turbidity=6.0, width=256),
                           rtol=0.05)
    assert sky_image("preetham", sun_direction=(0, 0, 0), width=64).max() == 0
    below = sky_image("preetham", sun_direction=(0.3, 0.3, -0.2), turbidity=1.0, width=64)
    assert np.isfinite(below).all() and below.min() >= 0 and below.max() <= RADIANCE_LIMIT


@pytest.mark.parametrize("kwargs", [dict(sun_size=0.0, sun_elevation=math.radians(60)),
                                    dict(sun_size=0.0, sun_elevation=math.radians(90)),
                                    dict(sun_size=math.radians(20), sun_elevation=math.radians(50)),
                                    dict(blender_version=(3, 4), sun_elevation=math.radians(120)),
                                    dict(blender_version=(3, 4), sun_size=0.3, sun_elevation=math.radians(120))])
def test_any_sun_carries_its_light_at_any_width(kwargs):
    """The smallest sun Blender makes (0.0005 rad), at 60 degrees and at the zenith (where a
    texel is a thin wedge), a large one, and Blender 3.4's unfolded 120 degrees (the sun at 60,
    turned round), small and large: the sun's light is the same at widths 256 and 1024, and not 0."""
    flux = {}
    for width in (256, 1024):
        on, off = (sky_image(width=width, sun_disc=disc, **kwargs) for disc in (True, False))
        solid = _texel_solid_angles(np.arange(width // 2), width)[:, None, None]
        flux[width] = ((on - off) * solid).sum((0, 1))
    assert flux[1024].min() > 10
    assert np.allclose(flux[256], flux[1024], rtol=0.005)


@pytest.mark.parametrize("call", [
    lambda: _core.sky_table("multiple", np.zeros((4, 3), np.float32) + [0, 0, 1], float("nan"), 0.1, 1, 1, 1),
    lambda: _core.sky_table("multiple", np.full((4, 3), np.nan, np.float32), 0.3, 0.1, 1, 1, 1),
    lambda: _core.sky_table("single", np.zeros((4, 3), np.float32) + [0, 0, 1], 0.3, float("inf"), 1, 1, 1),
    lambda: _core.sky_table("single", np.zeros((4, 3), np.float32) + [0, 0, 1], 0.3, 1.0, -1, 1, 1),
    lambda: _core.sky_sun("mulitple", 0.3, 1e-4, 1.0, 1, 1, 1),
    lambda: _core.sky_sun("single", 0.3, 0.0, 1.0, 1, 1, 1)])
def test_the_native_sky_refuses_bad_input_with_value_error(call):
    with pytest.raises(ValueError):
        call()


def test_a_small_sun_gets_an_inset_that_shows_its_disc_and_matches_the_image_around_it():
    from gridwalk.sky import sky_inset
    kwargs = dict(sun_elevation=math.radians(25), sun_rotation=math.radians(-30), width=1024)
    pixels, frame, extent = sky_inset("single", **kwargs)
    n = pixels.shape[0]
    f = np.array(frame).reshape(3, 3)
    assert np.allclose(f @ f.T, np.eye(3), atol=1e-6)
    el, az = math.radians(25), math.radians(90 + 30)         # (azimuth 90 degrees - rotation)
    assert np.allclose(f[2], [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)], atol=1e-6)
    # the disc 48 texels across in a square of its radius + 3 image texels
    h = math.radians(0.545) / 2
    assert extent == pytest.approx(math.tan(h + 3 * math.pi / 512))
    lum = pixels @ [0.2126, 0.7152, 0.0722]
    disc = lum > 100 * np.median(lum)
    assert abs(disc.sum() - math.pi * 24 ** 2) < 0.05 * math.pi * 24 ** 2
    assert lum[n // 2, n // 2] > 1.4 * lum[disc].min()                 # (the limb: darker)
    # the inset's border is the sky the image shows there
    image = sky_image("single", **kwargs)
    border = np.concatenate([pixels[0], pixels[-1], pixels[:, 0], pixels[:, -1]])
    t = (2 * (np.array([0.5, n - 0.5]) / n) - 1) * extent
    corners = [f[2] + x * f[0] + y * f[1] for x in t for y in t]
    for d in corners:
        d = d / np.linalg.norm(d)
        r = int((0.5 - math.asin(d[2]) / math.pi) * 512)
        c = int((0.5 - math.atan2(d[1], d[0]) / (2 * math.pi)) * 1024) % 1024
        assert np.allclose(image[r, c], border.mean(0), rtol=0.05)
    for other in (dict(sun_disc=False), dict(sun_size=0.2), dict(model="preetham")):
        assert sky_inset(**{**dict(model="single"), **kwargs, **other}) is None
