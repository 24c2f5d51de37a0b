// Ear clipping of one polygon in the plane (gridwalk.io.triangulate's
// concave polygons from NFF and PLY files).
//
// The polygon's n corners wind counter-clockwise. An ear is a convex corner
// whose triangle with its two neighbours holds no other reflex corner
// (corners at the same point as one of the three excepted). Clipping an ear
// changes only its two neighbours, which are asked again. Ears wait in a
// queue, in rounds: a corner whose neighbour was clipped in this round waits
// for the next, so that a convex run loses every other corner per round
// instead of becoming a fan around one corner. When the queue runs dry every
// corner is asked again (a corner becomes an ear, too, when a reflex corner in
// its triangle turns convex); where no ear is left (a self-intersecting or
// degenerate outline) the most convex corner, the first of equal ones, is
// clipped anyway, so the result always has n - 2 triangles.
//
// Which reflex corners lie in a triangle is asked of a uniform grid of them
// over the polygon's box (about one cell per reflex corner; clipped corners
// and corners turned convex leave their cell when a question meets them), so
// a clip costs about as much as the reflex corners near its triangle. Asking
// every reflex corner, as the numpy version this replaced did, made a concave
// polygon of n corners cost n^2: 11 s for a gear of 16,000 corners, minutes
// for 100,000; with the grid but ears taken last in, first out, a gear of
// 1,000,000 corners took 209 s (fans of long triangles, each meeting most of
// the grid).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gw {

// xy: n points (x, y interleaved). Returns 3 (n - 2) corner indices (none for
// n < 3), each triangle (previous corner, the ear, next corner).
std::vector<int64_t> ear_clip(const double* xy, size_t n);

}  // namespace gw
