// Emissive triangles as lights. A material with emits_light set lights other
// surfaces with what it emits (colour x emission + emission_color, its
// textures applied at the sampled point), from both sides of each triangle,
// as Cycles' mesh lights do. Direct lighting picks one emissive triangle per
// light sample, with probability proportional to its area times its
// emission's luminance (taken once, without textures), then a uniform point
// on it; the estimate divides by that probability, so it stays unbiased
// whatever the weights (moved instances keep theirs).
#pragma once
#include <cstdint>
#include <vector>

#include "buffer_pool.h"
#include "material.h"
#include "math.h"

namespace gw {

class Emitters {
public:
    Emitters() = default;
    // tri_vertices: 3 corners per triangle; tri_materials: each triangle's material.
    Emitters(const PooledVector<Vec3>& tri_vertices, const PooledVector<int32_t>& tri_materials,
             const std::vector<Material>& materials);

    bool empty() const { return tris_.empty(); }
    size_t size() const { return tris_.size(); }
    // The triangle for u in [0, 1), its selection probability, and u
    // rescaled to [0, 1) within the triangle's share (still stratified).
    int32_t pick(float u, float& probability, float& u_rest) const;
    // The probability that pick() selects triangle tri (0 for a triangle that is no emitter).
    float probability_of(int32_t tri) const;

private:
    std::vector<int32_t> tris_;   // the emissive triangles
    std::vector<double> cdf_;     // cdf_[i]: the weights of tris_[0..i] over the total
};

// The radiance a material emits (before textures: colour x emission + emission_color).
inline Vec3 emitted(const Material& m) { return m.color * m.emission + m.emission_color; }

}  // namespace gw
