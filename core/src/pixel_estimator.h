// Pixel estimation: where the camera samples of one pixel go (centre,
// jittered, random, Owen-scrambled Sobol, or Whitted's adaptive
// subdivision), the lens samples for depth of field, and the pixel filter.
#pragma once
#include <vector>

#include "camera.h"
#include "integrator.h"
#include "matte_coverage.h"

namespace gw {

// What a camera sample (or lattice point) gives: r, g, b, coverage (alpha),
// and the share of it a holdout took (FirstHit::holdout).
constexpr int kPointValues = 5;

struct PixelValue {
    Vec3 rgb;
    float alpha = 0;   // fraction of camera samples that hit geometry
    float holdout = 0;   // fraction of camera samples that met a holdout (Material::holdout)
    FirstHit first;
    MatteCoverage matte;   // with RenderSettings.matte_ranks > 0: the keys the samples met
};

// Per-thread scratch for adaptive sampling: one pixel's lattice, and the
// pixel corners of the current tile (traced once, shared by the tile's pixels).
struct PixelScratch {
    std::vector<float> lattice;       // kPointValues per lattice point of the current pixel
    std::vector<SampleMattes> lattice_mattes;   // with mattes: each lattice point's matte classes
    std::vector<uint32_t> stamp;      // == generation: the point is computed for this pixel
    uint32_t generation = 0;
    std::vector<float> corners;       // kPointValues per corner, (w + 1) x (h + 1)
    std::vector<FirstHit> corner_hits;
    std::vector<SampleMattes> corner_mattes;   // with mattes
    int x0 = 0, y0 = 0, w = 0;
};

class PixelEstimator {
public:
    PixelEstimator(const Accel& accel, const RenderSettings& s, const CameraDesc& camera);
    // (not copied or moved: the integrator keeps a pointer to camera_)
    PixelEstimator(const PixelEstimator&) = delete;
    PixelEstimator& operator=(const PixelEstimator&) = delete;
    // Call before the pixels of a tile (traces the shared corners in adaptive mode).
    void begin_tile(int x0, int y0, int w, int h, TraceContext& ctx, PixelScratch& sc) const;
    PixelValue pixel(int x, int y, TraceContext& ctx, PixelScratch& sc) const;

private:
    // One lattice point / camera position: dof_samples lens rays averaged into out (kPointValues).
    // sm: with mattes, the matte classes each lens ray sees, weighted 1 / dof_samples.
    void sample_point(float px, float py, uint32_t pixel_key, uint32_t sample, uint32_t samples,
                      TraceContext& ctx, float out[kPointValues], FirstHit* fh, SampleMattes* sm = nullptr) const;
    // The sample's matte classes into the pixel's keys, each layer's, with `weight`.
    void add_mattes(MatteCoverage& mc, const SampleMattes& sm, float weight) const;
    PixelValue adaptive(int x, int y, TraceContext& ctx, PixelScratch& sc) const;
    void lattice_point(uint32_t gx, uint32_t gy, int D, TraceContext& ctx, float out[kPointValues], FirstHit* fh,
                       SampleMattes* sm) const;

    const RenderSettings& s_;
    const Scene& scene_;
    Integrator integrator_;
    Camera camera_;
    bool lens_;
};

}  // namespace gw
