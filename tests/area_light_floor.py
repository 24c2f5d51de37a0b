"""A white diffuse floor under one flat area light, seen straight down, and the irradiance
Lambert's polygon formula gives it: the scene of the area-light tests (test49, test65)."""
import numpy as np

import gridwalk as gw
from polygon_irradiance import polygon_irradiance

N = 32
SIZE = 3.0          # the light: SIZE x SIZE (a rect), SIZE across (a disk), SIZE x 2 SIZE (an ellipse)
VIEW = 1.6          # the camera's view on the floor: VIEW x VIEW, centred on (CENTRE_X, 0)
CENTRE_X = 1.5      # (across the edge of the lights of SIZE)


def light(shape, height, size=SIZE):
    """The light, of radiance 1 (colour / area), centred over the origin, facing down. The rect's
    axes turn one way round its direction, the disk's and the ellipse's the other (Blender's)."""
    if shape == "rect":
        return gw.Light(kind="rect", position=(0, 0, height), size=(size, size), axis_u=(1, 0, 0), axis_v=(0, 1, 0),
                        direction=(0, 0, -1), color=(size * size,) * 3, inverse_square=True)
    if shape == "ellipse":
        return gw.Light(kind="ellipse", position=(0, 0, height), size=(size, 2 * size), axis_u=(1, 0, 0),
                        axis_v=(0, -1, 0), direction=(0, 0, -1), color=(np.pi * size * size / 2,) * 3,
                        inverse_square=True)
    return gw.Light(kind="disk", position=(0, 0, height), radius=size / 2, axis_u=(1, 0, 0), axis_v=(0, -1, 0),
                    direction=(0, 0, -1), color=(np.pi * (size / 2) ** 2,) * 3, inverse_square=True)


def outline(shape, height, size=SIZE):
    """The light's outline as a polygon (the disk's and the ellipse's: 128 sides of the same area)."""
    h = size / 2
    if shape == "rect":
        return np.array([[-h, -h, height], [h, -h, height], [h, h, height], [-h, h, height]], float)
    a = np.arange(128) * (2 * np.pi / 128)
    r = h * np.sqrt(2 * np.pi / (128 * np.sin(2 * np.pi / 128)))
    squash = 2.0 if shape == "ellipse" else 1.0
    return np.stack([r * np.cos(a), squash * r * np.sin(a), np.full(128, height)], axis=1)


def render(the_light, settings, centre=(CENTRE_X, 0.0)):
    """The floor (z = 0, 40 x 40) under the_light, N x N pixels over VIEW x VIEW around centre."""
    floor = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
    cam = gw.Camera(eye=(centre[0], centre[1], 5), target=(centre[0], centre[1], 0), up=(0, 1, 0),
                    projection="orthographic", ortho_height=VIEW, width=N, height=N)
    scene = gw.Scene(floor, np.array([[0, 1, 2], [0, 2, 3]]), materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)],
                     lights=[the_light], camera=cam)
    return gw.render(scene, gw.RenderSettings(**settings))[..., 0].reshape(-1)


def pixel_points(sub, centre=(CENTRE_X, 0.0)):
    """sub x sub points in each pixel, in the order (row, sub-row, column, sub-column)."""
    c = (np.arange(N * sub) + 0.5) / (N * sub) * VIEW - VIEW / 2
    x, y = np.meshgrid(centre[0] + c, centre[1] + c[::-1])
    return np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)


def expected(corners, sub=16, centre=(CENTRE_X, 0.0), irradiance=polygon_irradiance):
    """Each pixel's irradiance from a polygon of radiance 1, averaged over the pixel (sub x sub
    points: near the light's edge it changes within a pixel, and the render's box filter averages it)."""
    e = irradiance(pixel_points(sub, centre), corners).reshape(N, sub, N, sub)
    return e.mean(axis=(1, 3)).reshape(-1)


def scale():
    """The core's diffuse radiance per unit irradiance: from a far light (uniform points on
    it: beyond twice its diagonal), where nothing new applies."""
    got = render(light("rect", 12.0), dict(aa="jittered", aa_samples=4, filter="box", shadow="area",
                                            shadow_samples=16, threads=2))
    return float(np.mean(got / expected(outline("rect", 12.0))))
