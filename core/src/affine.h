// Affine maps of 3D space in double: a 3x3 linear part and a translation
// (rows as in Blender's matrices). Used where instances move (Scene::moved,
// moved_grid.h).
#pragma once
#include <algorithm>
#include <cmath>

#include "math.h"

namespace gw {

struct Affine {
    double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    // From a 4x4 matrix (its last row ignored) or the 3x4 rows of one.
    template <int Rows>
    static Affine from_rows(const double (&rows)[Rows][4]) {
        static_assert(Rows == 3 || Rows == 4, "an affine map has 3 rows (and maybe the 4th of a 4x4)");
        Affine a;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) a.m[r][c] = rows[r][c];
        return a;
    }
    Vec3d point(const Vec3d& p) const {
        Vec3d out;
        for (int r = 0; r < 3; ++r) out[r] = m[r][0] * p.x + m[r][1] * p.y + m[r][2] * p.z + m[r][3];
        return out;
    }
    Vec3d vector(const Vec3d& v) const {
        Vec3d out;
        for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v.x + m[r][1] * v.y + m[r][2] * v.z;
        return out;
    }
    // The largest row sum of |linear part| (the infinity norm): |vector(v)|inf <= norm() |v|inf.
    double norm() const {
        double n = 0;
        for (int r = 0; r < 3; ++r) n = std::max(n, std::abs(m[r][0]) + std::abs(m[r][1]) + std::abs(m[r][2]));
        return n;
    }
    // This map after `first`: x -> this(first(x)).
    Affine after(const Affine& first) const {
        Affine out;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                double s = c == 3 ? m[r][3] : 0.0;
                for (int k = 0; k < 3; ++k) s += m[r][k] * first.m[k][c];
                out.m[r][c] = s;
            }
        }
        return out;
    }
    // The inverse map; false when the linear part is singular (or the result not finite).
    bool inverse(Affine& out) const {
        const double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2], g = m[2][0],
                     h = m[2][1], k = m[2][2];
        const double det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g);
        if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
        const double inv[3][3] = {{(e * k - f * h) / det, (c * h - b * k) / det, (b * f - c * e) / det},
                                  {(f * g - d * k) / det, (a * k - c * g) / det, (c * d - a * f) / det},
                                  {(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det}};
        for (int r = 0; r < 3; ++r) {
            double t = 0;
            for (int col = 0; col < 3; ++col) {
                out.m[r][col] = inv[r][col];
                t -= inv[r][col] * m[col][3];
            }
            out.m[r][3] = t;
        }
        for (int r = 0; r < 3; ++r)
            for (int col = 0; col < 4; ++col)
                if (!std::isfinite(out.m[r][col])) return false;
        return true;
    }
};

}  // namespace gw
