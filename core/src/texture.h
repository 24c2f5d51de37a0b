// Images and the textures that sample them. An Image is a pixel array stored
// once however many textures use it: 8-bit images stay 8-bit (decoded from
// sRGB at lookup, after filtering), float images stay float. A Texture is the
// record a material (or the world) points at: which image, how to filter it,
// what lies outside it, and whether it gives the colour or the alpha channel
// (Blender's Image Texture node: Color and Alpha outputs). Row 0 of the pixel
// array is the TOP of the image; v = 0 is its bottom edge (UV convention).
#pragma once
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

// The texture record, bound to Python field by field as gridwalk._core.Texture.
struct Texture {
    int32_t image = -1;                                  // index into the scene's images
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
};

inline bool uv_mapped(const Texture& t) { return t.uv_transform != std::array<float, 6>{1, 0, 0, 0, 1, 0}; }

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

// Colour of a texture feeding a colour input: its alpha as grey (use_alpha),
// else its colour (premultiplied by sample_image where the texture says).
inline Vec3 color_of(const Texture& t, const Rgba& c) {
    return t.use_alpha ? Vec3(c.a, c.a, c.a) : c.rgb;
}

// Scalar value of a texture feeding a scalar input: its alpha (use_alpha), else
// the colour's luminance (Rec. 709 weights, Blender's colour-to-float conversion).
inline float scalar_of(const Texture& t, const Rgba& c) {
    if (t.use_alpha) return c.a;
    const Vec3 rgb = color_of(t, c);
    return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z;
}

// Equirectangular coordinates of a direction, as Blender's Environment
// Texture maps them (Z up): the image's centre (u = 0.5) lies along +X,
// u = 0.25 along +Y; v = 1 straight up, v = 0.5 on the horizon.
void equirect_uv(const Vec3& d, float& u, float& v);

}  // namespace gw
