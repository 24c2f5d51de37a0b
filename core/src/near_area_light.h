// A rect or disk light that fills nearly all of a shading point's view (a
// large light just above a floor), sampled by two strategies: points uniform
// in the solid angle the light subtends (lights.h, SphericalRect), and
// directions drawn cosine-weighted about the shading normal that happen to
// meet the light. Each light point picks one of the two (one-sample multiple
// importance sampling, Veach 1997, with the balance heuristic), the
// cosine-weighted one with probability `share`. The same light points, the
// same shadow rays.
//
// Why: sampling by solid angle weighs each point by the cosine at the shading
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

#include "lights.h"

namespace gw {

constexpr double kMixFrom = 0.9;          // the projected share P from which the strategies mix
constexpr double kMaxCosineShare = 0.98;  // the light's own points keep at least this much of the samples

struct NearArea {
    SphericalRect rect;   // the sampled rectangle (a disk's bounding square) as seen from the point
    double share = 0;     // the probability of a cosine-weighted direction (0: the light's points only)
    Vec3 radiance;        // colour / area
};

// Whether L is a rect or disk light near p (sampled by solid angle) that
// covers enough of the cosine-weighted directions about ns to mix: fills na.
// P is the sampled rectangle's projected solid angle (Lambert's polygon
// formula; for a disk, its bounding square's) over pi, a function of p and
// ns only, as the mixture needs.
inline bool near_area_light(const Light& L, const Vec3& p, const Vec3& ns, NearArea& na) {
    if (L.kind != LightKind::Rect && L.kind != LightKind::Disk) return false;
    if (na.rect.setup(L, sampled_width(L), sampled_height(L), p) != 1) return false;
    const SphericalRect& r = na.rect;
    const Vec3d corner[4] = {r.d, r.d + r.x * r.w, r.d + r.x * r.w + r.y * r.h, r.d + r.y * r.h};
    const Vec3d n(ns);
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3d a = normalize(corner[i]), b = normalize(corner[(i + 1) % 4]);
        const Vec3d c = cross(a, b);
        const double len = length(c);
        if (len > 0) sum += std::atan2(len, dot(a, b)) * dot(n, c) / len;
    }
    const double projected = std::abs(sum) / (2 * kPi);   // in [0, 1]: the polygon's share of the cosine's weight
    if (!(projected >= kMixFrom)) return false;
    na.share = std::min(projected * projected * projected * projected, kMaxCosineShare);
    const double area = L.kind == LightKind::Disk ? kPi * double(L.radius) * L.radius : double(L.size[0]) * L.size[1];
    na.radiance = L.color * float(1.0 / area);
    return true;
}

// The balance heuristic's estimate, radiance over the mixture's density:
// the light's points have density 1 / S over the rectangle's solid angle
// (a disk's points outside it count as drawn and lost), the
// cosine-weighted directions cos / pi.
inline Vec3 mixed_intensity(const NearArea& na, const Vec3& ns, const Vec3& wi) {
    const double cos_i = std::max(double(dot(ns, wi)), 0.0);
    const double density = (1 - na.share) / na.rect.S + na.share * cos_i / kPi;
    return na.radiance * float(1.0 / density);
}

// One light point of the mixture for (u1, u2) in [0,1)^2: u1 below `share`
// draws a cosine-weighted direction (u1 stretched back over [0, 1)), else a
// point on the light by its solid angle. Fills s; false where the sample
// brings no light (a direction that misses the light, a disk's point outside it).
inline bool sample_near_area(const Light& L, const NearArea& na, const Vec3& ns, float u1, float u2, LightSample& s) {
    if (u1 < na.share) {
        float x, y;
        concentric_disk(std::min(float(u1 / na.share), 0.99999994f), u2, x, y);
        Vec3 t, b;
        basis(ns, t, b);
        s.wi = normalize(t * x + b * y + ns * std::sqrt(std::max(0.0f, 1.0f - x * x - y * y)));
        // Where it meets the light's plane, from the light's emitting side (in double: the light can be near).
        const Vec3d w(s.wi), dir(L.direction);
        const double facing = dot(w, dir);
        if (!(facing < 0)) return false;
        const SphericalRect& r = na.rect;
        const Vec3d centre = r.d + r.x * (0.5 * r.w) + r.y * (0.5 * r.h);   // from p
        const double t_hit = dot(centre, dir) / facing;
        if (!(t_hit > 0) || std::isinf(t_hit)) return false;
        const Vec3d q = w * t_hit - centre;
        const double cx = dot(q, Vec3d(L.axis_u)), cy = dot(q, Vec3d(L.axis_v));
        const bool inside = L.kind == LightKind::Disk
                                ? cx * cx + cy * cy <= double(L.radius) * L.radius
                                : std::abs(cx) <= 0.5 * r.w && std::abs(cy) <= 0.5 * r.h;
        if (!inside) return false;
        s.dist = float(t_hit);
    } else {
        double cx, cy;
        const float v = std::min(float((u1 - na.share) / (1 - na.share)), 0.99999994f);
        if (!na.rect.sample(v, u2, s, cx, cy)) return false;
        if (L.kind == LightKind::Disk && cx * cx + cy * cy > double(L.radius) * L.radius) return false;
    }
    s.intensity = mixed_intensity(na, ns, s.wi);
    return true;
}

}  // namespace gw
