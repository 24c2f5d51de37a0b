#include "irradiance.h"

#include <algorithm>
#include <cmath>

namespace gw {
namespace {

constexpr int kNormalW = 64, kNormalH = 32;

Vec3 grid_direction(int x, int y, int w, int h) {
    const double phi = (0.5 - (x + 0.5) / w) * 2 * kPi;   // equirect_uv: u = 0.5 along +X, 0.25 along +Y
    const double e = ((y + 0.5) / h - 0.5) * kPi;
    return Vec3(float(std::cos(e) * std::cos(phi)), float(std::cos(e) * std::sin(phi)), float(std::sin(e)));
}

// Cells of `w` x `h` holding the mean of values given on a finer grid of the
// same layout (each fine value at its centre, weighted by its solid angle).
template <class Value>
RadianceMap average(int fine_w, int fine_h, int w, int h, Value value) {
    RadianceMap out;
    out.w = w;
    out.h = h;
    std::vector<Vec3d> sum(size_t(w) * size_t(h));
    std::vector<double> weight(sum.size(), 0.0);
    for (int y = 0; y < fine_h; ++y) {
        double z0, z1;
        elevation_band(y, fine_h, z0, z1);
        const double omega = (z1 - z0) * 2 * kPi / fine_w;
        const size_t row = size_t((y + 0.5) * h / fine_h) * size_t(w);
        for (int x = 0; x < fine_w; ++x) {
            const size_t k = row + size_t((x + 0.5) * w / fine_w);
            const Vec3 c = value(x, y);
            sum[k] = sum[k] + Vec3d(c) * omega;
            weight[k] += omega;
        }
    }
    out.rgb.resize(sum.size());
    for (size_t k = 0; k < sum.size(); ++k) out.rgb[k] = weight[k] > 0 ? Vec3(sum[k] / weight[k]) : Vec3();
    return out;
}

}  // namespace

void elevation_band(int y, int h, double& z0, double& z1) {
    z0 = std::sin((double(y) / h - 0.5) * kPi);
    z1 = std::sin((double(y + 1) / h - 0.5) * kPi);
}

double RadianceMap::solid_angle(int y) const {
    double z0, z1;
    elevation_band(y, h, z0, z1);
    return (z1 - z0) * 2 * kPi / w;
}

Vec3 RadianceMap::direction(int x, int y) const { return grid_direction(x, y, w, h); }

RadianceMap radiance_map(const Image& img, const Texture& t, float strength, int max_w) {
    const bool premultiply = t.premultiply && !t.unassociate;   // (the texel's own colour where both are set)
    // An image of fewer than 64 x 32 texels is read as if it had that many,
    // each texel repeated over the part of the sphere it covers, so that the
    // cells still resolve elevation: the one row of cells of an image one
    // texel tall (a strip, or the 1 x 1 stand-in for a missing image) lay on
    // the horizon, no cell lay above a floor, and the floor got no world light.
    const int fine_w = std::max(img.width(), kNormalW), fine_h = std::max(img.height(), kNormalH);
    return average(fine_w, fine_h, std::min(fine_w, max_w), std::min(fine_h, max_w / 2), [&](int x, int y) {
        const int ix = int(int64_t(x) * img.width() / fine_w), iy = int(int64_t(y) * img.height() / fine_h);
        return color_of(t, img.texel(ix, iy, true, premultiply)) * strength;
    });
}

RadianceMap coarser(const RadianceMap& map, int max_w) {
    return average(map.w, map.h, std::min(map.w, max_w), std::min(map.h, max_w / 2),
                   [&](int x, int y) { return map.rgb[size_t(y) * size_t(map.w) + size_t(x)]; });
}

bool split_bright(RadianceMap& map, RadianceMap& bright) {
    auto lum = [](const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    double power = 0;
    for (int y = 0; y < map.h; ++y)
        for (int x = 0; x < map.w; ++x) power += lum(map.rgb[size_t(y) * size_t(map.w) + size_t(x)]) * map.solid_angle(y);
    const double threshold = 20 * power / (4 * kPi);
    bright = map;
    bool any = false;
    for (size_t k = 0; k < map.rgb.size(); ++k) {
        const bool sun = threshold > 0 && lum(map.rgb[k]) > threshold;
        any = any || sun;
        (sun ? map.rgb[k] : bright.rgb[k]) = Vec3();
    }
    return any;
}

Irradiance::Irradiance(const RadianceMap& radiance) {
    // The cells' directions, radiance x solid angle and solid angle, once.
    const size_t n = radiance.rgb.size();
    std::vector<Vec3> dir(n), weighted(n);
    std::vector<float> omega(n);
    for (int y = 0; y < radiance.h; ++y)
        for (int x = 0; x < radiance.w; ++x) {
            const size_t k = size_t(y) * size_t(radiance.w) + size_t(x);
            dir[k] = radiance.direction(x, y);
            omega[k] = float(radiance.solid_angle(y));
            weighted[k] = radiance.rgb[k] * omega[k];
        }
    auto integrate = [&](const Vec3& normal) {
        Vec3d lit;
        double cosines = 0;
        for (size_t k = 0; k < n; ++k) {
            const float c = dot(normal, dir[k]);
            if (c <= 0) continue;
            lit = lit + Vec3d(weighted[k]) * double(c);
            cosines += double(c) * omega[k];
        }
        return cosines > 0 ? Vec3(lit / cosines) : Vec3();
    };
    e_.resize(size_t(kNormalW) * size_t(kNormalH));
    for (int y = 0; y < kNormalH; ++y)
        for (int x = 0; x < kNormalW; ++x) e_[size_t(y) * kNormalW + size_t(x)] = integrate(grid_direction(x, y, kNormalW, kNormalH));
    south_ = integrate(Vec3(0, 0, -1));
    north_ = integrate(Vec3(0, 0, 1));
}

Vec3 Irradiance::at(const Vec3& n) const {
    float u, v;
    equirect_uv(n, u, v);
    // Bilinear between the four nearest normals, wrapping in longitude;
    // beyond the first and last rows' centres, towards the pole's own value.
    const float fx = u * kNormalW - 0.5f, fy = v * kNormalH - 0.5f;
    const float x0f = std::floor(fx), tx = fx - x0f;
    const int x0 = ((int(x0f) % kNormalW) + kNormalW) % kNormalW, x1 = (x0 + 1) % kNormalW;
    auto row = [&](int y) {
        const Vec3* r = &e_[size_t(y) * kNormalW];
        return r[x0] * (1 - tx) + r[x1] * tx;
    };
    if (fy <= 0) return row(0) + (south_ - row(0)) * std::min(-fy * 2.0f, 1.0f);
    if (fy >= float(kNormalH - 1)) {
        const Vec3 last = row(kNormalH - 1);
        return last + (north_ - last) * std::min((fy - float(kNormalH - 1)) * 2.0f, 1.0f);
    }
    const int y0 = int(std::floor(fy));
    const float ty = fy - float(y0);
    return row(y0) * (1 - ty) + row(y0 + 1) * ty;
}

}  // namespace gw
