// Blender's Wave Texture (procedural.h).
#include <cmath>

#include "noise.h"
#include "procedural.h"

namespace gw {

Rgba wave_color(const Texture& t, const Vec3& point) {
    // (Cycles nudges the point off exact unit coordinates first.)
    const Vec3 p = (point * t.scale + Vec3(0.000001f, 0.000001f, 0.000001f)) * 0.999999f;
    float n;
    if (t.wave_type == WaveType::Bands) {
        n = t.wave_direction == WaveDirection::AxisX   ? p.x * 20.0f
            : t.wave_direction == WaveDirection::AxisY ? p.y * 20.0f
            : t.wave_direction == WaveDirection::AxisZ ? p.z * 20.0f
                                                   : (p.x + p.y + p.z) * 10.0f;
    } else {
        // (rings about an axis leave that axis out; spherical keeps all three)
        const Vec3 r(t.wave_direction == WaveDirection::AxisX ? 0.0f : p.x,
                     t.wave_direction == WaveDirection::AxisY ? 0.0f : p.y,
                     t.wave_direction == WaveDirection::AxisZ ? 0.0f : p.z);
        n = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z) * 20.0f;
    }
    n += t.phase;
    if (t.distortion != 0.0f) {
        const Vec3 q = p * t.detail_scale;
        const float at[3] = {q.x, q.y, q.z};
        // (Cycles 4.0 and later take Detail and Roughness as they come, a negative Detail giving
        // no octave and so NaN; 3.4 clamps them to [0, 15] and [0, 1], which the export does.
        // Past 64 octaves, which only a link or a script can ask for, more are not summed.)
        const float detail = std::min(t.detail, 64.0f);
        n += t.distortion * (fbm_noise(3, at, detail, t.roughness, t.noise_wrap) * 2.0f - 1.0f);
    }
    constexpr float kTwoPi = 6.2831853071795864f;
    float f;
    switch (t.wave_profile) {
    case WaveProfile::Sine: f = 0.5f + 0.5f * std::sin(n - 1.5707963267948966f); break;
    case WaveProfile::Saw: n /= kTwoPi; f = n - std::floor(n); break;
    default: n /= kTwoPi; f = std::abs(n - std::floor(n + 0.5f)) * 2.0f; break;
    }
    if (!std::isfinite(f)) f = 0.0f;
    return Rgba{Vec3(f, f, f), f};
}

}  // namespace gw
