// Every source of sample positions in one place: hashing, the named random
// streams, stratification, permutations, low-discrepancy sequences (Sobol
// with Owen scrambling, radical inverse), disk mapping and filter sampling.
//
// Every value is a hash of (seed, pixel, sample, dimension), so an image does
// not depend on the thread count or the order in which tiles are rendered.
#pragma once
#include <algorithm>
#include <cstdint>

#include "math.h"

namespace gw {

// 32-bit integer mixer (the "lowbias32" finaliser by Chris Wellons).
inline uint32_t mix32(uint32_t x) {
    x ^= x >> 16; x *= 0x7feb352dU;
    x ^= x >> 15; x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}
constexpr uint32_t kGoldenRatio32 = 0x9e3779b9U;   // 2^32 / phi: spreads small keys before mixing
inline uint32_t hash4(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    return mix32(a ^ mix32(b ^ mix32(c ^ mix32(d + kGoldenRatio32))));
}
inline float to_unit(uint32_t x) { return float(x >> 8) * (1.0f / 16777216.0f); }   // [0, 1)

// The independent random streams of a render. Each use of randomness mixes
// its own constant into the seed (or into its hash key), so that no two uses
// draw correlated numbers for the same pixel and sample.
enum class Stream : uint32_t {
    Path = 0,                     // shading: light samples, glossy directions (seed as is)
    Lens = 0x1e35a7bdU,           // depth of field: lens positions
    PixelSamples = 0x68e31da4U,   // anti-aliasing: sample positions in the pixel, Sobol scrambles
    LatticeJitter = 0x2545f491U,  // adaptive AA: jitter of a lattice point
    LatticePoint = 0xADU,         // adaptive AA: hash key of a lattice point
    AreaLightGrid = 0xA11U,       // the seed's area light: shuffle of the n x n light grid
    GlossyLobe = 0x61055U,        // first glossy bounce: shuffle of the pixel's lobe strata
    RoughRefraction = 0x7e4a5U,   // first rough refraction: the same, for the refracted lobe
};
inline uint32_t stream_seed(uint32_t seed, Stream s) { return seed ^ uint32_t(s); }
// The sample index under which values shared by all of a pixel's samples are
// drawn (a shuffle, a rotation); no pixel has this many samples.
constexpr uint32_t kWholePixel = 0xFFFFFFFFU;

inline uint32_t reverse_bits(uint32_t x) {
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffU) << 8) | ((x & 0xff00ff00U) >> 8);
    x = ((x & 0x0f0f0f0fU) << 4) | ((x & 0xf0f0f0f0U) >> 4);
    x = ((x & 0x33333333U) << 2) | ((x & 0xccccccccU) >> 2);
    x = ((x & 0x55555555U) << 1) | ((x & 0xaaaaaaaaU) >> 1);
    return x;
}

// A stream of uniform numbers for one (pixel, sample) pair.
class Rng {
public:
    Rng(uint32_t seed, uint32_t pixel, uint32_t sample) : a_(seed), b_(pixel), c_(sample) {}
    float next() { return to_unit(hash4(a_, b_, c_, dim_++)); }
    uint32_t next_u32() { return hash4(a_, b_, c_, dim_++); }
private:
    uint32_t a_, b_, c_, dim_ = 0;
};

// A bijection of [0, n) chosen by seed (cycle-walking an invertible mixer on
// the next power of two, then a rotation by a second hash of the seed):
// shuffles the area-light grid and the shared strata per pixel. The rotation
// makes where each i lands uniform over seeds for every n; cycle-walking
// alone favours some values when n is not a power of two, which would tie a
// pixel sample's position to its light or lens stratum (a bias).
inline uint32_t permute(uint32_t i, uint32_t n, uint32_t seed) {
    const uint32_t rotation = n > 1 ? mix32(seed ^ 0x5bd1e995U) % n : 0;
    uint32_t mask = n - 1;
    mask |= mask >> 1; mask |= mask >> 2; mask |= mask >> 4; mask |= mask >> 8; mask |= mask >> 16;
    do {
        i ^= seed & mask;
        i = (i * 0x2c1b3c6dU + (seed >> 7)) & mask;
        i ^= (i >> 3) & mask;
        i = (i * 0x297a2d39U) & mask;
        i ^= i >> 5;
        i &= mask;
    } while (i >= n);
    i += rotation;
    return i >= n ? i - n : i;
}

// Slot j of pixel sample `sample` in one stratified set of samples x n points
// shared by all of a pixel's samples (lens points, glossy lobe directions): the
// samples are shuffled by `key` and each takes every samples-th slot, so its
// own n points spread over the whole set as well.
inline uint32_t shared_slot(uint32_t sample, uint32_t samples, uint32_t key, uint32_t j) {
    return permute(sample, samples, key) + j * samples;
}

// Whether a shared set of samples x n strata is small enough for strat2 (its
// strata must stay apart in float); larger sets fall back to each sample's own.
inline bool shared_set_fits(uint32_t samples, uint32_t n) { return uint64_t(samples) * n <= (1u << 24); }

// Burley (2020) hash-based Owen scrambling, applied in reversed bit order.
inline uint32_t lk_permutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cU;
    x ^= x * 0xb82f1e52U;
    x ^= x * 0xc7afe638U;
    x ^= x * 0x8d22f6e6U;
    return x;
}
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) { return reverse_bits(lk_permutation(reverse_bits(x), seed)); }

// Second Sobol dimension (generator matrix of the polynomial x + 1); the
// first is reverse_bits.
inline uint32_t sobol_dim1(uint32_t i) {
    uint32_t r = 0;
    for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
        if (i & 1) r ^= v;
    return r;
}

// Radical inverse in base 2, as a float in [0, 1).
inline float radical_inverse(uint32_t i) { return float(reverse_bits(i) >> 8) * (1.0f / 16777216.0f); }

// Stratified 2D point j of a set of n (jittered on the first axis, Hammersley
// on the second, rotated by the set's own offset).
inline void strat2(uint32_t j, uint32_t n, float xi1, float rot, float& u1, float& u2) {
    u1 = (float(j) + xi1) / float(n);
    u2 = radical_inverse(j) + rot;
    if (u2 >= 1.0f) u2 -= 1.0f;
    u1 = std::min(u1, 0.99999994f);
}

// Shirley-Chiu concentric map of [0,1)^2 onto the unit disk (keeps strata compact).
inline void concentric_disk(float u1, float u2, float& x, float& y) {
    const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0 && b == 0) { x = y = 0; return; }
    float r, phi;
    if (std::abs(a) > std::abs(b)) { r = a; phi = float(kPi / 4) * (b / a); }
    else { r = b; phi = float(kPi / 2) - float(kPi / 4) * (a / b); }
    x = r * std::cos(phi);
    y = r * std::sin(phi);
}

// Filter importance sampling of a Gaussian of standard deviation `sigma`
// (clipped at 2 sigma): Box-Muller turns the (stratified) uniform pair into
// a pixel offset, so every sample has weight 1.
inline void gaussian_offset(float u, float v, float sigma, float& ox, float& oy) {
    const float r = sigma * std::sqrt(-2.0f * std::log(std::max(1.0f - u, 1e-7f)));
    const float phi = float(2 * kPi) * v;
    ox = std::min(std::max(r * std::cos(phi), -2 * sigma), 2 * sigma);
    oy = std::min(std::max(r * std::sin(phi), -2 * sigma), 2 * sigma);
}

}  // namespace gw
