// The sphere, an analytic primitive: bounds, intersection, normal and the
// hit point with its error bound.
//
// Intersection is numerically careful (Haines et al., Ray Tracing Gems
// ch. 7): the discriminant is formed from the ray's closest approach to the
// centre (here |f x d|^2, f the origin relative to the centre), which
// keeps its precision when the ray passes far from the centre relative to r,
// and the near root comes from c/q to avoid cancellation. Evaluated in
// double, so a 1e-3 sphere seen from 1e4 away is still resolved.
#pragma once
#include "bounds.h"
#include "ray.h"

namespace gw {

// The float box, rounded outwards so that it contains the exact sphere.
inline Bounds sphere_bounds(const Vec3& center, float radius) {
    Bounds b;
    const Vec3 r(radius, radius, radius);
    b.lo = center - r;
    b.hi = center + r;
    for (int a = 0; a < 3; ++a) { b.lo[a] = next_down(b.lo[a]); b.hi[a] = next_up(b.hi[a]); }
    return b;
}

__attribute__((always_inline)) inline bool intersect_sphere(const RayPre& r, const Vec3& center, float radius, float tmax, float& t_out) {
    const Vec3d c(center);
    const double R = radius;
    const Vec3d f = r.od() - c;
    const Vec3d d = r.dd();
    const double a = dot(d, d);
    // b^2 - a c = a (r^2 - |l|^2), l the closest-approach offset, and a |l|^2 =
    // |f x d|^2: the same stable discriminant without dividing by a (a
    // miss, most tests in a grid, ends here).
    const Vec3d fxd = cross(f, d);
    const double disc = a * (R * R) - dot(fxd, fxd);
    if (disc < 0) return false;
    const double b = dot(f, d);                          // half the usual b
    const double cc = dot(f, f) - R * R;
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double t0 = q != 0 ? cc / q : 0.0, t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
    const double lo = r.ray.tmin, hi = tmax;
    double t = t0;
    if (!(t > lo && t < hi)) {
        t = t1;
        if (!(t > lo && t < hi)) return false;
    }
    const float tf = float(t);
    if (!(tf > r.ray.tmin && tf < tmax)) return false;
    t_out = tf;
    return true;
}

// Outward unit normal at the ray's parameter t (in double).
inline Vec3 sphere_normal(const RayPre& r, float t, const Vec3& center) {
    const Vec3d p = r.od() + r.dd() * double(t);
    return Vec3(normalize(p - Vec3d(center)));
}

// The hit point re-projected onto the surface along the normal n (exact to
// double precision, then rounded once to float), and its error bound.
inline void sphere_point(const Vec3& center, float radius, const Vec3& n, Vec3& p, Vec3& p_err) {
    const Vec3d c(center);
    p = Vec3(c + Vec3d(n) * double(radius));
    p_err = vabs(p) * gamma_bound(3);
}

}  // namespace gw
