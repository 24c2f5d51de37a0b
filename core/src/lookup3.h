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

// The hash of n floats with one more word appended (n = 1-3).
inline float hash_floats_with(int n, const float* x, float extra) {
    float k[4];
    for (int i = 0; i < n; ++i) k[i] = x[i];
    k[n] = extra;
    return hash_floats(n + 1, k);
}

// Three hashes of n floats (n = 1-4) as a colour, as Cycles' hash_float*_to_float3
// forms them: the hash of the floats, then with 1 and 2 appended or, for four,
// of the floats reordered (z, x, w, y) and (w, z, y, x). (The Voronoi Texture's
// cell colours before Blender 5.0; the White Noise Texture's colour.)
inline void hash_floats_to_color(int n, const float* x, float* out) {
    out[0] = hash_floats(n, x);
    if (n < 4) {
        out[1] = hash_floats_with(n, x, 1.0f);
        out[2] = hash_floats_with(n, x, 2.0f);
    } else {
        const float a[4] = {x[2], x[0], x[3], x[1]}, b[4] = {x[3], x[2], x[1], x[0]};
        out[1] = hash_floats(4, a);
        out[2] = hash_floats(4, b);
    }
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
