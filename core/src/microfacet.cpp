// The GGX lobe's directional albedo table (microfacet.h).
#include "microfacet.h"

#include <array>

namespace gw {
namespace {

constexpr int kCosines = 32, kRoughness = 32, kStrata = 12;

// E(cos_o, alpha) at F = 1: the mean of G2 / G1 over glossy rays drawn from
// the visible normals, on a kStrata x kStrata grid of their midpoints; rows
// by roughness r = sqrt(alpha) in [0, 1], columns by sqrt(cos_o) in [0, 1]
// (dense near grazing, where E dips; cos_o 0 is taken at 1e-4: the lobe's
// limit is continuous there).
struct AlbedoTable {
    std::array<float, kCosines * kRoughness> e{};
    AlbedoTable() {
        for (int j = 0; j < kRoughness; ++j) {
            const float r = float(j) / float(kRoughness - 1), alpha = std::max(r * r, 1e-4f);
            for (int i = 0; i < kCosines; ++i) {
                const float x = float(i) / float(kCosines - 1), c = std::max(x * x, 1e-4f);
                const Vec3 wo(std::sqrt(1 - c * c), 0, c);
                double sum = 0;
                for (int a = 0; a < kStrata; ++a) {
                    for (int b = 0; b < kStrata; ++b) {
                        const Vec3 m = ggx_visible_normal(wo, alpha, (float(a) + 0.5f) / kStrata,
                                                          (float(b) + 0.5f) / kStrata);
                        const float cos_i = 2 * dot(wo, m) * m.z - wo.z;   // (wi = reflect(wo, m)).z
                        sum += ggx_ray_weight(c, cos_i, alpha);
                    }
                }
                e[size_t(j * kCosines + i)] = float(sum / (kStrata * kStrata));
            }
        }
    }
};

}  // namespace

float ggx_albedo(float cos_o, float alpha) {
    static const AlbedoTable table;
    // Bilinear in sqrt(cos_o) and r = sqrt(alpha).
    const float x = std::sqrt(std::min(std::max(cos_o, 0.0f), 1.0f)) * (kCosines - 1);
    const float y = std::min(std::max(std::sqrt(std::max(alpha, 0.0f)), 0.0f), 1.0f) * (kRoughness - 1);
    const int i = std::min(int(x), kCosines - 2), j = std::min(int(y), kRoughness - 2);
    const float fx = x - float(i), fy = y - float(j);
    const float* e = table.e.data();
    const float lo = e[j * kCosines + i] * (1 - fx) + e[j * kCosines + i + 1] * fx;
    const float hi = e[(j + 1) * kCosines + i] * (1 - fx) + e[(j + 1) * kCosines + i + 1] * fx;
    return std::max(lo * (1 - fy) + hi * fy, 1e-3f);
}

}  // namespace gw
