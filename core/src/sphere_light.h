// Sphere lights (Blender's point lights with a radius, and spots with one) in
// the two forms Cycles gives them, chosen by Blender's Soft Falloff (4.0+):
//
// - Soft (Soft Falloff on, Blender's default, and every Blender before 4.0):
//   a Lambertian disk of the sphere's radius through its centre, turned to
//   face the shading point: the sphere's radiance over the disk's cone, a
//   little narrower than the sphere's. Near the lamp it lights less than a
//   point light would: a floor point at distance d straight below it gets
//   I / d^2 times d^2 / (d^2 + r^2), and a surface the sphere cuts through
//   gets no sharp edge. Rays that look at the lamp from o see the disk facing
//   o, so that its light points and the rays that meet it estimate the same
//   light (multiple importance sampling weighs one against the other).
// - Uniform (Soft Falloff off): a sphere of uniform radiance. A point that
//   sees all of it gets what a point light at its centre would give (I / d^2,
//   the shell theorem); its light points are directions spread uniformly over
//   the cone the sphere subtends, so they are exact where the sphere dips below
//   a surface's horizon too.
//
// docs/blender.md has the measurements against Cycles. Radiances are in a
// camera ray's units: pi x the light's colour over the disk's area pi r^2
// (lights carry the diffuse BRDF's 1 / pi; blender_addon/export/lights.py).
#pragma once
#include "math.h"
#include "sampler.h"

