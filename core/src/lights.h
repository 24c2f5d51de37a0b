// Sampling a point on a light as seen from a shading point. Every light kind
// is "a point light whose position is drawn from its shape": point lights
// are exact points; sphere, rect and disk lights spread their intensity over
// their shape (soft shadows), and so does a spot light with a radius (its cone
// then weighs each sampled point by that point's direction to the shading
// point, which softens the cone's edge and lowers its peak when the light is
// near, as Cycles' spot lights do); the sun is a direction cone.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "enums.h"
#include "sampler.h"

namespace gw {

// The light record, bound to Python field by field as gridwalk._core.Light.
// See gridwalk.Light for the meaning of each field. prepare_light() checks a
// record and fills in the derived fields below it.
struct Light {
    LightKind kind = LightKind::Point;
    Vec3 position, color{1, 1, 1};
    float radius = 0;                     // sphere, disk, spot
    std::array<float, 2> size{1, 1};      // rect: along axis_u, axis_v
    Vec3 axis_u{1, 0, 0}, axis_v{0, 1, 0};
    Vec3 direction{0, 0, -1};             // sun, spot, rect, disk: where the light goes
    float angle = 0;                      // sun: angular diameter (radians)
    double spot_size = kPi / 4;           // spot: full cone angle (radians)
    float spot_blend = 0.15f;             // spot: soft edge, 0..1
    bool inverse_square = false;          // physical falloff (Blender's lights); NFF's lights have none
    bool casts_shadows = true;            // false: lights every point it faces (Blender's Cast Shadow off)
    // Derived by prepare_light:
    float spot_cos = -1;                  // cos(spot_size / 2)
};

// Validates `l` (throws std::invalid_argument naming `where` and the field),
// normalises its axes and direction and computes the derived fields.
void prepare_light(Light& l, const std::string& where);

struct LightSample {
    Vec3 wi;          // unit direction from the shading point towards the light
    float dist;       // distance to the sampled point (inf for the sun)
    Vec3 intensity;   // radiance-like contribution before the BRDF and cosine
};

// A rect light near p (within twice its diagonal of its centre, falling off
// physically) sampled uniformly in the solid angle it subtends at p, by Urena,
// Fajardo and King's area-preserving map of the spherical rectangle (EGSR
// 2013), in double: the estimate is radiance x cos x solid angle, bounded by
// the light's radiance x 2 pi, where uniform points on the rectangle weigh
// cos / distance^2 and explode as p nears it (a light 0.05 above a floor gave
// pixels 200 times Cycles' brightest). The rectangle is w x h in the light's
// (axis_u, axis_v) plane around its position.
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

// The rectangle sampled, for a rect light: the light itself; for a disk, its
// bounding square.
inline double sampled_width(const Light& L) { return L.kind == LightKind::Disk ? 2.0 * L.radius : L.size[0]; }
inline double sampled_height(const Light& L) { return L.kind == LightKind::Disk ? 2.0 * L.radius : L.size[1]; }

// A rect light near p, sampled by its solid angle (above): the estimate is
// radiance (colour / area) x solid angle. Returns as SphericalRect::setup,
// with `s` filled in on 1.
inline int sample_rect_solid_angle(const Light& L, const Vec3& p, float u1, float u2, LightSample& s) {
    SphericalRect sr;
    const int got = sr.setup(L, L.size[0], L.size[1], p);
    double cx, cy;
    if (got != 1) return got;
    if (!sr.sample(u1, u2, s, cx, cy)) return 0;
    s.intensity = L.color * float(sr.S / (sr.w * sr.h));
    return 1;
}

// A disk light near p: the spherical rectangle of its bounding square sampled
// as above, the points outside the disk weighing 0 (a quarter of them at
// most, fewer where the disk fills the view), so the estimate is radiance
// (colour / (pi r^2)) x the square's solid angle inside the disk, and
// unbiased. Uniform points on a 50 m disk 3 m above a floor gave its pixels
// ten times the rect's noise.
inline int sample_disk_solid_angle(const Light& L, const Vec3& p, float u1, float u2, LightSample& s) {
    SphericalRect sr;
    const double r = L.radius;
    const int got = sr.setup(L, 2 * r, 2 * r, p);
    double cx, cy;
    if (got != 1) return got;
    if (!sr.sample(u1, u2, s, cx, cy) || cx * cx + cy * cy > r * r) return 0;
    s.intensity = L.color * float(sr.S / (kPi * r * r));
    return 1;
}

// A spot's share of its light in a direction whose cosine to its axis is c:
// 0 outside the cone, a smoothstep over the blend region, 1 inside it.
inline float spot_cone(const Light& L, float c) {
    if (c <= L.spot_cos) return 0;
    const float edge = std::max(L.spot_blend * (1.0f - L.spot_cos), 1e-6f);
    const float x = std::min((c - L.spot_cos) / edge, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

// (u1, u2) in [0,1)^2; (0.5, 0.5) gives the light's centre (hard shadows).
inline bool sample_light(const Light& L, const Vec3& p, float u1, float u2, LightSample& s) {
    Vec3 pos = L.position;
    switch (L.kind) {
    case LightKind::Sun: {
        // Uniform direction inside the cone of half-angle angle/2 around -direction.
        Vec3 w = -L.direction;
        if (L.angle > 0 && !(u1 == 0.5f && u2 == 0.5f)) {
            const float cmax = std::cos(0.5f * L.angle);
            const float ct = 1.0f - u1 * (1.0f - cmax), st = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
            const float phi = float(2 * kPi) * u2;
            Vec3 t, b;
            basis(w, t, b);
            w = normalize(t * (st * std::cos(phi)) + b * (st * std::sin(phi)) + w * ct);
        }
        s.wi = w;
        s.dist = kInf;
        s.intensity = L.color;
        return true;
    }
    case LightKind::Spot:   // a spot with a radius is a sphere light whose cone is
        if (!(L.radius > 0)) break;   // applied to each sampled point's direction, as in Cycles
        [[fallthrough]];
    case LightKind::Sphere: {
        // A disk of the sphere's radius facing the shading point: the sphere's
        // silhouette (exact for distant points, close otherwise).
        Vec3 n = normalize(p - L.position), t, b;
        basis(n, t, b);
        float x, y;
        concentric_disk(u1, u2, x, y);
        pos = L.position + (t * x + b * y) * L.radius;
        break;
    }
    case LightKind::Rect:
        if (!(u1 == 0.5f && u2 == 0.5f))   // (the centre: a hard shadow's point light)
            if (const int by_angle = sample_rect_solid_angle(L, p, u1, u2, s); by_angle >= 0) return by_angle == 1;
        pos = L.position + L.axis_u * ((u1 - 0.5f) * L.size[0]) + L.axis_v * ((u2 - 0.5f) * L.size[1]);
        break;
    case LightKind::Disk: {
        if (!(u1 == 0.5f && u2 == 0.5f))   // (the centre: a hard shadow's point light)
            if (const int by_angle = sample_disk_solid_angle(L, p, u1, u2, s); by_angle >= 0) return by_angle == 1;
        float x, y;
        concentric_disk(u1, u2, x, y);
        pos = L.position + (L.axis_u * x + L.axis_v * y) * L.radius;
        break;
    }
    default:
        break;
    }
    Vec3 to = pos - p;
    // The distance without squaring it in float, which overflows from about
    // 1.8e19 (the direction came out 0, every point in shadow) and underflows
    // below about 1e-19 (the light was lost).
    s.dist = length(to);
    if (!(s.dist > 0)) return false;
    s.wi = to / s.dist;
    s.intensity = L.color;
    if (L.kind == LightKind::Rect || L.kind == LightKind::Disk) {
        const float c = dot(L.direction, -s.wi);   // one-sided Lambertian emitter
        if (c <= 0) return false;
        s.intensity *= c;
    } else if (L.kind == LightKind::Spot) {
        const float cone = spot_cone(L, dot(L.direction, -s.wi));
        if (!(cone > 0)) return false;
        s.intensity *= cone;
    }
    if (L.inverse_square) {
        const float d2 = dot(to, to);
        const Vec3 quick = s.intensity * (1.0f / d2);
        if (d2 >= std::numeric_limits<float>::min() && d2 <= std::numeric_limits<float>::max() &&
            std::max(quick.x, std::max(quick.y, quick.z)) <= std::numeric_limits<float>::max()) {
            s.intensity = quick;
        } else {   // beyond float's square or its range (a light nearer than ~1e-19): the product in double
            const double inv = 1.0 / (double(s.dist) * double(s.dist));
            const double top = std::numeric_limits<float>::max();
            s.intensity = Vec3(float(std::min(double(s.intensity.x) * inv, top)),
                               float(std::min(double(s.intensity.y) * inv, top)),
                               float(std::min(double(s.intensity.z) * inv, top)));
        }
    }
    return true;
}

// Whether a mirror or refraction ray sees the light's shape, as in Cycles'
// sharp reflections: rect and disk lights from their emitting side, sphere
// lights and spots with a radius (a sphere, its cone applied to the direction
// it is seen from), a sun with an angle. Point lights have no shape, and
// lights without distance falloff (NFF's) no radiance to show.
inline bool has_visible_shape(const Light& L) {
    switch (L.kind) {
    case LightKind::Rect: return L.inverse_square && L.size[0] > 0 && L.size[1] > 0;
    case LightKind::Disk:
    case LightKind::Sphere:
    case LightKind::Spot: return L.inverse_square && L.radius > 0;
    case LightKind::Sun: return L.angle > 0;
    default: return false;
    }
}

// Where the ray o + t d (d unit) meets the shape of a light with
// has_visible_shape(): t (inf for the sun) and the radiance it shows, in the
// units of a camera ray's colour (pi x the light's colour over its area or,
// for the sun, over its solid angle: the lights carry the diffuse BRDF's
// 1 / pi, see blender_addon/export/lights.py). False where the ray misses it
// or meets a rect or disk light from behind.
inline bool light_shape_hit(const Light& L, const Vec3& o, const Vec3& d, float& t, Vec3& radiance) {
    switch (L.kind) {
    case LightKind::Rect:
    case LightKind::Disk: {
        const float facing = dot(d, L.direction);
        if (!(facing < 0)) return false;                   // from behind (or along its plane)
        t = dot(L.position - o, L.direction) / facing;
        if (!(t > 0) || std::isinf(t)) return false;
        const Vec3 q = o + d * t - L.position;
        if (L.kind == LightKind::Rect) {
            if (!(std::abs(dot(q, L.axis_u)) <= 0.5f * L.size[0] && std::abs(dot(q, L.axis_v)) <= 0.5f * L.size[1]))
                return false;
            radiance = L.color * float(kPi / (double(L.size[0]) * double(L.size[1])));
        } else {
            if (!(dot(q, q) <= L.radius * L.radius)) return false;
            radiance = L.color * float(1.0 / (double(L.radius) * double(L.radius)));
        }
        return true;
    }
    case LightKind::Spot:
    case LightKind::Sphere: {   // (in double: the light may be small and far)
        const Vec3d oc = Vec3d(o) - Vec3d(L.position), dd(d);
        const double b = dot(oc, dd), c = dot(oc, oc) - double(L.radius) * double(L.radius);
        const double disc = b * b - c;
        if (!(disc >= 0)) return false;
        const double root = std::sqrt(disc), near = -b - root, far = -b + root;
        const double hit = near > 0 ? near : far;
        if (!(hit > 0)) return false;
        t = float(hit);
        radiance = L.color * float(1.0 / (double(L.radius) * double(L.radius)));
        if (L.kind == LightKind::Spot) {
            const float cone = spot_cone(L, -dot(L.direction, d));
            if (!(cone > 0)) return false;
            radiance *= cone;
        }
        return true;
    }
    case LightKind::Sun: {
        const double half = 0.5 * double(L.angle), cos_half = std::cos(half);
        if (!(-double(dot(d, L.direction)) >= cos_half)) return false;
        t = kInf;
        radiance = L.color * float(kPi / (2 * kPi * (1 - cos_half)));
        return true;
    }
    default:
        return false;
    }
}

}  // namespace gw
