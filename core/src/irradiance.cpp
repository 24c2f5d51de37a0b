#include "irradiance.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gw {
namespace {

// The real spherical harmonics' constants, orders 0-2.
constexpr double kY0 = 0.28209479177387814;   // 1 / (2 sqrt(pi))
constexpr double kY1 = 0.48860251190291992;   // sqrt(3 / (4 pi))
constexpr double kY2 = 1.0925484305920792;    // sqrt(15 / (4 pi))
constexpr double kY20 = 0.31539156525252005;  // sqrt(5 / (16 pi))
constexpr double kY22 = 0.54627421529603959;  // sqrt(15 / (16 pi))

struct D3 {
    double x = 0, y = 0, z = 0;
    void add(const Vec3& v, double w) { x += v.x * w; y += v.y * w; z += v.z * w; }
    void add(const D3& v, double w) { x += v.x * w; y += v.y * w; z += v.z * w; }
    Vec3 f() const { return Vec3(float(x), float(y), float(z)); }
};

}  // namespace

Vec3 Irradiance::at(const Vec3& n) const {
    const float x = n.x, y = n.y, z = n.z;
    const Vec3 e = c[0] + c[1] * y + c[2] * z + c[3] * x + c[4] * (x * y) + c[5] * (y * z) +
                   c[6] * (3 * z * z - 1) + c[7] * (x * z) + c[8] * (x * x - y * y);
    return Vec3(std::max(e.x, 0.0f), std::max(e.y, 0.0f), std::max(e.z, 0.0f));
}

Irradiance environment_irradiance(const Image& img, const Texture& t, float strength) {
    const int w = img.width(), h = img.height();
    // The image is taken as constant over each texel, and each texel's part of
    // every projection integrated exactly: dw = dphi dz with z = sin(elevation),
    // x = s cos phi, y = s sin phi, s = sqrt(1 - z^2). Column x spans
    // u in [x, x + 1] / w, phi = (0.5 - u) 2 pi (equirect_uv: u = 0.5 along +X,
    // 0.25 along +Y); the integrals of 1, cos phi, sin phi, cos 2 phi, sin 2 phi over it:
    const size_t n = size_t(w);
    std::vector<double> a0(n), ac1(n), as1(n), ac2(n), as2(n);
    for (int x = 0; x < w; ++x) {
        const double p1 = (0.5 - double(x) / w) * 2 * kPi, p0 = (0.5 - double(x + 1) / w) * 2 * kPi;
        const size_t k = size_t(x);
        a0[k] = p1 - p0;
        ac1[k] = std::sin(p1) - std::sin(p0);
        as1[k] = std::cos(p0) - std::cos(p1);
        ac2[k] = 0.5 * (std::sin(2 * p1) - std::sin(2 * p0));
        as2[k] = 0.5 * (std::cos(2 * p0) - std::cos(2 * p1));
    }
    // Antiderivatives in z of the elevation factors.
    auto s1 = [](double z) { return 0.5 * (z * std::sqrt(std::max(0.0, 1 - z * z)) + std::asin(z)); };   // s
    auto s2 = [](double z) { return z - z * z * z / 3; };                                               // s^2
    auto zs = [](double z) { return -std::pow(std::max(0.0, 1 - z * z), 1.5) / 3; };                     // z s
    auto z1 = [](double z) { return 0.5 * z * z; };                                                     // z
    auto q = [](double z) { return z * z * z - z; };                                                    // 3 z^2 - 1
    // Radiance projections L_lm (indexed as Irradiance::c), row by row: a
    // row's texels share their z band, so it needs only the sums of its
    // colours times the five column integrals.
    D3 L[9];
    const bool premultiply = t.premultiply && !t.unassociate;   // (the texel's own colour where both are set)
    for (int y = 0; y < h; ++y) {                                  // y counted from the bottom: v = (y + 0.5) / h
        D3 r0, rc1, rs1, rc2, rs2;
        for (int x = 0; x < w; ++x) {
            const Vec3 r = color_of(t, img.texel(x, y, true, premultiply));
            const size_t k = size_t(x);
            r0.add(r, a0[k]);
            rc1.add(r, ac1[k]);
            rs1.add(r, as1[k]);
            rc2.add(r, ac2[k]);
            rs2.add(r, as2[k]);
        }
        const double za = std::sin((double(y) / h - 0.5) * kPi), zb = std::sin((double(y + 1) / h - 0.5) * kPi);
        auto band = [&](auto f) { return f(zb) - f(za); };
        L[0].add(r0, kY0 * (zb - za));
        L[1].add(rs1, kY1 * band(s1));
        L[2].add(r0, kY1 * band(z1));
        L[3].add(rc1, kY1 * band(s1));
        L[4].add(rs2, kY2 * 0.5 * band(s2));                    // xy = s^2 sin(2 phi) / 2
        L[5].add(rs1, kY2 * band(zs));
        L[6].add(r0, kY20 * band(q));
        L[7].add(rc1, kY2 * band(zs));
        L[8].add(rc2, kY22 * band(s2));                         // x^2 - y^2 = s^2 cos(2 phi)
    }
    // E / pi = sum over l of (A_l / pi) L_lm Y_lm, A_l / pi = 1, 2/3, 1/4; the
    // basis constants are folded in so that at() multiplies by plain monomials.
    const double basis[9] = {kY0, kY1, kY1, kY1, kY2, kY2, kY20, kY2, kY22};
    const double order[9] = {1, 2.0 / 3, 2.0 / 3, 2.0 / 3, 0.25, 0.25, 0.25, 0.25, 0.25};
    Irradiance out;
    for (int i = 0; i < 9; ++i) {
        D3 v;
        v.add(L[i], basis[i] * order[i] * strength);
        out.c[i] = v.f();
    }
    return out;
}

}  // namespace gw
