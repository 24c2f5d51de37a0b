// Image storage and texture lookups. See texture.h.
#include "texture.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace gw {
namespace {

float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

const std::array<float, 256>& srgb_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.0f);
        return t;
    }();
    return table;
}

// Texel index along one axis for extension modes that wrap or clamp; -1 = outside (Clip).
int wrap(int i, int n, Extension e) {
    switch (e) {
    case Extension::Repeat: {
        const int m = i % n;
        return m < 0 ? m + n : m;
    }
    case Extension::Extend: return std::min(std::max(i, 0), n - 1);
    case Extension::Mirror: {
        // ... 1 0 | 0 1 ... n-1 | n-1 n-2 ...: texel -1 - k mirrors texel k (k >= 0)
        const int k = i < 0 ? -1 - i : i, m = k % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
    }
    default: return i >= 0 && i < n ? i : -1;
    }
}

// floor() as an int, saturated: texture coordinates can be huge or NaN.
int ifloor(float x) {
    if (!(x > -1e9f)) return -1000000000;
    if (!(x < 1e9f)) return 1000000000;
    return int(std::floor(x));
}

}  // namespace

Image::Image(int width, int height, int channels, bool srgb, std::vector<uint8_t> bytes, std::vector<float> floats,
             const std::string& where)
    : w_(width), h_(height), c_(channels), srgb_(srgb), bytes_(std::move(bytes)), floats_(std::move(floats)) {
    if (w_ < 1 || h_ < 1)
        throw std::invalid_argument(where + " is " + std::to_string(w_) + " x " + std::to_string(h_) +
                                    " pixels: an image needs at least one pixel");
    if (c_ < 1 || c_ > 4) throw std::invalid_argument(where + " must have 1 to 4 channels, got " + std::to_string(c_));
    const size_t n = size_t(w_) * size_t(h_) * size_t(c_);
    if (bytes_.empty() == floats_.empty() || (bytes_.empty() ? floats_.size() : bytes_.size()) != n)
        throw std::invalid_argument(where + ": the pixel array must hold width x height x channels = " +
                                    std::to_string(n) + " values");
    for (size_t i = 0; i < floats_.size(); ++i)
        if (!std::isfinite(floats_[i]))
            throw std::invalid_argument(where + " has a non-finite pixel value at index " + std::to_string(i / size_t(c_)));
}

Rgba Image::texel(int x, int y, bool decode, bool premultiply) const {
    const size_t k = (size_t(h_ - 1 - y) * size_t(w_) + size_t(x)) * size_t(c_);
    const bool has_alpha = c_ == 2 || c_ == 4;
    float v[4];
    if (floats_.empty()) {
        const auto& lut = srgb_table();
        const unsigned alpha = premultiply && has_alpha ? bytes_[k + size_t(c_ - 1)] : 255u;
        for (int i = 0; i < c_; ++i) {
            const bool colour = c_ >= 3 ? i < 3 : i == 0;
            // (premultiplied in bytes, truncating, as Cycles associates 8-bit images)
            const uint8_t b = colour ? uint8_t(unsigned(bytes_[k + size_t(i)]) * alpha / 255u) : bytes_[k + size_t(i)];
            v[i] = decode && srgb_ && colour ? lut[b] : float(b) * (1.0f / 255.0f);
        }
    } else {
        for (int i = 0; i < c_; ++i) {
            const float f = floats_[k + size_t(i)];
            const bool colour = c_ >= 3 ? i < 3 : i == 0;
            v[i] = srgb_ && colour ? srgb_to_linear(f) : f;
        }
        if (premultiply && has_alpha)
            for (int i = 0; i < c_ - 1; ++i) v[i] *= v[c_ - 1];
    }
    Rgba out;
    if (c_ >= 3) {
        out.rgb = Vec3(v[0], v[1], v[2]);
        if (c_ == 4) out.a = v[3];
    } else {
        out.rgb = Vec3(v[0], v[0], v[0]);
        if (c_ == 2) out.a = v[1];
    }
    return out;
}

namespace {
// A channel, gain and bias (Texture::channel; prefix "ramp_": those after the ramp) in range.
void check_adjustment(const std::string& where, const std::string& prefix, int32_t channel,
                      const std::array<float, 3>& gain, const std::array<float, 3>& bias) {
    if (channel < -1 || channel > 4)
        throw std::invalid_argument(where + "." + prefix + "channel = " + std::to_string(channel) +
                                    " is not -1 (the colour), 0-2 (red, green, blue), 3 (the luminance) or 4 (the average)");
    for (float x : gain)
        if (!std::isfinite(x)) throw std::invalid_argument(where + "." + prefix + "gain has a non-finite value");
    for (float x : bias)
        if (!std::isfinite(x)) throw std::invalid_argument(where + "." + prefix + "bias has a non-finite value");
}
}  // namespace

