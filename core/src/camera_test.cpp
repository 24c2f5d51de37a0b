// The camera's ray generator: orthographic rays are parallel, panoramic rays
// follow longitude and latitude, a mirrored camera flips x, the far clip is a
// plane across the view axis, and a camera 1e7 from the origin keeps its
// direction (eye and target in double).
#include <doctest/doctest.h>

#include "camera.h"

using namespace gw;

namespace {
CameraDesc desc(Projection p) {
    CameraDesc c;
    c.projection = p;
    c.eye = Vec3d(0, -10, 0);
    c.target = Vec3d(0, 0, 0);
    c.width = 64;
    c.height = 32;
    return c;
}
bool near(const Vec3& a, const Vec3& b, float eps = 1e-6f) { return length(a - b) <= eps; }
}  // namespace

TEST_CASE("orthographic rays are parallel to the view axis and start on the plane through the eye") {
    CameraDesc c = desc(Projection::Orthographic);
    c.ortho_height = 4;
    const Camera cam(c);
    const Ray a = cam.generate(0, 0, 0.5f, 0.5f), b = cam.generate(64, 32, 0.5f, 0.5f);
    CHECK(near(a.d, Vec3(0, 1, 0)));
    CHECK(near(b.d, Vec3(0, 1, 0)));
    CHECK(near(a.o, Vec3(-4, -10, 2)));   // top-left corner: the view is 8 x 4
    CHECK(near(b.o, Vec3(4, -10, -2)));
}

TEST_CASE("equirectangular rays follow longitude (left to right) and latitude (bottom to top)") {
    const Camera cam(desc(Projection::Equirectangular));
    CHECK(near(cam.generate(32, 16, 0.5f, 0.5f).d, Vec3(0, 1, 0)));     // the centre looks at the target
    CHECK(near(cam.generate(48, 16, 0.5f, 0.5f).d, Vec3(1, 0, 0)));     // longitude +90 deg: right
    CHECK(near(cam.generate(0, 16, 0.5f, 0.5f).d, Vec3(0, -1, 0)));     // longitude -180 deg: behind
    CHECK(near(cam.generate(32, 0, 0.5f, 0.5f).d, Vec3(0, 0, 1)));      // top row: up
}

TEST_CASE("a mirrored camera flips x and keeps y") {
    CameraDesc c = desc(Projection::Perspective);
    const Ray plain = Camera(c).generate(10, 5, 0.5f, 0.5f);
    c.mirror = true;
    const Ray mirrored = Camera(c).generate(10, 5, 0.5f, 0.5f), opposite = Camera(c).generate(54, 5, 0.5f, 0.5f);
    CHECK(near(plain.d, Vec3(-mirrored.d.x, mirrored.d.y, mirrored.d.z)));
    CHECK(near(plain.d, opposite.d));
}

TEST_CASE("the far clip is a plane across the view axis") {
    CameraDesc c = desc(Projection::Perspective);
    c.yon = 5;
    const Ray r = Camera(c).generate(0, 0, 0.5f, 0.5f);
    CHECK(r.tmax * r.d.y == doctest::Approx(5.0).epsilon(1e-6));
}

TEST_CASE("a camera 1e7 from the origin keeps its direction") {
    CameraDesc c = desc(Projection::Perspective);
    c.eye = Vec3d(1e7, 1e7, 0);
    c.target = c.eye + Vec3d(12, 15, 16) * (1.0 / 25.0);   // float32 would round this to whole units
    const Ray r = Camera(c).generate(32, 16, 0.5f, 0.5f);
    CHECK(near(r.d, Vec3(0.48f, 0.6f, 0.64f)));
}
