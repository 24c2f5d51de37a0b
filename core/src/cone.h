// The NFF cone frustum ("c" primitives; cylinders when the two radii are
// equal), open ends, no caps: bounds, intersection, normal and the hit point
// with its error bound. Evaluated in double.
//
// With axis unit vector h from base B to apex A (height H), slope
// k = (r_apex - r_base) / H and w = o - B, a point at parameter t lies on the
// surface when |w_perp + t d_perp|^2 = (r_base + k s(t))^2 with
// s(t) = (w + t d).h in [0, H].
#pragma once
#include "bounds.h"
#include "ray.h"

namespace gw {

struct ConeData {
    Vec3d base, axis;     // axis is unit length
    double height, r0, k; // r(s) = r0 + k s
};

// The float box of both end circles, rounded outwards.
inline Bounds cone_bounds(const ConeData& c) {
    Bounds b;
    const Vec3d ends[2] = {c.base, c.base + c.axis * c.height};
    const double rad[2] = {c.r0, c.r0 + c.k * c.height};
    for (int e = 0; e < 2; ++e)
        for (int a = 0; a < 3; ++a) {
            const double ext = rad[e] * std::sqrt(std::max(0.0, 1.0 - c.axis[a] * c.axis[a]));
            b.lo[a] = std::min(b.lo[a], next_down(float(ends[e][a] - ext)));
            b.hi[a] = std::max(b.hi[a], next_up(float(ends[e][a] + ext)));
        }
    return b;
}

__attribute__((always_inline)) inline bool intersect_cone(const RayPre& r, const ConeData& c, float tmax, float& t_out) {
    const Vec3d w = r.od() - c.base;
    const double wh = dot(w, c.axis), dh = dot(r.dd(), c.axis);
    const Vec3d wp = w - c.axis * wh, dp = r.dd() - c.axis * dh;
    const double rw = c.r0 + c.k * wh;
    const double a = dot(dp, dp) - c.k * c.k * dh * dh;
    const double b = dot(wp, dp) - c.k * rw * dh;      // half b
    const double cc = dot(wp, wp) - rw * rw;
    double roots[2];
    int n = 0;
    if (a == 0) {
        if (b == 0) return false;
        roots[n++] = -cc / (2 * b);
    } else {
        const double disc = b * b - a * cc;
        if (disc < 0) return false;
        const double q = -(b + std::copysign(std::sqrt(disc), b));
        double t0 = q / a, t1 = q != 0 ? cc / q : 0.0;
        if (t0 > t1) std::swap(t0, t1);
        roots[n++] = t0;
        roots[n++] = t1;
    }
    for (int i = 0; i < n; ++i) {
        const double t = roots[i];
        if (!(t > r.ray.tmin && t < tmax)) continue;
        const double s = wh + t * dh;
        if (s < 0 || s > c.height || c.r0 + c.k * s < 0) continue;
        const float tf = float(t);
        if (!(tf > r.ray.tmin && tf < tmax)) continue;
        t_out = tf;
        return true;
    }
    return false;
}

// Outward unit normal at the ray's parameter t.
inline Vec3 cone_normal(const RayPre& r, float t, const ConeData& c) {
    const Vec3d w = r.od() + r.dd() * double(t) - c.base;
    const double s = dot(w, c.axis);
    const Vec3d perp = w - c.axis * s;
    return Vec3(normalize(perp - c.axis * (c.k * (c.r0 + c.k * s))));
}

// The hit point re-projected onto the surface in double (as for spheres: o + t d
// carries t's rounding error along d, which no per-axis bound on |p| covers),
// and its error bound.
inline void cone_point(const RayPre& r, float t, const ConeData& c, Vec3& p, Vec3& p_err) {
    const Vec3d w = r.od() + r.dd() * double(t) - c.base;
    const double s = std::min(std::max(dot(w, c.axis), 0.0), c.height);
    Vec3d radial = w - c.axis * dot(w, c.axis);
    const double len = length(radial);
    radial = len > 0 ? radial / len : radial;
    p = Vec3(c.base + c.axis * s + radial * (c.r0 + c.k * s));
    p_err = vabs(p) * gamma_bound(3);
}

}  // namespace gw
