// Whitted shading with distribution effects. See integrator.h.
#include "integrator.h"

#include "lights.h"
#include "offset.h"

namespace gw {

Vec3 Integrator::camera_ray(const Ray& ray, const Vec3& view_axis, SampleState& st, TraceContext& ctx,
                            FirstHit* fh) const {
    return trace(ray, 1, 1.0f, false, RayType::Primary, st, ctx, fh, view_axis);
}

bool Integrator::visible(const Vec3& p, const Vec3& p_err, const Vec3& ng, const Vec3& wi, float dist,
                         TraceContext& ctx) const {
    Ray r;
    r.o = offset_origin(p, p_err, ng, wi);
    r.d = wi;
    // Stop just short of the light's sampled point (relative, so scale-free).
    r.tmax = std::isinf(dist) ? kInf : dist * (1.0f - 1e-5f);
    r.spawned = true;
    ++ctx.stats.rays[int(RayType::Shadow)];
    return !accel_.occluded(RayPre(r), ctx);
}

Vec3 Integrator::direct(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Material& m,
                        int depth, SampleState& st, TraceContext& ctx) const {
    Vec3 total;
    const auto& lights = scene_.lights();
    for (size_t li = 0; li < lights.size(); ++li) {
        const Light& L = lights[li];
        const bool has_area = L.kind == LightKind::Sphere ? L.radius > 0
                            : L.kind == LightKind::Rect   ? L.size[0] > 0 || L.size[1] > 0
                            : L.kind == LightKind::Disk   ? L.radius > 0
                            : L.kind == LightKind::Sun    ? L.angle > 0
                                                          : false;
        // How many light points this shading point uses, and where they come from.
        int count = 1;
        ShadowMode mode = has_area ? s_.shadow : ShadowMode::Hard;
        const uint32_t n = uint32_t(std::max(1, s_.shadow_samples));
        const uint32_t grid = n * n;
        if (mode == ShadowMode::Area && depth > 1) mode = ShadowMode::Random;   // grid only at primary hits
        if (mode == ShadowMode::Random) count = int(n);
        if (mode == ShadowMode::Area) count = int(std::max<uint32_t>(1, (grid + st.samples - 1) / st.samples));
        Vec3 sum;
        for (int j = 0; j < count; ++j) {
            float u1 = 0.5f, u2 = 0.5f;
            if (mode == ShadowMode::Random) {
                u1 = st.rng.next();
                u2 = st.rng.next();
            } else if (mode == ShadowMode::Area) {
                // The seed's area-light method: an n x n jittered grid of light
                // positions, shuffled per pixel so that the pixel's sub-samples
                // meet different positions.
                const uint32_t slot = (st.sample * uint32_t(count) + uint32_t(j)) % grid;
                const uint32_t key = hash4(st.seed, st.pixel, uint32_t(li), uint32_t(Stream::AreaLightGrid));
                const uint32_t cell = permute(slot, grid, key);
                u1 = (float(cell % n) + to_unit(hash4(key, cell, 1, 0))) / float(n);
                u2 = (float(cell / n) + to_unit(hash4(key, cell, 2, 0))) / float(n);
            }
            LightSample ls;
            if (!sample_light(L, sp.p, u1, u2, ls)) continue;
            if (dot(ng, ls.wi) <= 0) continue;
            const float cos_i = dot(ns, ls.wi);
            if (cos_i <= 0) continue;
            Vec3 f = m.color * (m.kd * cos_i);
            if (m.ks > 0) {
                const Vec3 h = normalize(ls.wi + wo);
                const float sp_ = m.ks * std::pow(std::max(dot(ns, h), 0.0f), m.shininess);
                f += Vec3(sp_, sp_, sp_);
            }
            const Vec3 c = f * ls.intensity;
            if (c.x <= 0 && c.y <= 0 && c.z <= 0) continue;
            if (visible(sp.p, sp.p_err, sp.ng, ls.wi, ls.dist, ctx)) sum += c;
        }
        total += sum * (1.0f / float(count));
    }
    return total;
}

Vec3 Integrator::reflect_glossy(const SurfacePoint& sp, const Vec3& ng, const Vec3& dir, const Material& m,
                                int depth, float weight, bool split, SampleState& st, TraceContext& ctx) const {
    Ray r;
    r.d = dir;
    r.spawned = true;
    if (m.roughness <= 0) {   // exact mirror
        r.o = offset_origin(sp.p, sp.p_err, sp.ng, dir);
        return trace(r, depth + 1, weight, split, RayType::Secondary, st, ctx, nullptr, Vec3());
    }
    // Normalised Phong lobe around the mirror direction, exponent from the
    // roughness by Walter et al.'s mapping e = 2 / alpha^2 - 2, alpha = roughness^2.
    // Importance sampling the normalised lobe gives weight 1 per sample;
    // directions below the surface count as black, so the estimate never
    // exceeds the mirror's.
    const float alpha = std::max(m.roughness * m.roughness, 1e-4f);
    const float e = std::max(2.0f / (alpha * alpha) - 2.0f, 0.0f);
    const int n = split ? 1 : std::max(1, s_.glossy_samples);
    Vec3 t, b;
    basis(dir, t, b);
    const float rot = st.rng.next();
    Vec3 sum;
    for (int j = 0; j < n; ++j) {
        float u1, u2;
        strat2(uint32_t(j), uint32_t(n), st.rng.next(), rot, u1, u2);
        const float ct = std::pow(1.0f - u1, 1.0f / (e + 1.0f)), s = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
        const float phi = float(2 * kPi) * u2;
        const Vec3 w = normalize(t * (s * std::cos(phi)) + b * (s * std::sin(phi)) + dir * ct);
        if (dot(w, ng) <= 0) continue;
        r.d = w;
        r.o = offset_origin(sp.p, sp.p_err, sp.ng, w);
        sum += trace(r, depth + 1, weight, true, RayType::Secondary, st, ctx, nullptr, Vec3());
    }
    return sum * (1.0f / float(n));
}

Vec3 Integrator::trace(const Ray& ray, int depth, float weight, bool split, RayType type, SampleState& st,
                       TraceContext& ctx, FirstHit* fh, const Vec3& view_axis) const {
    ++ctx.stats.rays[int(type)];
    const RayPre r(ray);
    Hit hit;
    hit.t = ray.tmax;
    if (!accel_.closest(r, hit, ctx)) return scene_.background();
    const SurfacePoint sp = scene_.surface(r, hit);
    const Material& m = scene_.materials()[size_t(sp.material)];
    if (fh) {
        fh->hit = true;
        fh->depth = hit.t * dot(ray.d, view_axis);
        fh->normal = sp.ns;
    }
    const Vec3 d = ray.d, wo = -d;
    const bool entering = dot(d, sp.ng) < 0;
    const Vec3 ng = entering ? sp.ng : -sp.ng;   // both normals face the incoming ray
    Vec3 ns = entering ? sp.ns : -sp.ns;
    if (dot(ns, wo) <= 0) ns = ng;              // interpolated normal facing away: use the true one
    Vec3 color = m.color * m.emission + direct(sp, ng, ns, wo, m, depth, st, ctx);
    if (depth >= s_.max_depth) return color;

    float refl = m.mirror, trans = 0;
    Vec3 tdir;
    if (m.transmittance > 0) {
        const float n1 = entering ? 1.0f : m.ior, n2 = entering ? m.ior : 1.0f, eta = n1 / n2;
        const float cos_i = std::min(dot(wo, ns), 1.0f);
        const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
        if (k < 0) {
            refl += m.transmittance;   // total internal reflection
        } else {
            const float cos_t = std::sqrt(k);
            tdir = normalize(d * eta + ns * (eta * cos_i - cos_t));
            const float r0 = ((n1 - n2) / (n1 + n2)) * ((n1 - n2) / (n1 + n2));
            const float c = 1.0f - (n1 <= n2 ? cos_i : cos_t);   // Schlick, angle on the rarer side
            const float F = r0 + (1.0f - r0) * c * c * c * c * c;
            refl += m.transmittance * F;
            trans = m.transmittance * (1.0f - F);
        }
    }
    if (refl > 0 && weight * refl > s_.min_weight) {
        Vec3 rdir = d - ns * (2.0f * dot(d, ns));
        if (dot(rdir, ng) <= 0) rdir = d - ng * (2.0f * dot(d, ng));
        color += reflect_glossy(sp, ng, normalize(rdir), m, depth, weight * refl, split, st, ctx) * refl;
    }
    if (trans > 0 && weight * trans > s_.min_weight && dot(tdir, ng) < 0) {
        Ray tr;
        tr.d = tdir;
        tr.spawned = true;
        tr.o = offset_origin(sp.p, sp.p_err, sp.ng, tdir);
        color += trace(tr, depth + 1, weight * trans, split, RayType::Secondary, st, ctx, nullptr, Vec3()) * trans;
    }
    return color;
}

}  // namespace gw
