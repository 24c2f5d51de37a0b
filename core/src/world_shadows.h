// Shadows of the world's light (RenderSettings.world_shadows): what the scene
// blocks of the ambient light and of the environment's irradiance
// (irradiance.h), which are otherwise unoccluded.
//
// A diffuse surface facing n gets (1 / pi) of the integral of L(w) V(w) cos
// over its hemisphere. The unblocked integral is known (the ambient colour, or
// the environment's nine-coefficient irradiance), so only the blocked part is
// estimated: light = unblocked - (1 / pi) mean of L (1 - V) cos / pdf over the
// sampled directions, clamped at 0. Where nothing blocks the sky the estimate
// is exact and noise-free; in a crevice it carries the noise of the blocked
// directions. Directions are drawn, with probability 1/2 each, from the
// environment's brightness (a coarse luminance map of at most 512 x 256
// texels, each sampled uniformly in solid angle: suns are found) and from the
// cosine about n (which covers the hemisphere wherever the image is dark);
// the pdf is their mixture, which bounds every sample's weight.
#pragma once
#include <vector>

#include "math.h"
#include "texture.h"

namespace gw {

class WorldMap {
public:
    WorldMap() = default;
    // The luminance map of an equirectangular environment (texture t over img).
    WorldMap(const Image& img, const Texture& t);

    bool empty() const { return total_ <= 0; }
    // A direction drawn in proportion to the map's luminance per solid angle, (u1, u2) in [0, 1)^2.
    Vec3 sample(float u1, float u2) const;
    // The density of sample() at direction d, per steradian.
    float pdf(const Vec3& d) const;

private:
    int w_ = 0, h_ = 0;
    std::vector<float> lum_;       // h_ x w_, row 0 at the bottom (as Image::texel)
    std::vector<double> rows_;     // cumulative share of each row (luminance x solid angle), last = 1
    std::vector<double> cols_;     // per row, the cumulative share of each column within it
    double total_ = 0;             // sum of luminance x solid angle: pdf = luminance / total
};

// A cosine-distributed direction about n (unit), and its density cos / pi.
Vec3 cosine_direction(const Vec3& n, float u1, float u2);

}  // namespace gw
