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
// nothing; an axis whose bounds a NaN coordinate enters separates nothing
// either (its comparisons are false). (Scene refuses non-finite corners.)
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
        // An axis along a box axis (or zero: a degenerate triangle, or an edge
        // along that axis) separates nothing the caller's cell range has not:
        // skipped. For a triangle in a plane of the box axes (floors, walls,
        // boxes) that leaves its three edges' normals in that plane, a 2D test.
        auto keep = [&](double x, double y, double z, double lo, double hi) {
            double* u = u_[j];
            u[0] = x; u[1] = y; u[2] = z;
            const double r = std::abs(x) * half[0] + std::abs(y) * half[1] + std::abs(z) * half[2];
            const double slack = 1e-12 * (std::abs(x) + std::abs(y) + std::abs(z)) * mag;
            lo_[j] = lo - r - slack;
            hi_[j] = hi + r + slack;
            ++j;
        };
        // The normal, the most selective, first. All three corners are
        // projected: a computed normal need not be exactly perpendicular to
        // the triangle (a sliver's is mostly rounding).
        {
            const double x = e[0][1] * e[1][2] - e[0][2] * e[1][1], y = e[0][2] * e[1][0] - e[0][0] * e[1][2],
                         z = e[0][0] * e[1][1] - e[0][1] * e[1][0];
            if (int(x != 0) + int(y != 0) + int(z != 0) >= 2) {
                const double p0 = x * v[0][0] + y * v[0][1] + z * v[0][2];
                const double p1 = x * v[1][0] + y * v[1][1] + z * v[1][2];
                const double p2 = x * v[2][0] + y * v[2][1] + z * v[2][2];
                keep(x, y, z, std::min(p0, std::min(p1, p2)), std::max(p0, std::max(p1, p2)));
            }
        }
        // Edge i (corner i to corner i + 1) crossed with box axis k: zero
        // along k, and (e_q, -e_p) along the other two axes p, q. Its two
        // components are the edge's own, so it is exactly perpendicular to the
        // edge as computed, and the edge's corners project alike up to double
        // rounding of the edge (far inside the slack): its first corner and
        // the opposite one bound the triangle.
        for (int i = 0; i < 3; ++i) {
            const double* s = v[i];
            const double* o = v[(i + 2) % 3];
            for (int k = 0; k < 3; ++k) {
                const int p = (k + 1) % 3, q = (k + 2) % 3;
                const double up = e[i][q], uq = -e[i][p];
                if (up == 0 || uq == 0) continue;
                const double ps = up * s[p] + uq * s[q], po = up * o[p] + uq * o[q];
                double u[3];
                u[k] = 0;
                u[p] = up;
                u[q] = uq;
                // (po NaN, the opposite corner's: these give NaN, so the axis
                // separates nothing; std::min and std::max would give ps.)
                keep(u[0], u[1], u[2], ps < po ? ps : po, ps > po ? ps : po);
            }
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