namespace gw {

// Soft: the point (u1, u2) of the disk of radius r whose normal is n (unit,
// from its centre towards the lit point), from its centre. Its light points
// weigh the cosine there, -n . wi.
inline Vec3 soft_disk_offset(const Vec3& n, float r, float u1, float u2) {
    Vec3 t, b;
    basis(n, t, b);
    float x, y;
    concentric_disk(u1, u2, x, y);
    return (t * x + b * y) * r;
}

// Soft: where the ray o + t d (d unit) meets the disk of radius r through c
// facing o, and the radiance it sees there. (In double: the light may be small and far.)
inline bool soft_disk_hit(const Vec3& c, float r, const Vec3& color, const Vec3& o, const Vec3& d, float& t,
                          Vec3& radiance) {
    const Vec3d n = normalize(Vec3d(o) - Vec3d(c)), dd(d);
    const double facing = dot(dd, n);
    if (!(facing < 0)) return false;
    const double hit = dot(Vec3d(c) - Vec3d(o), n) / facing;
    const Vec3d q = Vec3d(o) + dd * hit - Vec3d(c);
    const double r2 = double(r) * r;
    if (!(hit > 0) || !(dot(q, q) <= r2)) return false;
    t = float(hit);
    radiance = color * float(1.0 / r2);
    return true;
}

// Soft: the density, per unit solid angle at p, of the disk's light points
// (uniform on its area) in direction wi (unit); 0 where wi misses the disk.
inline double soft_disk_density(const Vec3& c, float r, const Vec3& p, const Vec3& wi) {
    const Vec3d n = normalize(Vec3d(p) - Vec3d(c)), w(wi);
    const double facing = dot(w, n);
    if (!(facing < 0)) return 0;
    const double t = dot(Vec3d(c) - Vec3d(p), n) / facing;
    const Vec3d q = Vec3d(p) + w * t - Vec3d(c);
    const double r2 = double(r) * r;
    if (!(t > 0) || !(dot(q, q) <= r2)) return 0;
    return t * t / (kPi * r2 * -facing);
}

// Uniform: where the ray o + t d (d unit) meets the sphere of radius r
// around c (its near side, or from inside its far side), and its radiance.
inline bool sphere_hit(const Vec3& c, float r, const Vec3& color, const Vec3& o, const Vec3& d, float& t,
                       Vec3& radiance) {
    const Vec3d oc = Vec3d(o) - Vec3d(c), dd(d);
    const double b = dot(oc, dd), k = dot(oc, oc) - double(r) * double(r);
    const double disc = b * b - k;
    if (!(disc >= 0)) return false;
    const double root = std::sqrt(disc), near = -b - root, far = -b + root;
    const double hit = near > 0 ? near : far;
    if (!(hit > 0)) return false;
    t = float(hit);
    radiance = color * float(1.0 / (double(r) * double(r)));
    return true;
}

// Uniform: 1 - cos of the half angle of the cone that the sphere (radius^2
// r2) subtends at distance^2 d2 > r2 (without the cancellation of 1 - cos).
inline double sphere_cone_width(double d2, double r2) {
    const double sin2 = r2 / d2;
    return sin2 / (1 + std::sqrt(1 - sin2));
}

// Uniform: the direction wi to the light point (u1, u2) of the sphere of
// radius r around c seen from p, the distance to it, and the factor of the
// light's colour it brings: directions uniform in the cone the sphere
// subtends (the colour's radiance, colour / (pi r^2), over their density);
// from inside the sphere, which fills the whole sky, cosine-weighted about
// the shading normal n (a diffuse surface then gets the same light from every
// point). (0.5, 0.5), hard shadows, is its centre's direction with a point
// light's 1 / d^2 (exact for a point that sees the whole sphere), as the soft
// disk's centre. False at the centre itself and below the horizon.
inline bool sample_sphere_cap(const Vec3& c, float r, const Vec3& p, const Vec3& n, float u1, float u2, Vec3& wi,
                              float& dist, double& scale) {
    const Vec3d to = Vec3d(c) - Vec3d(p);
    const double d2 = dot(to, to), r2 = double(r) * r;
    if (!(d2 > 0)) return false;
    const double d = std::sqrt(d2);
    const Vec3d axis = to / d;
    if (u1 == 0.5f && u2 == 0.5f) {
        wi = Vec3(axis);
        dist = float(d2 > r2 ? d - r : d);
        scale = 1 / d2;
        return true;
    }
    if (d2 > r2) {
        const double width = sphere_cone_width(d2, r2), below = double(u1) * width;   // 1 - cos
        const double ct = 1 - below, st = std::sqrt(std::max(0.0, below * (2 - below))), phi = 2 * kPi * double(u2);
        Vec3 t, b;
        basis(Vec3(axis), t, b);
        const Vec3d w = normalize(axis * ct + (Vec3d(t) * std::cos(phi) + Vec3d(b) * std::sin(phi)) * st);
        wi = Vec3(w);
        dist = float(d * ct - std::sqrt(std::max(0.0, r2 - d2 * st * st)));
        scale = 2 * width / r2;
        return true;
    }
    Vec3 t, b;
    basis(n, t, b);
    float x, y;
    concentric_disk(u1, u2, x, y);
    const double z = std::sqrt(std::max(0.0, 1.0 - double(x) * x - double(y) * y));
    if (!(z > 0)) return false;
    const Vec3d w = normalize(Vec3d(t) * double(x) + Vec3d(b) * double(y) + Vec3d(n) * z);
    const double along = -dot(to, w);
    wi = Vec3(w);
    dist = float(-along + std::sqrt(std::max(0.0, along * along - (d2 - r2))));
    scale = 1 / (r2 * z);
    return true;
}

// Uniform: the density, per unit solid angle at p (shading normal n), of
// sample_sphere_cap's directions in direction wi (unit). Whether wi lies in the cone is decided
// by its distance from the centre, |to x wi|, not by its cosine, which a
// float direction cannot resolve for a small or far lamp (its cone's 1 - cos
// of 1e-7 at an angular radius of 5e-4), with a slack of 2^-22 of d for the
// float direction's own rounding (the sampled directions must all count).
inline double sphere_cap_density(const Vec3& c, float r, const Vec3& p, const Vec3& n, const Vec3& wi) {
    const Vec3d to = Vec3d(c) - Vec3d(p), w = normalize(Vec3d(wi));
    const double d2 = dot(to, to), r2 = double(r) * r;
    if (!(d2 > r2)) return std::max(dot(Vec3d(n), w), 0.0) / kPi;
    const Vec3d off = cross(to, w);
    const double reach = double(r) + std::sqrt(d2) * 0x1p-22;
    return dot(w, to) > 0 && dot(off, off) <= reach * reach ? 1 / (2 * kPi * sphere_cone_width(d2, r2)) : 0;
}

}  // namespace gw
