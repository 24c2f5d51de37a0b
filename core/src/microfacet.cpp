// The GGX lobe's directional albedo table (microfacet.h).
#include "microfacet.h"

#include <array>
#include <mutex>

namespace gw {
namespace {

constexpr int kCosines = 32, kRoughness = 32, kStrata = 12;

// Calls f(j, i, alpha, c, wo) for the nodes of a layer of nr roughnesses by nc view cosines:
// rows by roughness r = sqrt(alpha) in [0, 1], columns by sqrt(cos_o) in [0, 1] (dense near
// grazing, where the albedos dip; cos_o 0 is taken at 1e-4: the lobe's limit is continuous
// there); wo is the view at cosine c in the frame whose z is the normal.
template <class F>
void for_each_node(int nr, int nc, F f) {
    for (int j = 0; j < nr; ++j) {
        const float r = float(j) / float(nr - 1), alpha = std::max(r * r, 1e-4f);
        for (int i = 0; i < nc; ++i) {
            const float x = float(i) / float(nc - 1), c = std::max(x * x, 1e-4f);
            f(j, i, alpha, c, Vec3(std::sqrt(1 - c * c), 0, c));
        }
    }
}

// E(cos_o, alpha) at F = 1: the mean of G2 / G1 over glossy rays drawn from
// the visible normals, on a kStrata x kStrata grid of their midpoints; rows
// by roughness r = sqrt(alpha) in [0, 1], columns by sqrt(cos_o) in [0, 1]
// (dense near grazing, where E dips; cos_o 0 is taken at 1e-4: the lobe's
// limit is continuous there).
struct AlbedoTable {
    std::array<float, kCosines * kRoughness> e{};
    AlbedoTable() {
        for_each_node(kRoughness, kCosines, [&](int j, int i, float alpha, float c, const Vec3& wo) {
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
        });
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
        for_each_node(kRoughness, kCosines, [&](int j, int i, float alpha, float c, const Vec3& wo) {
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
        });
    }
};

// E_glass(cos_o, alpha, eta): what a rough dielectric interface (Integrator::rough_glass)
// returns of a white world, single scattering: per microfacet normal drawn from the visible
// normals, F G2 / G1 of the reflection plus (1 - F) G2 / G1 of the refraction, F the exact
// Fresnel (1 past total internal reflection); eta = n2 / n1 (beyond over the view's side) at
// kEta nodes spaced evenly in log eta over [1/3, 3], each node's 16 x 16 layer (cos_o and
// roughness as above; E_glass is smooth in both) integrated the first time it is needed (a few
// milliseconds; a scene uses one or two IORs). 16 x 16 strata, the first variable
// u = 1 - (1 - s)^2 (weight 2 (1 - s)), so that the steep normals of GGX's tail, where the
// refracted rays lose most, get their share: midpoints of 8 x 8 strata put 0.9995 where 64 x 64
// give 0.968 (IOR 1.5 seen from inside, head on, alpha 0.16); these within 0.004 of those.
constexpr int kEta = 17, kGlassCosines = 16, kGlassRoughness = 16, kGlassStrata = 16;
constexpr float kEtaRange = 3.0f;

float glass_eta(int k) { return std::exp(std::log(kEtaRange) * (2.0f * float(k) / float(kEta - 1) - 1.0f)); }

void glass_layer(float eta, float* e) {
    for_each_node(kGlassRoughness, kGlassCosines, [&](int j, int i, float alpha, float c, const Vec3& wo) {
        double sum = 0;
        for (int a = 0; a < kGlassStrata; ++a) {
            const float s = (float(a) + 0.5f) / kGlassStrata, u = 1 - (1 - s) * (1 - s);
            for (int b = 0; b < kGlassStrata; ++b) {
                const Vec3 m = ggx_visible_normal(wo, alpha, u, (float(b) + 0.5f) / kGlassStrata);
                const float cm = std::min(dot(wo, m), 1.0f);
                if (!(cm > 0)) continue;
                const float q = 1.0f - (1.0f - cm * cm) / (eta * eta);
                const float f = q <= 0 ? 1.0f : fresnel_dielectric(cm, eta);
                float v = f * ggx_ray_weight(c, 2 * cm * m.z - wo.z, alpha);
                if (q > 0) {   // the refracted direction's z: -wo.z / eta + m.z (cm / eta - sqrt(q))
                    const float cos_t = wo.z / eta - m.z * (cm / eta - std::sqrt(q));
                    v += (1 - f) * ggx_ray_weight(c, cos_t, alpha);
                }
                sum += double(v) * 2 * (1 - s);
            }
        }
        e[j * kGlassCosines + i] = float(sum / (kGlassStrata * kGlassStrata));
    });
}

struct GlassTable {
    std::array<float, kGlassCosines * kGlassRoughness * kEta> e{};
    std::array<std::once_flag, kEta> built;
    const float* layer(int k) {
        float* out = e.data() + size_t(k) * kGlassCosines * kGlassRoughness;
        std::call_once(built[size_t(k)], [&] { glass_layer(glass_eta(k), out); });
        return out;
    }
};

// Bilinear in sqrt(cos_o) and sqrt(alpha) over a layer of nc cosines x nr roughnesses.
float bilinear(const float* e, float cos_o, float alpha, int nc = kCosines, int nr = kRoughness) {
    const float x = std::sqrt(std::min(std::max(cos_o, 0.0f), 1.0f)) * float(nc - 1);
    const float y = std::min(std::max(std::sqrt(std::max(alpha, 0.0f)), 0.0f), 1.0f) * float(nr - 1);
    const int i = std::min(int(x), nc - 2), j = std::min(int(y), nr - 2);
    const float fx = x - float(i), fy = y - float(j);
    const float lo = e[j * nc + i] * (1 - fx) + e[j * nc + i + 1] * fx;
    const float hi = e[(j + 1) * nc + i] * (1 - fx) + e[(j + 1) * nc + i + 1] * fx;
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

float ggx_glass_albedo(float cos_o, float alpha, float eta) {
    static GlassTable table;
    const float s = std::log(std::min(std::max(eta, 1 / kEtaRange), kEtaRange)) / std::log(kEtaRange);
    const float y = (s + 1) * 0.5f * float(kEta - 1);
    const int k = std::min(int(y), kEta - 2);
    const float t = y - float(k);
    const float lo = bilinear(table.layer(k), cos_o, alpha, kGlassCosines, kGlassRoughness);
    const float hi = t > 0 ? bilinear(table.layer(k + 1), cos_o, alpha, kGlassCosines, kGlassRoughness) : lo;
    return std::max(lo * (1 - t) + hi * t, 1e-3f);
}

float ggx_albedo(float cos_o, float alpha) {
    static const AlbedoTable table;
    return std::max(bilinear(table.e.data(), cos_o, alpha), 1e-3f);
}

}  // namespace gw
