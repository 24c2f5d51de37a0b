// Primitive / box overlap (overlap.h): never "apart" for a triangle or sphere
// that has a point in the box (checked against points sampled on the
// primitive), and "apart" where a plane or a gap clearly separates them.
#include <doctest/doctest.h>

#include <random>

#include "overlap.h"

using namespace gw;

namespace {

// Whether any of a dense set of points of triangle abc (barycentric lattice,
// edges included) lies inside the box centred at m with half sizes h.
bool sampled_meets(const Vec3& a, const Vec3& b, const Vec3& c, const double m[3], const double h[3]) {
    const int k = 40;
    for (int i = 0; i <= k; ++i)
        for (int j = 0; i + j <= k; ++j) {
            const double u = double(i) / k, v = double(j) / k, w = 1 - u - v;
            bool in = true;
            for (int ax = 0; ax < 3 && in; ++ax) {
                const double p = w * a[ax] + u * b[ax] + v * c[ax];
                in = std::abs(p - m[ax]) <= h[ax];
            }
            if (in) return true;
        }
    return false;
}

Vec3 random_point(std::mt19937& rng, float scale) {
    std::uniform_real_distribution<float> u(-scale, scale);
    return Vec3(u(rng), u(rng), u(rng));
}

// Checks the test's answer for the box centred at m against sampled points,
// counting boxes holding a sampled point (in) and boxes found apart.
void check_answer(const Vec3& a, const Vec3& b, const Vec3& c, const double m[3], const double h[3], int& in,
                  int& apart) {
    const TriangleBoxTest test(a, b, c, h);
    const bool sampled_in = sampled_meets(a, b, c, m, h);
    in += sampled_in;
    if (sampled_in) CHECK(test.meets(m));
    // Apart answers must be true: outside the box's bounds of the corners, or
    // separated by the plane, which the sampling cannot show; so check that
    // the box grown by a hair still admits no sampled point.
    if (!test.meets(m)) {
        ++apart;
        const double grown[3] = {h[0] * 1.0001, h[1] * 1.0001, h[2] * 1.0001};
        CHECK_FALSE(sampled_meets(a, b, c, m, grown));
    }
}

}  // namespace

TEST_CASE("a triangle with a point in the box always meets it; most separated ones are found apart") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.05, 0.5);
    int apart = 0, sampled_in = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        // Small and large triangles, slivers among them, against small boxes.
        const float scale = trial % 3 == 0 ? 0.3f : 1.5f;
        const Vec3 a = random_point(rng, scale);
        const Vec3 b = trial % 7 == 0 ? a + (random_point(rng, scale) - a) * 1e-3f : random_point(rng, scale);
        const Vec3 c = random_point(rng, scale);
        const double m[3] = {u(rng), u(rng), u(rng)};
        const double h[3] = {size(rng), size(rng), size(rng)};
        check_answer(a, b, c, m, h, sampled_in, apart);
    }
    CHECK(sampled_in > 2000);
    CHECK(apart > 2000);
}

TEST_CASE("a sloped triangle is apart from the boxes of its bounds that only its bounds reach") {
    // The triangle x + y + z = 1 (x, y, z >= 0) and unit-ish cells of a 2 x 2 x 2 grid over [0, 1]^3.
    const Vec3 a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
    const double h[3] = {0.25, 0.25, 0.25};
    const TriangleBoxTest test(a, b, c, h);
    const double near[3] = {0.25, 0.25, 0.25}, far[3] = {0.75, 0.75, 0.75}, side[3] = {0.75, 0.25, 0.25};
    CHECK(test.meets(near));
    CHECK_FALSE(test.meets(far));   // the triangle's bounds cover this cell, the triangle does not
    CHECK(test.meets(side));
}

