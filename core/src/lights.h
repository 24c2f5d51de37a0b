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
#include "ray.h"
#include "sampler.h"
#include "sphere_light.h"

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
    bool soft_falloff = true;             // sphere, spot with a radius: see sphere_light.h
    // Blender's Ray Visibility of a light object, as Cycles reads it: false leaves out its
    // diffuse light (visible_diffuse), its highlights and what glossy and sharp mirror rays see
    // of its shape (visible_glossy), and what refraction rays see of it (visible_transmission).
    bool visible_diffuse = true, visible_glossy = true, visible_transmission = true;
    // Derived by prepare_light:
    float spot_cos = -1;                  // cos(spot_size / 2)
};

// A sphere light or spot with a radius that is a sphere of uniform radiance
// (Blender's Soft Falloff off; sphere_light.h), not the soft disk (which,
// of radius 0, is a point light).
inline bool uniform_sphere(const Light& L) { return !L.soft_falloff && L.inverse_square && L.radius > 0; }

// Validates `l` (throws std::invalid_argument naming `where` and the field),
// normalises its axes and direction and computes the derived fields.
void prepare_light(Light& l, const std::string& where);

struct LightSample {
    Vec3 wi;          // unit direction from the shading point towards the light
    float dist;       // distance to the sampled point (inf for the sun)
    Vec3 intensity;   // radiance-like contribution before the BRDF and cosine
};

