// Axis-aligned bounding boxes.
#pragma once
#include <cstring>
#include "math.h"

namespace gw {

struct Bounds {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    void grow(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void grow(const Bounds& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return !(lo.x <= hi.x); }
};

// The box of n points (x, y, z floats in a row): four points, twelve floats, at
// a time in three lanes of four (each lane sees every axis in turn), then the
// lanes gathered per axis. The same extremes as a point-by-point pass (where
// +0 and -0 tie for one, either may be kept: they compare equal everywhere the
// box is used).
inline Bounds bounds_of(const Vec3* points, size_t n) {
    typedef float F4 __attribute__((vector_size(16)));
    const float* f = &points[0].x;
    const size_t groups = n / 4;
    F4 lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = F4{} + kInf, hi[k] = F4{} - kInf;
    for (size_t g = 0; g < groups; ++g)
        for (int k = 0; k < 3; ++k) {
            F4 v;
            std::memcpy(&v, f + 12 * g + 4 * k, sizeof v);
            lo[k] = v < lo[k] ? v : lo[k];
            hi[k] = v > hi[k] ? v : hi[k];
        }
    Bounds b;
    for (int k = 0; k < 3; ++k)
        for (int lane = 0; lane < 4; ++lane) {
            const int axis = (4 * k + lane) % 3;
            b.lo[axis] = std::min(b.lo[axis], lo[k][lane]);
            b.hi[axis] = std::max(b.hi[axis], hi[k][lane]);
        }
    for (size_t i = 4 * groups; i < n; ++i) b.grow(points[i]);
    return b;
}

// The box b grown as the adaptive grid pads its root, in double: by 1e-5 of
// its size (at least 1e-6 of its coordinates' magnitude, and 1e-12, so that a
// point scene has a size) and by 1e-6 of each coordinate. Rays that the float
// tests may hit within their rounding lie inside it.
inline void padded_box(const Bounds& b, double lo[3], double hi[3]) {
    double maxext = 0, mag = 0;
    for (int a = 0; a < 3; ++a) {
        maxext = std::max(maxext, double(b.hi[a]) - double(b.lo[a]));
        mag = std::max(mag, std::max(std::abs(double(b.lo[a])), std::abs(double(b.hi[a]))));
    }
    const double pad = 1e-5 * std::max(std::max(maxext, mag * 1e-6), 1e-12);
    for (int a = 0; a < 3; ++a) {
        lo[a] = double(b.lo[a]) - pad - std::abs(double(b.lo[a])) * 1e-6;
        hi[a] = double(b.hi[a]) + pad + std::abs(double(b.hi[a])) * 1e-6;
    }
}

}  // namespace gw
