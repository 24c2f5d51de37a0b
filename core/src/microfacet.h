// GGX (Trowbridge-Reitz) microfacet reflection, the lobe of glossy surfaces
// (roughness > 0) for lamp highlights and for glossy reflection rays, as
// Cycles' Principled and Glossy BSDFs use it:
// * alpha = roughness^2 (Blender's mapping);
// * Smith's height-correlated masking-shadowing G2 = 1 / (1 + L(wo) + L(wi));
// * Schlick's Fresnel per channel from the reflectance at normal incidence f0;
// * glossy rays drawn from the distribution of the normals that wo sees
//   (Heitz 2018), weighted F G2 / G1(wo);
// * Cycles' Multiscatter GGX (its default from Blender 4.0) as the
//   single-scattering lobe times 1 + f0 (1 - E) / E, where E(cos_o, alpha) is
//   the lobe's directional albedo at F = 1 (Turquin 2019): the energy that
//   single scattering loses at high roughness comes back, tinted by f0.
// A lamp's intensity carries the 1 / pi of the diffuse term (lights.h), so
// the highlight's factor is pi x the BRDF x cos_i.
#pragma once
#include <cmath>

#include "math.h"

namespace gw {

inline float ggx_alpha(float roughness) { return std::max(roughness * roughness, 1e-4f); }

// Smith's Lambda of a direction at cosine c (> 0) to the normal.
inline float ggx_lambda(float c, float a2) {
    const float c2 = c * c;
    return 0.5f * (std::sqrt(1 + a2 * std::max(1 - c2, 0.0f) / std::max(c2, 1e-12f)) - 1);
}

// Schlick's Fresnel, rising from f0 at normal incidence to 1 at grazing.
inline Vec3 schlick(const Vec3& f0, float c) {
    const float k = 1 - std::min(std::max(c, 0.0f), 1.0f), k2 = k * k, k5 = k2 * k2 * k;
    return f0 + (Vec3(1, 1, 1) - f0) * k5;
}

// The relative IOR of a dielectric whose reflectance at normal incidence is f0.
inline float dielectric_eta(float f0) {
    const float r = std::sqrt(std::min(std::max(f0, 0.0f), 0.9999f));
    return (1 + r) / (1 - r);
}

// The exact (unpolarised) Fresnel reflectance of light arriving at cosine c
// on a dielectric of relative IOR eta >= 1 (from outside).
inline float fresnel_dielectric(float c, float eta) {
    c = std::min(std::max(c, 0.0f), 1.0f);
    const float g = std::sqrt(std::max(eta * eta - 1 + c * c, 0.0f));
    if (!(g > 0)) return 1;   // (grazing on an IOR that rounds to 1: the limit, where 0 / 0 would be NaN)
    const float a = (g - c) / (g + c), b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return 0.5f * a * a * (1 + b * b);
}

// A surface's reflectance as two shares: a mirror of weight `mirror`, its
// Schlick curve rising from `tint` (a metal's colour), and a dielectric of
// weight `dielectric` (what is not metal, or a layer of it), the exact
// Fresnel of the IOR whose reflectance at normal incidence is f0 (Cycles'
// Principled BSDF, whose Specular IOR Level scales that f0, does the same).
struct Fresnel {
    Vec3 tint;
    float mirror = 0, f0 = 0, dielectric = 0;
};

// The lobe's directional albedo at F = 1 for a view at cosine cos_o
// (a table over cos_o and roughness, integrated once).
float ggx_albedo(float cos_o, float alpha);

// The lobe's directional albedo with the exact Fresnel of the dielectric of
// reflectance f0 at normal incidence at each microfacet (single scattering;
// a table over cos_o, roughness and 8 values of f0, interpolated linearly in
// f0, integrated on first use).
float ggx_dielectric_albedo(float cos_o, float alpha, float f0);

// What a rough dielectric interface returns of a white world, reflection and refraction
// together, single scattering (Integrator::rough_glass), seen from cos_o; eta: the index beyond
// the surface over the view's side's (a table over cos_o, roughness and 17 values of eta in
// [1/3, 3], integrated on first use). Multiscatter glass divides by it.
float ggx_glass_albedo(float cos_o, float alpha, float eta);

// Multiscatter GGX's factor on the single-scattering lobe is 1 + f0 g, with
// this gain g = (1 - E) / E.
inline float ggx_multiscatter_gain(float cos_o, float alpha) {
    const float e = ggx_albedo(cos_o, alpha);
    return (1 - e) / e;
}

// What a lobe seen from wo (unit, ns the shading normal) fixes for every
// light sample or ray of a shading point: set up once, not per sample.
struct GgxView {
    Vec3 ns, wo, tint, mirror_scale;  // the scales: each share's weight times its multiscatter factor
    float eta = 1, dielectric_scale = 0, a2 = 0, cos_o = 0, s_o = 0;
    bool seen = false;                // wo above the lobe's normal
};

// sqrt(c^2 + a2 (1 - c^2)): Smith's 1 + 2 Lambda = this / c.
inline float ggx_smith_root(float c, float a2) { return std::sqrt(c * c + a2 * std::max(1 - c * c, 0.0f)); }

inline GgxView ggx_view(const Vec3& ns, const Vec3& wo, float alpha, const Fresnel& f, bool multiscatter) {
    GgxView v;
    v.cos_o = dot(ns, wo);
    v.seen = v.cos_o > 0;
    if (!v.seen) return v;
    v.ns = ns, v.wo = wo, v.tint = f.tint, v.a2 = alpha * alpha;
    v.s_o = ggx_smith_root(v.cos_o, v.a2);
    const float gain = multiscatter ? ggx_multiscatter_gain(v.cos_o, alpha) : 0.0f;
    v.mirror_scale = (Vec3(1, 1, 1) + f.tint * gain) * f.mirror;
    v.dielectric_scale = (1 + f.f0 * gain) * f.dielectric;
    v.eta = dielectric_eta(f.f0);
    return v;
}

// The lobe's Fresnel (with multiscatter's factors) where light meets the microfacets at cosine c.
inline Vec3 ggx_fresnel(const GgxView& v, float c) {
    const float d = v.dielectric_scale > 0 ? fresnel_dielectric(c, v.eta) * v.dielectric_scale : 0.0f;
    return schlick(v.tint, c) * v.mirror_scale + Vec3(d, d, d);
}

// The lobe's albedo for the view, with Fresnel at the view's angle (and the
// multiscatter factor): what it reflects of light arriving from all around
// its mirror direction.
inline Vec3 ggx_albedo_fresnel(const GgxView& v) {
    return ggx_fresnel(v, v.cos_o) * ggx_albedo(v.cos_o, std::sqrt(v.a2));
}

// The highlight of a light from wi (unit): F D G2 pi / (4 cos_o) (times the
// multiscatter factor), times the light's intensity. With S = sqrt(c^2 +
// a2 (1 - c^2)) on each side, G2 = 2 c_o c_i / (S_o c_i + S_i c_o) and
// pi D = a2 / k^2, k = sin^2 h + a2 cos^2 h, so the whole is
// a2 c_i / (2 k^2 (S_o c_i + S_i c_o)): one division.
inline Vec3 ggx_highlight(const GgxView& v, const Vec3& wi) {
    const float cos_i = dot(v.ns, wi);
    if (!v.seen || !(cos_i > 0)) return Vec3();
    const Vec3 sum = wi + v.wo;                  // along h, |sum| in (0, 2]
    const float len2 = dot(sum, sum);
    if (!(len2 > 1e-12f)) return Vec3();
    const Vec3 side = cross(v.ns, sum);
    // (both x |sum|: k below is x len2; the sine from a cross product, as 1 - cos^2 in float
    // loses the lobes whose alpha^2 is under 1e-4)
    const float cos_h = dot(v.ns, sum), sin2_h = dot(side, side);
    const float k = sin2_h + cos_h * cos_h * v.a2;
    const float s_i = ggx_smith_root(cos_i, v.a2);
    const float q = len2 / k;   // (k alone squared underflows for alpha under 3e-4 at grazing cosines)
    const float value = (v.a2 * q) * (q * cos_i) / (2 * (v.s_o * cos_i + s_i * v.cos_o));
    return ggx_fresnel(v, dot(wi, sum) / std::sqrt(len2)) * value;
}

// The density (per unit solid angle) with which the lobe's rays (ggx_visible_normal, then the
// mirror direction about that normal) take the direction wi (unit): D G1(wo) / (4 cos_o), that is
// a2 / (2 pi k^2 (cos_o + S_o)) with k as in ggx_highlight. 0 below the lobe's normal.
inline float ggx_pdf(const GgxView& v, const Vec3& wi) {
    if (!v.seen || !(dot(v.ns, wi) > 0)) return 0;
    const Vec3 sum = wi + v.wo;
    const float len2 = dot(sum, sum);
    if (!(len2 > 1e-12f)) return 0;
    const Vec3 side = cross(v.ns, sum);
    const float cos_h = dot(v.ns, sum), k = dot(side, side) + cos_h * cos_h * v.a2;
    const float q = len2 / k;
    return (v.a2 * q) * q / (float(2 * kPi) * (v.cos_o + v.s_o));
}

// A microfacet normal seen from wo, drawn from the visible normals'
// distribution, in the frame whose z is the normal (wo.z > 0); u1, u2 in [0, 1).
inline Vec3 ggx_visible_normal(const Vec3& wo, float alpha, float u1, float u2) {
    // The view in the frame where the lobe is a hemisphere (stretched by 1 / alpha).
    const Vec3 v = normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
    const float lsq = v.x * v.x + v.y * v.y;
    const Vec3 t1 = lsq > 0 ? Vec3(-v.y, v.x, 0) / std::sqrt(lsq) : Vec3(1, 0, 0);
    const Vec3 t2 = cross(v, t1);
    // A point on the disk, its half behind the view squashed to the projected hemisphere.
    const float r = std::sqrt(u1), phi = float(2 * kPi) * u2;
    const float p1 = r * std::cos(phi), s = 0.5f * (1 + v.z);
    const float p2 = (1 - s) * std::sqrt(std::max(1 - p1 * p1, 0.0f)) + s * r * std::sin(phi);
    const Vec3 n = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(1 - p1 * p1 - p2 * p2, 0.0f));
    return normalize(Vec3(alpha * n.x, alpha * n.y, std::max(n.z, 0.0f)));
}

// G2 / G1(wo): the weight of a glossy ray drawn with ggx_visible_normal (before Fresnel).
inline float ggx_ray_weight(float cos_o, float cos_i, float alpha) {
    if (!(cos_i > 0)) return 0;
    const float a2 = alpha * alpha, lo = ggx_lambda(cos_o, a2);
    return (1 + lo) / (1 + lo + ggx_lambda(cos_i, a2));
}

}  // namespace gw
