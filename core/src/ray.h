// Rays, hit records and the per-ray data precomputed once before traversal.
#pragma once
#include <cstdint>

#include "math.h"

namespace gw {

enum class PrimKind : int32_t { Miss = 0, Triangle = 1, Sphere = 2, Cone = 3 };

// What a ray is for, as far as an object's visibility goes (Material::seen_by).
enum class RayKind : uint8_t { Camera, Glossy, Transmission, Other };

struct Ray {
    Vec3 o, d;
    float tmin = 0.0f, tmax = kInf;
    // A ray resumed past a hit at t (the Integrator passing a surface hidden from it or a
    // cut-out): tmin is the float below t, and of the hits at exactly t only those of primitives
    // above `after` count, as hits are ordered by t and then by index. So a surface in the plane
    // of the one passed is still met (an object's bottom face on a floor), and the one passed
    // is not. -1 (the default): every hit in (tmin, tmax) counts. (Checked where a test finds
    // a hit, not per test: resumed rays are few.)
    int32_t after = -1;
    // True for rays leaving a surface (secondary and shadow rays): hits closer
    // than the intersection test's own error bound are then taken to be the
    // surface the ray leaves and rejected (see triangle.h). Rays from arbitrary
    // points (camera, batch queries) keep every hit, like Embree.
    bool spawned = false;
    // A glossy ray whose lobe samples the environment's sun as a light
    // (Integrator::sun_highlight): a miss sees the environment less its sun.
    bool without_sun = false;
    RayKind kind = RayKind::Other;   // what the ray is for (Material::seen_by)
    // A camera ray gone on behind a shadow catcher: it passes every other catcher (Integrator::trace).
    bool behind_catcher = false;
    // A glossy ray whose lobe shares the emissive triangles with light sampling
    // (multiple importance sampling, Integrator::emitter_weight): n x the lobe's density
    // for this direction over the shading point's light points for emitters; 0 for every
    // other ray. mis_offset: how far the ray's origin lies from that shading point along
    // it (it moves on past alpha cut-outs).
    float emitter_mis = 0, mis_offset = 0;
};

// Closest-hit record. prim is the global primitive index (triangles, then
// spheres, then cones); t == tmax until something is hit.
struct Hit {
    float t = kInf;
    int32_t prim = -1;
    float u = 0, v = 0;
};

// Everything a primitive test needs that depends only on the ray.
struct RayPre {
    Ray ray;
    // Watertight triangle test (Woop, Benthin, Wald 2013): axis permutation and shear.
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
    float ox = 0, oy = 0, oz = 0;   // the origin in the permuted axes
    // Double-precision copies for the analytic (quadric) primitives (exact
    // conversions, made where a quadric is tested: most rays meet none).
    Vec3d od() const { return Vec3d(ray.o); }
    Vec3d dd() const { return Vec3d(ray.d); }
    bool valid = false;   // false for NaN/Inf/zero directions: such a ray hits nothing

    explicit RayPre(const Ray& r) : ray(r) {
        valid = finite3(r.o) && finite3(r.d) && (r.d.x != 0 || r.d.y != 0 || r.d.z != 0) &&
                !std::isnan(r.tmin) && !std::isnan(r.tmax) && r.tmin <= r.tmax;
        if (!valid) return;
        kz = max_axis(vabs(r.d));
        kx = kz == 2 ? 0 : kz + 1;
        ky = kx == 2 ? 0 : kx + 1;
        if (r.d[kz] < 0) std::swap(kx, ky);   // keep the winding so the edge tests keep their sign
        sx = r.d[kx] / r.d[kz];
        sy = r.d[ky] / r.d[kz];
        sz = 1.0f / r.d[kz];
        ox = r.o[kx];
        oy = r.o[ky];
        oz = r.o[kz];
    }
};

}  // namespace gw
