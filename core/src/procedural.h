// Blender's smaller procedural textures, as Cycles evaluates them, each at
// the (mapped) point p, in its own file: the Wave (wave.cpp), Magic
// (magic.cpp), White Noise (white_noise.cpp) and Brick (brick.cpp) Textures.
// Their constants are Cycles' own, so that the patterns line up with a Cycles
// render of the same node (tests/blender/test_b41). The Noise and Voronoi
// Textures have their own headers (noise.h, voronoi.h).
#pragma once
#include "texture.h"

namespace gw {

// The Wave texture: its value as grey, alpha the same (Blender's Fac).
Rgba wave_color(const Texture& t, const Vec3& p);

// The Magic texture: its colour, alpha the colour's average (Blender's Fac).
Rgba magic_color(const Texture& t, const Vec3& p);

// The White Noise texture: hashes of the bits of the point's coordinates in
// t.dimensions (1: w; 2: x, y; 3: the point; 4: the point and w; unscaled),
// its colour three of them and alpha the first (Blender's Value).
Rgba white_noise_color(const Texture& t, const Vec3& p);

// The Brick texture: its colour, alpha the mortar's share (Blender's Fac).
Rgba brick_color(const Texture& t, const Vec3& p);

}  // namespace gw
