// Axis-aligned bounding boxes.
#pragma once
#include "math.h"

namespace gw {

struct Bounds {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    void grow(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void grow(const Bounds& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return !(lo.x <= hi.x); }
};

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
