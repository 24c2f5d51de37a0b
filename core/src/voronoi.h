// Blender's Voronoi Texture, as Cycles evaluates it: one point in each unit
// cell of the point x scale, placed by Bob Jenkins' lookup3 hash of the
// cell (moved off the cell's corner by `randomness`); the nearest point (F1),
// the second nearest (F2) or a smooth blend of all (Smooth F1), by one of four
// distance metrics; or the distance to the nearest cell border (Distance to
// Edge) or half the nearest point's distance to its own nearest (N-Sphere
// Radius), in 1 to 4 dimensions, summed over octaves as Blender 4.0
// and later sum them; its Distance, Color (a hashed colour per cell), Position
// and W outputs. The constants are Cycles' own, so that the cells line up
// with a Cycles render of the same node (tests/blender/test_b40).
#pragma once
#include "texture.h"

namespace gw {

// The Voronoi texture t at the (mapped) point p: the output t.voronoi_output
// names (Distance and W as grey; alpha 1).
Rgba voronoi_color(const Texture& t, const Vec3& p);

}  // namespace gw
