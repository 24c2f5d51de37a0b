// Flat lights (rect, disk, ellipse) near the shading point (within twice the
// diagonal of the rectangle sampled: the light, or its bounding rectangle, from its
// centre; Blender's lights, with physical falloff). Uniform points on such a
// light weigh cos / distance^2, which explodes as the point nears it (a light
// 0.05 above a floor gave pixels 200 times Cycles' brightest), so these are
// sampled here instead, by two strategies:
// * points uniform in the solid angle the light subtends (SphericalRect):
//   each weighs radiance x cos x solid angle, never more than radiance x 2 pi.
//   A disk or an ellipse is sampled over its bounding rectangle, the points
//   outside it weighing 0 (at most a quarter of them, fewer where it fills
//   the view);
// * for a light that fills nearly all of the view (a large light just above a
//   floor), directions drawn cosine-weighted about the shading normal that
//   happen to meet the light, mixed with the above: each light point picks one
//   of the two (one-sample multiple importance sampling, Veach 1997, with the
//   balance heuristic), the cosine-weighted one with probability `share`. The
//   same light points, the same shadow rays.
//
// Why the mix: by solid angle each point weighs by the cosine at the shading
// point, which varies from 0 to 1 over a light filling the hemisphere (the
// estimate's coefficient of variation per sample tends to 0.58); drawn by the
// cosine, the directions that meet such a light all weigh alike. A 50 m light
// 3 m above a floor gave its pixels a standard deviation of a fifth of their
// mean at Blender's default samples, where Cycles (which mixes the same two
// strategies) is smooth.
//
// When: the cosine-weighted directions that miss the light bring nothing, and
// those losses cost more than the cosine's spread saves unless the light
// covers almost all of the cosine's weight. Integrated numerically for a point
// under square lights, the coefficient of variation per sample:
// P = 0.83 (the light's projected solid angle over pi): solid angle alone
// 0.245, any mix worse; P = 0.92: 0.32 alone, 0.27 mixed; P = 0.95: 0.37 and
// 0.22; P = 0.99: 0.50 and 0.08; P = 0.999: 0.54 and 0.04. So the mix starts
// at P = 0.9, with share P^4 (the best share found rises from 0.85 at
// P = 0.95 to 0.99 at 0.999), at most 0.98.
#pragma once
#include <cmath>
#include <limits>

#include "lights.h"

namespace gw {

// A rectangle w x h in a light's (axis_u, axis_v) plane around its position,
// sampled uniformly in the solid angle it subtends at p by Urena, Fajardo and
// King's area-preserving map of the spherical rectangle (EGSR 2013), in double.
struct SphericalRect {
    Vec3d x, y, z;      // the light's axes, z towards p's side
    Vec3d d;            // from p to the corner (-w/2, -h/2)
    double w = 0, h = 0, x0 = 0, y0 = 0, x1 = 0, y1 = 0, z0 = 0;
    double S = 0;       // the solid angle
    double k = 0, b0 = 0, b1 = 0;

    // -1 where this does not apply (the light is far, not facing along its
    // direction, or of zero size: the caller samples its area), 0 where p gets
    // no light, 1 when set up.
    int setup(const Light& L, double w_, double h_, const Vec3& p) {
        w = w_;
        h = h_;
        x = Vec3d(L.axis_u);
        y = Vec3d(L.axis_v);
        const Vec3d o(p), c(L.position), dir(L.direction);
        z = cross(x, y);
        if (!(w > 0 && h > 0) || !L.inverse_square || std::abs(dot(x, y)) > 1e-6 || std::abs(dot(dir, z)) < 1 - 1e-6)
            return -1;
        const Vec3d to_centre = c - o;
        if (dot(to_centre, to_centre) > 4.0 * (w * w + h * h)) return -1;
        if (!(dot(dir, to_centre) < 0)) return 0;     // behind the light (or in its plane): one-sided emitter
        d = to_centre - x * (0.5 * w) - y * (0.5 * h);
        x0 = dot(d, x);
        y0 = dot(d, y);
        x1 = x0 + w;
        y1 = y0 + h;
        z0 = dot(d, z);
        if (z0 > 0) {
            z0 = -z0;
            z = -z;
        }
        if (!(z0 < 0)) return 0;
        // The inward normals of the four great circles through the rectangle's
        // edges, the spherical rectangle's inner angles, and its area S.
        const Vec3d n0 = Vec3d(0, z0, -y0) / std::sqrt(z0 * z0 + y0 * y0);
        const Vec3d n1 = Vec3d(-z0, 0, x1) / std::sqrt(z0 * z0 + x1 * x1);
        const Vec3d n2 = Vec3d(0, -z0, y1) / std::sqrt(z0 * z0 + y1 * y1);
        const Vec3d n3 = Vec3d(z0, 0, -x0) / std::sqrt(z0 * z0 + x0 * x0);
        const auto angle = [](const Vec3d& a, const Vec3d& b) { return std::acos(std::clamp(-dot(a, b), -1.0, 1.0)); };
        const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
        k = 2 * kPi - g2 - g3;
        S = g0 + g1 - k;
        b0 = n0.z;
        b1 = n2.z;
        return S > 0 ? 1 : 0;
    }

