// Pixel estimation. See pixel_estimator.h.
#include "pixel_estimator.h"

namespace gw {
namespace {

// A pixel's light, never below 0: world shadows' samples may be (their mean is not).
Vec3 non_negative(const Vec3& c) { return Vec3(std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f)); }

}  // namespace

PixelEstimator::PixelEstimator(const Accel& accel, const RenderSettings& s, const CameraDesc& camera)
    : s_(s), scene_(accel.scene()), integrator_(accel, s), camera_(camera), lens_(camera.aperture > 0) {
    integrator_.set_camera(&camera_);
}

void PixelEstimator::add_mattes(MatteCoverage& mc, const SampleMattes& sm, float weight) const {
    const int layers = scene_.matte_layers();
    for (int i = 0; i < sm.n; ++i)
        for (int l = 0; l < layers; ++l)
            mc.layer[l].add(scene_.class_key(sm.id[i], l), sm.weight[i] * weight);
}

void PixelEstimator::sample_point(float px, float py, uint32_t pixel_key, uint32_t sample, uint32_t samples,
                                  TraceContext& ctx, float out[kPointValues], FirstHit* fh, SampleMattes* sm) const {
    const uint32_t nd = uint32_t(std::max(1, s_.dof_samples));
    Rng lens_rng(stream_seed(s_.seed, Stream::Lens), pixel_key, sample);
    // The lens points of all the pixel's samples (samples x nd) form one
    // stratified set (sampler.h, shared_slot), rotated and shuffled per pixel.
    float rot = 0;
    uint32_t key = 0;
    const bool shared = lens_ && samples > 1 && shared_set_fits(samples, nd);
    const uint32_t sample_in_set = shared ? sample : 0, set_samples = shared ? samples : 1;
    if (shared) {
        Rng pixel_rng(stream_seed(s_.seed, Stream::Lens), pixel_key, kWholePixel);
        rot = pixel_rng.next();
        key = pixel_rng.next_u32();
    } else if (lens_) {
        rot = lens_rng.next();
    }
    Vec3 sum;
    float hits = 0, held = 0;
    for (uint32_t j = 0; j < nd && !ctx.cancelled(); ++j) {   // (a cancelled pixel is not kept)
        float lu = 0.5f, lv = 0.5f;
        if (lens_)
            strat2(shared_slot(sample_in_set, set_samples, key, j), nd * set_samples, lens_rng.next(), rot, lu, lv);
        const Ray ray = camera_.generate(px, py, lu, lv);
        FirstHit local;
        if (Camera::none(ray)) {   // no ray (a fisheye's corner): black and opaque, as Cycles' film has it
            hits += 1;
        } else {
            SampleState st{Rng(stream_seed(s_.seed, Stream::Path), pixel_key, sample * nd + j), s_.seed, pixel_key, sample * nd + j, samples * nd};
            sum += integrator_.camera_ray(ray, camera_.depth_axis(ray), st, ctx, &local);
            hits += local.alpha;
            held += local.holdout;
        }
        if (fh && j == 0) *fh = local;
        if (sm) sm->add(local.mattes, 1.0f / float(nd));
    }
    const float inv = 1.0f / float(nd);
    out[0] = sum.x * inv; out[1] = sum.y * inv; out[2] = sum.z * inv; out[3] = hits * inv; out[4] = held * inv;
}