void validate_texture(const Texture& t, const std::string& where) {
    if (!enum_valid(t.interpolation)) throw std::invalid_argument(where + ".interpolation is not an interpolation");
    if (!enum_valid(t.extension)) throw std::invalid_argument(where + ".extension is not an extension");
    for (float x : t.uv_transform)
        if (!std::isfinite(x)) throw std::invalid_argument(where + ".uv_transform has a non-finite value");
    check_adjustment(where, "", t.channel, t.gain, t.bias);
    check_adjustment(where, "ramp_", t.ramp_channel, t.ramp_gain, t.ramp_bias);
    if (t.ramp.empty() && adjusts_after_ramp(t))
        throw std::invalid_argument(where + " adjusts the value after a ramp (ramp_channel, ramp_gain, ramp_bias, "
                                    "ramp_clamp) but has no ramp");
    if (!enum_valid(t.kind)) throw std::invalid_argument(where + ".kind is not a texture kind");
    if (!enum_valid(t.coordinates)) throw std::invalid_argument(where + ".coordinates is not a texture coordinate");
    if (!enum_valid(t.projection)) throw std::invalid_argument(where + ".projection is not an image projection");
    if (!std::isfinite(t.projection_blend)) throw std::invalid_argument(where + ".projection_blend is not finite");
    for (float x : t.vector_transform)
        if (!std::isfinite(x)) throw std::invalid_argument(where + ".vector_transform has a non-finite value");
    for (float x : t.color1)
        if (!std::isfinite(x)) throw std::invalid_argument(where + ".color1 has a non-finite value");
    for (float x : t.color2)
        if (!std::isfinite(x)) throw std::invalid_argument(where + ".color2 has a non-finite value");
    if (!std::isfinite(t.scale)) throw std::invalid_argument(where + ".scale is not finite");
    if (!enum_valid(t.gradient)) throw std::invalid_argument(where + ".gradient is not a gradient type");
    if (!enum_valid(t.ramp_interpolation))
        throw std::invalid_argument(where + ".ramp_interpolation is not a ramp interpolation");
    if (t.ramp.size() % 5 || t.ramp.size() > 5 * kMaxRampStops)
        throw std::invalid_argument(where + ".ramp has " + std::to_string(t.ramp.size()) +
                                    " values: 5 per stop (position, R, G, B, A), at most " +
                                    std::to_string(kMaxRampStops) + " stops");
    for (size_t i = 0; i < t.ramp.size(); ++i)
        if (!std::isfinite(t.ramp[i]))
            throw std::invalid_argument(where + ".ramp stop " + std::to_string(i / 5) + " has a non-finite value");
    for (size_t i = 5; i < t.ramp.size(); i += 5)
        if (!(t.ramp[i] >= t.ramp[i - 5]))
            throw std::invalid_argument(where + ".ramp stop " + std::to_string(i / 5) +
                                        " lies before the one before it: give the stops in increasing position");
    if (!enum_valid(t.noise_type)) throw std::invalid_argument(where + ".noise_type is not a noise type");
    if (!enum_valid(t.voronoi_feature)) throw std::invalid_argument(where + ".voronoi_feature is not a Voronoi feature");
    if (!enum_valid(t.voronoi_metric)) throw std::invalid_argument(where + ".voronoi_metric is not a distance metric");
    if (!enum_valid(t.voronoi_output)) throw std::invalid_argument(where + ".voronoi_output is not a Voronoi output");
    if (!enum_valid(t.wave_type)) throw std::invalid_argument(where + ".wave_type is not a wave type");
    if (!enum_valid(t.wave_direction)) throw std::invalid_argument(where + ".wave_direction is not a wave direction");
    if (!enum_valid(t.wave_profile)) throw std::invalid_argument(where + ".wave_profile is not a wave profile");
    if ((t.wave_type == WaveType::Bands && t.wave_direction == WaveDirection::Spherical) ||
        (t.wave_type == WaveType::Rings && t.wave_direction == WaveDirection::Diagonal))
        throw std::invalid_argument(where + ".wave_direction = " + enum_id(t.wave_direction) + " does not go with " +
                                    enum_id(t.wave_type) + ": bands go along x, y, z or diagonal, rings about x, "
                                    "y, z or spherical");
    if (t.depth < 0 || t.depth > 10)
        throw std::invalid_argument(where + ".depth = " + std::to_string(t.depth) + " is not in [0, 10]");
    if (!std::isfinite(t.brick_width) || !std::isfinite(t.row_height))
        throw std::invalid_argument(where + ": brick_width and row_height must be finite");
    for (float c : {t.mortar[0], t.mortar[1], t.mortar[2]})
        if (!std::isfinite(c)) throw std::invalid_argument(where + ".mortar is not finite");
    if (t.dimensions < 1 || t.dimensions > 4)
        throw std::invalid_argument(where + ".dimensions = " + std::to_string(t.dimensions) +
                                    " is not 1, 2, 3 or 4");
    const std::pair<const char*, float> noise_values[] = {{"w", t.w}, {"detail", t.detail},
        {"roughness", t.roughness}, {"lacunarity", t.lacunarity}, {"distortion", t.distortion},
        {"noise_offset", t.noise_offset}, {"noise_gain", t.noise_gain}, {"exponent", t.exponent},
        {"randomness", t.randomness}, {"smoothness", t.smoothness}, {"detail_scale", t.detail_scale},
        {"phase", t.phase}, {"mortar_size", t.mortar_size}, {"mortar_smooth", t.mortar_smooth}, {"brick_bias", t.brick_bias},
        {"offset_amount", t.offset_amount}, {"squash_amount", t.squash_amount}};
    for (const auto& [name, x] : noise_values)
        if (!std::isfinite(x)) throw std::invalid_argument(where + "." + name + " is not finite");
    if (t.kind != TextureKind::Image && t.image != -1)
        throw std::invalid_argument(where + ".image = " + std::to_string(t.image) + ": a " + enum_id(t.kind) +
                                    " texture has no image (-1)");
    if (t.tiles.size() % 2)
        throw std::invalid_argument(where + ".tiles must be (tile number, image) pairs, got " +
                                    std::to_string(t.tiles.size()) + " numbers");
    if (!t.tiles.empty() && t.kind != TextureKind::Image)
        throw std::invalid_argument(where + ".tiles: a " + enum_id(t.kind) + " texture has no image tiles");
    for (size_t i = 0; i < t.tiles.size(); i += 2)
        if (t.tiles[i] < 1001 || t.tiles[i] > 2000)
            throw std::invalid_argument(where + ".tiles: tile number " + std::to_string(t.tiles[i]) +
                                        " is not a UDIM tile (1001 to 2000)");
}

