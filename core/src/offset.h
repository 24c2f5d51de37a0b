// Spawning secondary rays without self-intersection. The hit point carries a
// conservative per-axis error bound p_err (pbrt-v3 3.9.5); the new origin is
// moved along the geometric normal by the bound projected on the normal, then
// rounded one ulp further away. The offset scales with the hit point's own
// rounding error, so there is no epsilon tied to the scene's scale.
#pragma once
#include "math.h"

namespace gw {

// n: unit geometric normal; w: direction of the new ray.
inline Vec3 offset_origin(const Vec3& p, const Vec3& p_err, const Vec3& n, const Vec3& w) {
    const float d = dot(vabs(n), p_err);
    Vec3 off = n * d;
    if (dot(w, n) < 0) off = -off;
    Vec3 po = p + off;
    for (int a = 0; a < 3; ++a) {
        if (off[a] > 0) po[a] = next_up(po[a]);
        else if (off[a] < 0) po[a] = next_down(po[a]);
    }
    return po;
}

}  // namespace gw
