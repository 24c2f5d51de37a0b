// Tangents for normal maps. See tangents.h.
#include "tangents.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>

#include "math.h"

namespace gw {
namespace {

// What makes corners share a tangent, as MikkTSpace merges them: the
// position, the normal and the UV there (bit for bit: exporters give a corner
// its own vertex where normals are per corner, custom or split by sharp
// edges) and the orientation of the UV map on the triangle.
struct CornerKey {
    uint32_t p[3], n[3], u, v;
    bool mirrored;
    auto tie() const { return std::tie(p[0], p[1], p[2], n[0], n[1], n[2], u, v, mirrored); }
    bool operator<(const CornerKey& o) const { return tie() < o.tie(); }
    bool operator==(const CornerKey& o) const { return tie() == o.tie(); }
};

uint32_t bits(float x) {
    if (x == 0) x = 0;   // -0 and +0 are one UV
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

Vec3d along_plane(const Vec3d& t, const Vec3d& n) { return t - n * dot(n, t); }

}  // namespace

std::vector<float> corner_tangents(const float* verts, const int32_t* tris, size_t nt, const float* normals,
                                   const float* uvs) {
    std::vector<float> out(12 * nt, 0.0f);
    std::vector<Vec3d> face_t(nt), face_n(nt);   // dp/du (zero where the UVs have no area), the unit face normal
    std::vector<CornerKey> keys(3 * nt);
    std::vector<double> weight(3 * nt);          // the corner's angle (MikkTSpace weighs by it)
    auto vertex = [&](const float* a, int32_t i) { return Vec3d(a[3 * size_t(i)], a[3 * size_t(i) + 1], a[3 * size_t(i) + 2]); };
    for (size_t t = 0; t < nt; ++t) {
        const int32_t* f = tris + 3 * t;
        const Vec3d p[3] = {vertex(verts, f[0]), vertex(verts, f[1]), vertex(verts, f[2])};
        const float* uv = uvs + 6 * t;
        const Vec3d e1 = p[1] - p[0], e2 = p[2] - p[0];
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
        const Vec3d uv_normal = cross(dpdu, dpdv);   // the UV map's orientation on the triangle
        for (int j = 0; j < 3; ++j) {
            // Mirrored: the UV map's orientation against the corner's normal (the
            // vertex normal: outward, where a mirrored object's winding is not), else the face's.
            const Vec3d nc = normals ? vertex(normals, f[j]) : face_n[t];
            CornerKey& k = keys[3 * t + j];
            for (int a = 0; a < 3; ++a) {
                k.p[a] = bits(float(p[j][a]));
                k.n[a] = normals ? bits(normals[3 * size_t(f[j]) + a]) : bits(float(face_n[t][a]));
            }
            k.u = bits(uv[2 * j]);
            k.v = bits(uv[2 * j + 1]);
            k.mirrored = dot(nc, uv_normal) < 0;
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
        const Vec3d n = normals ? vertex(normals, tris[first]) : face_n[first / 3];
        Vec3d sum(0, 0, 0);
        for (size_t k = lo; k < hi; ++k) {
            const size_t c = order[k];
            const Vec3d tc = along_plane(face_t[c / 3], n);
            const double l = length(tc);
            if (l > 0 && std::isfinite(l)) sum += tc * (weight[c] / l);
        }
        const double sl = length(sum);
        if (sl > 0 && std::isfinite(sl))
            for (size_t k = lo; k < hi; ++k) {
                float* o = &out[4 * order[k]];
                o[0] = float(sum.x / sl);
                o[1] = float(sum.y / sl);
                o[2] = float(sum.z / sl);
                o[3] = keys[order[k]].mirrored ? -1.0f : 1.0f;
            }
        lo = hi;
    }
    return out;
}

}  // namespace gw
