// Ray/cone-frustum intersection for NFF "c" primitives (cylinders when the
// two radii are equal). Open ends, no caps. Evaluated in double.
//
// With axis unit vector h from base B to apex A (height H), slope
// k = (r_apex - r_base) / H and w = o - B, a point at parameter t lies on the
// surface when |w_perp + t d_perp|^2 = (r_base + k s(t))^2 with
// s(t) = (w + t d).h in [0, H].
#pragma once
#include "ray.h"

namespace gw {

struct ConeData {
    Vec3d base, axis;     // axis is unit length
    double height, r0, k; // r(s) = r0 + k s
};

inline bool intersect_cone(const RayPre& r, const ConeData& c, float tmax, float& t_out) {
    const Vec3d w = r.od - c.base;
    const double wh = dot(w, c.axis), dh = dot(r.dd, c.axis);
    const Vec3d wp = w - c.axis * wh, dp = r.dd - c.axis * dh;
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

}  // namespace gw
