// Whitted shading (Blinn-Phong, shadows, mirror reflection, refraction with
// the exact dielectric Fresnel and total internal reflection) plus the distribution-ray
// effects: soft shadows from area lights and glossy reflection.
#pragma once
#include "matte_coverage.h"
#include "accel.h"
#include "microfacet.h"
#include "sampler.h"
#include "settings.h"

namespace gw {

// What one camera sample needs to know to draw its random numbers: its own
// stream, plus the pixel-level layout used by the shuffled area-light grid.
struct SampleState {
    Rng rng;
    uint32_t seed, pixel;
    uint32_t sample;    // index of this pixel sample
    uint32_t samples;   // pixel samples in the pixel
};

// First-hit data for the Depth and Normal passes.
struct FirstHit {
    bool hit = false;
    float depth = kInf;   // distance along the camera's view axis
    Vec3 normal;          // world-space shading normal (outward)
    Vec3 albedo;          // the surface's base colour (the Denoising Albedo pass)
    float alpha = 0;      // coverage: 1 opaque, a partly covered surface's alpha over what lies behind, 0 a miss
    // With matte keys (Scene::has_matte_keys): the matte class of the
    // primitive hit with its share of the ray (its alpha), and those a partly
    // covered surface shows behind it with the rest (matte_coverage.h).
    RayMattes mattes;
    float holdout = 0;    // the share of the ray a holdout surface takes (Material::holdout)
};

class Integrator {
public:
    Integrator(const Accel& accel, const RenderSettings& s);
    // The camera that renders, for textures at Camera and Window coordinates
    // (without one, those read 0); it must outlive the integrator's use.
    void set_camera(const Camera* camera) { camera_ = camera; }
    Vec3 camera_ray(const Ray& ray, const Vec3& view_axis, SampleState& st, TraceContext& ctx, FirstHit* fh) const;

private:
    Vec3 trace(const Ray& ray, int depth, float weight, bool split, RayType type, SampleState& st,
               TraceContext& ctx, FirstHit* fh, const Vec3& view_axis) const;
    // traced: the GGX lobe of the shares whose reflection rays are traced from here, where they
    // share the emitters' and the shaped lamps' highlights with the light points (multiple
    // importance sampling); else null.
    Vec3 direct(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Material& m,
                int depth, bool split, SampleState& st, TraceContext& ctx, const GgxView* traced = nullptr) const;
    // The emissive triangles' light (scene.emitters()), sampled as one area light.
    Vec3 from_emitters(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Material& m,
                       int depth, bool split, SampleState& st, TraceContext& ctx, const GgxView* traced) const;
    // The power heuristic's weight of what an emissive triangle that `ray` meets at sp emits:
    // below 1 for a glossy ray whose lobe shares the emitters with light sampling
    // (Ray::emitter_mis), 1 for every other ray and primitive.
    float emitter_weight(const Ray& ray, const Hit& hit, const SurfacePoint& sp) const;
    // How many rays a glossy lobe traces (glossy_lobe).
    int glossy_rays(bool split) const { return split ? 1 : std::max(1, s_.glossy_samples); }
    // The light of the environment's bright cells (a sun) that reaches a diffuse point, / pi.
    Vec3 sun_seen(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split, SampleState& st,
                  TraceContext& ctx) const;
    // What the scene blocks of the world's light at a diffuse point (world_shadows.h).
    Vec3 world_blocked(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split,
                       SampleState& st, TraceContext& ctx) const;
    // How many points on a light a shading point uses in this shadow mode, and
    // the j-th of them as (u1, u2) in [0, 1)^2 for light li (stratified per pixel in Area mode).
    int light_points(ShadowMode mode, const SampleState& st) const;
    // The mode that places the points of a light with no centre to aim at
    // (emitters, the world): Hard draws one at random, as Random does.
    ShadowMode spread_mode() const { return s_.shadow == ShadowMode::Hard ? ShadowMode::Random : s_.shadow; }
    void light_point(ShadowMode mode, uint32_t li, int j, int count, int depth, bool split, SampleState& st,
                     float& u1, float& u2) const;
    // The rays around the mirror direction (or, `through`, the refracted
    // direction) `dir` that a rough surface scatters into: the exact ray at
    // roughness 0, else a normalised Phong lobe of the roughness; with `ggx`
    // (a reflection), the GGX lobe's rays instead, weighted by its Fresnel and
    // shadowing (dir unused).
    // (mis: the GGX rays share the emitters and the lamps' shapes with their light points,
    // Ray::emitter_mis and lamps_in_lobe.)
    Vec3 glossy_lobe(const SurfacePoint& sp, const Vec3& ng, const Vec3& dir, float roughness, int depth,
                     float weight, bool split, bool through, SampleState& st, TraceContext& ctx,
                     const GgxView* ggx = nullptr, bool mis = false) const;
    // The lamps whose shapes the glossy ray r (leaving sp, ns its lobe's normal) meets unblocked:
    // their radiance, each weighted by the power heuristic against its light points, whose
    // density it takes from light_density; ray_density: the lobe's rays' (n x ggx_pdf).
    Vec3 lamps_in_lobe(const Ray& r, const SurfacePoint& sp, const Vec3& ns, double ray_density, float alpha,
                       SampleState& st, TraceContext& ctx) const;
    // Whether a GGX lobe of this alpha at p and lamp L's light points share its highlight
    // (multiple importance sampling): L has a shape and the lobe is narrower than L seen from p;
    // a wider lobe is L's points' alone. direct() and lamps_in_lobe ask alike.
    bool shares_lamp(const Light& L, const Vec3& p, float alpha) const;
    // Rough glass (roughness > 0, transmittance > 0, IOR not 1): a GGX microfacet dielectric
    // (Walter et al. 2007). Each of the lobe's samples draws a microfacet normal m from those the
    // view sees and traces both the reflection about m, weighing F G2 / G1, and the refraction
    // through m, weighing (1 - F) G2 / G1 (tinted where the glass tints what it lets through),
    // F the exact Fresnel at m; with Material::multiscatter, divided by what one such
    // interface returns of a white world (ggx_glass_albedo). n1, n2: the indices on the view's
    // side and beyond.
    Vec3 rough_glass(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Material& m,
                     float n1, float n2, int depth, float weight, bool split, SampleState& st,
                     TraceContext& ctx) const;
    // The world's light on a diffuse point by its normal, less what the scene blocks (world shadows).
    Vec3 world_light_at(const SurfacePoint& sp, const Vec3& ng, const Vec3& ns, int depth, bool split,
                        SampleState& st, TraceContext& ctx) const;
    // A shadow catcher's share of its light, with shadows over without, per channel (Material::shadow_catcher).
    Vec3 kept_light(const SurfacePoint& sp, const Ray& ray, int depth, bool split, SampleState& st,
                    TraceContext& ctx) const;
    // The light L as a glossy lobe far narrower than it reflects it: its
    // radiance in the mirror direction, if unblocked, times the lobe's albedo.
    Vec3 mirrored_light(const Light& L, const SurfacePoint& sp, const Vec3& ng, const GgxView& lobe, float radius,
                        TraceContext& ctx) const;
    // The lights whose shapes the mirror or refraction ray r (leaving sp) sees before
    // any surface (lights.h, light_shape_hit): their radiance, summed (lights are
    // transparent, as in Cycles: the ray goes on to what lies behind).
    Vec3 lights_seen(const Ray& r, TraceContext& ctx) const;
    // The environment's sun as a GGX lobe wider than it reflects it (sampled; see the .cpp).
    Vec3 sun_highlight(const SurfacePoint& sp, const Vec3& ng, const GgxView& lobe, int depth, bool split,
                       SampleState& st, TraceContext& ctx) const;
    bool samples_sun(float alpha) const { return alpha > sun_radius_; }
    // The sun's light points (light key: lights + key), each weighing response(wi, s): a colour
    // times a scalar s (skipped unless both are positive), times the sun's radiance / pi /
    // density where unblocked. sun_seen and sun_highlight.
    template <class Response>
    Vec3 sun_light(const SurfacePoint& sp, const Vec3& ng, uint32_t key, int depth, bool split, SampleState& st,
                   TraceContext& ctx, Response response) const;
    Vec3 visible(const Vec3& p, const Vec3& p_err, const Vec3& ng, const Vec3& wi, float dist,
                 TraceContext& ctx, bool glass_blocks = false) const;
    Vec3 transmission(Ray r, TraceContext& ctx, bool glass_blocks = false) const;
    // The ray moved on past its hit (a cut-out, a surface hidden from it): see integrator.cpp.
    Ray past(const Hit& hit, const SurfacePoint& sp, const Ray& ray) const;
    Vec3 point_light_seen(const SurfacePoint& sp, const Vec3& wi, float dist, const Vec3& c, const Vec3& c_shared,
                          bool casts_shadows, TraceContext& ctx, bool through_glass = true) const;
    // Whether a surface seen by the ray's kind lies on it (those hidden from it are passed).
    bool blocked(Ray r, TraceContext& ctx) const;
    Vec3 continue_through(const Hit& hit, const SurfacePoint& sp, const Ray& ray, int depth, float weight, bool split,
                          RayType type, SampleState& st, TraceContext& ctx, FirstHit* fh, const Vec3& view_axis,
                          const Vec3& depth_origin) const;
    // (emission_weight: emitter_weight's, on what the surface emits)
    Vec3 shade_hit(const SurfacePoint& sp, const Ray& ray, const Material& m, int depth, float weight, bool split,
                   SampleState& st, TraceContext& ctx, float emission_weight = 1) const;

    const Accel& accel_;
    const Scene& scene_;
    const RenderSettings& s_;
    const Camera* camera_ = nullptr;
    bool shaped_lights_ = false;   // a light has a shape that mirror rays see (lights_seen)
    // Scenes of more than kManyLights lights with distance falloff (a string of lights, a city):
    // direct() evaluates kLightPicks of those per shading point, drawn by power over squared
    // distance, instead of every one (picked_[i]: light i is drawn so; empty: every light is
    // evaluated); light_x_ ... light_reach2_ are the draw's per-light constants, in arrays the
    // draw's loop reads in step.
    static constexpr size_t kManyLights = 64;
    static constexpr int kLightPicks = 8;
    std::vector<char> picked_;
    bool drawn(size_t light) const { return !picked_.empty() && picked_[light]; }
    std::vector<float> light_x_, light_y_, light_z_, light_power_, light_reach_, light_reach2_;
    float sun_radius_ = kInf;      // the environment's sun's angular radius (none: infinite)
};

}  // namespace gw