TEST_CASE("degenerate and non-finite triangles are never called apart from a box they may touch") {
    const double h[3] = {0.5, 0.5, 0.5}, m[3] = {0, 0, 0}, far_a[3] = {-3, -3, 0}, far_b[3] = {3, 3, 5};
    // A segment through the box, a point inside it.
    CHECK(TriangleBoxTest(Vec3(-2, 0.1f, 0.1f), Vec3(2, 0.1f, 0.1f), Vec3(0, 0.1f, 0.1f), h).meets(m));
    CHECK(TriangleBoxTest(Vec3(0.2f, 0.2f, 0.2f), Vec3(0.2f, 0.2f, 0.2f), Vec3(0.2f, 0.2f, 0.2f), h).meets(m));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // A NaN corner, whichever: the box at the origin, and boxes off the line
    // of the two finite corners (an edge's axis through them would call those apart).
    for (int corner = 0; corner < 3; ++corner) {
        Vec3 v[3] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
        v[corner] = Vec3(nan, 0, 0);
        const TriangleBoxTest test(v[0], v[1], v[2], h);
        for (const double* at : {m, far_a, far_b}) CHECK(test.meets(at));
    }
    // A diagonal segment passing beside the box's corner (its bounds overlap
    // the box: only the segment's own direction separates them) is apart.
    CHECK_FALSE(TriangleBoxTest(Vec3(-2, -0.8f, 0.1f), Vec3(2, 3.2f, 0.1f), Vec3(0, 1.2f, 0.1f), h).meets(m));
}

TEST_CASE("triangles in a plane of the box axes are tested in that plane, as sloped ones are") {
    // Floors, walls and boxes: triangles with a constant coordinate and edges
    // along the axes. The axes along a box axis are the caller's (its cell
    // range), so boxes are taken where the triangle's bounds reach them.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::uniform_real_distribution<double> size(0.05, 0.4);
    int apart = 0, in_count = 0, tried = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const int flat = trial % 3;   // the constant axis
        const float level = u(rng) * 0.5f;
        auto point = [&](float p, float q) {
            Vec3 v;
            v[flat] = level;
            v[(flat + 1) % 3] = p;
            v[(flat + 2) % 3] = q;
            return v;
        };
        // Half the triangles are a quad's halves (two edges along the axes).
        const float p0 = u(rng), q0 = u(rng), p1 = u(rng), q1 = u(rng);
        const Vec3 a = point(p0, q0), b = trial % 2 ? point(p1, q0) : point(u(rng), u(rng)), c = point(p1, q1);
        const double h[3] = {size(rng), size(rng), size(rng)};
        double m[3];
        bool reach = true;   // the box meets the triangle's bounds (the caller's test)
        for (int ax = 0; ax < 3; ++ax) {
            m[ax] = ax == flat ? level + 0.9 * u(rng) * h[ax] : u(rng);   // (the plane passes through the box)
            const double lo = std::min({a[ax], b[ax], c[ax]}), hi = std::max({a[ax], b[ax], c[ax]});
            reach = reach && m[ax] + h[ax] >= lo && m[ax] - h[ax] <= hi;
        }
        if (!reach) continue;
        ++tried;
        check_answer(a, b, c, m, h, in_count, apart);
    }
    CHECK(tried > 2000);
    CHECK(in_count > 500);
    CHECK(apart > 200);   // boxes beside a diagonal edge, inside the bounds
}

TEST_CASE("far from the origin, a triangle touching a cell within rounding is still listed") {
    // A cell of size 1e-3 at 1e5: the triangle's plane passes 1e-9 inside the cell's corner.
    const double h[3] = {0.5e-3, 0.5e-3, 0.5e-3};
    const double m[3] = {1e5 + 0.5e-3, 1e5 + 0.5e-3, 1e5 + 0.5e-3};
    const float x = float(1e5);
    // Plane z = x0 (the cell's lower z face, exactly representable).
    CHECK(TriangleBoxTest(Vec3(x - 1, x - 1, x), Vec3(x + 1, x - 1, x), Vec3(x, x + 1, x), h).meets(m));
}

TEST_CASE("a sphere meets a box exactly when its centre is within its radius of it") {
    const double h[3] = {0.5, 0.5, 0.5}, m[3] = {0, 0, 0};
    CHECK(sphere_meets_box(Vec3(0, 0, 0), 0.1f, m, h));          // inside
    CHECK(sphere_meets_box(Vec3(1.0f, 0, 0), 0.5f, m, h));        // touching a face
    CHECK(sphere_meets_box(Vec3(1.2f, 1.2f, 0), 1.0f, m, h));     // near an edge: gap 0.7 * sqrt 2 = 0.99
    CHECK_FALSE(sphere_meets_box(Vec3(1.3f, 1.3f, 0), 1.0f, m, h));   // gap 0.8 * sqrt 2 = 1.13
    CHECK_FALSE(sphere_meets_box(Vec3(1.3f, 1.3f, 1.3f), 1.3f, m, h));   // corner: gap 0.8 * sqrt 3 = 1.39
}