PixelValue PixelEstimator::pixel(int x, int y, TraceContext& ctx, PixelScratch& sc) const {
    if (s_.aa == AAMode::Adaptive) return adaptive(x, y, ctx, sc);
    const uint32_t key = uint32_t(y) * uint32_t(camera_.width()) + uint32_t(x);
    const uint32_t n = uint32_t(std::max(1, s_.aa_samples));
    const uint32_t count = s_.aa == AAMode::Center ? 1 : n * n;
    Rng prng(stream_seed(s_.seed, Stream::PixelSamples), key, 0);
    const uint32_t shuffle = prng.next_u32(), sx = prng.next_u32(), sy = prng.next_u32();
    PixelValue pv;
    float acc[kPointValues] = {0, 0, 0, 0, 0}, wsum = 0;
    const bool mattes = s_.matte_ranks > 0 && scene_.has_matte_keys();
    SampleMattes sm;
    for (uint32_t s = 0; s < count; ++s) {
        float u = 0.5f, v = 0.5f;
        switch (s_.aa) {
        case AAMode::Jittered: u = (float(s % n) + prng.next()) / float(n); v = (float(s / n) + prng.next()) / float(n); break;
        case AAMode::Random: u = prng.next(); v = prng.next(); break;
        case AAMode::Sobol: {
            const uint32_t i = owen_scramble(s, shuffle);
            u = to_unit(owen_scramble(reverse_bits(i), sx));
            v = to_unit(owen_scramble(sobol_dim1(i), sy));
            break;
        }
        default: break;
        }
        float ox = u - 0.5f, oy = v - 0.5f;
        if (s_.filter == PixelFilter::Gaussian && count > 1) gaussian_offset(u, v, s_.filter_width, ox, oy);
        float out[kPointValues];
        sm.clear();
        sample_point(float(x) + 0.5f + ox, float(y) + 0.5f + oy, key, s, count, ctx, out, s == 0 ? &pv.first : nullptr,
                     mattes ? &sm : nullptr);
        if (mattes) add_mattes(pv.matte, sm, 1.0f / float(count));
        for (int c = 0; c < kPointValues; ++c) acc[c] += out[c];
        wsum += 1;
    }
    pv.rgb = non_negative(Vec3(acc[0], acc[1], acc[2]) * (1.0f / wsum));
    pv.alpha = acc[3] / wsum;
    pv.holdout = acc[4] / wsum;
    return pv;
}

// Whitted's adaptive supersampling on a lattice of 2^D x 2^D squares per
// pixel. Lattice points are addressed globally and seeded by their global
// address, so a point shared by two pixels (or two tiles) gets the same
// jittered position and value wherever it is computed. Pixel corners are
// traced once per tile; inner points once per pixel.
void PixelEstimator::lattice_point(uint32_t gx, uint32_t gy, int D, TraceContext& ctx, float out[kPointValues],
                                   FirstHit* fh, SampleMattes* sm) const {
    // Every point is jittered within the finest cell around it. (Jittering a
    // pixel corner by up to half a pixel lets all four corners fall on the same
    // side of an edge that crosses the pixel, which then never subdivides.)
    const float spacing = 1.0f / float(1 << D);
    const uint32_t key = hash4(gx, gy, uint32_t(D), uint32_t(Stream::LatticePoint));
    Rng jr(stream_seed(s_.seed, Stream::LatticeJitter), key, 0);
    const float px = float(gx) / float(1 << D) + (jr.next() - 0.5f) * spacing;
    const float py = float(gy) / float(1 << D) + (jr.next() - 0.5f) * spacing;
    if (sm) sm->clear();
    sample_point(px, py, key, 0, 1, ctx, out, fh, sm);
}

void PixelEstimator::begin_tile(int x0, int y0, int w, int h, TraceContext& ctx, PixelScratch& sc) const {
    if (s_.aa != AAMode::Adaptive) return;
    const int D = s_.adaptive_depth;
    sc.x0 = x0; sc.y0 = y0; sc.w = w;
    sc.corners.assign(size_t(w + 1) * (h + 1) * kPointValues, 0.0f);
    sc.corner_hits.assign(size_t(w + 1) * (h + 1), FirstHit());
    const bool mattes = s_.matte_ranks > 0 && scene_.has_matte_keys();
    sc.corner_mattes.assign(mattes ? size_t(w + 1) * (h + 1) : 0, SampleMattes());
    for (int j = 0; j <= h && !ctx.cancelled(); ++j)
        for (int i = 0; i <= w; ++i) {
            const size_t k = size_t(j) * (w + 1) + i;
            lattice_point(uint32_t(x0 + i) << D, uint32_t(y0 + j) << D, D, ctx, &sc.corners[kPointValues * k], &sc.corner_hits[k],
                          mattes ? &sc.corner_mattes[k] : nullptr);
        }
}

