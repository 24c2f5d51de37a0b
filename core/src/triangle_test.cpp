// The triangle test: its rounding-error bound on t contains the true error,
// spawned rays never re-hit their own triangle, and shared edges leak no ray.
#include <doctest/doctest.h>

#include <random>

#include "offset.h"
#include "triangle.h"

using namespace gw;

namespace {

// t of the ray's hit with the triangle's plane, in long double (the "exact" t).
long double exact_t(const Ray& ray, const Vec3 v[3]) {
    using L = long double;
    L e1[3], e2[3], n[3], w[3];
    for (int a = 0; a < 3; ++a) {
        e1[a] = L(v[1][a]) - L(v[0][a]);
        e2[a] = L(v[2][a]) - L(v[0][a]);
        w[a] = L(v[0][a]) - L(ray.o[a]);
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const L num = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
    const L den = n[0] * L(ray.d.x) + n[1] * L(ray.d.y) + n[2] * L(ray.d.z);
    return num / den;
}

// A secondary ray leaving triangle v in direction d from a point inside it
// rounded to float, offset as the renderer offsets it.
Ray spawned_ray(const Vec3 v[3], const Vec3& d) {
    Vec3 p, p_err;
    triangle_point(v[0], v[1], v[2], 0.25f, 0.35f, p, p_err);
    Ray ray;
    ray.d = d;
    ray.o = offset_origin(p, p_err, triangle_normal(v[0], v[1], v[2]), ray.d);
    ray.spawned = true;
    return ray;
}

}  // namespace

TEST_CASE("the t error bound contains the true error at every scale") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int checked = 0;
    for (float scale : {1e-4f, 1.0f, 1e3f, 1e6f}) {
        for (float offset : {0.0f, 10.0f, 1e4f}) {
            for (int i = 0; i < 20000; ++i) {
                Vec3 v[3];
                const Vec3 base(u(rng) * scale * 10 + offset, u(rng) * scale * 10, u(rng) * scale * 10);
                for (auto& p : v) p = base + Vec3(u(rng), u(rng), u(rng)) * scale;
                Ray ray;
                ray.o = Vec3(u(rng), u(rng), u(rng)) * (scale * 30) + Vec3(offset, 0, 0);
                const Vec3 target = v[0] * 0.3f + v[1] * 0.3f + v[2] * 0.4f;
                ray.d = normalize(target - ray.o);
                const RayPre r(ray);
                if (!r.valid) continue;
                float t, b1, b2, err = -1;
                if (!intersect_triangle(r, &v[0].x, kInf, t, b1, b2, &err)) continue;
                const long double te = exact_t(ray, v);
                CHECK(std::fabs((long double)t - te) <= (long double)err);
                ++checked;
            }
        }
    }
    CHECK(checked > 100000);
}

TEST_CASE("a ray spawned from its own triangle, offset as the renderer offsets it, does not hit it again") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int spawned = 0;
    for (int i = 0; i < 20000; ++i) {
        const float scale = std::pow(10.0f, u(rng) * 4);
        Vec3 v[3];
        for (auto& p : v) p = Vec3(u(rng), u(rng), u(rng)) * scale + Vec3(scale * 3, 0, 0);
        const RayPre r(spawned_ray(v, normalize(Vec3(u(rng), u(rng), u(rng)))));
        if (!r.valid) continue;
        float t, b1, b2;
        CHECK_FALSE(intersect_triangle(r, &v[0].x, kInf, t, b1, b2));
        ++spawned;
    }
    CHECK(spawned > 19000);
}

TEST_CASE("rays through a shared edge hit at least one of the two triangles (watertight)") {
    // Two triangles sharing the edge (0,0,0)-(1,1,0), with opposite windings
    // traversed the same way; rays aimed exactly at points of the edge.
    const Vec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    const Vec3 b[3] = {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), w(-1.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        const float s = u(rng);
        const Vec3 on_edge(s, s, 0);
        Ray ray;
        ray.o = Vec3(w(rng) * 3, w(rng) * 3, 2.0f + u(rng));
        ray.d = on_edge - ray.o;
        const RayPre r(ray);
        float t, b1, b2;
        const int hits = int(intersect_triangle(r, &a[0].x, kInf, t, b1, b2)) +
                         int(intersect_triangle(r, &b[0].x, kInf, t, b1, b2));
        CHECK(hits >= 1);
    }
}

// Far from unit scale the float test's products leave float's range (T
// overflows from about 5e12, det falls under 2^-60 below about 1e-9, edges
// underflow below about 1e-19) and intersect_sheared_double finishes the
// test: its t, error bound and spawned-ray rejection must hold there too,
// with the geometric normal that offsets spawned rays (in float its squared
// length overflowed or underflowed at these scales: the normal came out 0 and
// spawned rays re-hit their own triangle).
TEST_CASE("beyond float's products, the double path's t error bound holds and spawned rays do not re-hit") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float scale : {1e-21f, 1e-15f, 1e14f, 1e20f}) {
        int checked = 0, spawned = 0;
        for (int i = 0; i < 5000; ++i) {
            Vec3 v[3];
            const Vec3 base(u(rng) * scale * 10, u(rng) * scale * 10, u(rng) * scale * 10);
            for (auto& p : v) p = base + Vec3(u(rng), u(rng), u(rng)) * scale;
            Ray ray;
            ray.o = Vec3(u(rng), u(rng), u(rng)) * (scale * 30);
            ray.d = normalize(v[0] * 0.3f + v[1] * 0.3f + v[2] * 0.4f - ray.o);
            const RayPre r(ray);
            if (!r.valid) continue;
            float t, b1, b2, err = -1;
            if (intersect_triangle(r, &v[0].x, kInf, t, b1, b2, &err)) {
                const long double te = exact_t(ray, v);
                CHECK(std::fabs((long double)t - te) <= (long double)err);
                ++checked;
            }
            const RayPre ro(spawned_ray(v, normalize(Vec3(u(rng), u(rng), u(rng)))));
            if (!ro.valid) continue;
            INFO("scale ", scale);
            CHECK(std::fabs(length(triangle_normal(v[0], v[1], v[2])) - 1.0f) < 1e-6f);
            CHECK_FALSE(intersect_triangle(ro, &v[0].x, kInf, t, b1, b2));
            ++spawned;
        }
        INFO("scale ", scale);
        CHECK(checked > 4500);
        CHECK(spawned > 4500);
    }
}
