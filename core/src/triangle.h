// The triangle: bounds, watertight intersection, normals and the hit point
// with its error bound.
//
// Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013).
// Shared edges are evaluated with bit-identical edge functions in both
// triangles, so a ray through an edge or vertex of a closed mesh cannot slip
// through. When an edge function is exactly zero it is recomputed in double,
// as the paper recommends, so the tie is decided consistently.
#pragma once
#include "bounds.h"
#include "ray.h"

namespace gw {

inline Bounds triangle_bounds(const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    Bounds b;
    b.grow(v0); b.grow(v1); b.grow(v2);
    return b;
}

// Unit geometric normal; its side follows the winding v0 -> v1 -> v2. The
// edges are scaled by powers of two (exact, see scaled_to_unit) before their
// cross product, whose squared length otherwise overflowed for edges from
// about 4e9 and underflowed below about 1e-10 (the normal came out 0 or
// garbage, and spawned rays re-hit their own triangle). Bit-identical to the
// plain formula wherever that stays in range.
inline Vec3 triangle_normal(const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    int e1, e2;
    return normalize(cross(scaled_to_unit(v1 - v0, e1), scaled_to_unit(v2 - v0, e2)));
}

// The point with barycentrics (b1, b2) of v1, v2, and a conservative bound of
// its rounding error (pbrt-v3 3.9.3).
inline void triangle_point(const Vec3& v0, const Vec3& v1, const Vec3& v2, float b1, float b2, Vec3& p,
                           Vec3& p_err) {
    const float b0 = 1.0f - b1 - b2;
    const Vec3 a = v0 * b0, b = v1 * b1, c = v2 * b2;
    p = a + b + c;
    p_err = (vabs(a) + vabs(b) + vabs(c)) * gamma_bound(7);
}

// Vertex normals interpolated at (b1, b2); false where they cancel out (the
// caller then keeps the geometric normal).
inline bool triangle_shading_normal(const Vec3& n0, const Vec3& n1, const Vec3& n2, float b1, float b2, Vec3& ns) {
    const float b0 = 1.0f - b1 - b2;
    const Vec3 n = n0 * b0 + n1 * b1 + n2 * b2;
    const float len = length(n);
    if (!(len > 0 && std::isfinite(len))) return false;
    ns = n / len;
    return true;
}

// The watertight test's second half in double, from the sheared corners
// (Ax .. Ckz, floats, the same for every triangle sharing a corner): for
// triangles whose float products leave float's range. T is a cubic in the
// corners' coordinates relative to the ray's origin: from about 5e12 it
// overflows, and below about 1e-9 its digits go (det under 2^-60), which made
// such triangles invisible. The edge functions, det and T are exact or nearly
// so in double over the whole float range. (Out of line, and the only call
// from the walks' hot code into plain x86-64 code: inlined, it cost the
// 8-wide tests 2% more instructions in registers it took; it runs only for
// such triangles.)
__attribute__((noinline, cold)) inline bool intersect_sheared_double(const RayPre& r, float Ax, float Ay, float Bx,
                                                                    float By, float Cx, float Cy, float Akz,
                                                                    float Bkz, float Ckz, float tmax, float& t_out,
                                                                    float& b1, float& b2, float* t_err) {
    double U = double(Cx) * double(By) - double(Cy) * double(Bx);
    double V = double(Ax) * double(Cy) - double(Ay) * double(Cx);
    double W = double(Bx) * double(Ay) - double(By) * double(Ax);
    if (std::min(U, std::min(V, W)) < 0 && std::max(U, std::max(V, W)) > 0) return false;
    double det = U + V + W;
    if (!(det != 0)) return false;
    const double sz = double(r.sz);
    const double Az = sz * double(Akz), Bz = sz * double(Bkz), Cz = sz * double(Ckz);
    double T = U * Az + V * Bz + W * Cz;
    if (det < 0) { det = -det; T = -T; U = -U; V = -V; W = -W; }
    const float t = float(T / det);
    if (!(t > r.ray.tmin && t < tmax)) return false;
    if (r.ray.spawned || t_err) {   // the float test's bound (below), in double
        const double max_zt = std::max(std::abs(Az), std::max(std::abs(Bz), std::abs(Cz)));
        const double max_xt = std::max(std::abs(double(Ax)), std::max(std::abs(double(Bx)), std::abs(double(Cx))));
        const double max_yt = std::max(std::abs(double(Ay)), std::max(std::abs(double(By)), std::abs(double(Cy))));
        const double dz = gamma_bound(3) * max_zt;
        const double dx = gamma_bound(5) * (max_xt + max_zt), dy = gamma_bound(5) * (max_yt + max_zt);
        const double de = 2.0 * (gamma_bound(2) * max_xt * max_yt + dy * max_xt + dx * max_yt);
        const double max_e = std::max(std::abs(U), std::max(std::abs(V), std::abs(W)));
        const float dt = float(3.0 * (gamma_bound(3) * max_e * max_zt + de * max_zt + dz * max_e) / det);
        if (t_err) *t_err = dt;
        if (r.ray.spawned && !(t > dt)) return false;
    }
    t_out = t;
    b1 = float(V / det);
    b2 = float(W / det);
    return true;
}

// Returns true and sets t, b1, b2 (barycentrics of v1, v2) for a hit with
// tmin < t < tmax. Triangles are two-sided.
// v points at the triangle's 9 coordinates (v0, v1, v2), read in the ray's
// permuted axis order straight from memory.
// t_err, when given, receives the bound on t's rounding error (computed for
// every ray that reaches it, spawned or not; the unit tests check it).
__attribute__((always_inline)) inline bool intersect_triangle(const RayPre& r, const float* v, float tmax, float& t_out, float& b1, float& b2,
                               float* t_err = nullptr) {
    const float Akz = v[r.kz] - r.oz, Bkz = v[3 + r.kz] - r.oz, Ckz = v[6 + r.kz] - r.oz;
    const float Ax = (v[r.kx] - r.ox) - r.sx * Akz, Ay = (v[r.ky] - r.oy) - r.sy * Akz;
    const float Bx = (v[3 + r.kx] - r.ox) - r.sx * Bkz, By = (v[3 + r.ky] - r.oy) - r.sy * Bkz;
    const float Cx = (v[6 + r.kx] - r.ox) - r.sx * Ckz, Cy = (v[6 + r.ky] - r.oy) - r.sy * Ckz;
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    // Exactly zero (or a product that underflows, which only costs the
    // recompute): decide the edge in double.
    if (U * V * W == 0.0f) {
        const double Ud = double(Cx) * double(By) - double(Cy) * double(Bx);
        const double Vd = double(Ax) * double(Cy) - double(Ay) * double(Cx);
        const double Wd = double(Bx) * double(Ay) - double(By) * double(Ax);
        U = float(Ud);
        V = float(Vd);
        W = float(Wd);
        // An edge below float's range (coordinates under about 1e-19), or a
        // det too small for T's digits (under about 1e-9; then U V W
        // underflows and every such test comes here, the SIMD lanes' too):
        // all in double.
        const double sum = Ud + Vd + Wd;
        if (__builtin_expect((U == 0 && Ud != 0) || (V == 0 && Vd != 0) || (W == 0 && Wd != 0) ||
                                 (sum != 0 && std::abs(sum) < 0x1p-60), 0))
            return intersect_sheared_double(r, Ax, Ay, Bx, By, Cx, Cy, Akz, Bkz, Ckz, tmax, t_out, b1, b2, t_err);
    }
    if (std::min(U, std::min(V, W)) < 0 && std::max(U, std::max(V, W)) > 0) return false;
    float det = U + V + W;
    if (det == 0.0f) return false;
    const float Az = r.sz * Akz, Bz = r.sz * Bkz, Cz = r.sz * Ckz;
    float T = U * Az + V * Bz + W * Cz;
    if (det < 0) { det = -det; T = -T; U = -U; V = -V; W = -W; }
    // The hit is decided on t itself (not on T against tmax * det, whose
    // rounding differs), so the nearest of several hits does not depend on
    // the order they are tested in.
    const float inv = 1.0f / det;
    const float t = T * inv;
    // T or det overflowed (coordinates from about 5e12): t is inf, NaN or
    // (det inf, T finite) 0, and is worked out in double (the SIMD lanes
    // hand these triangles here).
    constexpr float kMax = std::numeric_limits<float>::max();
    if (!(t > r.ray.tmin && t < tmax)) {
        if (__builtin_expect(!(std::abs(T) <= kMax && det <= kMax), 0))
            return intersect_sheared_double(r, Ax, Ay, Bx, By, Cx, Cy, Akz, Bkz, Ckz, tmax, t_out, b1, b2, t_err);
        return false;
    }
    if (__builtin_expect(!(det <= kMax), 0))   // (t = 0 accepted by a negative tmin)
        return intersect_sheared_double(r, Ax, Ay, Bx, By, Cx, Cy, Akz, Bkz, Ckz, tmax, t_out, b1, b2, t_err);
    // Conservative bound on the rounding error of t (pbrt-v3 3.9.6): for a
    // ray leaving a surface, a hit closer than the bound may be that surface,
    // so it is rejected. This is what keeps a ray spawned exactly on a
    // triangle (zero position error, e.g. an axis-aligned floor) from
    // re-hitting it.
    if (r.ray.spawned || t_err) {
        const float max_zt = std::max(std::abs(Az), std::max(std::abs(Bz), std::abs(Cz)));
        const float max_xt = std::max(std::abs(Ax), std::max(std::abs(Bx), std::abs(Cx)));
        const float max_yt = std::max(std::abs(Ay), std::max(std::abs(By), std::abs(Cy)));
        const float dz = gamma_bound(3) * max_zt;
        const float dx = gamma_bound(5) * (max_xt + max_zt), dy = gamma_bound(5) * (max_yt + max_zt);
        const float de = 2.0f * (gamma_bound(2) * max_xt * max_yt + dy * max_xt + dx * max_yt);
        const float max_e = std::max(std::abs(U), std::max(std::abs(V), std::abs(W)));
        const float dt = 3.0f * (gamma_bound(3) * max_e * max_zt + de * max_zt + dz * max_e) * inv;
        if (t_err) *t_err = dt;
        if (r.ray.spawned && !(t > dt)) return false;
    }
    t_out = t;
    b1 = V * inv;
    b2 = W * inv;
    return true;
}

}  // namespace gw
