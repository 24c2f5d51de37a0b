#include "emitters.h"

#include <algorithm>

namespace gw {
namespace {

double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace

Emitters::Emitters(const PooledVector<Vec3>& tri_vertices, const PooledVector<int32_t>& tri_materials,
                   const std::vector<Material>& materials) {
    // (most scenes have no emissive material: no pass over their triangles)
    if (std::none_of(materials.begin(), materials.end(), [](const Material& m) { return m.emits_light; })) return;
    std::vector<double> weights;
    double total = 0;
    for (size_t i = 0; i < tri_materials.size(); ++i) {
        const Material& m = materials[size_t(tri_materials[i])];
        if (!m.emits_light) continue;
        const Vec3 e = emitted(m);
        // (a textured colour counts as white here: the texture is read per sample)
        double lum = m.color_texture >= 0 ? double(m.emission) + luminance(m.emission_color) : luminance(e);
        if (m.emission_texture >= 0)
            lum = (m.color_texture >= 0 ? double(m.emission) : luminance(m.color * m.emission)) +
                  luminance(m.emission_color);
        const Vec3 *v = &tri_vertices[3 * i];
        const Vec3d a(v[0]), ab = Vec3d(v[1]) - a, ac = Vec3d(v[2]) - a;
        const double area = 0.5 * length(cross(ab, ac));
        const double w = lum * area;
        if (!(w > 0) || !std::isfinite(w)) continue;
        tris_.push_back(int32_t(i));
        weights.push_back(w);
        total += w;
    }
    cdf_.resize(weights.size());
    double run = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        run += weights[i];
        cdf_[i] = run / total;
    }
    if (!cdf_.empty()) cdf_.back() = 1.0;
}

int32_t Emitters::pick(float u, float& probability, float& u_rest) const {
    const double x = double(u);
    const size_t k = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), x) - cdf_.begin());
    const size_t i = std::min(k, cdf_.size() - 1);
    const double lo = i ? cdf_[i - 1] : 0.0, hi = cdf_[i];
    probability = float(hi - lo);
    u_rest = float(std::min(std::max((x - lo) / (hi - lo), 0.0), 0.99999994));
    return tris_[i];
}

float Emitters::probability_of(int32_t tri) const {
    const auto at = std::lower_bound(tris_.begin(), tris_.end(), tri);   // (tris_ ascends)
    if (at == tris_.end() || *at != tri) return 0;
    const size_t i = size_t(at - tris_.begin());
    return float(cdf_[i] - (i ? cdf_[i - 1] : 0.0));
}

}  // namespace gw
