// Whether a primitive meets an axis-aligned box, for listing primitives in the
// grid cells they really touch rather than in every cell of their bounding
// box (a sloped or diagonal triangle's box holds many cells it never enters).
// Conservative: a false answer means the primitive stays clear of the box
// by more than double-precision rounding; callers pad the box for float's.
#pragma once
#include <cmath>

#include "math.h"

namespace gw {

// Separating-axis test of a triangle against boxes of one size (a grid's
// cells, padded), set up once per triangle and then asked per box centre.
// The box's own three axes are left to the caller (a grid's cell range from
// the triangle's bounds is that test); the others are the triangle's normal
// and the nine cross products of its edges with the box axes. Along each
// axis u the triangle's corners project onto [min u.v, max u.v], and the box
// centred at m reaches u.m +- r(u) with r(u) = sum |u_k| half_k; they are
// apart when u.m falls outside [min - r, max + r]. Those bounds are widened
// for double rounding (relative to the coordinates' magnitude), so a false
// answer is certain. Degenerate triangles have zero axes, which separate
// nothing; NaN corners make every comparison false: "meets".
class TriangleBoxTest {
public:
    TriangleBoxTest(const Vec3& a, const Vec3& b, const Vec3& c, const double half[3]) {
        const double v[3][3] = {{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}};
        double e[3][3], mag = 0;
        for (int k = 0; k < 3; ++k) {
            e[0][k] = v[1][k] - v[0][k];
            e[1][k] = v[2][k] - v[1][k];
            e[2][k] = v[0][k] - v[2][k];
            mag = std::max(mag, half[k]);
            for (int i = 0; i < 3; ++i) mag = std::max(mag, std::abs(v[i][k]));
        }
        int j = 0;
        auto add = [&](double x, double y, double z) {
            // An axis along a box axis (or zero: a degenerate triangle, or an
            // edge along that axis) separates nothing the caller's cell range
            // has not: skipped. For a triangle in a plane of the box axes
            // (floors, walls, boxes) that leaves its three edges' normals in
            // that plane, a 2D test.
            if (int(x != 0) + int(y != 0) + int(z != 0) <= 1) return;
            double* u = u_[j];
            u[0] = x; u[1] = y; u[2] = z;
            const double p0 = x * v[0][0] + y * v[0][1] + z * v[0][2];
            const double p1 = x * v[1][0] + y * v[1][1] + z * v[1][2];
            const double p2 = x * v[2][0] + y * v[2][1] + z * v[2][2];
            const double norm1 = std::abs(x) + std::abs(y) + std::abs(z);
            const double r = std::abs(x) * half[0] + std::abs(y) * half[1] + std::abs(z) * half[2];
            const double slack = 1e-12 * norm1 * mag;
            lo_[j] = std::min(p0, std::min(p1, p2)) - r - slack;
            hi_[j] = std::max(p0, std::max(p1, p2)) + r + slack;
            ++j;
        };
        add(e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
            e[0][0] * e[1][1] - e[0][1] * e[1][0]);   // the normal: the most selective, first
        for (int i = 0; i < 3; ++i) {   // e x X = (0, e_z, -e_y), e x Y = (-e_z, 0, e_x), e x Z = (e_y, -e_x, 0)
            add(0, e[i][2], -e[i][1]);
            add(-e[i][2], 0, e[i][0]);
            add(e[i][1], -e[i][0], 0);
        }
        axes_ = j;
    }

    // Whether the triangle meets the box of the constructor's half sizes centred at m.
    bool meets(const double m[3]) const {
        return axes_ == 10 ? meets_along<10>(m) : meets_along(m, axes_);   // (all ten: the loop unrolled)
    }

private:
    template <int N = 0>
    bool meets_along(const double m[3], int count = N) const {
        for (int j = 0; j < (N ? N : count); ++j) {
            const double c = u_[j][0] * m[0] + u_[j][1] * m[1] + u_[j][2] * m[2];
            if (c < lo_[j] || c > hi_[j]) return false;
        }
        return true;
    }

    double u_[10][3], lo_[10], hi_[10];
    int axes_;
};

// Whether a sphere meets the box of half sizes `half` centred at m: its centre
// lies within its radius of the box (the radius widened a little, as the
// sphere's own bounds are rounded outwards, and for double rounding).
inline bool sphere_meets_box(const Vec3& center, float radius, const double m[3], const double half[3]) {
    double d2 = 0, mag = std::abs(double(radius));
    for (int k = 0; k < 3; ++k) {
        const double gap = std::max(std::abs(double(center[k]) - m[k]) - half[k], 0.0);
        d2 += gap * gap;
        mag = std::max(mag, std::abs(m[k]) + half[k]);
    }
    const double r = std::abs(double(radius)) * (1 + 1e-6) + 1e-12 * mag;
    return !(d2 > r * r);
}

}  // namespace gw
