// Blender's Brick Texture (procedural.h).
#include <cmath>
#include <cstdint>

#include "procedural.h"

namespace gw {

namespace {

// Cycles' integer noise for a brick's tint, in [0, 1).
float brick_noise(uint32_t n) {
    n = (n + 1013u) & 0x7fffffffu;
    n = (n >> 13) ^ n;
    const uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
    return 0.5f * (float(nn) / 1073741824.0f);
}

// floor() as an int, as Cycles gets it on x86 (a Brick Width or Row Height of 0
// or below, which Blender's sockets accept, divides into values out of int range).
int floor_int(float x) { return x86_int(std::floor(x)); }

}  // namespace

Rgba brick_color(const Texture& t, const Vec3& point) {
    const Vec3 p = point * t.scale;
    float width = t.brick_width, offset = 0.0f;
    const int row = floor_int(p.y / t.row_height);
    if (t.offset_frequency != 0 && t.squash_frequency != 0) {
        // (C's remainder: rows below 0 count as Cycles counts them)
        // (in 64 bits: INT_MIN % -1 would trap)
        width *= (int64_t(row) % t.squash_frequency) != 0 ? 1.0f : t.squash_amount;
        offset = (int64_t(row) % t.offset_frequency) != 0 ? 0.0f : width * t.offset_amount;
    }
    const int brick = floor_int((p.x + offset) / width);
    const float x = (p.x + offset) - width * float(brick), y = p.y - t.row_height * float(row);
    const float tint_raw = brick_noise((uint32_t(row) << 16) + (uint32_t(brick) & 0xFFFFu)) + t.brick_bias;
    const float tint = tint_raw > 0.0f ? (tint_raw < 1.0f ? tint_raw : 1.0f) : 0.0f;
    float edge = std::min(std::min(x, y), std::min(width - x, t.row_height - y));
    float f;
    if (edge >= t.mortar_size) {
        f = 0.0f;
    } else if (t.mortar_smooth == 0.0f) {
        f = 1.0f;
    } else {
        edge = 1.0f - edge / t.mortar_size;
        const float s = edge / t.mortar_smooth, ss = s * s;   // (smoothstep)
        f = s <= 0.0f ? 0.0f : s >= 1.0f ? 1.0f : 3.0f * ss - 2.0f * ss * s;
    }
    Vec3 c(t.color1[0], t.color1[1], t.color1[2]);
    if (f != 1.0f) c = c * (1.0f - tint) + Vec3(t.color2[0], t.color2[1], t.color2[2]) * tint;
    const Vec3 out = c * (1.0f - f) + Vec3(t.mortar[0], t.mortar[1], t.mortar[2]) * f;
    return Rgba{out, f};
}

}  // namespace gw
