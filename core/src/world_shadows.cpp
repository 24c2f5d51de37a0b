#include "world_shadows.h"

#include <algorithm>
#include <cmath>

#include "sampler.h"

namespace gw {
namespace {

size_t pick(const double* cdf, size_t n, double u) {
    return std::min(size_t(std::upper_bound(cdf, cdf + n, u) - cdf), n - 1);
}

}  // namespace

WorldMap::WorldMap(const RadianceMap& radiance) {
    w_ = radiance.w;
    h_ = radiance.h;
    rgb_ = radiance.rgb;
    lum_.resize(radiance.rgb.size());
    for (size_t k = 0; k < lum_.size(); ++k) {
        const Vec3& c = radiance.rgb[k];
        lum_[k] = std::max(0.0f, 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z);
    }
    // The coarse texels' shares: luminance x solid angle.
    rows_.assign(size_t(h_), 0.0);
    cols_.assign(lum_.size(), 0.0);
    for (int y = 0; y < h_; ++y) {
        double z0, z1;
        elevation_band(y, h_, z0, z1);
        const double omega = (z1 - z0) * 2 * kPi / w_;
        double run = 0;
        for (int x = 0; x < w_; ++x) {
            if (lum_[size_t(y) * size_t(w_) + size_t(x)] > 0) solid_angle_ += omega;
            run += double(lum_[size_t(y) * size_t(w_) + size_t(x)]) * omega;
            cols_[size_t(y) * size_t(w_) + size_t(x)] = run;
        }
        rows_[size_t(y)] = run;
        total_ += run;
        if (run > 0)
            for (int x = 0; x < w_; ++x) cols_[size_t(y) * size_t(w_) + size_t(x)] /= run;
    }
    if (!(total_ > 0) || !std::isfinite(total_)) {
        total_ = 0;
        return;
    }
    double run = 0;
    for (int y = 0; y < h_; ++y) {
        run += rows_[size_t(y)];
        rows_[size_t(y)] = run / total_;
    }
    rows_.back() = 1.0;
}

Vec3 WorldMap::sample(float u1, float u2) const {
    // A row by its share, then a column within it; u1 and u2 rescaled within
    // the picks place the direction uniformly in the texel's solid angle.
    const size_t y = pick(rows_.data(), rows_.size(), double(u1));
    const double r0 = y ? rows_[y - 1] : 0.0, r1 = rows_[y];
    const double a = std::min(std::max((double(u1) - r0) / std::max(r1 - r0, 1e-300), 0.0), 1.0);
    const double* row = &cols_[y * size_t(w_)];
    const size_t x = pick(row, size_t(w_), double(u2));
    const double c0 = x ? row[x - 1] : 0.0, c1 = row[x];
    const double b = std::min(std::max((double(u2) - c0) / std::max(c1 - c0, 1e-300), 0.0), 1.0);
    double z0, z1;
    elevation_band(int(y), h_, z0, z1);
    const double z = z0 + (z1 - z0) * a;
    const double u = (double(x) + b) / w_;
    const double phi = (0.5 - u) * 2 * kPi;                     // equirect_uv's longitude
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    return Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
}

size_t WorldMap::cell(const Vec3& d) const {
    float u, v;
    equirect_uv(d, u, v);
    const int x = std::min(std::max(int(u * float(w_)), 0), w_ - 1);
    const int y = std::min(std::max(int(v * float(h_)), 0), h_ - 1);
    return size_t(y) * size_t(w_) + size_t(x);
}

float WorldMap::pdf(const Vec3& d) const { return empty() ? 0.0f : float(double(lum_[cell(d)]) / total_); }

Vec3 WorldMap::radiance(const Vec3& d) const { return rgb_.empty() ? Vec3() : rgb_[cell(d)]; }

Vec3 cosine_direction(const Vec3& n, float u1, float u2) {
    float x, y;
    concentric_disk(u1, u2, x, y);
    Vec3 t, b;
    basis(n, t, b);
    return normalize(t * x + b * y + n * std::sqrt(std::max(0.0f, 1.0f - x * x - y * y)));
}

}  // namespace gw