PixelValue PixelEstimator::adaptive(int x, int y, TraceContext& ctx, PixelScratch& sc) const {
    const int D = s_.adaptive_depth;
    const int side = (1 << D) + 1;
    // Entries are reused across pixels; a stamp per entry marks the ones this
    // pixel computed, so a pixel that never subdivides costs O(1), not O(4^D).
    if (sc.stamp.size() != size_t(side) * side) {
        sc.lattice.assign(size_t(side) * side * kPointValues, 0.0f);
        sc.stamp.assign(size_t(side) * side, 0);
        sc.generation = 0;
    }
    if (++sc.generation == 0) {
        std::fill(sc.stamp.begin(), sc.stamp.end(), 0u);
        sc.generation = 1;
    }
    PixelValue pv;
    const int ci = x - sc.x0, cj = y - sc.y0;
    pv.first = sc.corner_hits[size_t(cj) * (sc.w + 1) + ci];
    const bool mattes = s_.matte_ranks > 0 && scene_.has_matte_keys();
    if (mattes && sc.lattice_mattes.size() != size_t(side) * side) sc.lattice_mattes.assign(size_t(side) * side, SampleMattes());
    // A lattice point's rgba, and (with mattes) the primitives its lens rays see.
    auto point = [&](int i, int j, const SampleMattes** seen = nullptr) -> const float* {
        if ((i == 0 || i == side - 1) && (j == 0 || j == side - 1)) {
            const size_t k = size_t(cj + (j ? 1 : 0)) * (sc.w + 1) + ci + (i ? 1 : 0);
            if (seen) *seen = &sc.corner_mattes[k];
            return &sc.corners[kPointValues * k];
        }
        const size_t k = size_t(j) * side + i;
        float* e = &sc.lattice[kPointValues * k];
        if (sc.stamp[k] != sc.generation) {
            lattice_point((uint32_t(x) << D) + uint32_t(i), (uint32_t(y) << D) + uint32_t(j), D, ctx, e, nullptr,
                          mattes ? &sc.lattice_mattes[k] : nullptr);
            sc.stamp[k] = sc.generation;
        }
        if (seen) *seen = &sc.lattice_mattes[k];
        return e;
    };
    const float thr = s_.adaptive_threshold;
    // Subdivision with an explicit stack of squares (i, j, size, weight).
    struct Sq { int i, j, size; float w; };
    Sq stack[64];
    int top = 0;
    stack[top++] = {0, 0, 1 << D, 1.0f};
    float acc[kPointValues] = {0, 0, 0, 0, 0};
    while (top > 0) {
        const Sq q = stack[--top];
        const float* c[4] = {point(q.i, q.j), point(q.i + q.size, q.j), point(q.i, q.j + q.size),
                             point(q.i + q.size, q.j + q.size)};
        float diff = 0;
        // (the colour, and the held-out share: a black holdout against a dark surface differs there only)
        for (int ch : {0, 1, 2, 4}) {
            const float lo = std::min(std::min(c[0][ch], c[1][ch]), std::min(c[2][ch], c[3][ch]));
            const float hi = std::max(std::max(c[0][ch], c[1][ch]), std::max(c[2][ch], c[3][ch]));
            diff = std::max(diff, hi - lo);
        }
        if (q.size > 1 && diff > thr) {
            const int h = q.size / 2;
            stack[top++] = {q.i, q.j, h, q.w * 0.25f};
            stack[top++] = {q.i + h, q.j, h, q.w * 0.25f};
            stack[top++] = {q.i, q.j + h, h, q.w * 0.25f};
            stack[top++] = {q.i + h, q.j + h, h, q.w * 0.25f};
        } else {
            for (int ch = 0; ch < kPointValues; ++ch) acc[ch] += q.w * 0.25f * (c[0][ch] + c[1][ch] + c[2][ch] + c[3][ch]);
            if (mattes) {   // each corner's primitives, with the corner's weight
                const int ij[4][2] = {{q.i, q.j}, {q.i + q.size, q.j}, {q.i, q.j + q.size}, {q.i + q.size, q.j + q.size}};
                for (const auto& p : ij) {
                    const SampleMattes* seen = nullptr;
                    point(p[0], p[1], &seen);
                    add_mattes(pv.matte, *seen, q.w * 0.25f);
                }
            }
        }
    }
    pv.rgb = non_negative(Vec3(acc[0], acc[1], acc[2]));
    pv.alpha = acc[3];
    pv.holdout = acc[4];
    return pv;
}

}  // namespace gw
