// Images and the textures that sample them. An Image is a pixel array stored
// once however many textures use it: 8-bit images stay 8-bit (decoded from
// sRGB at lookup, after filtering), float images stay float. A Texture is the
// record a material (or the world) points at: which image, how to filter it,
// what lies outside it, and whether it gives the colour or the alpha channel
// (Blender's Image Texture node: Color and Alpha outputs). Row 0 of the pixel
// array is the TOP of the image; v = 0 is its bottom edge (UV convention).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "enums.h"
#include "math.h"

namespace gw {

struct Rgba {
    Vec3 rgb;
    float a = 1;
};

class Image {
public:
    // Exactly one of bytes / floats holds width * height * channels values
    // (channels 1: grey, 2: grey + alpha, 3: RGB, 4: RGBA). srgb: the colour
    // channels are sRGB-encoded (decoded to linear at lookup); alpha never is.
    // Throws std::invalid_argument naming `where`.
    Image(int width, int height, int channels, bool srgb, std::vector<uint8_t> bytes, std::vector<float> floats,
          const std::string& where);

    int width() const { return w_; }
    int height() const { return h_; }
    int channels() const { return c_; }
    bool is_float() const { return !floats_.empty(); }
    bool srgb() const { return srgb_; }
    size_t memory_bytes() const { return bytes_.size() + floats_.size() * sizeof(float); }
    const std::vector<uint8_t>& bytes() const { return bytes_; }
    const std::vector<float>& floats() const { return floats_; }
    // The texel in column x, row y counted from the BOTTOM (in range), linear;
    // with decode false an 8-bit sRGB texel's colour stays encoded (byte / 255);
    // premultiply: the colour times alpha (in bytes for an 8-bit image).
    Rgba texel(int x, int y, bool decode = true, bool premultiply = false) const;

private:
    int w_, h_, c_;
    bool srgb_;
    std::vector<uint8_t> bytes_;
    std::vector<float> floats_;
};

// Blender's Color Ramp holds at most 32 stops; the exporter may give Cycles'
// table of 256 entries instead (blender_addon/export/color_ramp.py).
constexpr size_t kMaxRampStops = 256;

// The texture record, bound to Python field by field as gridwalk._core.Texture.
struct Texture {
    // What gives the value: an image (`image`), or a pattern computed at the
    // hit (Blender's procedural textures; `image` is then -1).
    TextureKind kind = TextureKind::Image;
    int32_t image = -1;                                  // index into the scene's images
    // Where the lookup happens: the hit's (u, v, 0) from the UV map, or its
    // Generated or Object coordinates (Scene::hit_point); then mapped by
    // vector_transform (a 3 x 4 row-major affine map: Blender's Mapping node
    // on that vector). An image takes the result's (x, y) as its (u, v),
    // mapped on by uv_transform. The identity changes nothing, to the bit.
    TextureCoords coordinates = TextureCoords::UV;
    std::array<float, 12> vector_transform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    // An image's projection of that point (Blender's Image Texture node's
    // Projection, as Cycles projects): Flat takes its (x, y); Sphere and Tube
    // the point's angles about the centre of the unit box (map_to_sphere /
    // map_to_tube of 2 (p - 0.5)); Box three flat lookups along the object's
    // axes, blended by the object-space normal (Scene(object_normals=...)),
    // projection_blend wide (0: the dominant axis alone).
    ImageProjection projection = ImageProjection::Flat;
    float projection_blend = 0;
    // Checker: color1 where the cubes of side 1 / scale have an even parity
    // as Cycles counts it (checker_color), color2 elsewhere; scale as Blender's Scale.
    std::array<float, 3> color1 = {0.8f, 0.8f, 0.8f}, color2 = {0.2f, 0.2f, 0.2f};
    float scale = 5.0f;
    // Gradient: the shape of the ramp (Blender's Gradient Texture's type); its
    // value, clamped to [0, 1], is the grey colour.
    Gradient gradient = Gradient::Linear;
    // Noise (noise.h): Perlin noise of the point times scale, in
    // dimensions (1: w; 2: x, y; 3: the point; 4: the point and w, w
    // times scale too), moved by `distortion` times noise first, summed over
    // 1 + detail octaves (a fraction blends the last in), each `lacunarity`
    // times finer and `roughness` times as strong, as noise_type says
    // (noise_offset and noise_gain: the multifractals' Offset and Gain); fBM with
    // `normalize` maps the sum into [0, 1]. The value is the alpha (Blender's
    // Fac output: use_alpha) and the colour's red; green and blue are the
    // noise at two other places (its Color output). Blender's defaults.
    // noise_wrap: the coordinates wrap every 100000 (Blender 4.0 and later; 3.4
    // takes them as they are: noise.h's signed_noise).
    NoiseType noise_type = NoiseType::Fbm;
    int32_t dimensions = 3;
    float w = 0, detail = 2, roughness = 0.5f, lacunarity = 2, distortion = 0, noise_offset = 0, noise_gain = 1;
    bool normalize = true, noise_wrap = true;
    // Voronoi (voronoi.h): one point per unit cell of the point x scale (in
    // `dimensions`, w as for noise), moved within its cell by `randomness`;
    // voronoi_feature picks the nearest (F1), the second nearest (F2) or a
    // blend of all by `smoothness` (Smooth F1), by voronoi_metric (Minkowski's
    // `exponent`); summed over 1 + detail octaves as the noise is (detail,
    // roughness, lacunarity; `normalize` divides by the largest distance);
    // voronoi_output: the Distance, Color, Position or W output. voronoi_pcg:
    // the points and colours are hashed as Blender 5.0 hashes them (PCG of the
    // integer cell), else as before (lookup3 of its corner's float bits).
    VoronoiFeature voronoi_feature = VoronoiFeature::F1;
    VoronoiMetric voronoi_metric = VoronoiMetric::Euclidean;
    VoronoiOutput voronoi_output = VoronoiOutput::Distance;
    float exponent = 0.5f, randomness = 1, smoothness = 1;
    bool voronoi_pcg = true;
    // Wave (procedural.h): bands or rings (wave_type) across or about
    // wave_direction, 20 per unit of the point x scale, shifted by `phase` and
    // by `distortion` x fBM noise of the point x detail_scale (detail and
    // roughness as the Noise's, lacunarity 2, normalized), through
    // wave_profile; the value is the colour, as grey, and the alpha.
    WaveType wave_type = WaveType::Bands;
    WaveDirection wave_direction = WaveDirection::AxisX;
    WaveProfile wave_profile = WaveProfile::Sine;
    float detail_scale = 1, phase = 0;
    // Magic (procedural.h): sines and cosines of the point (modulo 2 pi, as
    // Blender 3.4 and later take it) x scale, nested `depth` times (0-10),
    // each scaled by `distortion`; the alpha is the colour's average
    // (Blender's Fac).
    int32_t depth = 2;
    // Brick (procedural.h): in the (x, y) plane of the point x scale, rows
    // of row_height, bricks of brick_width, every offset_frequency-th row
    // shifted by offset_amount of a brick and every squash_frequency-th
    // row's bricks squash_amount as wide (neither where either frequency is
    // 0); each brick's colour is color1 tinted towards color2 by a hashed
    // amount plus brick_bias, inside a `mortar` colour mortar_size wide, blended
    // over mortar_smooth; the alpha is the mortar's share (Blender's Fac).
    std::array<float, 3> mortar = {0, 0, 0};
    float mortar_size = 0.02f, mortar_smooth = 0.1f, brick_bias = 0, brick_width = 0.5f, row_height = 0.25f,
          offset_amount = 0.5f, squash_amount = 1;
    int32_t offset_frequency = 2, squash_frequency = 2;
    // A colour ramp the value goes through last (Blender's Color Ramp node,
    // RGB mode): 5 floats per stop, position then RGBA, positions in
    // increasing order, at most kMaxRampStops; empty: none. The ramp's input is the value after the
    // adjustments below, grey as it is, else its luminance.
    std::vector<float> ramp;
    RampInterpolation ramp_interpolation = RampInterpolation::Linear;
    Interpolation interpolation = Interpolation::Linear;
    Extension extension = Extension::Repeat;
    bool use_alpha = false;                              // the Alpha output instead of Color
    // The colour multiplied by alpha before filtering (an 8-bit image's in its
    // bytes, truncating): Cycles' Image Texture gives associated colour.
    bool premultiply = false;
    // The colour divided by alpha after filtering (before decoding an 8-bit
    // sRGB image; where alpha is neither 0 nor 1): Cycles' Color output when
    // the node's Alpha output is used, which makes associated colour straight again.
    bool unassociate = false;
    // The texture coordinates are mapped before the lookup: u' = m0 u + m1 v + m2,
    // v' = m3 u + m4 v + m5 (Blender's Mapping node between the UV map and an
    // Image Texture: a 2 x 3 affine map). The identity changes nothing, to the bit.
    std::array<float, 6> uv_transform = {1, 0, 0, 0, 1, 0};
    // UDIM tiles (Blender's tiled images): pairs of (tile number, image index);
    // empty: the texture reads `image` alone. A tiled texture reads, at the
    // mapped (u, v), the tile numbered 1001 + 10 int(v) + int(u) (int truncates,
    // as Cycles picks the tile), at (u - int(u), v - int(v)), extended as
    // `extension` says; where no tile lies, or u or v is at or below -1 or u at
    // or above 10, it reads magenta (1, 0, 1, 1), Cycles' missing texture.
    // `image` is then one of the tiles' images (its size sets a bump map's step).
    std::vector<int32_t> tiles;
    // What the value goes through before the material reads it (Blender's
    // Separate Color, Math, Mix and Invert nodes between the image and the
    // shader's input): `channel` -1 the colour, 0-2 its red, green or blue
    // channel as grey, 3 its luminance as grey, 4 the average of its three
    // (a vector, such as a Voronoi's Position, read as a number, as Cycles
    // converts it) as grey (use_alpha: the alpha, as
    // grey); then colour x gain + bias, channel by channel; then clamped to
    // [0, 1] where `clamp` is set. The defaults change nothing, to the bit.
    int32_t channel = -1;
    std::array<float, 3> gain = {1, 1, 1};
    std::array<float, 3> bias = {0, 0, 0};
    bool clamp = false;
    // The same adjustments of the ramp's colour, after the ramp (the nodes
    // between a Color Ramp and the shader's input): ramp_channel -1 the
    // colour, 0-2 a channel, 3 its luminance, 4 its average, as grey; then x
    // ramp_gain + ramp_bias; then clamped where ramp_clamp is set. Only with a
    // ramp; the defaults change nothing.
    int32_t ramp_channel = -1;
    std::array<float, 3> ramp_gain = {1, 1, 1};
    std::array<float, 3> ramp_bias = {0, 0, 0};
    bool ramp_clamp = false;
};

// Whether channel, gain, bias and clamp change a value (see Texture::channel).
inline bool changes(int32_t channel, const std::array<float, 3>& gain, const std::array<float, 3>& bias, bool clamp) {
    return channel != -1 || gain != std::array<float, 3>{1, 1, 1} || bias != std::array<float, 3>{0, 0, 0} || clamp;
}

// Whether the texture's value is adjusted before its ramp (see Texture::channel), and after it.
inline bool adjusts(const Texture& t) { return changes(t.channel, t.gain, t.bias, t.clamp); }
inline bool adjusts_after_ramp(const Texture& t) {
    return changes(t.ramp_channel, t.ramp_gain, t.ramp_bias, t.ramp_clamp);
}

inline bool uv_mapped(const Texture& t) { return t.uv_transform != std::array<float, 6>{1, 0, 0, 0, 1, 0}; }

inline bool vector_mapped(const Texture& t) {
    return t.vector_transform != std::array<float, 12>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
}

// Whether the texture is an image looked up at the UV map's (u, v) as it
// was before procedural textures and other coordinates: what a normal map
// and the world's environment take (a bump map of one takes its texels' slopes).
inline bool plain_image(const Texture& t) {
    return t.kind == TextureKind::Image && t.coordinates == TextureCoords::UV && !vector_mapped(t) && t.ramp.empty() &&
           t.projection == ImageProjection::Flat;
}

// The ramp's colour at f (see Texture::ramp; t.ramp not empty): Blender's
// Color Ramp, as Cycles evaluates it.
Vec3 ramp_color(const Texture& t, float f);

// p mapped by t.vector_transform (see Texture).
inline Vec3 map_vector(const Texture& t, const Vec3& p) {
    const auto& m = t.vector_transform;
    return Vec3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

// The coordinates a Noise or Voronoi texture reads at the (mapped) point p, in
// t.dimensions (1: w; 2: x, y; 3: the point; 4: the point and w), all times
// t.scale, as Cycles' nodes scale their vector and W: out holds 4.
inline void pattern_coords(const Texture& t, const Vec3& p, float* out) {
    const Vec3 q = p * t.scale;
    const float w = t.w * t.scale;
    if (t.dimensions == 1) {
        out[0] = w;
        return;
    }
    for (int i = 0; i < std::min(t.dimensions, 3); ++i) out[i] = q[i];
    if (t.dimensions == 4) out[3] = w;
}

// Blender's Checker Texture at the (mapped) vector p: color1 or color2, as
// Cycles decides between them (its cube index per axis is taken from p x
// scale nudged by +1e-6 and shrunk by 0.999999, which keeps a plane at an
// integer coordinate, such as a face of the unit cube, on one side).
Rgba checker_color(const Texture& t, const Vec3& p);

// Blender's Gradient Texture at the (mapped) vector p: grey, its value as
// Cycles computes it for t.gradient, clamped to [0, 1].
Rgba gradient_color(const Texture& t, const Vec3& p);

// (u, v) mapped by t.uv_transform (see Texture).
inline void map_uv(const Texture& t, float& u, float& v) {
    const auto& m = t.uv_transform;
    const float x = m[0] * u + m[1] * v + m[2], y = m[3] * u + m[4] * v + m[5];
    u = x;
    v = y;
}

// Checks the enums and that uv_transform is finite (the image index is checked
// by the scene, which knows the images); throws std::invalid_argument naming
// `where` and the field.
void validate_texture(const Texture& t, const std::string& where);

// The image under texture coordinates (u, v), filtered and extended as `t`
// says; its colour times alpha when t.premultiply is set, divided by it after
// filtering when t.unassociate is (before decoding an 8-bit sRGB image).
Rgba sample_image(const Image& img, const Texture& t, float u, float v);

// The image a texture reads at (u, v) (see Texture::tiles): t.image, or the
// tile under (u, v), whose coordinates within the tile replace (u, v); -1 where
// no tile lies there.
int32_t texture_image(const Texture& t, float& u, float& v);

// Cycles' colour for a texture it cannot read (a missing UDIM tile): magenta.
inline Rgba missing_texel() { return Rgba{Vec3(1, 0, 1), 1}; }

// Rec. 709 luminance: Blender's colour-to-float conversion.
inline float luminance(const Vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// v through a channel (of the colour rgb: v becomes that grey, unless
// channel is -1), gain, bias and clamp (see Texture::channel).
inline Vec3 adjust_value(int32_t channel, const std::array<float, 3>& gain, const std::array<float, 3>& bias,
                         bool clamp, const Vec3& rgb, Vec3 v) {
    if (channel >= 0) {
        const float grey = channel == 0   ? rgb.x
                           : channel == 1 ? rgb.y
                           : channel == 2 ? rgb.z
                           : channel == 3 ? luminance(rgb)
                                          : (rgb.x + rgb.y + rgb.z) * (1.0f / 3.0f);
        v = Vec3(grey, grey, grey);
    }
    v = Vec3(v.x * gain[0] + bias[0], v.y * gain[1] + bias[1], v.z * gain[2] + bias[2]);
    if (clamp) {
        auto unit = [](float x) { return x > 0 ? (x < 1 ? x : 1) : 0; };   // (NaN -> 0)
        v = Vec3(unit(v.x), unit(v.y), unit(v.z));
    }
    return v;
}

// v (the texture's colour, or its alpha as grey) through the texture's
// channel, gain, bias and clamp (see Texture::channel).
inline Vec3 adjusted(const Texture& t, const Rgba& c, Vec3 v) {
    return adjust_value(t.use_alpha ? -1 : t.channel, t.gain, t.bias, t.clamp, c.rgb, v);
}

// Colour of a texture feeding a colour input: its alpha as grey (use_alpha),
// else its colour (premultiplied by sample_image where the texture says), then
// the texture's channel, gain, bias and clamp (see Texture::channel), then its
// ramp, if it has one (the value grey as it is, else its luminance), and the
// adjustments after the ramp.
inline Vec3 color_of(const Texture& t, const Rgba& c) {
    Vec3 v = t.use_alpha ? Vec3(c.a, c.a, c.a) : c.rgb;
    if (adjusts(t)) v = adjusted(t, c, v);
    if (t.ramp.empty()) return v;
    v = ramp_color(t, v.x == v.y && v.y == v.z ? v.x : luminance(v));
    if (adjusts_after_ramp(t)) v = adjust_value(t.ramp_channel, t.ramp_gain, t.ramp_bias, t.ramp_clamp, v, v);
    return v;
}

// Scalar value of a texture feeding a scalar input: a grey value (the alpha,
// a channel, the luminance) as it is, else the colour's luminance (Rec. 709
// weights, Blender's colour-to-float conversion), after color_of's adjustments.
inline float scalar_of(const Texture& t, const Rgba& c) {
    const Vec3 rgb = color_of(t, c);
    const bool grey = t.ramp.empty() ? t.use_alpha || t.channel >= 0 : t.ramp_channel >= 0;
    if (grey && rgb.x == rgb.y && rgb.y == rgb.z) return rgb.x;
    return luminance(rgb);
}

// Equirectangular coordinates of a direction, as Blender's Environment
// Texture maps them (Z up): the image's centre (u = 0.5) lies along +X,
// u = 0.25 along +Y; v = 1 straight up, v = 0.5 on the horizon.
void equirect_uv(const Vec3& d, float& u, float& v);

}  // namespace gw
