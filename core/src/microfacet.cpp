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

// E_F(cos_o, alpha, f0): the same mean with each ray weighted by the exact
// dielectric Fresnel at its microfacet, for kF0 reflectances at normal
// incidence (0 and 1 at the ends: E_F is 0 and E there), on 8 x 8 strata.
constexpr int kF0 = 8, kDielectricStrata = 8;
constexpr float kF0Nodes[kF0] = {0.0f, 0.02f, 0.04f, 0.08f, 0.16f, 0.32f, 0.64f, 1.0f};

struct DielectricTable {
    std::array<float, kCosines * kRoughness * kF0> e{};
    DielectricTable() {
        for (int j = 0; j < kRoughness; ++j) {
            const float r = float(j) / float(kRoughness - 1), alpha = std::max(r * r, 1e-4f);
            for (int i = 0; i < kCosines; ++i) {
                const float x = float(i) / float(kCosines - 1), c = std::max(x * x, 1e-4f);
                const Vec3 wo(std::sqrt(1 - c * c), 0, c);
                double sum[kF0] = {};
                for (int a = 0; a < kDielectricStrata; ++a) {
                    for (int b = 0; b < kDielectricStrata; ++b) {
                        const Vec3 m = ggx_visible_normal(wo, alpha, (float(a) + 0.5f) / kDielectricStrata,
                                                          (float(b) + 0.5f) / kDielectricStrata);
                        const float cos_m = dot(wo, m), cos_i = 2 * cos_m * m.z - wo.z;
                        const float w = ggx_ray_weight(c, cos_i, alpha);
                        if (!(w > 0)) continue;
                        for (int k = 1; k < kF0; ++k) {
                            const float f = k == kF0 - 1 ? 1.0f : fresnel_dielectric(cos_m, dielectric_eta(kF0Nodes[k]));
                            sum[k] += w * f;
                        }
                    }
                }
                for (int k = 0; k < kF0; ++k)
                    e[size_t((k * kRoughness + j) * kCosines + i)] =
                        float(sum[k] / (kDielectricStrata * kDielectricStrata));
            }
        }
    }
};

// Bilinear in sqrt(cos_o) and sqrt(alpha) over a kCosines x kRoughness layer.
float bilinear(const float* e, float cos_o, float alpha) {
    const float x = std::sqrt(std::min(std::max(cos_o, 0.0f), 1.0f)) * (kCosines - 1);
    const float y = std::min(std::max(std::sqrt(std::max(alpha, 0.0f)), 0.0f), 1.0f) * (kRoughness - 1);
    const int i = std::min(int(x), kCosines - 2), j = std::min(int(y), kRoughness - 2);
    const float fx = x - float(i), fy = y - float(j);
    const float lo = e[j * kCosines + i] * (1 - fx) + e[j * kCosines + i + 1] * fx;
    const float hi = e[(j + 1) * kCosines + i] * (1 - fx) + e[(j + 1) * kCosines + i + 1] * fx;
    return lo * (1 - fy) + hi * fy;
}

}  // namespace

float ggx_dielectric_albedo(float cos_o, float alpha, float f0) {
    static const DielectricTable table;
    f0 = std::min(std::max(f0, 0.0f), 1.0f);
    int k = 0;
    while (k < kF0 - 2 && f0 > kF0Nodes[k + 1]) ++k;
    const float t = (f0 - kF0Nodes[k]) / (kF0Nodes[k + 1] - kF0Nodes[k]);
    const float* e = table.e.data();
    const float lo = bilinear(e + size_t(k) * kCosines * kRoughness, cos_o, alpha);
    const float hi = bilinear(e + size_t(k + 1) * kCosines * kRoughness, cos_o, alpha);
    return std::max(lo * (1 - t) + hi * t, 0.0f);
}

float ggx_albedo(float cos_o, float alpha) {
    static const AlbedoTable table;
    return std::max(bilinear(table.e.data(), cos_o, alpha), 1e-3f);
}

}  // namespace gw
