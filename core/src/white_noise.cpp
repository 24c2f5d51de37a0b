// Blender's White Noise Texture (procedural.h).
#include <cmath>

#include "lookup3.h"
#include "procedural.h"

namespace gw {

Rgba white_noise_color(const Texture& t, const Vec3& p) {
    // The coordinates (unscaled: the node has no Scale): x, y, z and w in 4D, the
    // first n of them in 2D and 3D, w alone in 1D.
    const int n = t.dimensions;
    const float k[4] = {n == 1 ? t.w : p.x, p.y, p.z, t.w};
    float c[3];
    if (t.use_alpha) {
        c[0] = c[1] = c[2] = hash_floats(n, k);
    } else {
        hash_floats_to_color(n, k, c);
    }
    return Rgba{Vec3(c[0], c[1], c[2]), c[0]};
}

}  // namespace gw