// A spot's share of its light in a direction whose cosine to its axis is c:
// 0 outside the cone, a smoothstep over the blend region, 1 inside it.
inline float spot_cone(const Light& L, float c) {
    if (c <= L.spot_cos) return 0;
    const float edge = std::max(L.spot_blend * (1.0f - L.spot_cos), 1e-6f);
    const float x = std::min((c - L.spot_cos) / edge, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

// Weighs `value` by a spot's cone in the direction `out` (unit) in which the
// light leaves it (other lights: unchanged); false where the cone gives nothing.
inline bool through_spot_cone(const Light& L, const Vec3& out, Vec3& value) {
    if (L.kind != LightKind::Spot) return true;
    const float cone = spot_cone(L, dot(L.direction, out));
    if (!(cone > 0)) return false;
    value *= cone;
    return true;
}

// Rect, disk and ellipse lights: flat, one-sided (Lambertian) emitters.
inline bool is_flat(const Light& L) {
    return L.kind == LightKind::Rect || L.kind == LightKind::Disk || L.kind == LightKind::Ellipse;
}

// A flat light's area.
inline double flat_area(const Light& L) {
    return L.kind == LightKind::Disk      ? kPi * double(L.radius) * L.radius
           : L.kind == LightKind::Ellipse ? 0.25 * kPi * double(L.size[0]) * L.size[1]
                                          : double(L.size[0]) * L.size[1];
}

// About the angle from the light's centre to its rim as seen from p: the
// tangent of it (no more than it's worth: radians are dearer), at most 2; a
// flat light's by its half diagonal; 0 for a point.
inline float angular_radius(const Light& L, const Vec3& p) {
    if (L.kind == LightKind::Sun) return 0.5f * L.angle;
    const float half = L.kind == LightKind::Rect      ? 0.5f * std::sqrt(L.size[0] * L.size[0] + L.size[1] * L.size[1])
                       : L.kind == LightKind::Ellipse ? 0.5f * std::max(L.size[0], L.size[1])
                                                      : L.radius;
    if (!(half > 0)) return 0;
    const Vec3 to = L.position - p;
    const float d2 = dot(to, to);
    return half * half >= 4 * d2 ? 2.0f : half / std::sqrt(d2);
}

// Whether the point of a flat light's plane at (cx, cy) from its centre,
// along axis_u and axis_v, lies on the light.
inline bool on_flat_light(const Light& L, double cx, double cy) {
    switch (L.kind) {
    case LightKind::Rect: return std::abs(cx) <= 0.5 * L.size[0] && std::abs(cy) <= 0.5 * L.size[1];
    case LightKind::Disk: return cx * cx + cy * cy <= double(L.radius) * L.radius;
    case LightKind::Ellipse: {
        const double a = 0.5 * L.size[0], b = 0.5 * L.size[1];   // (> 0: has_visible_shape, has_area)
        return (cx * cx) / (a * a) + (cy * cy) / (b * b) <= 1.0;
    }
    default: return false;
    }
}

// Colour x a weight, the weight in double and the product clamped to float's
// range per channel (a tiny light near p has an enormous weight: inf x 0 would
// put NaN in the pixel).
inline Vec3 scaled_color(const Vec3& color, double weight) {
    const double top = std::numeric_limits<float>::max();
    return Vec3(float(std::min(double(color.x) * weight, top)), float(std::min(double(color.y) * weight, top)),
                float(std::min(double(color.z) * weight, top)));
}

// (u1, u2) in [0,1)^2; (0.5, 0.5) gives the light's centre (hard shadows).
// n: the shading normal at p (a uniform sphere light around p samples about it).
// Flat lights get uniform points on their area here; near the
// shading point, where those weigh cos / distance^2 and explode,
// Integrator::direct samples them by near_area_light.h instead.
inline bool sample_light(const Light& L, const Vec3& p, const Vec3& n, float u1, float u2, LightSample& s) {
    Vec3 pos = L.position;
    Vec3 facing;   // a soft sphere light's disk: its normal, towards p
    switch (L.kind) {
    case LightKind::Sun: {
        // Uniform direction inside the cone of half-angle angle/2 around -direction.
        Vec3 w = -L.direction;
        s.intensity = L.color;   // (the disc's centre, Hard shadows' point: a facing surface gets the colour)
        if (L.angle > 0 && !(u1 == 0.5f && u2 == 0.5f)) {
            const float cmax = std::cos(0.5f * L.angle);
            const float ct = 1.0f - u1 * (1.0f - cmax), st = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
            const float phi = float(2 * kPi) * u2;
            Vec3 t, b;
            basis(w, t, b);
            w = normalize(t * (st * std::cos(phi)) + b * (st * std::sin(phi)) + w * ct);
            // The colour is the irradiance on a surface facing the sun, whatever its angle, as in
            // Cycles 4.0+ (radiance colour / (pi sin^2 of the half angle), as light_shape_hit shows
            // it); a uniform direction in the cone then carries the colour x 2 / (1 + cos(angle / 2)).
            s.intensity = L.color * float(2.0 / (1.0 + std::cos(0.5 * double(L.angle))));
        }
        s.wi = w;
        s.dist = kInf;
        return true;
    }
    case LightKind::Spot:   // a spot with a radius is a sphere light whose cone is
        if (!(L.radius > 0)) break;   // applied to each sampled point's direction, as in Cycles
        [[fallthrough]];
    case LightKind::Sphere:
        if (uniform_sphere(L)) {
            double scale;
            if (!sample_sphere_cap(L.position, L.radius, p, n, u1, u2, s.wi, s.dist, scale)) return false;
            s.intensity = scaled_color(L.color, scale);
            return through_spot_cone(L, -s.wi, s.intensity);
        }
        facing = normalize(p - L.position);
        pos = L.position + soft_disk_offset(facing, L.radius, u1, u2);
        break;
    case LightKind::Rect:
        pos = L.position + L.axis_u * ((u1 - 0.5f) * L.size[0]) + L.axis_v * ((u2 - 0.5f) * L.size[1]);
        break;
    case LightKind::Disk: {
        float x, y;
        concentric_disk(u1, u2, x, y);
        pos = L.position + (L.axis_u * x + L.axis_v * y) * L.radius;
        break;
    }
    case LightKind::Ellipse: {
        float x, y;
        concentric_disk(u1, u2, x, y);
        pos = L.position + L.axis_u * (x * 0.5f * L.size[0]) + L.axis_v * (y * 0.5f * L.size[1]);
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
    if (is_flat(L)) {
        const float c = dot(L.direction, -s.wi);   // one-sided Lambertian emitter
        if (c <= 0) return false;
        s.intensity *= c;
    } else if (L.kind == LightKind::Spot || L.kind == LightKind::Sphere) {
        // The soft disk, Lambertian: its cosine towards the point. (A light without falloff,
        // NFF's, has no radiance for it to shape: its points are averaged, soft shadows alone.)
        if (L.radius > 0 && L.inverse_square) {
            const float c = -dot(facing, s.wi);
            if (!(c > 0)) return false;
            s.intensity *= c;
        }
        if (!through_spot_cone(L, -s.wi, s.intensity)) return false;
    }
    if (L.inverse_square) {
        const float d2 = dot(to, to);
        const Vec3 quick = s.intensity * (1.0f / d2);
        if (d2 >= std::numeric_limits<float>::min() && d2 <= std::numeric_limits<float>::max() &&
            std::max(quick.x, std::max(quick.y, quick.z)) <= std::numeric_limits<float>::max()) {
            s.intensity = quick;
        } else {   // beyond float's square or its range (a light nearer than ~1e-19): the product in double
            s.intensity = scaled_color(s.intensity, 1.0 / (double(s.dist) * double(s.dist)));
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
    case LightKind::Rect:
    case LightKind::Ellipse: return L.inverse_square && L.size[0] > 0 && L.size[1] > 0;
    case LightKind::Disk:
    case LightKind::Sphere:
    case LightKind::Spot: return L.inverse_square && L.radius > 0;
    case LightKind::Sun: return L.angle > 0;
    default: return false;
    }
}

// Whether a ray of `kind` leaving a surface (a reflection, or a refraction: Transmission) sees
// the light's shape: it has one (has_visible_shape) and the light's Ray Visibility lets it.
inline bool shape_seen_by(const Light& L, RayKind kind) {
    return (kind == RayKind::Transmission ? L.visible_transmission : L.visible_glossy) && has_visible_shape(L);
}

// Where the ray o + t d (d unit) meets the shape of a light with
// has_visible_shape(): t (inf for the sun) and the radiance it shows, in the
// units of a camera ray's colour (pi x the light's colour over its area or,
// for the sun, over pi sin^2 of its half angle: the lights carry the diffuse BRDF's
// 1 / pi, see blender_addon/export/lights.py). False where the ray misses it
// or meets a flat light from behind.
inline bool light_shape_hit(const Light& L, const Vec3& o, const Vec3& d, float& t, Vec3& radiance) {
    switch (L.kind) {
    case LightKind::Rect:
    case LightKind::Disk:
    case LightKind::Ellipse: {
        const float facing = dot(d, L.direction);
        if (!(facing < 0)) return false;                   // from behind (or along its plane)
        t = dot(L.position - o, L.direction) / facing;
        if (!(t > 0) || std::isinf(t)) return false;
        const Vec3 q = o + d * t - L.position;
        if (L.kind == LightKind::Disk) {   // (in its own float arithmetic, which stored reference images hold)
            if (!(dot(q, q) <= L.radius * L.radius)) return false;
            radiance = L.color * float(1.0 / (double(L.radius) * double(L.radius)));
            return true;
        }
        if (!on_flat_light(L, dot(q, L.axis_u), dot(q, L.axis_v))) return false;
        radiance = L.color * float(kPi / flat_area(L));
        return true;
    }
    case LightKind::Spot:
    case LightKind::Sphere: {
        if (!(uniform_sphere(L) ? sphere_hit(L.position, L.radius, L.color, o, d, t, radiance)
                                : soft_disk_hit(L.position, L.radius, L.color, o, d, t, radiance)))
            return false;
        return through_spot_cone(L, -d, radiance);
    }
    case LightKind::Sun: {
        const double half = 0.5 * double(L.angle), cos_half = std::cos(half);
        if (!(-double(dot(d, L.direction)) >= cos_half)) return false;
        t = kInf;
        const double sin_half = std::sin(half);   // (radiance colour / (pi sin^2): a facing surface gets the colour)
        radiance = L.color * float(1.0 / (sin_half * sin_half));
        return true;
    }
    default:
        return false;
    }
}

}  // namespace gw
