// Blender's White Noise Texture (procedural.h).
#include <cmath>

#include "lookup3.h"
#include "procedural.h"

namespace gw {

Rgba white_noise_color(const Texture& t, const Vec3& p) {
    // The coordinates (unscaled: the node has no Scale) and, for the green
    // and blue, the same with one more coordinate (1 and 2) or, in 4D, the
    // coordinates reordered, as Cycles' hash_float*_to_float3 forms them.
    const int n = t.dimensions;
    float k[4] = {p.x, p.y, p.z, t.w};
    if (n == 1) k[0] = t.w;
    const float value = hash_floats(n, k);
    if (t.use_alpha) return Rgba{Vec3(value, value, value), value};
    float g, b;
    if (n < 4) {
        float more[4] = {k[0], k[1], k[2], 0.0f};
        more[n] = 1.0f;
        g = hash_floats(n + 1, more);
        more[n] = 2.0f;
        b = hash_floats(n + 1, more);
    } else {
        const float zxwy[4] = {k[2], k[0], k[3], k[1]}, wzyx[4] = {k[3], k[2], k[1], k[0]};
        g = hash_floats(4, zxwy);
        b = hash_floats(4, wzyx);
    }
    return Rgba{Vec3(value, g, b), value};
}

}  // namespace gw
