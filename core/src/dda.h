// What both grids' walks share: the direction a walk follows, and clipping a
// ray to a box.
#pragma once
#include "ray.h"

namespace gw {

// The direction the DDA follows. Components below 2^-40 of the largest are
// taken as 0: over the whole scene they move the ray by less than 2^-40 of
// its size, far below any cell (whose lists are padded by a thousandth of a
// cell), and their reciprocals would overflow. Rays reach the walks with |d|
// within [2^-64, 2^64] (the integrator's are unit vectors; batch.cpp rescales
// others), so every 1/d of the result is finite. Its zeros are +0.
inline Vec3 dda_d(const Vec3& d) {
    const float m = std::max(std::abs(d.x), std::max(std::abs(d.y), std::abs(d.z)));
    Vec3 out;
    for (int a = 0; a < 3; ++a) out[a] = std::abs(d[a]) >= m * 0x1p-40f ? d[a] : 0.0f;
    return out;
}

// 1/dir in double, inf where dir (dda_d's direction) is 0: what both walks
// step by and clip_to_box_d takes.
// (dda_d's zeros are +0, so 1 / 0 is +inf: no branch.)
inline void dda_inverse(const Vec3& dir, double inv[3]) {
    for (int a = 0; a < 3; ++a) inv[a] = 1.0 / double(dir[a]);
}

// How far along the ray a walk must have gone before it accepts a hit at t:
// t plus 2^-20 of it, above a triangle test's rounding of t (about 2^-24 of
// the distance from the ray's origin), so that a primitive in a later cell
// whose computed t rounds below the hit's is still tested. For the walks whose
// ray parameters are doubles (adaptive_walk.inc, the uniform grid's).
__attribute__((always_inline)) inline double reach(float t) { return double(t) + std::abs(double(t)) * 0x1p-20; }

// Clips [t0, t1] to the box [lo, hi], in double; false when nothing is left.
// dir is the DDA's direction (dda_d) and inv holds 1/dir in double (inf
// where dir is 0). A ray that does not move along an axis keeps its segment
// when its origin lies within that slab. An axis the DDA direction dropped (a
// component below 2^-40 of the largest) is still clipped with the ray's own
// component: inside the box it moves the ray by less than 2^-40 of the box,
// but a ray from far away may travel so far before reaching the box that it
// moves by the box's size or more (origin (0, 1e30, 2), direction
// (1, -1e30, -2) reaches (1, 0, 0) at t = 1).
//
// The box's own interval along the ray is widened by 2^-20 of its ends before
// [t0, t1] is cut to it: a box that holds a primitive must also hold the hits
// its float test reports, which can lie outside it by the test's rounding (a
// ray aimed at a triangle's corner on the box, where double finds the ray
// passing just outside). That rounding is about 2^-24 of the distance from
// the ray's origin.
__attribute__((always_inline)) inline bool clip_to_box_d(const Vec3& lo, const Vec3& hi, const Ray& ray, const Vec3& dir, const double inv[3],
                          double& t0, double& t1) {
    double n = -std::numeric_limits<double>::infinity(), f = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        double tn, tf;
        if (dir[a] == 0) {
            if (ray.d[a] == 0) {
                if (ray.o[a] < lo[a] || ray.o[a] > hi[a]) return false;
                continue;
            }
            tn = (double(lo[a]) - double(ray.o[a])) / double(ray.d[a]);
            tf = (double(hi[a]) - double(ray.o[a])) / double(ray.d[a]);
        } else {
            tn = (double(lo[a]) - double(ray.o[a])) * inv[a];
            tf = (double(hi[a]) - double(ray.o[a])) * inv[a];
        }
        n = std::max(n, std::min(tn, tf));
        f = std::min(f, std::max(tn, tf));
    }
    t0 = std::max(t0, n - std::abs(n) * 0x1p-20);
    t1 = std::min(t1, f + std::abs(f) * 0x1p-20);
    return t0 <= t1;
}

// A ray as the walks follow it, set up once: the DDA direction, its
// reciprocal, and the origin and direction in double.
struct DdaRay {
    Vec3 dir;            // dda_d(ray.d)
    double inv[3];       // 1 / dir, inf where dir is 0
    double o[3], d[3];   // the ray's own origin and direction
    bool moving;         // dir has no zero component (clip() then needs no special case)
    explicit DdaRay(const Ray& ray) : dir(dda_d(ray.d)) {
        dda_inverse(dir, inv);
        for (int a = 0; a < 3; ++a) {
            o[a] = ray.o[a];
            d[a] = ray.d[a];
        }
        moving = dir.x != 0 && dir.y != 0 && dir.z != 0;
    }
    // clip_to_box_d(lo, hi, ray, dir, inv, t0, t1), with the same arithmetic;
    // without its per-axis branches when the ray moves along every axis.
    __attribute__((always_inline)) bool clip(const Vec3& lo, const Vec3& hi, const Ray& ray, double& t0, double& t1) const {
        if (!moving) return clip_to_box_d(lo, hi, ray, dir, inv, t0, t1);
        double n = -std::numeric_limits<double>::infinity(), f = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            const double tn = (double(lo[a]) - o[a]) * inv[a], tf = (double(hi[a]) - o[a]) * inv[a];
            n = std::max(n, std::min(tn, tf));
            f = std::min(f, std::max(tn, tf));
        }
        t0 = std::max(t0, n - std::abs(n) * 0x1p-20);
        t1 = std::min(t1, f + std::abs(f) * 0x1p-20);
        return t0 <= t1;
    }
};

}  // namespace gw
