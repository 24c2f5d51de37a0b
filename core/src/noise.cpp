// Blender's Noise Texture. See noise.h.
#include "noise.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "lookup3.h"

namespace gw {
namespace {

constexpr int kMaxDims = 4;

// The offset, each component in [100, 200], that Cycles adds to an n-dimensional
// point to read the noise somewhere else for seed 0 .. n + 1 (its
// random_float*_offset: n seeds for the distortion, two for the colour).
// Constants, hashed once.
const float* random_offset(int n, int seed) {
    struct Table {
        float at[kMaxDims + 1][kMaxDims + 2][kMaxDims];
        Table() {
            for (int dims = 1; dims <= kMaxDims; ++dims)
                for (int k = 0; k < dims + 2; ++k) {
                    const float s = float(k);
                    for (int i = 0; i < dims; ++i) {
                        const float key[2] = {s, float(i)};
                        at[dims][k][i] = 100.0f + (dims == 1 ? hash_floats(1, &s) : hash_floats(2, key)) * 100.0f;
                    }
                }
        }
    };
    static const Table table;
    return table.at[n][seed];
}

inline float flip(float x, uint32_t bit) { return bit ? -x : x; }

// The lattice gradient picked by hash h, dotted with the offset f from its corner.
float gradient_dot(int n, uint32_t h, const float* f) {
    switch (n) {
    case 1: {
        const uint32_t g = h & 15;
        return flip(float(1 + (g & 7)), g & 8) * f[0];
    }
    case 2: {
        const uint32_t g = h & 7;
        const float u = g < 4 ? f[0] : f[1], v = 2.0f * (g < 4 ? f[1] : f[0]);
        return flip(u, g & 1) + flip(v, g & 2);
    }
    case 3: {
        const uint32_t g = h & 15;
        const float u = g < 8 ? f[0] : f[1];
        const float v = g < 4 ? f[1] : (g == 12 || g == 14) ? f[0] : f[2];
        return flip(u, g & 1) + flip(v, g & 2);
    }
    default: {
        const uint32_t g = h & 31;
        const float u = g < 24 ? f[0] : f[1], v = g < 16 ? f[1] : f[2], s = g < 8 ? f[2] : f[3];
        return flip(u, g & 1) + flip(v, g & 2) + flip(s, g & 4);
    }
    }
}

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

// Perlin's lattice noise at x (n dimensions, |x| < 100000): the corners'
// gradients blended with faded weights, x first (corner bit 0), then y, z, w.
float perlin(int n, const float* x) {
    int32_t cell[kMaxDims];
    float frac[kMaxDims], weight[kMaxDims];
    for (int i = 0; i < n; ++i) {
        const float fl = std::floor(x[i]);
        // (beyond int range, as x86's conversion gives it: Blender 3.4 does not wrap)
        cell[i] = x86_int(fl);
        frac[i] = x[i] - fl;
        weight[i] = fade(frac[i]);
    }
    float corner[1 << kMaxDims];
    const int corners = 1 << n;
    for (int c = 0; c < corners; ++c) {
        uint32_t key[kMaxDims];
        float f[kMaxDims];
        for (int i = 0; i < n; ++i) {
            const int bit = (c >> i) & 1;
            key[i] = uint32_t(cell[i]) + uint32_t(bit);
            f[i] = bit ? frac[i] - 1.0f : frac[i];
        }
        corner[c] = gradient_dot(n, hash_words(n, key), f);
    }
    for (int i = 0, m = corners; i < n; ++i, m /= 2)
        for (int c = 0; c < m / 2; ++c)
            corner[c] = corner[2 * c] + weight[i] * (corner[2 * c + 1] - corner[2 * c]);
    return corner[0];
}

// Cycles' per-dimension factors that bring each noise into about [-1, 1].
constexpr float kNoiseScale[kMaxDims + 1] = {0, 0.2500f, 0.6616f, 0.9820f, 0.8344f};

// The octaves' sum for the texture's fractal type at p (n dimensions).
float fractal(const Texture& t, int n, const float* p0, float detail, float roughness) {
    float p[kMaxDims];
    for (int i = 0; i < n; ++i) p[i] = p0[i];
    auto scaled = [&](float s) {
        float q[kMaxDims];
        for (int i = 0; i < n; ++i) q[i] = s * p[i];
        return signed_noise(n, q, t.noise_wrap);
    };
    auto finer = [&] {
        for (int i = 0; i < n; ++i) p[i] *= t.lacunarity;
    };
    const int octaves = int(detail);
    const float rest = detail - std::floor(detail);
    const float offset = t.noise_offset, gain = t.noise_gain;
    switch (t.noise_type) {
    case NoiseType::Fbm: {
        float scale = 1.0f, amp = 1.0f, max_amp = 0.0f, sum = 0.0f;
        for (int i = 0; i <= octaves; ++i) {
            sum += scaled(scale) * amp;
            max_amp += amp;
            amp *= roughness;
            scale *= t.lacunarity;
        }
        const float whole = t.normalize ? 0.5f * sum / max_amp + 0.5f : sum;
        if (rest == 0.0f) return whole;
        const float more = sum + scaled(scale) * amp;
        const float blended = t.normalize ? 0.5f * more / (max_amp + amp) + 0.5f : more;
        return whole + rest * (blended - whole);
    }
    case NoiseType::Multifractal: {
        float value = 1.0f, power = 1.0f;
        for (int i = 0; i <= octaves; ++i) {
            value *= power * scaled(1.0f) + 1.0f;
            power *= roughness;
            finer();
        }
        if (rest != 0.0f) value *= rest * power * scaled(1.0f) + 1.0f;
        return value;
    }
    case NoiseType::HeteroTerrain: {
        float power = roughness;
        float value = offset + scaled(1.0f);
        finer();
        for (int i = 1; i <= octaves; ++i) {
            value += (scaled(1.0f) + offset) * power * value;
            power *= roughness;
            finer();
        }
        if (rest != 0.0f) value += rest * ((scaled(1.0f) + offset) * power * value);
        return value;
    }
    case NoiseType::HybridMultifractal: {
        float power = 1.0f, value = 0.0f, weight = 1.0f;
        for (int i = 0; weight > 0.001f && i <= octaves; ++i) {
            weight = std::min(weight, 1.0f);
            const float signal = (scaled(1.0f) + offset) * power;
            power *= roughness;
            value += weight * signal;
            weight *= gain * signal;
            finer();
        }
        if (rest != 0.0f && weight > 0.001f) value += rest * std::min(weight, 1.0f) * ((scaled(1.0f) + offset) * power);
        return value;
    }
    case NoiseType::RidgedMultifractal: {
        float power = roughness;
        float signal = offset - std::abs(scaled(1.0f));
        signal *= signal;
        float value = signal;
        for (int i = 1; i <= octaves; ++i) {
            finer();
            const float weight = std::min(std::max(signal * gain, 0.0f), 1.0f);
            signal = offset - std::abs(scaled(1.0f));
            signal *= signal;
            signal *= weight;
            value += signal * power;
            power *= roughness;
        }
        return value;
    }
    }
    return 0.0f;
}

}  // namespace

float signed_noise(int n, const float* x, bool wrap) {
    float p[kMaxDims];
    for (int i = 0; i < n; ++i) {
        // (a coordinate of a million or more moves by half a cell after the wrap, which
        // would otherwise leave it on a lattice point, where the noise is 0)
        const float wrapped = wrap ? std::fmod(x[i], 100000.0f) + (std::abs(x[i]) >= 1000000.0f ? 0.5f : 0.0f) : x[i];
        p[i] = std::isfinite(wrapped) ? wrapped : 0.0f;
    }
    const float r = perlin(n, p);
    return std::isfinite(r) ? kNoiseScale[n] * r : 0.0f;
}

float fbm_noise(int n, const float* x, float detail, float roughness, bool wrap) {
    Texture fbm;
    fbm.noise_type = NoiseType::Fbm;
    fbm.lacunarity = 2.0f;
    fbm.normalize = true;
    fbm.noise_wrap = wrap;
    return fractal(fbm, n, x, detail, roughness);
}

Rgba noise_color(const Texture& t, const Vec3& point) {
    const int n = t.dimensions;
    float p[kMaxDims];
    pattern_coords(t, point, p);
    const float detail = std::min(std::max(t.detail, 0.0f), 15.0f);
    const float roughness = std::max(t.roughness, 0.0f);
    if (t.distortion != 0.0f) {
        float moved[kMaxDims];
        for (int k = 0; k < n; ++k) {
            const float* off = random_offset(n, k);
            float at[kMaxDims];
            for (int i = 0; i < n; ++i) at[i] = p[i] + off[i];
            moved[k] = signed_noise(n, at, t.noise_wrap) * t.distortion;
        }
        for (int i = 0; i < n; ++i) p[i] += moved[i];
    }
    // (Settings Blender accepts, such as Roughness 1000 over 15 octaves, overflow:
    // Cycles shows such a value as 0.)
    auto finite = [](float x) { return std::isfinite(x) ? x : 0.0f; };
    const float value = finite(fractal(t, n, p, detail, roughness));
    if (t.use_alpha) return Rgba{Vec3(value, value, value), value};
    float channel[2];
    for (int k = 0; k < 2; ++k) {
        const float* off = random_offset(n, n + k);
        float at[kMaxDims];
        for (int i = 0; i < n; ++i) at[i] = p[i] + off[i];
        channel[k] = finite(fractal(t, n, at, detail, roughness));
    }
    return Rgba{Vec3(value, channel[0], channel[1]), value};
}

}  // namespace gw
