// Bob Jenkins' lookup3 hash of up to four 32-bit words, seeded as Cycles
// seeds it for each count (its util/hash.h): what picks the Noise Texture's
// lattice gradients and the Voronoi Texture's points and colours.
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

}  // namespace gw
