// Deterministic random numbers: every value is a hash of (seed, pixel,
// sample, dimension), so an image does not depend on the thread count or the
// order in which tiles are rendered.
#pragma once
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
inline uint32_t hash4(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    return mix32(a ^ mix32(b ^ mix32(c ^ mix32(d + 0x9e3779b9U))));
}
inline float to_unit(uint32_t x) { return float(x >> 8) * (1.0f / 16777216.0f); }   // [0, 1)

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

}  // namespace gw
