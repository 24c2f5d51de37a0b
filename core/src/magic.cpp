// Blender's Magic Texture (procedural.h).
#include <cfloat>
#include <cmath>

#include "procedural.h"

namespace gw {

Rgba magic_color(const Texture& t, const Vec3& point) {
    // (The point modulo 2 pi, so that far points keep their precision, as
    // Cycles takes it; then scaled.)
    constexpr float kTwoPi = 6.2831853071795864f;
    const Vec3 p(std::fmod(point.x, kTwoPi), std::fmod(point.y, kTwoPi), std::fmod(point.z, kTwoPi));
    const float scale = t.scale;
    float x = std::sin((p.x + p.y + p.z) * 5.0f * scale);
    float y = std::cos((-p.x + p.y - p.z) * 5.0f * scale);
    float z = -std::cos((-p.x - p.y + p.z) * 5.0f * scale);
    // (a subnormal distortion counts as 0: dividing by it below would overflow)
    const float d = std::abs(t.distortion) < FLT_MIN ? 0.0f : t.distortion;
    const int depth = t.depth;
    if (depth > 0) {
        x *= d;
        y *= d;
        z *= d;
        y = -std::cos(x - y + z) * d;
        // The further levels, each replacing one coordinate (Cycles' order).
        if (depth > 1) x = std::cos(x - y - z) * d;
        if (depth > 2) z = std::sin(-x - y - z) * d;
        if (depth > 3) x = -std::cos(-x + y - z) * d;
        if (depth > 4) y = -std::sin(-x + y + z) * d;
        if (depth > 5) y = -std::cos(-x + y + z) * d;
        if (depth > 6) x = std::cos(x + y + z) * d;
        if (depth > 7) z = std::sin(x + y - z) * d;
        if (depth > 8) x = -std::cos(-x - y + z) * d;
        if (depth > 9) y = -std::sin(x - y + z) * d;
    }
    if (d != 0.0f) {
        x /= 2.0f * d;
        y /= 2.0f * d;
        z /= 2.0f * d;
    }
    auto finite = [](float v) { return std::isfinite(v) ? v : 0.0f; };
    const Vec3 c(finite(0.5f - x), finite(0.5f - y), finite(0.5f - z));
    return Rgba{c, (c.x + c.y + c.z) * (1.0f / 3.0f)};
}

}  // namespace gw