int32_t texture_image(const Texture& t, float& u, float& v) {
    if (t.tiles.empty()) return t.image;
    // (the comparisons also turn NaN away, before any conversion to int)
    if (!(u > -1.0f && u < 10.0f && v > -1.0f && v < 100.0f)) return -1;
    const int tx = int(u), ty = int(v);   // (truncated toward zero, as Cycles does)
    const int32_t number = 1001 + 10 * ty + tx;
    for (size_t i = 0; i < t.tiles.size(); i += 2)
        if (t.tiles[i] == number) {
            u -= float(tx);
            v -= float(ty);
            return t.tiles[i + 1];
        }
    return -1;
}

namespace {

// Blender's Color Ramp at f: the stops' colours, before the first and after
// the last stop their colours, between two stops as t.ramp_interpolation says
// (Constant: the lower stop's).
Vec3 ramp_at(const Texture& t, float f) {
    const float* r = t.ramp.data();
    const size_t n = t.ramp.size() / 5;
    auto color = [&](size_t k) { return Vec3(r[5 * k + 1], r[5 * k + 2], r[5 * k + 3]); };
    if (!(f > r[0])) return color(0);
    if (f >= r[5 * (n - 1)]) return color(n - 1);
    size_t lo = 0, hi = n - 1;                             // r[5 lo] <= f < r[5 hi]
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        (r[5 * mid] <= f ? lo : hi) = mid;
    }
    const size_t k = hi;                                   // stops k - 1 and k enclose f
    if (t.ramp_interpolation == RampInterpolation::Constant) return color(k - 1);
    const float a = r[5 * (k - 1)], b = r[5 * k];
    float s = (f - a) / (b - a);                           // (b > a: a <= f < b)
    if (t.ramp_interpolation == RampInterpolation::Ease) s = s * s * (3.0f - 2.0f * s);
    return color(k - 1) * (1.0f - s) + color(k) * s;
}

}  // namespace

// As Cycles evaluates a Color Ramp: from a table of the ramp at 256 evenly
// spaced values of [0, 1], f clamped to [0, 1], read between its entries
// (the entry below f where the ramp is Constant). The two entries around f
// are computed here instead of stored.
Vec3 ramp_color(const Texture& t, float f) {
    constexpr int kTable = 256;
    const float x = (f > 0 ? (f < 1 ? f : 1) : 0) * float(kTable - 1);   // (NaN -> 0)
    const int i = int(x);
    const float s = x - float(i);
    const Vec3 below = ramp_at(t, float(i) / float(kTable - 1));
    if (t.ramp_interpolation == RampInterpolation::Constant || !(s > 0)) return below;
    return below * (1.0f - s) + ramp_at(t, float(i + 1) / float(kTable - 1)) * s;
}

