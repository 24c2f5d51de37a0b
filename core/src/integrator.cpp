// Whitted shading with distribution effects. See integrator.h.
#include "integrator.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "light_density.h"
#include "lights.h"
#include "microfacet.h"
#include "near_area_light.h"
#include "offset.h"

namespace gw {

// Surfaces hidden from a ray that it passes before it is seen as a miss (Material::seen_by), and
// surfaces that cast no shadow that a shadow ray passes.
constexpr int kMaxHiddenCrossings = 4096;

namespace {

// White, with the share `metal` (in [0, 1]) of it taking the base colour.
Vec3 metal_tint(const Material& m, float metal) {
    return Vec3(1, 1, 1) + (metal_color_of(m) - Vec3(1, 1, 1)) * metal;
}

// The specular weight at normal incidence: ks without the normalised Phong
// lobe's (shininess + 8) / 8 (the Principled mapping's (1 - metallic) F0 + metallic).
float specular_weight(const Material& m) { return std::min(m.ks * 8.0f / (m.shininess + 8.0f), 1.0f); }

// The share of a surface whose dielectric specular layer reflects the scene
// (Material::dielectric_reflection): what is neither mirror (metal) nor glass.
float dielectric_share(const Material& m) {
    return m.dielectric_reflection ? std::max(1.0f - m.mirror - m.transmittance, 0.0f) : 0.0f;
}

// The non-metal's reflectance at normal incidence (white): the specular
// weight's non-metal part, per unit of non-metal (the Principled mapping's F0).
float dielectric_f0(const Material& m) {
    if (!(m.metallic < 1)) return 0;
    return std::min(std::max((specular_weight(m) - m.metallic) / (1 - m.metallic), 0.0f), 1.0f);
}

// A glossy surface's whole reflectance (what its lamp highlights take): the
// metallic share rising from the base colour, the rest a dielectric.
Fresnel specular_fresnel(const Material& m) {
    Fresnel f;
    const float s = specular_weight(m);
    if (!(s > 0)) return f;
    f.tint = metal_color_of(m);
    f.mirror = std::min(std::max(m.metallic, 0.0f), s);
    f.f0 = dielectric_f0(m);
    f.dielectric = f.f0 > 0 ? 1 - std::max(m.metallic, 0.0f) : 0.0f;
    return f;
}

// What the dielectric layer reflects, seen from cos_o, of light arriving from
// all around: what its rays return from a white world (the GGX lobe's albedo
// with the Fresnel at each microfacet, and multiscatter's gain), the Fresnel
// at the view's angle where it is sharp. A layered diffuse
// (Material::layered_diffuse) gets the rest. (The Fresnel at the view's angle
// times the lobe's albedo, first used here, took 0.476 where the rays return
// 0.082 at roughness 0.8 seen at cos 0.1: the diffuse lost up to 40% at
// silhouettes, a review found.)
float layer_albedo(const Material& m, float f0, float cos_o) {
    if (!(m.roughness > 0)) return fresnel_dielectric(cos_o, dielectric_eta(f0));
    const float alpha = ggx_alpha(m.roughness), e = ggx_dielectric_albedo(cos_o, alpha, f0);
    return std::min(m.multiscatter ? e * (1 + f0 * ggx_multiscatter_gain(cos_o, alpha)) : e, 1.0f);
}

// The colour of the mirror reflection of weight refl > 0 (shade_hit): the
// metallic share's base colour, a Glass BSDF's colour, else white.
Vec3 reflection_tint(const Material& m, float refl) {
    return m.metallic > 0        ? metal_tint(m, std::min(m.metallic, m.mirror) / refl)
           : m.tints_reflection ? m.color
                                : Vec3(1, 1, 1);
}

// What of a glossy surface's highlight its reflection rays do not see (they
// see the emitters: trace() returns what they emit): the whole specular less
// the mirror share (beyond the metal, out of the dielectric) and less the
// dielectric layer's share; nothing behind glass's Fresnel reflection ray.
// Lamps, which those rays do not see, take the whole specular in direct().
Fresnel emitter_fresnel(const Material& m) {
    if (m.transmittance > 0) return Fresnel();
    Fresnel f = specular_fresnel(m);
    // (a mirror beyond the metal, white, takes its weight out of the dielectric's reflectance
    // at normal incidence: the dielectric is scaled down by that share of it)
    const float beyond_metal = std::max(m.mirror - f.mirror, 0.0f), reflectance = f.dielectric * f.f0;
    f.mirror = std::max(f.mirror - m.mirror, 0.0f);
    if (beyond_metal > 0)
        f.dielectric = reflectance > beyond_metal ? f.dielectric * (1 - beyond_metal / reflectance) : 0.0f;
    f.dielectric = std::max(f.dielectric - dielectric_share(m), 0.0f);
    return f;
}

// Whether a lobe reflects anything (a share of some weight).
bool carries(const GgxView& v) {
    return v.seen && (v.dielectric_scale > 0 || v.mirror_scale.x > 0 || v.mirror_scale.y > 0 || v.mirror_scale.z > 0);
}

// A glossy surface's (roughness > 0) GGX lobe, of the reflectance f.
GgxView glossy_view(const Material& m, const Fresnel& f, const Vec3& ns, const Vec3& wo) {
    return ggx_view(ns, wo, ggx_alpha(m.roughness), f, m.multiscatter);
}

// The shares of a lobe that no ray carries (direct()'s `own`: all of it where no reflection rays
// are traced, or for lights that rays do not see) take a light by its points alone, so a lobe
// much narrower than a light would be met by few of its points, each weighing
// D's peak: a sun 0.4 radians wide on a metal of roughness 0.01 summed to
// 0.5-2.3% of a mirror's highlight at 16 x 4 samples a pixel, and widening
// the lobe instead (to a fifth of the light's radius) dimmed a rect light's
// reflection by 25-40%. (The shares whose rays are traced take it by multiple importance
// sampling with those rays instead, tails and all.) Where alpha is below kMirrorLobe of the light's
// (tangent) radius, the reflected lobe lies well inside the light's image, and
// the highlight is the light seen in the mirror direction times the lobe's
// albedo with Fresnel and its share within about half the light's radius
// (mirrored_light): within a few percent inside the reflection, sharp at its
// edge, no noise.
constexpr float kMirrorLobe = 0.1f;

// Whether any channel of v is positive.
bool any_positive(const Vec3& v) { return v.x > 0 || v.y > 0 || v.z > 0; }

// The density per solid angle with which from_emitters' light points reach a point of an
// emissive triangle picked with `probability`, dist away, cos_l being |area normal . direction|
// (the area normal twice the triangle's area long; both sides emit).
double emitter_point_density(double probability, double dist, double cos_l) {
    return probability * dist * dist / (0.5 * cos_l);
}

// The (u1, u2) of a lobe's n rays at a shading point (glossy_lobe, rough_glass): at a path's
// first glossy bounce (not split) the pixel's samples' directions form one stratified set, as
// the lens points do (sampler.h, shared_slot), shuffled per pixel and depth; split paths (inside
// the first bounce's n rays) draw at random.
struct LobeStrata {
    uint32_t n, key, sample, samples;
    float rot;
    LobeStrata(SampleState& st, bool split, int rays, int depth, Stream stream) : n(uint32_t(rays)) {
        const bool shared = !split && st.samples > 1 && shared_set_fits(st.samples, n);
        key = shared ? hash4(st.seed, st.pixel, uint32_t(depth), uint32_t(stream)) : 0;
        rot = shared ? to_unit(mix32(key)) : st.rng.next();
        sample = shared ? st.sample : 0;
        samples = shared ? st.samples : 1;
    }
    void point(int j, SampleState& st, float& u1, float& u2) const {
        strat2(shared_slot(sample, samples, key, uint32_t(j)), n * samples, st.rng.next(), rot, u1, u2);
    }
};

// lamps_in_lobe's Russian roulette on small weights.
constexpr float kLampRoulette = 0.1f;

// A lobe shares a lamp's highlight with the lamp's points (Integrator::shares_lamp) while its
// alpha is under this times the lamp's angular radius. A wider lobe gave its rays weights near 0
// (the lamp's points are far denser), and the work of weighing both sides cost the Cycles
// benchmark's scene (a rough floor under a 1.5 m area light) about a tenth of its render time.
constexpr float kShareLobe = 1.0f;

// The least integer whose square is at least x.
uint32_t ceil_sqrt(uint32_t x) {
    uint32_t r = uint32_t(std::sqrt(double(x)));
    while (uint64_t(r) * r < x) ++r;
    while (r > 0 && uint64_t(r - 1) * (r - 1) >= x) --r;
    return r;
}

// A dielectric layer's reflection rays (shade_hit) where the layer alone reflects less than
// this, seen from the view, are traced by Russian roulette. Measured as error x time against
// tracing every one (RMSE against each one's 200-spp reference, 4 and 16 spp, three seeds):
// SPD balls size 3 as the Cycles benchmark builds them (a rough Principled floor) 16 spp 1.24x
// as efficient at 0.25 (the same RMSE, 0.81x the time), 1.09x at 0.1; a dark glossy floor
// under a sky, whose reflection is most of its colour, 1.02x at 0.25 and 0.4x at 0.5.
constexpr float kLayerRoulette = 0.25f;

}  // namespace

Integrator::Integrator(const Accel& accel, const RenderSettings& s) : accel_(accel), scene_(accel.scene()), s_(s) {
    for (const Light& L : scene_.lights()) shaped_lights_ = shaped_lights_ || has_visible_shape(L);
    // More than kManyLights lights that fall off with distance: direct() draws kLightPicks of them.
    const auto& lights = scene_.lights();
    auto drawable = [](const Light& L) { return L.inverse_square && L.kind != LightKind::Sun; };
    const size_t falling = size_t(std::count_if(lights.begin(), lights.end(), drawable));
    if (falling > kManyLights) {
        const size_t n = lights.size();
        picked_.resize(n);
        light_x_.resize(n), light_y_.resize(n), light_z_.resize(n);
        light_power_.resize(n), light_reach_.resize(n), light_reach2_.resize(n);
        for (size_t i = 0; i < n; ++i) {
            const Light& L = lights[i];
            picked_[i] = drawable(L);
            light_x_[i] = L.position.x, light_y_[i] = L.position.y, light_z_[i] = L.position.z;
            // (its brightest channel, over the whole sphere for a spot; 0 for a light not drawn;
            // an area light's size bounds how close its power can count as coming from one point)
            light_power_[i] = picked_[i] ? std::max(L.color.x, std::max(L.color.y, L.color.z)) : 0.0f;
            const float size = L.kind == LightKind::Rect || L.kind == LightKind::Ellipse
                                   ? 0.5f * std::hypot(L.size[0], L.size[1])   // (its corners' reach)
                                   : L.radius;
            light_reach_[i] = size;
            light_reach2_[i] = std::max(size * size, 1e-30f);
        }
    }
    if (!scene_.sun_map().empty()) sun_radius_ = float(std::sqrt(scene_.sun_map().solid_angle() / kPi));
}

// The environment's sun (its bright cells, scene.sun_map()) seen in a GGX lobe of alpha wider than
// the sun: sampled as a light, the lobe's Fresnel f (what its rays carry) times D G2 / (4 cos_o)
// times the sun's radiance over the density of the sun's points, one shadow ray each, as many as
// a light with a size gets; the lobe's rays leave the sun out (Ray::without_sun). Its rays alone
// met the sun with a small chance and its whole radiance (thousands of times the sky's):
// fireflies over every glossy surface under an HDRI with a sun, Principled dielectrics included.
Vec3 Integrator::sun_highlight(const SurfacePoint& sp, const Vec3& ng, const GgxView& lobe, int depth, bool split,
                               SampleState& st, TraceContext& ctx) const {
    if (!lobe.seen) return Vec3();
    // (pi x the BRDF x cos_i; the sun's points after sun_seen's in the grid's key)
    return sun_light(sp, ng, 3, depth, split, st, ctx, [&](const Vec3& wi, float& s) {
        s = 1;
        return ggx_highlight(lobe, wi);
    });
}

Vec3 Integrator::camera_ray(const Ray& ray, const Vec3& view_axis, SampleState& st, TraceContext& ctx,
                            FirstHit* fh) const {
    Ray r = ray;
    r.kind = RayKind::Camera;
    return trace(r, 1, 1.0f, false, RayType::Primary, st, ctx, fh, view_axis);
}

// 1 where the light is seen, 0 where it is blocked, per channel; in between
// behind surfaces that let light through, tinted by coloured glass (only
// scenes with such materials pay for it). glass_blocks: only alpha's
// uncovered part lets light through (transmission()).
Vec3 Integrator::visible(const Vec3& p, const Vec3& p_err, const Vec3& ng, const Vec3& wi, float dist,
                          TraceContext& ctx, bool glass_blocks) const {
    Ray r;
    r.o = offset_origin(p, p_err, ng, wi);
    r.d = wi;
    // Stop just short of the light's sampled point (relative, so scale-free).
    r.tmax = std::isinf(dist) ? kInf : dist * (1.0f - 1e-5f);
    r.spawned = true;
    if (ctx.unshadowed) return Vec3(1, 1, 1);
    ++ctx.stats.rays[int(RayType::Shadow)];
    if (scene_.transparent_shadows()) return transmission(r, ctx, glass_blocks);
    return accel_.occluded(RayPre(r), ctx) ? Vec3(0, 0, 0) : Vec3(1, 1, 1);
}

// A light point's contribution c, and c_shared, the part weighted against the glossy rays that
// meet the same light (multiple importance sampling): those rays pass alpha cut-outs but not
// glass (the light behind glass reaches them by its own refraction rays, at full weight), so
// c_shared sees the light through cut-outs only.
Vec3 Integrator::point_light_seen(const SurfacePoint& sp, const Vec3& wi, float dist, const Vec3& c,
                                  const Vec3& c_shared, bool casts_shadows, TraceContext& ctx,
                                  bool through_glass) const {
    if (!casts_shadows) return c + c_shared;
    // (a light hidden from transmission rays reaches no point through glass: Cycles carries that
    // light by a transmission bounce; alpha cut-outs still let it pass)
    if (!through_glass) return (c + c_shared) * visible(sp.p, sp.p_err, sp.ng, wi, dist, ctx, true);
    if (!scene_.transparent_shadows() || !any_positive(c_shared))
        return (c + c_shared) * visible(sp.p, sp.p_err, sp.ng, wi, dist, ctx);
    Vec3 sum = c_shared * visible(sp.p, sp.p_err, sp.ng, wi, dist, ctx, true);
    if (any_positive(c)) sum += c * visible(sp.p, sp.p_err, sp.ng, wi, dist, ctx);
    return sum;
}

// The ray moved on past its hit, unbent (a cut-out, a surface hidden from it). Inside a
// triangle the same ray is resumed, from the same origin, meeting only what comes after the hit
// in the order of t and then primitive index (Ray::after): a surface in the plane of the one
// passed is still met (a cube's bottom face hidden from the camera, on a floor: moving the origin
// off the face moved it past the floor too, and the floor showed holes where the face was met
// first). Within kEdgeBand of its triangle's edges the ray may meet the neighbouring triangle at
// the same point, a t a few ulps on, and would cross the surface twice: there the origin moves
// just beyond the surface instead, as all passes did before; so it does past a sphere or cone,
// whose test gives the root nearest tmin (the one passed, which Ray::after would reject) and not
// the far one beyond it.
Ray Integrator::past(const Hit& hit, const SurfacePoint& sp, const Ray& ray) const {
    constexpr float kEdgeBand = 0x1p-16f;
    Ray next = ray;
    if (size_t(hit.prim) < scene_.num_triangles() && std::min(std::min(hit.u, hit.v), 1.0f - hit.u - hit.v) > kEdgeBand) {
        next.tmin = next_down(hit.t);
        next.after = hit.prim;
        return next;
    }
    next.o = offset_origin(sp.p, sp.p_err, sp.ng, ray.d);
    next.tmin = 0;
    next.after = -1;
    next.spawned = true;
    const float moved = length(next.o - ray.o);
    if (!std::isinf(ray.tmax)) next.tmax = std::max(ray.tmax - moved, 0.0f);
    if (ray.emitter_mis > 0) next.mis_offset = ray.mis_offset + moved;
    return next;
}

// Whitted's transparent shadows: each surface on the way passes (1 - alpha)
// of the light uncovered plus its transmittance of the covered part, tinted
// by its colour where it tints what it refracts (coloured glass).
Vec3 Integrator::transmission(Ray r, TraceContext& ctx, bool glass_blocks) const {
    Vec3 through(1, 1, 1);
    // (64 crossings of surfaces that shadow; as many as kMaxHiddenCrossings of ones that cast none)
    for (int crossings = 0, passed_by = 0; crossings < 64 && passed_by < kMaxHiddenCrossings;) {
        const RayPre rp(r);
        Hit hit;
        hit.t = r.tmax;
        if (!accel_.closest(rp, hit, ctx)) return through;
        const SurfacePoint sp = scene_.surface(rp, hit);
        const Material& m = scene_.materials()[size_t(sp.material)];
        if (!m.lets_light_through()) return Vec3(0, 0, 0);
        ++(m.visible_shadow ? crossings : passed_by);
        if (m.visible_shadow) {   // (a surface that casts no shadow passes it all)
            const float alpha = m.alpha_texture >= 0 ? scene_.alpha_at(m, hit, TextureView::at(sp, r.d, camera_)) : m.alpha;
            float passed = glass_blocks ? 0.0f : std::min(std::max(m.transmittance, 0.0f), 1.0f);
            if (passed > 0 && m.ior != 1.0f) {   // less what the surface reflects: the exact Fresnel at the
                // ray's angle, taken on the rarer side (the ray is not bent, so both crossings are alike and
                // none is a total internal reflection); IOR 1: none
                const float eta = m.ior > 1.0f ? m.ior : 1.0f / m.ior;
                passed *= 1.0f - fresnel_dielectric(std::abs(dot(r.d, sp.ng)), eta);
            }
            const Vec3 tint = refraction_tint(m);
            through = through * (Vec3(1, 1, 1) * (1 - alpha) + tint * (alpha * passed));
            if (std::max(through.x, std::max(through.y, through.z)) <= 1e-4f) return Vec3(0, 0, 0);
        }
        r = past(hit, sp, r);
        ++ctx.stats.rays[int(RayType::Shadow)];
    }
    return Vec3(0, 0, 0);
}

// The shadowing of diffuse light by the bumps a normal map stands for
// (Chiang, Li & Burley, "Taming the Shadow Terminator", 2019, as Cycles
// applies it): 0 for light below the horizon of the normal before the map
// (smooth), else G1 of a microfacet slope distribution whose roughness
// alpha^2 = tan^2(d) / 8 grows with the angle d the map turned the normal
// through: light grazing the smooth surface fades out instead of ending at
// the terminator of the tilted normal.
static float bump_shadowing(const Vec3& smooth, const Vec3& mapped, const Vec3& wi) {
    const float cos_i = dot(smooth, wi);
    if (!(cos_i > 0)) return 0;
    const float cos_d = std::min(std::abs(dot(smooth, mapped)), 1.0f);
    if (cos_d >= 1) return 1;
    const float tan2_d = (1 - cos_d * cos_d) / std::max(cos_d * cos_d, 1e-12f);
    const float alpha2 = std::min(std::max(0.125f * tan2_d, 0.0f), 1.0f);
    const float tan2_i = (1 - cos_i * cos_i) / (cos_i * cos_i);
    return 2 / (1 + std::sqrt(1 + alpha2 * tan2_i));
}

Vec3 Integrator::direct(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Material& m,
                        int depth, bool split, SampleState& st, TraceContext& ctx, const GgxView* traced) const {
    Vec3 total;
    const Vec3 smooth = dot(sp.ng, ng) < 0 ? -sp.unmapped : sp.unmapped;   // (on ng's side, as ns is)
    const auto& lights = scene_.lights();
    const GgxView glossy = m.roughness > 0 ? glossy_view(m, specular_fresnel(m), ns, wo) : GgxView();
    // Where reflection rays are traced from here (traced), they see the lamps' shapes too, and
    // the light points of a lamp with a shape take the traced shares' highlight by multiple
    // importance sampling (glossy_lobe takes the rays' part); what no ray carries (rest) they
    // take whole, as every share of a lamp without a shape or with hard shadows.
    const Fresnel untraced = traced ? emitter_fresnel(m) : Fresnel();
    const GgxView rest = untraced.mirror > 0 || untraced.dielectric > 0 ? glossy_view(m, untraced, ns, wo) : GgxView();
    const double rays_per_point = traced ? double(glossy_rays(split)) / double(light_points(s_.shadow, st)) : 0.0;
    // One light's direct light at the point (all its light points).
    auto one = [&](size_t li) -> Vec3 {
        Vec3 out;
        const Light& L = lights[li];
        const bool has_area = L.kind == LightKind::Sphere || L.kind == LightKind::Spot ? L.radius > 0
                            : L.kind == LightKind::Rect   ? L.size[0] > 0 || L.size[1] > 0
                            : L.kind == LightKind::Disk   ? L.radius > 0
                            : L.kind == LightKind::Ellipse ? L.size[0] > 0 && L.size[1] > 0
                            : L.kind == LightKind::Sun    ? L.angle > 0
                                                          : false;
        // A sharp mirror reflects what its rays see: a light with a shape (lights_seen),
        // nothing of a Blender point light, as in Cycles. Its share of the highlight is
        // theirs, as an emitter's is (from_emitters), and so is sharp glass's (its Fresnel
        // reflection ray sees the light), and a dielectric layer's that reflects (its rays see
        // it too). (Lights without falloff, NFF's, keep
        // Whitted's highlight: the SPD scenes' mirror balls show it.)
        const bool reflected = m.roughness <= 0 && (L.inverse_square || has_visible_shape(L));
        const float highlight = !L.visible_glossy ? 0.0f
                                : reflected ? m.ks * std::max(1.0f - m.mirror - m.transmittance - dielectric_share(m), 0.0f)
                                            : m.ks;
        const float diffuse = L.visible_diffuse ? m.kd : 0.0f;
        // How many light points this shading point uses, and where they come from.
        const ShadowMode mode = has_area ? s_.shadow : ShadowMode::Hard;
        const int count = light_points(mode, st);
        const bool glossy_highlight = m.roughness > 0 && highlight > 0;
        // (lights without falloff other than the sun, which Blender does not make, have
        // no radiance that their light points' intensities stand for: sampled only)
        const float radius = glossy_highlight && has_visible_shape(L) &&
                                     (L.inverse_square || L.kind == LightKind::Sun)
                                 ? angular_radius(L, sp.p) : 0.0f;
        const bool mirrored = ggx_alpha(m.roughness) < kMirrorLobe * radius;
        // (a drawn light's points take the rays' share of its highlight whole, at weight 1: the
        // rays skip drawn lights, lamps_in_lobe)
        const bool rays_see = traced && L.visible_glossy && mode != ShadowMode::Hard &&
                              shares_lamp(L, sp.p, ggx_alpha(m.roughness));
        const bool shared = rays_see && !drawn(li);
        const GgxView& own = rays_see ? rest : glossy;   // what the light points take whole
        const bool own_highlight = glossy_highlight && carries(own);
        if (mirrored && own_highlight) out += mirrored_light(L, sp, ng, own, radius, ctx);
        // A flat light near the point: set up once for its light points (near_area_light.h).
        NearArea near;
        const int near_state = mode != ShadowMode::Hard ? near_area_light(L, sp.p, ns, near) : -1;
        Vec3 sum;
        for (int j = 0; j < count; ++j) {
            float u1, u2;
            light_point(mode, uint32_t(li), j, count, depth, split, st, u1, u2);
            LightSample ls;
            if (near_state == 0) continue;   // (no light reaches the point; its light points are drawn all the same)
            if (!(near_state == 1 ? sample_near_area(L, near, ns, u1, u2, ls) : sample_light(L, sp.p, ns, u1, u2, ls)))
                continue;
            if (dot(ng, ls.wi) <= 0) continue;
            const float cos_i = dot(ns, ls.wi);
            if (cos_i <= 0) continue;
            Vec3 f = m.color * (diffuse * cos_i * (sp.mapped ? bump_shadowing(smooth, ns, ls.wi) : 1.0f));
            Vec3 f_shared;
            if (shared) {   // (the power heuristic: the rays' density over the light points')
                const double ratio = rays_per_point * double(ggx_pdf(*traced, ls.wi)) /
                                     light_density(L, near_state, near, sp.p, ns, ls.wi, ls.dist);
                f_shared = ggx_highlight(*traced, ls.wi) * float(1 / (1 + ratio * ratio));
            } else if (rays_see) {
                f_shared = ggx_highlight(*traced, ls.wi);
            }
            if (glossy_highlight) {
                if (!mirrored && own_highlight) f += ggx_highlight(own, ls.wi);
            } else if (highlight > 0) {
                const Vec3 h = normalize(ls.wi + wo);
                const float sp_ = highlight * std::pow(std::max(dot(ns, h), 0.0f), m.shininess);
                f += m.metallic > 0 ? metal_tint(m, std::min(1.0f, m.metallic * (m.shininess + 8.0f) / (8.0f * m.ks))) * sp_
                                    : Vec3(sp_, sp_, sp_);
            }
            const Vec3 c = f * ls.intensity, c_shared = f_shared * ls.intensity;
            if (!any_positive(c) && !any_positive(c_shared)) continue;
            sum += point_light_seen(sp, ls.wi, ls.dist, c, c_shared, L.casts_shadows, ctx, L.visible_transmission);
        }
        return out + sum * (1.0f / float(count));
    };
    if (picked_.empty()) {
        for (size_t li = 0; li < lights.size(); ++li) total += one(li);
    } else {
        // Many lights: the lights that are not picked (suns, lights without falloff) whole, and
        // kLightPicks of the others, each drawn with a probability proportional to its power times
        // its cosine at the point over its squared distance (none for a light wholly below the
        // point's horizon, which lights nothing there), weighing its light 1 / (picks x
        // probability): the same mean.
        for (size_t li = 0; li < lights.size(); ++li)
            if (!picked_[li]) total += one(li);
        // (the weights first, over the lights' arrays, which the compiler vectorises; then their
        // running sum)
        const size_t n = lights.size();
        thread_local std::vector<double> weight;
        thread_local std::vector<double> cdf;
        weight.resize(n);
        cdf.resize(n);
        // (in double: a light 1e13 away, which float's d^3 overflows, keeps its weight)
        const double px = sp.p.x, py = sp.p.y, pz = sp.p.z, nx = ns.x, ny = ns.y, nz = ns.z;
        for (size_t li = 0; li < n; ++li) {
            const double dx = light_x_[li] - px, dy = light_y_[li] - py, dz = light_z_[li] - pz;
            const double d2 = std::max(dx * dx + dy * dy + dz * dz, double(light_reach2_[li]));
            const double facing = std::max(nx * dx + ny * dy + nz * dz + light_reach_[li], 0.0);
            const double w = light_power_[li] * facing / (d2 * std::sqrt(d2));
            weight[li] = w >= 0 ? std::min(w, 1e300) : 0.0;   // (on a light's centre: finite; NaN: none)
        }
        double run = 0;
        for (size_t li = 0; li < n; ++li) {
            run += weight[li];
            cdf[li] = run;
        }
        if (run > 0 && std::isfinite(run)) {
            for (int k = 0; k < kLightPicks; ++k) {
                const double x = double(st.rng.next()) * run;
                const size_t li = size_t(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin());
                if (li >= lights.size() || !picked_[li]) continue;   // (x at the very top: rounding)
                const double p = (cdf[li] - (li ? cdf[li - 1] : 0.0)) / run;
                if (!(p > 0)) continue;
                total += one(li) * float(1.0 / (double(kLightPicks) * p));
            }
        }
    }
    if (!scene_.emitters().empty()) total += from_emitters(sp, ng, ns, wo, m, depth, split, st, ctx, traced);
    return total;
}

Vec3 Integrator::mirrored_light(const Light& L, const SurfacePoint& sp, const Vec3& ng, const GgxView& lobe,
                                float radius, TraceContext& ctx) const {
    if (!lobe.seen) return Vec3();
    const Vec3 r = lobe.ns * (2.0f * lobe.cos_o) - lobe.wo;
    if (!(dot(r, ng) > 0)) return Vec3();
    float t;
    Vec3 radiance;
    if (!light_shape_hit(L, sp.p, r, t, radiance)) return Vec3();
    const Vec3 seen = L.casts_shadows ? radiance * visible(sp.p, sp.p_err, sp.ng, r, t, ctx) : radiance;
    // (less the lobe's tails beyond the light: GGX's normals lie within angle t of the
    // normal with probability tan^2 t / (alpha^2 + tan^2 t), here t about half the
    // light's radius, the mirror direction at its centre)
    const float t2 = 0.25f * radius * radius;
    return seen * ggx_albedo_fresnel(lobe) * (t2 / (lobe.a2 + t2));
}

int Integrator::light_points(ShadowMode mode, const SampleState& st) const {
    const uint32_t n = uint32_t(std::max(1, s_.shadow_samples));
    if (mode == ShadowMode::Random) return int(n);
    if (mode == ShadowMode::Area) return int(std::max<uint32_t>(1, (n * n + st.samples - 1) / st.samples));
    return 1;
}

void Integrator::light_point(ShadowMode mode, uint32_t li, int j, int count, int depth, bool split,
                             SampleState& st, float& u1, float& u2) const {
    u1 = u2 = 0.5f;   // Hard: the light's centre
    // (The rays of a split glossy bounce share their sample's index, so
    // the light grid would give them all one point: they draw at random.)
    if (mode == ShadowMode::Random || (mode == ShadowMode::Area && split)) {
        u1 = st.rng.next();
        u2 = st.rng.next();
    } else if (mode == ShadowMode::Area) {
        // The seed's area-light method: an n x n jittered grid of light
        // positions, shuffled per pixel so that the pixel's sub-samples
        // meet different positions. At every hit of a sample's path:
        // each depth has its own shuffle and jitter (depth 1 keeps the
        // primary hits' key), so a mirror's or a refraction's hits are
        // stratified over the pixel's samples too.
        // A pixel of more samples than the n x n strata (anti-aliasing raised, shadow samples
        // not) takes a finer grid, one stratum per sample: with n x n it met the same n x n
        // jittered points over and over (4 per pixel at 16 x 16 samples and n = 2), and
        // its soft shadows and world shadows stayed as grainy as at 2 x 2.
        const uint32_t n = uint32_t(std::max(1, s_.shadow_samples));
        const uint32_t side = n * n >= st.samples ? n : ceil_sqrt(st.samples), grid = side * side;
        const uint32_t slot = (st.sample * uint32_t(count) + uint32_t(j)) % grid;
        const uint32_t light_key = li + uint32_t(depth - 1) * kGoldenRatio32;
        const uint32_t key = hash4(st.seed, st.pixel, light_key, uint32_t(Stream::AreaLightGrid));
        const uint32_t cell = permute(slot, grid, key);
        u1 = (float(cell % side) + to_unit(hash4(key, cell, 1, 0))) / float(side);
        u2 = (float(cell / side) + to_unit(hash4(key, cell, 2, 0))) / float(side);
    }
}

Vec3 Integrator::world_blocked(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split,
                               SampleState& st, TraceContext& ctx) const {
    // World shadows (world_shadows.h): the world's light these directions
    // would bring that the scene blocks, as a mean of L (1 - V) cos / pdf / pi,
    // over the points a light with a size gets (the world is the light after
    // the emitters in the grid's key).
    const ShadowMode mode = spread_mode();
    const int count = light_points(s_.shadow, st);
    const WorldMap& map = scene_.world_map();
    Vec3 sum;
    for (int j = 0; j < count; ++j) {
        float u1, u2;
        light_point(mode, uint32_t(scene_.lights().size()) + 1, j, count, depth, split, st, u1, u2);
        Vec3 wi;
        if (!map.empty() && u1 < 0.5f) {
            wi = scene_.from_environment(map.sample(u1 * 2.0f, u2));
        } else {
            wi = cosine_direction(ns, map.empty() ? u1 : (u1 - 0.5f) * 2.0f, u2);
        }
        const float cos_i = dot(ns, wi);
        if (!(cos_i > 0)) continue;
        const float cosine_pdf = cos_i * float(1 / kPi);
        const float pdf = map.empty() ? cosine_pdf : 0.5f * (map.pdf(scene_.to_environment(wi)) + cosine_pdf);
        if (!(pdf > 0)) continue;
        // Below the true surface the surface itself blocks the world.
        const Vec3 vis = dot(ng, wi) > 0 ? visible(sp.p, sp.p_err, sp.ng, wi, kInf, ctx) : Vec3(0, 0, 0);
        if (std::min(vis.x, std::min(vis.y, vis.z)) >= 1) continue;
        sum += scene_.world_light(wi) * (Vec3(1, 1, 1) - vis) * (cos_i * float(1 / kPi) / pdf);
    }
    return sum * (1.0f / float(count));
}

Vec3 Integrator::sun_seen(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split,
                          SampleState& st, TraceContext& ctx) const {
    // The environment's bright cells (a sun) as a light: points drawn on them
    // by their luminance, each lighting what sees it (never below 0, unlike
    // the blocked-part estimate, whose variance a sun would make huge). The
    // sun is the light after the world in the grid's key.
    return sun_light(sp, ng, 2, depth, split, st, ctx, [&](const Vec3& wi, float& s) {
        s = dot(ns, wi);
        return Vec3(1, 1, 1);
    });
}

template <class Response>
Vec3 Integrator::sun_light(const SurfacePoint& sp, const Vec3& ng, uint32_t key, int depth, bool split,
                           SampleState& st, TraceContext& ctx, Response response) const {
    const WorldMap& sun = scene_.sun_map();
    const int count = light_points(s_.shadow, st);
    Vec3 sum;
    for (int j = 0; j < count; ++j) {
        float u1, u2;
        light_point(spread_mode(), uint32_t(scene_.lights().size()) + key, j, count, depth, split, st, u1, u2);
        const Vec3 e = sun.sample(u1, u2), wi = scene_.from_environment(e);
        const float pdf = sun.pdf(e);
        if (!(pdf > 0) || dot(ng, wi) <= 0) continue;
        float s;
        const Vec3 f = response(wi, s);
        if (!(s > 0) || !(f.x > 0 || f.y > 0 || f.z > 0)) continue;
        sum += f * sun.radiance(e) * visible(sp.p, sp.p_err, sp.ng, wi, kInf, ctx) * (s * float(1 / kPi) / pdf);
    }
    return sum * (1.0f / float(count));
}

Vec3 Integrator::from_emitters(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo,
                               const Material& m, int depth, bool split, SampleState& st, TraceContext& ctx,
                               const GgxView* traced) const {
    // The emissive triangles as one area light after the lamps (its index in
    // the light grid's key): the same number of points per shading point and
    // the same stratification as a lamp with a size.
    const ShadowMode mode = spread_mode();
    const int count = light_points(s_.shadow, st);
    const Vec3* corners = scene_.triangle_vertices();
    const Vec3 smooth = dot(sp.ng, ng) < 0 ? -sp.unmapped : sp.unmapped;   // (as in direct())
    // A glossy surface's own reflection rays see the emitters (trace() returns what they emit):
    // the highlight sampled here is what they leave out (emitter_fresnel).
    const Fresnel rest = m.roughness > 0 ? emitter_fresnel(m) : Fresnel();
    const bool glossy_highlight = rest.mirror > 0 || rest.dielectric > 0;
    const GgxView glossy = glossy_highlight ? glossy_view(m, rest, ns, wo) : GgxView();
    const float sharp_highlight = m.ks * std::max(1.0f - m.mirror - m.transmittance - dielectric_share(m), 0.0f);
    // Where the shares whose rays are traced (traced) meet emitters by those rays too, each way
    // weighs its estimate by the power heuristic over both densities (Veach's multiple importance
    // sampling, as Cycles does): a small emitter's highlight on a rough surface comes from its
    // light points, a large one's on a nearly sharp surface from the rays. The rays alone took
    // it before: fireflies wherever a small panel lit a rough metal or Principled floor.
    const double ray_density = traced ? double(glossy_rays(split)) / double(count) : 0.0;
    Vec3 sum;
    for (int j = 0; j < count; ++j) {
        float u1, u2;
        light_point(mode, uint32_t(scene_.lights().size()), j, count, depth, split, st, u1, u2);
        float probability, u_rest;
        const int32_t tri = scene_.emitters().pick(u1, probability, u_rest);
        // A uniform point on the triangle: barycentrics (1 - s, s (1 - u2), s u2), s = sqrt(u_rest).
        const float s = std::sqrt(u_rest);
        Hit at;
        at.prim = tri;
        at.u = s * (1.0f - u2);
        at.v = s * u2;
        const Vec3 *v = corners + 3 * size_t(tri);
        const Vec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
        const Vec3 q = v[0] + e1 * at.u + e2 * at.v;
        const Vec3 area_normal = cross(e1, e2);   // twice the area, along the normal
        const Vec3 to = q - sp.p;
        const float dist = length(to);
        if (!(dist > 0)) continue;
        const Vec3 wi = to / dist;
        if (dot(ng, wi) <= 0) continue;
        const float cos_i = dot(ns, wi);
        if (cos_i <= 0) continue;
        // Both sides emit: |cos| at the light. Radiance L over area A seen from
        // distance d lights like an intensity L cos A / d^2; the diffuse term's
        // 1 / pi is folded in here, as in every light's colour.
        const float cos_l = std::abs(dot(area_normal, wi));   // (x 2 A)
        const Material& em = scene_.materials()[size_t(scene_.triangle_material(tri))];
        // (what an emitter's alpha leaves uncovered emits nothing, as the camera sees it)
        Material e = em;
        if (em.varies()) {   // (the point as a ray from sp along wi meets it: its normals as shading sees them)
            Ray toward;
            toward.o = sp.p;
            toward.d = wi;
            e = scene_.shade(em, at, TextureView::at(scene_.surface(RayPre(toward), at), wi, camera_));
        }
        const Vec3 radiance = emitted(e) * e.alpha;
        // (in double: a point nearer than ~1e-19 would square to 0 in float)
        const double scale = 0.5 * double(cos_l) / (kPi * double(dist) * double(dist) * double(probability));
        const Vec3 intensity = radiance * float(std::min(scale, double(std::numeric_limits<float>::max())));
        Vec3 f = m.color * (m.kd * cos_i * (sp.mapped ? bump_shadowing(smooth, ns, wi) : 1.0f));
        Vec3 f_shared;
        // An emitter hidden from glossy rays gives no highlight (as Cycles leaves a mesh light's glossy
        // part out for an object with Glossy off); its diffuse light stays.
        if (traced && em.visible_glossy) {   // (the light point's density per solid angle; the rays' over it, per point)
            const double ratio = ray_density * double(ggx_pdf(*traced, wi)) /
                                 emitter_point_density(probability, dist, cos_l);
            f_shared = ggx_highlight(*traced, wi) * float(1 / (1 + ratio * ratio));
        }
        if (!em.visible_glossy) {
        } else if (m.roughness > 0) {
            if (glossy_highlight) f += ggx_highlight(glossy, wi);
        } else if (sharp_highlight > 0) {   // (a mirror's rays see the emitter itself: its highlight is theirs)
            const Vec3 h = normalize(wi + wo);
            const float spec = sharp_highlight * std::pow(std::max(dot(ns, h), 0.0f), m.shininess);
            f += m.metallic > 0 ? metal_tint(m, std::min(1.0f, m.metallic * (m.shininess + 8.0f) / (8.0f * m.ks))) * spec
                                : Vec3(spec, spec, spec);
        }
        const Vec3 c = f * intensity, c_shared = f_shared * intensity;
        if (!any_positive(c) && !any_positive(c_shared)) continue;
        sum += point_light_seen(sp, wi, dist, c, c_shared, true, ctx);
    }
    return sum * (1.0f / float(count));
}

Vec3 Integrator::rough_glass(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo,
                             const Material& m, float n1, float n2, int depth, float weight, bool split,
                             SampleState& st, TraceContext& ctx) const {
    const float alpha = ggx_alpha(m.roughness), eta = n1 / n2;
    Vec3 t, b;
    basis(ns, t, b);
    const Vec3 wo_local(dot(wo, t), dot(wo, b), dot(wo, ns));
    if (!(wo_local.z > 0)) return Vec3();
    const int n = glossy_rays(split);
    const LobeStrata strata(st, split, n, depth, Stream::RoughRefraction);
    const Vec3 reflect_tint = m.tints_reflection ? m.color : Vec3(1, 1, 1);
    const Vec3 pass_tint = refraction_tint(m);
    Ray r;
    r.spawned = true;
    Vec3 sum;
    for (int j = 0; j < n; ++j) {
        float u1, u2;
        strata.point(j, st, u1, u2);
        const Vec3 h = ggx_visible_normal(wo_local, alpha, u1, u2);
        const Vec3 mh = normalize(t * h.x + b * h.y + ns * h.z);
        const float c = std::min(dot(wo, mh), 1.0f);
        if (!(c > 0)) continue;
        const float k = 1.0f - eta * eta * (1.0f - c * c);   // (below 0: total internal reflection)
        const float F = k <= 0 ? 1.0f : fresnel_dielectric(c, n2 / n1);
        // (Only n > 1 rays split the sample: one ray goes on as the sample's own.)
        const bool split_on = split || n > 1;
        if (F > 0 && weight * F > s_.min_weight) {
            const Vec3 w = normalize(mh * (2.0f * c) - wo);
            const float g = ggx_ray_weight(wo_local.z, dot(w, ns), alpha);
            if (g > 0 && dot(w, ng) > 0) {
                r.d = w;
                r.o = offset_origin(sp.p, sp.p_err, sp.ng, w);
                r.kind = RayKind::Glossy;
                sum += trace(r, depth + 1, weight * F, split_on, RayType::Secondary, st, ctx, nullptr, Vec3()) *
                       reflect_tint * (F * g);
            }
        }
        if (F < 1 && weight * (1 - F) > s_.min_weight) {
            const Vec3 w = normalize(-wo * eta + mh * (eta * c - std::sqrt(k)));
            const float g = ggx_ray_weight(wo_local.z, -dot(w, ns), alpha);
            if (g > 0 && dot(w, ng) < 0) {
                r.d = w;
                r.o = offset_origin(sp.p, sp.p_err, sp.ng, w);
                r.kind = RayKind::Transmission;
                sum += trace(r, depth + 1, weight * (1 - F), split_on, RayType::Secondary, st, ctx, nullptr, Vec3()) *
                       pass_tint * ((1 - F) * g);
            }
        }
    }
    // Multiscatter GGX (Material::multiscatter, Blender 4+'s default): what single scattering
    // loses between the microfacets is returned, over reflection and refraction alike, as
    // Cycles' multiscatter glass conserves a white world's light.
    const float gain = m.multiscatter ? 1.0f / ggx_glass_albedo(wo_local.z, alpha, n2 / n1) : 1.0f;
    return sum * (gain / float(n));
}

bool Integrator::shares_lamp(const Light& L, const Vec3& p, float alpha) const {
    return has_visible_shape(L) && alpha < kShareLobe * angular_radius(L, p);
}

Vec3 Integrator::lamps_in_lobe(const Ray& r, const SurfacePoint& sp, const Vec3& ns, double ray_density,
                               float alpha, SampleState& st, TraceContext& ctx) const {
    Vec3 sum;
    const double points = double(light_points(s_.shadow, st));
    for (size_t li = 0; li < scene_.lights().size(); ++li) {
        const Light& L = scene_.lights()[li];
        if (drawn(li)) continue;   // (its light points take its highlight whole: direct())
        float t;
        Vec3 radiance;
        if (!shape_seen_by(L, r.kind) || !light_shape_hit(L, r.o, r.d, t, radiance) || !shares_lamp(L, sp.p, alpha))
            continue;
        NearArea near;   // (as direct() sets it up for this point)
        const int near_state = near_area_light(L, sp.p, ns, near);
        const double ratio = points * light_density(L, near_state, near, sp.p, ns, r.d, t) / ray_density;
        float weight = float(1 / (1 + ratio * ratio));
        if (!(weight > 0)) continue;
        // A weight under kLampRoulette (a wide lobe, whose light points take nearly all of the lamp)
        // tests the lamp's visibility with probability weight / kLampRoulette, weighing the
        // inverse: the same mean, without a shadow ray for every such ray.
        if (weight < kLampRoulette) {
            if (st.rng.next() * kLampRoulette >= weight) continue;
            weight = kLampRoulette;
        }
        // (what lies before the light hides it, as it hides the light's points from their shared
        // part: alpha's uncovered part lets it through, glass does not, the refraction rays take
        // what comes through glass; nothing, where it casts no shadows; lights are transparent,
        // as in Cycles)
        sum += L.casts_shadows ? radiance * weight * visible(sp.p, sp.p_err, sp.ng, r.d, t, ctx, true)
                               : radiance * weight;
    }
    return sum;
}

float Integrator::emitter_weight(const Ray& ray, const Hit& hit, const SurfacePoint& sp) const {
    if (!(ray.emitter_mis > 0) || size_t(hit.prim) >= scene_.num_triangles()) return 1;
    const float probability = scene_.emitters().probability_of(hit.prim);
    if (!(probability > 0)) return 1;
    // The density with which from_emitters' light points reach this point, per solid angle at
    // the shading point the ray left (as there: twice the area along the normal, both sides emit).
    const Vec3* v = scene_.triangle_vertices() + 3 * size_t(hit.prim);
    const double cos_l = std::abs(double(dot(cross(v[1] - v[0], v[2] - v[0]), ray.d)));
    const double dist = double(ray.mis_offset) + double(length(sp.p - ray.o));
    const double ratio = emitter_point_density(probability, dist, cos_l) / double(ray.emitter_mis);
    return float(1 / (1 + ratio * ratio));
}

Vec3 Integrator::glossy_lobe(const SurfacePoint& sp, const Vec3& ng, const Vec3& dir, float roughness,
                             int depth, float weight, bool split, bool through, SampleState& st,
                             TraceContext& ctx, const GgxView* ggx, bool mis) const {
    Ray r;
    r.d = dir;
    r.spawned = true;
    r.kind = through ? RayKind::Transmission : RayKind::Glossy;
    if (roughness <= 0) {   // exact mirror or refraction
        r.o = offset_origin(sp.p, sp.p_err, sp.ng, dir);
        const Vec3 seen = shaped_lights_ ? lights_seen(r, ctx) : Vec3();
        return trace(r, depth + 1, weight, split, RayType::Secondary, st, ctx, nullptr, Vec3()) + seen;
    }
    // Normalised Phong lobe around the mirror (or refracted) direction,
    // exponent from the roughness by Walter et al.'s mapping
    // e = 2 / alpha^2 - 2, alpha = roughness^2. Importance sampling the
    // normalised lobe gives weight 1 per sample; directions on the wrong side
    // of the surface (below it for a reflection, above it for a refraction)
    // count as black, so the estimate never exceeds the exact ray's. (For a
    // refraction this is the reflection's lobe around the refracted ray, not
    // a microfacet BTDF: rough glass blurs what lies behind it as much as
    // a rough mirror blurs what it reflects.)
    const float alpha = std::max(roughness * roughness, 1e-4f);
    const float e = std::max(2.0f / (alpha * alpha) - 2.0f, 0.0f);
    const int n = glossy_rays(split);
    // (Ray::emitter_mis: n over the emitters' light points per shading point, times the density)
    const float mis_scale = mis ? float(n) / float(light_points(s_.shadow, st)) : 0.0f;
    const bool emitters = mis && !scene_.emitters().empty();
    const bool lamps = mis && shaped_lights_ && s_.shadow != ShadowMode::Hard;
    Vec3 t, b;
    basis(ggx ? ggx->ns : dir, t, b);
    // (GGX: the view in the frame of the shading normal)
    const Vec3 wo_local = ggx ? Vec3(dot(ggx->wo, t), dot(ggx->wo, b), dot(ggx->wo, ggx->ns)) : Vec3();
    if (ggx && !(wo_local.z > 0)) return Vec3();
    const LobeStrata strata(st, split, n, depth, through ? Stream::RoughRefraction : Stream::GlossyLobe);
    Vec3 sum;
    for (int j = 0; j < n; ++j) {
        float u1, u2;
        strata.point(j, st, u1, u2);
        Vec3 w, fresnel(1, 1, 1);
        if (ggx) {
            const Vec3 h = ggx_visible_normal(wo_local, alpha, u1, u2);
            const Vec3 mh = t * h.x + b * h.y + ggx->ns * h.z;
            const float cos_m = dot(ggx->wo, mh);
            w = normalize(mh * (2.0f * cos_m) - ggx->wo);
            const float g = ggx_ray_weight(wo_local.z, dot(w, ggx->ns), alpha);
            if (!(g > 0)) continue;
            fresnel = ggx_fresnel(*ggx, cos_m) * g;
            // (a density that rounds to 0 leaves the emitter to the light points: weight 0 here)
            if (emitters) r.emitter_mis = std::max(mis_scale * ggx_pdf(*ggx, w), 1e-30f);
        } else {
            const float ct = std::pow(1.0f - u1, 1.0f / (e + 1.0f)), s = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
            const float phi = float(2 * kPi) * u2;
            w = normalize(t * (s * std::cos(phi)) + b * (s * std::sin(phi)) + dir * ct);
        }
        if (through ? dot(w, ng) >= 0 : dot(w, ng) <= 0) continue;
        r.d = w;
        r.o = offset_origin(sp.p, sp.p_err, sp.ng, w);
        r.without_sun = ggx && samples_sun(alpha);
        // (Only n > 1 rays split the sample: one ray goes on as the sample's own.)
        Vec3 seen = trace(r, depth + 1, weight, split || n > 1, RayType::Secondary, st, ctx, nullptr, Vec3());
        if (lamps) seen += lamps_in_lobe(r, sp, ggx->ns, double(n) * double(ggx_pdf(*ggx, w)), alpha, st, ctx);
        sum += seen * fresnel;
    }
    return sum * (1.0f / float(n));
}

// Whether a surface the ray's kind sees lies on it (surfaces hidden from it are passed).
bool Integrator::blocked(Ray r, TraceContext& ctx) const {
    if (!scene_.hides_from_rays()) return accel_.occluded(RayPre(r), ctx);
    for (int hidden = 0; hidden < kMaxHiddenCrossings; ++hidden) {
        const RayPre rp(r);
        Hit hit;
        hit.t = r.tmax;
        if (!accel_.closest(rp, hit, ctx)) return false;
        const SurfacePoint sp = scene_.surface(rp, hit);
        if (scene_.materials()[size_t(sp.material)].seen_by(r.kind)) return true;
        r = past(hit, sp, r);
    }
    return false;
}

Vec3 Integrator::lights_seen(const Ray& r, TraceContext& ctx) const {
    Vec3 sum;
    for (const Light& L : scene_.lights()) {
        float t;
        Vec3 radiance;
        if (!shape_seen_by(L, r.kind) || !light_shape_hit(L, r.o, r.d, t, radiance)) continue;
        // (any surface before the light hides it: glass in front shows it by its own refraction ray)
        Ray shadow = r;
        shadow.tmax = std::isinf(t) ? kInf : t * (1.0f - 1e-5f);
        ++ctx.stats.rays[int(RayType::Shadow)];
        if (!blocked(shadow, ctx)) sum += radiance;
    }
    return sum;
}

Vec3 Integrator::trace(const Ray& ray_in, int depth, float weight, bool split, RayType type, SampleState& st,
                       TraceContext& ctx, FirstHit* fh, const Vec3& view_axis) const {
    ++ctx.stats.rays[int(type)];
    // Surfaces hidden from this kind of ray (Material::seen_by) are passed here, as a traversal
    // that skips them would: neither a bounce nor a cut-out's crossing (whose stack is capped).
    Ray ray = ray_in;
    RayPre r(ray);
    Hit hit;
    hit.t = ray.tmax;
    bool found = accel_.closest(r, hit, ctx);
    // (a camera ray gone on behind a shadow catcher passes every catcher, as Cycles' does: a
    // catcher made of a closed slab met its own underside, in the top's shadow, and covered all)
    for (int hidden = 0; found && (scene_.hides_from_rays() || ray.behind_catcher); ++hidden) {
        const SurfacePoint at = scene_.surface(r, hit);
        const Material& seen = scene_.materials()[size_t(at.material)];
        if (seen.seen_by(ray.kind) && !(ray.behind_catcher && seen.shadow_catcher)) break;
        ray = past(hit, at, ray);
        r = RayPre(ray);
        hit = Hit();
        hit.t = ray.tmax;
        found = hidden + 1 < kMaxHiddenCrossings && accel_.closest(r, hit, ctx);
    }
    if (!found) {
        if (fh && scene_.world().transparent) return Vec3();   // fh: the camera's own path
        // A glossy ray whose lobe samples the sun sees the environment's radiance map less its
        // sun (world_map(): 512 x 256 cells, what the sun map was split from), so that the two
        // add up to the environment. (The texture less the sun's cells was 14% too bright on a
        // rough metal: its filtering spreads the sun beyond them; the texel less the cell's mean
        // went negative in darker texels, black dots.)
        if (ray.without_sun) return scene_.world_map().radiance(scene_.to_environment(ray.d));
        return scene_.miss(ray.d);
    }
    SurfacePoint sp = scene_.surface(r, hit);
    const Material& stored = scene_.materials()[size_t(sp.material)];
    // (the ray's side of the hit, for the textures: only where the material has some)
    const bool mapped = stored.normal_texture >= 0 || stored.bump_texture >= 0;
    const TextureView view = mapped || stored.varies() ? TextureView::at(sp, ray.d, camera_) : TextureView();
    if (mapped) {
        sp.unmapped = sp.ns;
        sp.ns = scene_.mapped_normal(stored, hit, sp, view);
        sp.mapped = true;
    }
    Material textured;
    if (stored.varies()) textured = scene_.shade(stored, hit, view);
    const Material& m = stored.varies() ? textured : stored;
    if (fh) {
        fh->hit = true;
        fh->alpha = 1;
        fh->depth = hit.t * dot(ray.d, view_axis) + dot(ray.o - ray_in.o, view_axis);   // (from past hidden surfaces)
        fh->normal = sp.ns;
        // (a metal share of its own colour, Material::own_metal_color: the two shares' colours)
        fh->albedo = m.own_metal_color ? m.color * std::min(m.kd, 1.0f) + m.metal_color * std::min(m.metallic, 1.0f)
                                       : m.color;
        fh->mattes.clear();
        if (scene_.has_matte_keys()) fh->mattes.add(scene_.matte_class(size_t(hit.prim)), 1.0f);
        fh->holdout = 0;
    }
    // A holdout: nothing seen, and on the camera's path the film is clear here (no data passes,
    // no matte). The Holdout shader holds out from every ray; an object set to Holdout from
    // camera rays only (other rays see its material, as in Cycles), and keeps its cut-outs.
    const bool held = m.holdout || (m.holdout_camera && ray.kind == RayKind::Camera);
    if (held && m.alpha >= 1) {
        if (fh) *fh = FirstHit(), fh->holdout = 1;
        return Vec3();
    }
    if (fh && m.shadow_catcher && !held && m.alpha > 0) {
        // A shadow catcher on the camera's path (Material::shadow_catcher): the passes keep it;
        // the colour and coverage are what lies behind, under its shadow where it covers (alpha).
        const float a = std::min(m.alpha, 1.0f);
        const Vec3 kept = kept_light(sp, ray, depth, split, st, ctx) * a + Vec3(1, 1, 1) * (1 - a);
        const FirstHit front = *fh;
        FirstHit beyond;
        Ray on = ray;
        on.behind_catcher = true;
        const Vec3 behind =
            continue_through(hit, sp, on, depth, weight, split, type, st, ctx, &beyond, view_axis, ray_in.o);
        *fh = front;
        const float shadow = 1.0f - (kept.x + kept.y + kept.z) * (1.0f / 3.0f);
        fh->alpha = beyond.alpha + (1 - beyond.alpha) * shadow;
        fh->holdout = beyond.holdout;
        return behind * kept;
    }
    if (m.alpha < 1) {   // partly covered: blend with what lies behind
        if (m.alpha <= 0) {   // a cut-out: the passes and the coverage see what lies behind
            if (fh) fh->hit = false, fh->alpha = 0, fh->mattes.clear();
            return continue_through(hit, sp, ray, depth, weight, split, type, st, ctx, fh, view_axis, ray_in.o);
        }
        // On the camera's path what lies behind is traced with a FirstHit of its
        // own: with Film Transparent its misses are transparent, and its
        // coverage makes this sample's alpha (the passes keep this surface).
        FirstHit beyond;
        const Vec3 behind = continue_through(hit, sp, ray, depth, weight * (1 - m.alpha), split, RayType::Secondary, st, ctx,
                                             fh ? &beyond : nullptr, view_axis, ray_in.o);
        if (fh) {
            if (held) {   // (the passes see what lies behind)
                const RayMattes behind_mattes = beyond.mattes;
                *fh = beyond;
                fh->mattes.clear();
                fh->mattes.add(behind_mattes, 1 - m.alpha);
            } else {
                fh->mattes.clear();
                if (scene_.has_matte_keys()) {
                    fh->mattes.add(scene_.matte_class(size_t(hit.prim)), m.alpha);
                    fh->mattes.add(beyond.mattes, 1 - m.alpha);
                }
            }
            fh->alpha = (held ? 0 : m.alpha) + (1 - m.alpha) * beyond.alpha;
            fh->holdout = (held ? m.alpha : 0) + (1 - m.alpha) * beyond.holdout;
        }
        if (held) return behind * (1 - m.alpha);
        Material opaque = m;
        opaque.alpha = 1;
        const Vec3 front =
            shade_hit(sp, ray, opaque, depth, weight * m.alpha, split, st, ctx, emitter_weight(ray, hit, sp));
        return front * m.alpha + behind * (1 - m.alpha);
    }
    return shade_hit(sp, ray, m, depth, weight, split, st, ctx, emitter_weight(ray, hit, sp));
}

// The world's light on a diffuse point by its normal ns, less what the scene
// blocks of it (world shadows), / pi.
Vec3 Integrator::world_light_at(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split,
                                SampleState& st, TraceContext& ctx) const {
    Vec3 a = scene_.ambient(ns);
    // (unclamped: a shading point's estimate may dip below 0 where a sun is
    // blocked; the pixel's mean is the estimate, clamped once, in pixel())
    if (s_.world_shadows) {
        a = a - world_blocked(sp, ng, ns, depth, split, st, ctx);
        if (!scene_.sun_map().empty()) a = a - scene_.sun_ambient(ns) + sun_seen(sp, ng, ns, depth, split, st, ctx);
    }
    return a;
}

// A shadow catcher's share of its light (Material::shadow_catcher): the light a
// white diffuse surface there gets from the lights, emitters and world with
// shadows, over the light it gets without them (the same light points: st is
// replayed), per channel in [0, 1]; 1 where it gets none. (Each camera sample's
// share, averaged over the pixel's samples; Cycles divides the pixel's sums.
// A sample's estimate with world shadows may dip below 0 where a sun is
// blocked: its share is clamped at 0.)
Vec3 Integrator::kept_light(const SurfacePoint& sp, const Ray& ray, int depth, bool split, SampleState& st,
                            TraceContext& ctx) const {
    const Vec3 wo = -ray.d;
    const bool entering = dot(ray.d, sp.ng) < 0;
    const Vec3 ng = entering ? sp.ng : -sp.ng;
    const Vec3 ns_lit = entering ? sp.ns : -sp.ns;
    const Vec3 ns = dot(ns_lit, wo) <= 0 ? ng : ns_lit;
    Material white;
    white.color = Vec3(1, 1, 1);
    white.kd = 1;
    auto light = [&](SampleState& s) {
        Vec3 l = direct(sp, ng, ns_lit, wo, white, depth, split, s, ctx);
        if (scene_.has_ambient()) l += world_light_at(sp, ng, ns, depth, split, s, ctx);
        return l;
    };
    SampleState replay = st;
    const Vec3 shadowed = light(st);
    struct Unshadowed {   // (set while the light without shadows is taken, whatever happens)
        TraceContext& c;
        explicit Unshadowed(TraceContext& c) : c(c) { c.unshadowed = true; }
        ~Unshadowed() { c.unshadowed = false; }
    };
    Vec3 open;
    {
        const Unshadowed guard(ctx);
        open = light(replay);
    }
    auto share = [](float a, float b) { return b > 0 ? std::min(std::max(a / b, 0.0f), 1.0f) : 1.0f; };
    return Vec3(share(shadowed.x, open.x), share(shadowed.y, open.y), share(shadowed.z, open.z));
}

// Rays pass a surface's uncovered part (alpha < 1) unchanged and unbent.
Vec3 Integrator::continue_through(const Hit& hit, const SurfacePoint& sp, const Ray& ray, int depth, float weight,
                                  bool split, RayType type, SampleState& st, TraceContext& ctx, FirstHit* fh,
                                  const Vec3& view_axis, const Vec3& depth_origin) const {
    if (depth >= s_.max_depth + 16)   // a stack of cut-outs: seen as a miss
        return fh && scene_.world().transparent ? Vec3() : scene_.miss(ray.d);
    const Ray next = past(hit, sp, ray);
    // The passes measure depth from the camera: a moved origin moved it along ray.d.
    FirstHit behind;
    const Vec3 c = trace(next, depth + 1, weight, split, type, st, ctx, fh ? &behind : nullptr, view_axis);
    if (fh) fh->alpha = behind.alpha, fh->holdout = behind.holdout;
    if (fh && behind.hit) {
        *fh = behind;
        fh->depth += dot(next.o - depth_origin, view_axis);
    }
    return c;
}

Vec3 Integrator::shade_hit(const SurfacePoint& sp, const Ray& ray, const Material& m, int depth,
                           float weight, bool split, SampleState& st, TraceContext& ctx, float emission_weight) const {
    const Vec3 d = ray.d, wo = -d;
    const bool entering = dot(d, sp.ng) < 0;
    const Vec3 ng = entering ? sp.ng : -sp.ng;   // both normals face the incoming ray
    Vec3 ns = entering ? sp.ns : -sp.ns;
    // Lamps and emitters light the point by the interpolated normal even where it
    // turns away from the viewer, as Cycles' diffuse does: the geometric normal
    // lit such points where the interpolated one faces away from the light too
    // (a Weighted Normal modifier's rim, lit slivers Cycles leaves black).
    const Vec3 ns_lit = ns;
    if (dot(ns, wo) <= 0) ns = ng;              // interpolated normal facing away: the true one (reflections, ambient)
    // The dielectric layer (Material::dielectric_reflection, layered_diffuse): its Fresnel
    // reflectance at normal incidence, and what it reflects seen from here.
    const float layer = dielectric_share(m), f0d = layer > 0 || m.layered_diffuse ? dielectric_f0(m) : 0.0f;
    const float cos_o = std::min(std::max(dot(wo, ns), 0.0f), 1.0f);
    float layer_seen = layer > 0 && f0d > 0 ? layer * fresnel_dielectric(cos_o, dielectric_eta(f0d)) : 0.0f;
    // What the lights see (direct(), from_emitters()): a layered diffuse gets kd less the layer's
    // albedo seen from wo; where this hit traces no reflection or refraction rays (the last
    // generation, or a path weight under min_weight), the highlights those rays would have seen
    // (emitters, lights with a shape) are sampled as a surface without mirror, glass or
    // reflecting layer has them (they were lost there: a rough Principled floor under an
    // emissive panel rendered black at max_depth 1, a review found).
    const bool layered = m.layered_diffuse && m.kd > 0 && f0d > 0;
    const bool rays = depth < s_.max_depth && weight * (m.mirror + m.transmittance + layer_seen) > s_.min_weight;
    const bool untraced = !rays && (m.mirror > 0 || m.transmittance > 0 || layer > 0);
    std::optional<Material> under;   // (a copy only where one of the two applies)
    if (layered || untraced) {
        under.emplace(m);
        if (layered) under->kd = m.kd * (1 - layer_albedo(m, f0d, cos_o));
        if (untraced) under->mirror = 0, under->transmittance = 0, under->dielectric_reflection = false;
    }
    const Material& lit = under ? *under : m;
    // The GGX rays traced below (the metal's share and the layer's, as one set of rays) and
    // from_emitters' light points share the emitters' highlights (multiple importance sampling),
    // where both reach the same directions: the interpolated normal faces the viewer.
    const bool mis = rays && m.roughness > 0 && !(m.transmittance > 0) && (m.mirror > 0 || layer_seen > 0) &&
                     dot(ns_lit, wo) > 0 &&
                     (!scene_.emitters().empty() || (shaped_lights_ && s_.shadow != ShadowMode::Hard));
    std::optional<GgxView> traced;
    if (mis) {
        Fresnel f;   // (the layer's share without the roulette's boost: what its rays return on average)
        f.tint = m.mirror > 0 ? reflection_tint(m, m.mirror) : Vec3();
        f.mirror = m.mirror, f.f0 = f0d, f.dielectric = layer_seen > 0 ? layer : 0.0f;
        traced = glossy_view(m, f, ns, wo);
    }
    Vec3 color = m.color * (m.emission * emission_weight) +
                 direct(sp, ng, ns_lit, wo, lit, depth, split, st, ctx, traced ? &*traced : nullptr);
    if (m.emission_color.x > 0 || m.emission_color.y > 0 || m.emission_color.z > 0)
        color += m.emission_color * emission_weight;
    if (scene_.has_ambient() && lit.kd > 0) color += m.color * world_light_at(sp, ng, ns, depth, split, st, ctx) * lit.kd;
    if (depth >= s_.max_depth) return color;

    float refl = m.mirror, trans = 0;
    Vec3 tdir;
    if (m.transmittance > 0 && m.roughness > 0 && m.ior != 1.0f) {
        if (weight * m.transmittance > s_.min_weight)
            color += rough_glass(sp, ng, ns, wo, m, entering ? 1.0f : m.ior, entering ? m.ior : 1.0f, depth,
                                 weight * m.transmittance, split, st, ctx) * m.transmittance;
    } else if (m.transmittance > 0) {
        const float n1 = entering ? 1.0f : m.ior, n2 = entering ? m.ior : 1.0f, eta = n1 / n2;
        const float cos_i = std::min(dot(wo, ns), 1.0f);
        const float k = 1.0f - eta * eta * (1.0f - cos_i * cos_i);
        if (k < 0) {
            refl += m.transmittance;   // total internal reflection
        } else {
            const float cos_t = std::sqrt(k);
            tdir = normalize(d * eta + ns * (eta * cos_i - cos_t));
            // The exact unpolarised Fresnel, as Cycles' glass (Schlick's approximation was 20% low
            // at 60 degrees on IOR 1.5). IOR 1 is no interface at all: nothing reflects.
            const float F = n1 == n2 ? 0.0f : fresnel_dielectric(cos_i, n2 / n1);
            refl += m.transmittance * F;
            trans = m.transmittance * (1.0f - F);
        }
    }
    // The reflection rays carry the mirror share (metal, glass's Fresnel) in its tint and the
    // dielectric layer's share (Material::dielectric_reflection) by its own Fresnel: one set of
    // rays for both.
    const float w = weight * (refl + layer_seen);
    // A layer alone reflecting little (under kLayerRoulette, seen from here) traces its rays
    // with probability layer_seen / kLayerRoulette, weighted by the inverse (Russian roulette:
    // unbiased; st.rng, so images stay independent of threads and tiles).
    float boost = 1;
    if (!(refl > 0) && layer_seen > 0 && layer_seen < kLayerRoulette && w > s_.min_weight) {
        const float p = layer_seen / kLayerRoulette;
        if (st.rng.next() >= p) layer_seen = 0;
        else boost = 1 / p;
    }
    if ((refl > 0 || layer_seen > 0) && w > s_.min_weight) {
        const Vec3 tint = refl > 0 ? reflection_tint(m, refl) : Vec3();
        layer_seen *= boost;
        if (m.roughness > 0 && !(m.transmittance > 0)) {
            // A glossy mirror (metal, a Glossy BSDF, a dielectric's layer): the GGX lobe, each
            // share's Fresnel rising from its colour.
            // (where the light points share these rays' highlights, `traced` is this lobe without
            // the roulette's boost: its dielectric scale is linear in the layer's weight)
            GgxView lobe;
            if (traced) {
                lobe = *traced;
                lobe.dielectric_scale *= layer_seen > 0 ? boost : 0.0f;
            } else {
                Fresnel f;
                f.tint = tint, f.mirror = refl, f.f0 = f0d, f.dielectric = layer_seen > 0 ? layer * boost : 0.0f;
                lobe = glossy_view(m, f, ns, wo);
            }
            color += glossy_lobe(sp, ng, d, m.roughness, depth, w, split, false, st, ctx, &lobe, mis);
            if (samples_sun(ggx_alpha(m.roughness))) color += sun_highlight(sp, ng, lobe, depth, split, st, ctx);
        } else {
            Vec3 rdir = d - ns * (2.0f * dot(d, ns));
            if (dot(rdir, ng) <= 0) rdir = d - ng * (2.0f * dot(d, ng));
            const Vec3 reflected = glossy_lobe(sp, ng, normalize(rdir), m.roughness, depth, w, split, false, st, ctx);
            color += reflected * (tint * refl + Vec3(layer_seen, layer_seen, layer_seen));
        }
    }
    if (trans > 0 && weight * trans > s_.min_weight && dot(tdir, ng) < 0) {
        // (IOR 1 bends nothing, however rough the surface: the ray goes straight on)
        const float roughness = m.ior == 1.0f ? 0.0f : m.roughness;
        const Vec3 passed = glossy_lobe(sp, ng, tdir, roughness, depth, weight * trans, split, true, st, ctx) * trans;
        color += passed * refraction_tint(m);
    }
    return color;
}

}  // namespace gw
