// Tangents for normal maps. See tangents.h.
#include "tangents.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "math.h"

namespace gw {
namespace {

// What makes corners share a tangent: the vertex, the UV there (bit for bit)
// and the orientation of the UV map on the triangle.
struct CornerKey {
    int32_t vertex;
    uint32_t u, v;
    bool mirrored;
    bool operator<(const CornerKey& o) const {
        if (vertex != o.vertex) return vertex < o.vertex;
        if (u != o.u) return u < o.u;
        if (v != o.v) return v < o.v;
        return mirrored < o.mirrored;
    }
    bool operator==(const CornerKey& o) const {
        return vertex == o.vertex && u == o.u && v == o.v && mirrored == o.mirrored;
    }
};

uint32_t bits(float x) {
    if (x == 0) x = 0;   // -0 and +0 are one UV
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

Vec3d at(const PooledVector<float>& a, size_t i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }

Vec3d along_plane(const Vec3d& t, const Vec3d& n) { return t - n * dot(n, t); }

}  // namespace

std::vector<float> corner_tangents(const PooledVector<float>& verts, const PooledVector<int32_t>& tris,
                                   const PooledVector<float>& normals, const PooledVector<float>& uvs) {
    const size_t nt = tris.size() / 3;
    std::vector<float> out(12 * nt, 0.0f);
    std::vector<Vec3d> face_t(nt), face_n(nt);   // dp/du (zero where the UVs have no area), the unit face normal
    std::vector<CornerKey> keys(3 * nt);
    std::vector<double> weight(3 * nt);          // the corner's angle (MikkTSpace weighs by it)
    for (size_t t = 0; t < nt; ++t) {
        const Vec3d p0 = at(verts, size_t(tris[3 * t])), p1 = at(verts, size_t(tris[3 * t + 1])),
                    p2 = at(verts, size_t(tris[3 * t + 2]));
        const float* uv = &uvs[6 * t];
        const Vec3d e1 = p1 - p0, e2 = p2 - p0;
        const double du1 = double(uv[2]) - uv[0], dv1 = double(uv[3]) - uv[1];
        const double du2 = double(uv[4]) - uv[0], dv2 = double(uv[5]) - uv[1];
        const double det = du1 * dv2 - du2 * dv1;
        const Vec3d n = cross(e1, e2);
        const double nl = length(n);
        face_n[t] = nl > 0 ? n * (1.0 / nl) : Vec3d(0, 0, 0);
        Vec3d dpdu(0, 0, 0), dpdv(0, 0, 0);
        if (det != 0 && std::isfinite(det)) {
            dpdu = (e1 * dv2 - e2 * dv1) * (1.0 / det);
            dpdv = (e2 * du1 - e1 * du2) * (1.0 / det);
        }
        face_t[t] = dpdu;
        const bool mirrored = dot(cross(face_n[t], dpdu), dpdv) < 0;
        const Vec3d p[3] = {p0, p1, p2};
        for (int j = 0; j < 3; ++j) {
            keys[3 * t + j] = {tris[3 * t + j], bits(uv[2 * j]), bits(uv[2 * j + 1]), mirrored};
            const Vec3d a = p[(j + 1) % 3] - p[j], b = p[(j + 2) % 3] - p[j];
            const double la = length(a), lb = length(b);
            weight[3 * t + j] = la > 0 && lb > 0 ? std::acos(std::clamp(dot(a, b) / (la * lb), -1.0, 1.0)) : 0.0;
        }
    }
    // Corners grouped by key; each group's tangent is the angle-weighted sum
    // of its triangles' dp/du in the plane of the corner's normal.
    std::vector<uint32_t> order(3 * nt);
    for (size_t i = 0; i < order.size(); ++i) order[i] = uint32_t(i);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    for (size_t lo = 0; lo < order.size();) {
        size_t hi = lo + 1;
        while (hi < order.size() && keys[order[hi]] == keys[order[lo]]) ++hi;
        const size_t first = order[lo];
        const Vec3d n = normals.empty() ? face_n[first / 3] : at(normals, size_t(keys[first].vertex));
        Vec3d sum(0, 0, 0);
        for (size_t k = lo; k < hi; ++k) {
            const size_t c = order[k];
            const Vec3d nc = normals.empty() ? face_n[c / 3] : n;
            const Vec3d tc = along_plane(face_t[c / 3], nc);
            const double l = length(tc);
            if (l > 0 && std::isfinite(l)) sum += tc * (weight[c] / l);
        }
        const double sl = length(sum);
        for (size_t k = lo; k < hi; ++k) {
            const size_t c = order[k];
            // (Flat triangles, without vertex normals, keep their own tangent:
            // their normals differ across the vertex.)
            Vec3d tc = sum;
            double l = sl;
            if (normals.empty()) {
                tc = along_plane(face_t[c / 3], face_n[c / 3]);
                l = length(tc);
            }
            if (!(l > 0) || !std::isfinite(l)) continue;
            tc = tc * (1.0 / l);
            float* o = &out[4 * c];
            o[0] = float(tc.x);
            o[1] = float(tc.y);
            o[2] = float(tc.z);
            o[3] = keys[c].mirrored ? -1.0f : 1.0f;
        }
        lo = hi;
    }
    return out;
}

}  // namespace gw