    // The point for (u1, u2), uniform in solid angle: s.dist and s.wi, and
    // (cx, cy) its coordinates along axis_u and axis_v from the centre.
    // False where it lies at p.
    bool sample(float u1, float u2, LightSample& s, double& cx, double& cy) const {
        // u1 picks the x that splits off that fraction of S, u2 a y along the
        // chord at that x, uniform in solid angle.
        const double au = double(u1) * S + k;
        const double fu = (std::cos(au) * b0 - b1) / std::sin(au);
        const double cu = std::clamp((fu > 0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0 * b0), -1.0, 1.0);
        const double xu = std::clamp(-(cu * z0) / std::sqrt(std::max(1.0 - cu * cu, 1e-300)), x0, x1);
        const double dd = std::sqrt(xu * xu + z0 * z0);
        const double h0 = y0 / std::sqrt(dd * dd + y0 * y0), h1 = y1 / std::sqrt(dd * dd + y1 * y1);
        const double hv = h0 + double(u2) * (h1 - h0), hv2 = hv * hv;
        const double yv = std::clamp(hv2 < 1.0 - 1e-12 ? hv * dd / std::sqrt(1.0 - hv2) : y1, y0, y1);
        const Vec3d q = d + x * (xu - x0) + y * (yv - y0);   // the point on the light, from p (in its plane)
        const double dist = length(q);
        if (!(dist > 0)) return false;
        s.dist = float(dist);
        s.wi = Vec3(q / dist);
        cx = xu - x0 - 0.5 * w;
        cy = yv - y0 - 0.5 * h;
        return true;
    }
};

// The rectangle sampled, for a rect light: the light itself; for a disk or
// an ellipse, its bounding rectangle.
inline double sampled_width(const Light& L) { return L.kind == LightKind::Disk ? 2.0 * L.radius : L.size[0]; }
inline double sampled_height(const Light& L) { return L.kind == LightKind::Disk ? 2.0 * L.radius : L.size[1]; }

constexpr double kMixFrom = 0.9;          // the projected share P from which the strategies mix
constexpr double kMaxCosineShare = 0.98;  // the light's own points keep at least this much of the samples

struct NearArea {
    SphericalRect rect;   // the sampled rectangle (a disk's bounding square) as seen from the point
    double share = 0;     // the probability of a cosine-weighted direction (0: the light's points only)
    double area = 0;      // the light's
};

// The share of the cosine-weighted directions about n that meet the polygon
// corner[0..k) (seen from p): its projected solid angle over pi, by Lambert's
// formula. The sum is oriented by its value about m, which points from p
// into the polygon's plane (the whole polygon lies in front of m, so that sum
// has the outline's sign); parts below n's horizon count negatively, so the
// share errs low, never high.
inline double projected_share(const Vec3d* corner, int k, const Vec3d& n, const Vec3d& m) {
    double sum_n = 0, sum_m = 0;
    for (int i = 0; i < k; ++i) {
        const Vec3d a = normalize(corner[i]), b = normalize(corner[(i + 1) % k]);
        const Vec3d c = cross(a, b);
        const double len = length(c);
        if (!(len > 0)) continue;
        const double g = std::atan2(len, dot(a, b)) / len;
        sum_n += g * dot(n, c);
        sum_m += g * dot(m, c);
    }
    return std::max(sum_m < 0 ? -sum_n : sum_n, 0.0) / (2 * kPi);
}

// Sets up the sampling of a flat light near p once for all of a shading
// point's light points, and whether it covers enough of the cosine-weighted
// directions about ns to mix (share > 0): P, its projected solid angle over
// pi (a disk's or an ellipse's through a 16-gon inscribed in it, where its
// bounding rectangle's is high enough), is a function of p and ns only, as
// the mixture needs. Returns as SphericalRect::setup: -1 where the light is
// not such a light (the caller samples it by sample_light), 0 where p gets no
// light from it, 1 when set up.
inline int near_area_light(const Light& L, const Vec3& p, const Vec3& ns, NearArea& na) {
    if (!is_flat(L)) return -1;
    const int got = na.rect.setup(L, sampled_width(L), sampled_height(L), p);
    if (got != 1) return got;
    const SphericalRect& r = na.rect;
    na.area = flat_area(L);
    na.share = 0;
    const Vec3d n(ns), m = -r.z;
    const Vec3d corner[4] = {r.d, r.d + r.x * r.w, r.d + r.x * r.w + r.y * r.h, r.d + r.y * r.h};
    double P = projected_share(corner, 4, n, m);
    if (P >= kMixFrom && L.kind != LightKind::Rect) {
        // (The rectangle's corners outside a round light would make P high
        // where the light itself fills little of the view: just beside a disk
        // lying on a floor, mixing gave 2-6 times the noise.)
        constexpr int kSides = 16;
        Vec3d outline[kSides];
        const Vec3d centre = r.d + r.x * (0.5 * r.w) + r.y * (0.5 * r.h);
        for (int i = 0; i < kSides; ++i) {
            const double a = 2 * kPi * i / kSides;
            outline[i] = centre + r.x * (0.5 * r.w * std::cos(a)) + r.y * (0.5 * r.h * std::sin(a));
        }
        P = projected_share(outline, kSides, n, m);
    }
    if (P >= kMixFrom) na.share = std::min(P * P * P * P, kMaxCosineShare);
    return 1;
}

// The balance heuristic's estimate, radiance over the mixture's density:
// the light's points have density 1 / S over the rectangle's solid angle
// (a disk's points outside it count as drawn and lost), the
// cosine-weighted directions cos / pi.
inline Vec3 mixed_intensity(const Light& L, const NearArea& na, const Vec3& ns, const Vec3& wi) {
    if (na.share == 0) return scaled_color(L.color, na.rect.S / na.area);   // radiance x S
    const double cos_i = std::max(double(dot(ns, wi)), 0.0);
    const double density = (1 - na.share) / na.rect.S + na.share * cos_i / kPi;
    return scaled_color(L.color, 1.0 / (na.area * density));
}

// One light point of a light set up by near_area_light, for (u1, u2) in
// [0,1)^2: u1 below `share` draws a cosine-weighted direction (u1 stretched
// back over [0, 1)), else a point on the light by its solid angle. Fills s; false where the sample
// brings no light (a direction that misses the light, a disk's point outside it).
inline bool sample_near_area(const Light& L, const NearArea& na, const Vec3& ns, float u1, float u2, LightSample& s) {
    if (u1 < na.share) {
        float x, y;
        concentric_disk(std::min(float(u1 / na.share), 0.99999994f), u2, x, y);
        Vec3 t, b;
        basis(ns, t, b);
        s.wi = normalize(t * x + b * y + ns * std::sqrt(std::max(0.0f, 1.0f - x * x - y * y)));
        // Where it meets the light's plane (its axes', as the rectangle sampled),
        // from the light's emitting side (in double: the light can be near).
        const Vec3d w(s.wi);
        if (!(dot(w, Vec3d(L.direction)) < 0)) return false;
        const SphericalRect& r = na.rect;
        const Vec3d centre = r.d + r.x * (0.5 * r.w) + r.y * (0.5 * r.h);   // from p
        const double t_hit = dot(centre, r.z) / dot(w, r.z);
        if (!(t_hit > 0) || std::isinf(t_hit)) return false;
        const Vec3d q = w * t_hit - centre;
        const double cx = dot(q, r.x), cy = dot(q, r.y);
        if (!on_flat_light(L, cx, cy)) return false;
        s.dist = float(t_hit);
    } else {
        double cx, cy;
        const float v = std::min(float((u1 - na.share) / (1 - na.share)), 0.99999994f);
        if (!na.rect.sample(v, u2, s, cx, cy)) return false;
        if (L.kind != LightKind::Rect && !on_flat_light(L, cx, cy)) return false;
    }
    s.intensity = mixed_intensity(L, na, ns, s.wi);
    return true;
}

}  // namespace gw
