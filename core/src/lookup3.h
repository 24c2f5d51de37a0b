// The hashes Cycles' procedural textures use (its util/hash.h): Bob Jenkins'
// lookup3 of up to four 32-bit words, seeded for each count (the Noise
// Texture's lattice gradients; the Voronoi Texture's points and colours before
// Blender 5.0), and the PCG hashes of 2 to 4 integers in Cycles' signed form
// (Jarzynski & Olano 2020; the Voronoi Texture's from Blender 5.0).
#pragma once
#include <cstdint>
#include <cstring>

namespace gw {

inline uint32_t rotl(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

// lookup3's hash of n words (n = 1-4), seeded as Cycles seeds it for n:
// its last mixing step, after the full one for a fourth word.
inline uint32_t hash_words(int n, const uint32_t* k) {
    uint32_t a = 0xdeadbeefu + (uint32_t(n) << 2) + 13u, b = a, c = a;
    a += k[0];
    if (n > 1) b += k[1];
    if (n > 2) c += k[2];
    if (n == 4) {
        a -= c; a ^= rotl(c, 4);  c += b;
        b -= a; b ^= rotl(a, 6);  a += c;
        c -= b; c ^= rotl(b, 8);  b += a;
        a -= c; a ^= rotl(c, 16); c += b;
        b -= a; b ^= rotl(a, 19); a += c;
        c -= b; c ^= rotl(b, 4);  b += a;
        a += k[3];
    }
    c ^= b; c -= rotl(b, 14);
    a ^= c; a -= rotl(c, 11);
    b ^= a; b -= rotl(a, 25);
    c ^= b; c -= rotl(b, 16);
    a ^= c; a -= rotl(c, 4);
    b ^= a; b -= rotl(a, 14);
    c ^= b; c -= rotl(b, 24);
    return c;
}

inline uint32_t bits_of(float x) {
    uint32_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
}

// The hash of n floats' bits as a float in [0, 1] (Cycles' hash_float*_to_float).
inline float hash_floats(int n, const float* x) {
    uint32_t k[4];
    for (int i = 0; i < n; ++i) k[i] = bits_of(x[i]);
    return float(hash_words(n, k)) * (1.0f / 4294967296.0f);
}

// Cycles' signed PCG hash of n (2-4) integers, each result in [0, 2^31), as a
// float in [0, 1] (its hash_int*_to_float*). (Unsigned arithmetic for the
// wrap-around; the shift is arithmetic, as on Cycles' signed integers.)
inline void hash_pcg(int n, const int32_t* key, float* out) {
    uint32_t v[4] = {0, 0, 0, 0};
    for (int i = 0; i < n; ++i) v[i] = uint32_t(key[i]) * 1664525u + 1013904223u;
    auto mix = [&] {
        if (n == 2) {
            v[0] += v[1] * 1664525u;
            v[1] += v[0] * 1664525u;
        } else if (n == 3) {
            v[0] += v[1] * v[2];
            v[1] += v[2] * v[0];
            v[2] += v[0] * v[1];
        } else {
            v[0] += v[1] * v[3];
            v[1] += v[2] * v[0];
            v[2] += v[0] * v[1];
            v[3] += v[1] * v[2];
        }
    };
    mix();
    for (int i = 0; i < n; ++i) v[i] ^= uint32_t(int32_t(v[i]) >> 16);
    mix();
    for (int i = 0; i < n; ++i) out[i] = float(v[i] & 0x7FFFFFFFu) * (1.0f / 2147483648.0f);
}

}  // namespace gw
