// Blender's Noise Texture, as Cycles evaluates it: Perlin noise in 1 to 4
// dimensions whose lattice gradients come from Bob Jenkins' lookup3 hash of
// the cell's integer corner, scaled per dimension into about [-1, 1], summed
// over octaves by one of Blender's five fractal types, with its Distortion
// and its Color output (the noise at two further places, offset by hashed
// amounts). The constants are Cycles' own, so that the patterns line up with
// a Cycles render of the same node (tests/blender/test_b39).
#pragma once
#include "texture.h"

namespace gw {

// The Noise texture t at the (mapped) point p: rgb the Color output, a the
// Fac output (the colour's red). (The green and blue are computed only
// where t takes the Color output, not use_alpha.)
Rgba noise_color(const Texture& t, const Vec3& p);

// Cycles' signed Perlin noise in n dimensions (1-4) at x[0 .. n): its
// lattice noise scaled into about [-1, 1], 0 where it is not finite. With
// `wrap` (Blender 4.0 and later) the coordinates are wrapped every 100000 as
// Cycles wraps them, and moved by 1/2 from a million on; Blender 3.4 takes
// them as they are. (Also for the tests.)
float signed_noise(int n, const float* x, bool wrap);

// Cycles' fBM of n-dimensional noise at x[0 .. n), normalized into about
// [0, 1]: 1 + detail octaves (as given: none below 0, and NaN), each twice as
// fine and `roughness` times as strong (the Wave Texture's distortion).
float fbm_noise(int n, const float* x, float detail, float roughness, bool wrap);

}  // namespace gw
