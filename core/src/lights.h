// Sampling a point on a light as seen from a shading point. Every light kind
// is "a point light whose position is drawn from its shape": point and spot
// lights are exact points; sphere, rect and disk lights spread their
// intensity over their shape (soft shadows); the sun is a direction cone.
#pragma once
#include "scene.h"
#include "sampler.h"

namespace gw {

struct LightSample {
    Vec3 wi;          // unit direction from the shading point towards the light
    float dist;       // distance to the sampled point (inf for the sun)
    Vec3 intensity;   // radiance-like contribution before the BRDF and cosine
};

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
        pos = L.position + L.axis_u * ((u1 - 0.5f) * L.width) + L.axis_v * ((u2 - 0.5f) * L.height);
        break;
    case LightKind::Disk: {
        float x, y;
        concentric_disk(u1, u2, x, y);
        pos = L.position + (L.axis_u * x + L.axis_v * y) * L.radius;
        break;
    }
    default:
        break;
    }
    Vec3 to = pos - p;
    const float d2 = dot(to, to);
    if (!(d2 > 0)) return false;
    s.dist = std::sqrt(d2);
    s.wi = to / s.dist;
    s.intensity = L.color;
    if (L.kind == LightKind::Rect || L.kind == LightKind::Disk) {
        const float c = dot(L.direction, -s.wi);   // one-sided Lambertian emitter
        if (c <= 0) return false;
        s.intensity *= c;
    } else if (L.kind == LightKind::Spot) {
        const float c = dot(L.direction, -s.wi);
        if (c <= L.spot_cos) return false;
        const float edge = std::max(L.spot_blend * (1.0f - L.spot_cos), 1e-6f);
        const float x = std::min((c - L.spot_cos) / edge, 1.0f);
        s.intensity *= x * x * (3.0f - 2.0f * x);   // smoothstep over the blend region
    }
    if (L.inverse_square) s.intensity *= 1.0f / d2;
    return true;
}

}  // namespace gw
