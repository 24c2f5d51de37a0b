// The density, per unit solid angle at the shading point, with which a lamp's
// light points (sample_light, or sample_near_area for a flat light near the
// point) land in a direction: what multiple importance sampling weighs a
// glossy ray that meets the lamp's shape against (Integrator::direct and
// glossy_lobe).
#pragma once
#include "near_area_light.h"

namespace gw {

// The density of L's light points in direction wi (unit) from p, where wi
// meets the light at distance dist; near_state and near are what
// near_area_light(L, p, ns, near) returned and set. 0 where no light point
// lands in that direction.
inline double light_density(const Light& L, int near_state, const NearArea& near, const Vec3& p, const Vec3& ns,
                            const Vec3& wi, float dist) {
    switch (L.kind) {
    case LightKind::Sun: {   // uniform in the cone of half-angle angle / 2
        const double cos_half = std::cos(0.5 * double(L.angle));
        return 1.0 / (2 * kPi * (1 - cos_half));
    }
    case LightKind::Spot:
    case LightKind::Sphere:   // (sphere_light.h)
        return uniform_sphere(L) ? sphere_cap_density(L.position, L.radius, p, ns, wi)
                                 : soft_disk_density(L.position, L.radius, p, wi);
    case LightKind::Rect:
    case LightKind::Disk:
    case LightKind::Ellipse: {
        if (near_state == 0) return 0;
        if (near_state == 1)   // by the solid angle of its rectangle, mixed with cosine-weighted directions
            return (1 - near.share) / near.rect.S + near.share * std::max(double(dot(ns, wi)), 0.0) / kPi;
        const double cos_l = -double(dot(L.direction, wi));   // uniform on its area, one-sided
        if (!(cos_l > 0)) return 0;
        return double(dist) * double(dist) / (flat_area(L) * cos_l);
    }
    default:
        return 0;
    }
}

}  // namespace gw
