// Shadows of the world's light (RenderSettings.world_shadows): what the scene
// blocks of the ambient light and of the environment's irradiance
// (irradiance.h), which are otherwise unoccluded.
//
// A diffuse surface facing n gets (1 / pi) of the integral of L(w) V(w) cos
// over its hemisphere. The unblocked integral is known (the ambient colour, or
// the environment's irradiance table), so only the share that gets through is
// estimated, from shadow rays toward the world: the sum of L V cos / pdf over
// the sum of L cos / pdf for the same directions, per channel. Where nothing
// blocks the sky the share is exactly 1 (no noise); it never leaves [0, 1]; a
// ratio of two sums, its bias shrinks as 1 / (rays per shading point). (An
// unblocked-minus-blocked estimate, tried first, had to be clamped at 0 and
// was 40% too bright in a sun's umbra with 16 rays per point.) Directions are
// drawn, with probability 1/2 each, from the environment's brightness (the
// luminance of its radiance map of at most 512 x 256 cells, each sampled
// uniformly in solid angle: suns are found) and from the cosine about n (which
// covers the hemisphere wherever the image is dark); the pdf is their mixture.
#pragma once
#include <vector>

#include "irradiance.h"
#include "math.h"

namespace gw {

class WorldMap {
public:
    WorldMap() = default;
    // The luminance map of an environment's radiance map (irradiance.h).
    explicit WorldMap(const RadianceMap& radiance);

    bool empty() const { return total_ <= 0; }
    // A direction drawn in proportion to the map's luminance per solid angle, (u1, u2) in [0, 1)^2.
    Vec3 sample(float u1, float u2) const;
    // The density of sample() at direction d, per steradian.
    float pdf(const Vec3& d) const;
    // The map's radiance along d (its cell's mean: the radiance the irradiance
    // table integrates, so that what is blocked and what is lit agree).
    Vec3 radiance(const Vec3& d) const;
    // The solid angle of its cells that hold light (a sun's size), in steradians.
    double solid_angle() const { return solid_angle_; }

private:
    int w_ = 0, h_ = 0;
    size_t cell(const Vec3& d) const;
    std::vector<Vec3> rgb_;        // h_ x w_ radiance, row 0 at the bottom (as Image::texel)
    std::vector<float> lum_;       // its luminance
    std::vector<double> rows_;     // cumulative share of each row (luminance x solid angle), last = 1
    std::vector<double> cols_;     // per row, the cumulative share of each column within it
    double total_ = 0;             // sum of luminance x solid angle: pdf = luminance / total
    double solid_angle_ = 0;
};

// A cosine-distributed direction about n (unit), and its density cos / pi.
Vec3 cosine_direction(const Vec3& n, float u1, float u2);

}  // namespace gw