Rgba gradient_color(const Texture& t, const Vec3& p) {
    float f = 0;
    switch (t.gradient) {
    case Gradient::Linear: f = p.x; break;
    case Gradient::Quadratic: { const float r = std::max(p.x, 0.0f); f = r * r; break; }
    case Gradient::Easing: {
        const float r = std::min(std::max(p.x, 0.0f), 1.0f), s = r * r;
        f = 3.0f * s - 2.0f * s * r;
        break;
    }
    case Gradient::Diagonal: f = (p.x + p.y) * 0.5f; break;
    case Gradient::Radial: f = std::atan2(p.y, p.x) / (2.0f * float(M_PI)) + 0.5f; break;
    case Gradient::Spherical:
    case Gradient::QuadraticSphere: {
        const float r = std::max(0.999999f - std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 0.0f);
        f = t.gradient == Gradient::Spherical ? r : r * r;
        break;
    }
    }
    f = f > 0 ? (f < 1 ? f : 1) : 0;   // (NaN -> 0)
    return Rgba{Vec3(f, f, f), 1};
}

Rgba checker_color(const Texture& t, const Vec3& p) {
    // The cube index along an axis, as Cycles computes it; an index beyond
    // int range (a point 2^31 cubes out, or NaN) counts as 0.
    auto parity = [&](float x) {
        const float f = std::floor((x * t.scale + 0.000001f) * 0.999999f);
        if (!(std::abs(f) < 2147483648.0f)) return 0;
        return int(std::abs(int64_t(f)) & 1);
    };
    const int xi = parity(p.x), yi = parity(p.y), zi = parity(p.z);
    const bool first = (xi == yi) == (zi != 0);
    const auto& c = first ? t.color1 : t.color2;
    return Rgba{Vec3(c[0], c[1], c[2]), 1};
}

Rgba sample_image(const Image& img, const Texture& t, float u, float v) {
    const int w = img.width(), h = img.height();
    if (t.extension == Extension::Clip && !(u >= 0 && u <= 1 && v >= 0 && v <= 1)) return Rgba{Vec3(), 0};
    // As Cycles: an 8-bit sRGB image is premultiplied, filtered and
    // unassociated as stored (encoded), and decoded last; a float image is
    // linear texel by texel. (Decoding first made a small linear-filtered
    // checker 12% brighter and a premultiplied transparent PNG 14%.) Closest
    // texels that are not divided again take the decoding table.
    const bool late =
        !img.is_float() && img.srgb() && (t.unassociate || t.interpolation != Interpolation::Closest);
    auto fetch = [&](int x, int y) {
        const int xi = wrap(x, w, t.extension), yi = wrap(y, h, t.extension);
        return xi < 0 || yi < 0 ? Rgba{Vec3(), 0} : img.texel(xi, yi, !late, t.premultiply);
    };
    const float x = u * float(w), y = v * float(h);
    Rgba out;
    if (t.interpolation == Interpolation::Closest) {
        out = fetch(ifloor(x), ifloor(y));
    } else {
        const float xs = x - 0.5f, ys = y - 0.5f;
        const int x0 = ifloor(xs), y0 = ifloor(ys);
        const float fx = std::isfinite(xs) ? xs - std::floor(xs) : 0, fy = std::isfinite(ys) ? ys - std::floor(ys) : 0;
        const Rgba a = fetch(x0, y0), b = fetch(x0 + 1, y0), c = fetch(x0, y0 + 1), d = fetch(x0 + 1, y0 + 1);
        const float wa = (1 - fx) * (1 - fy), wb = fx * (1 - fy), wc = (1 - fx) * fy, wd = fx * fy;
        out = Rgba{a.rgb * wa + b.rgb * wb + c.rgb * wc + d.rgb * wd, a.a * wa + b.a * wb + c.a * wc + d.a * wd};
    }
    if (t.unassociate && out.a != 0 && out.a != 1) out.rgb = out.rgb / out.a;
    if (late) out.rgb = Vec3(srgb_to_linear(out.rgb.x), srgb_to_linear(out.rgb.y), srgb_to_linear(out.rgb.z));
    return out;
}

void equirect_uv(const Vec3& d, float& u, float& v) {
    u = 0.5f - std::atan2(d.y, d.x) * float(0.5 / kPi);
    v = 0.5f + std::atan2(d.z, std::hypot(d.x, d.y)) * float(1 / kPi);
}

}  // namespace gw
