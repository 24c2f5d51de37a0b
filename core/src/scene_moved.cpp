// Scene::moved: the next version of a scene whose instances moved (a
// viewport's transform edit), made in the core from the instances' object-space
// arrays, so that the scene's arrays need not be assembled in Python and copied
// in again.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

#include "affine.h"
#include "scene.h"

namespace gw {
namespace {

[[noreturn]] void bad_move(size_t i, const std::string& what) {
    throw std::invalid_argument("moves[" + std::to_string(i) + "]: " + what);
}

struct Range {
    size_t begin, end;
    bool operator<(const Range& o) const { return begin < o.begin; }
};

// Sorts the ranges; false when two overlap.
bool disjoint(std::vector<Range>& r) {
    std::sort(r.begin(), r.end());
    for (size_t i = 1; i < r.size(); ++i)
        if (r[i].begin < r[i - 1].end) return false;
    return true;
}

bool inside(const std::vector<Range>& sorted, size_t x) {
    auto it = std::upper_bound(sorted.begin(), sorted.end(), Range{x, x});
    return it != sorted.begin() && x < std::prev(it)->end;
}

Vec3d point_at(const std::vector<float>& xyz, size_t i) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }

// The map of object-space normals to world space, as the exporter's
// normal_matrix (blender_addon/export/_matrix.py) computes it: the inverse
// transpose of the linear part (the cofactors over the determinant), or its
// cofactor matrix where it cannot be inverted (an object scaled to zero along
// an axis: the cofactors map its normals as they map its edges' cross
// products, along the flattened surface's normal).
Affine normal_map(const Affine& a) {
    Affine out = a;
    // Row r of the cofactor matrix: the cross product of the other two rows, in cyclic order.
    double cof[3][3];
    for (int r = 0; r < 3; ++r) {
        const double* p = a.m[(r + 1) % 3];
        const double* q = a.m[(r + 2) % 3];
        cof[r][0] = p[1] * q[2] - p[2] * q[1];
        cof[r][1] = p[2] * q[0] - p[0] * q[2];
        cof[r][2] = p[0] * q[1] - p[1] * q[0];
    }
    const double det = a.m[0][0] * cof[0][0] + a.m[0][1] * cof[0][1] + a.m[0][2] * cof[0][2];
    bool invertible = det != 0 && std::isfinite(det);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(cof[r][c] / det)) invertible = false;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out.m[r][c] = invertible ? cof[r][c] / det : cof[r][c];
    return out;
}

// v / |v| rounded to float (v itself when its length is 0).
void store_unit(const Vec3d& v, float* out) {
    const double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    for (int a = 0; a < 3; ++a) out[a] = float(len > 0 ? v[a] / len : v[a]);
}

}  // namespace

std::shared_ptr<Scene> Scene::moved(const std::vector<RigidMove>& moves) const {
    const size_t nv = verts_.size() / 3, nt = num_triangles();
    std::vector<Range> vranges, tranges;
    for (size_t i = 0; i < moves.size(); ++i) {
        const RigidMove& m = moves[i];
        if (m.positions.size() % 3) bad_move(i, "positions must have shape (k, 3)");
        const size_t k = m.positions.size() / 3;
        if (m.vertex_start > nv || k > nv - m.vertex_start)
            bad_move(i, "vertices " + std::to_string(m.vertex_start) + " + " + std::to_string(k) +
                            " lie beyond the scene's " + std::to_string(nv));
        if (m.triangle_start > nt || m.triangle_count > nt - m.triangle_start)
            bad_move(i, "triangles " + std::to_string(m.triangle_start) + " + " + std::to_string(m.triangle_count) +
                            " lie beyond the scene's " + std::to_string(nt));
        if (normals_.empty() && (m.flat || !m.normals.empty()))
            bad_move(i, "the scene has no normals, so a move gives none");
        if (!normals_.empty() && !m.flat && m.normals.size() != m.positions.size())
            bad_move(i, "normals must have the shape of positions (the scene has normals)");
        if (m.flat && !m.normals.empty()) bad_move(i, "a flat instance's normals are its face normals: give none");
        for (const auto& row : m.matrix)
            for (double x : row)
                if (!std::isfinite(x)) bad_move(i, "the matrix has a non-finite value");
        for (size_t j = 0; j < m.positions.size(); ++j)
            if (!std::isfinite(m.positions[j])) bad_move(i, "positions has a non-finite value");
        for (size_t j = 0; j < m.normals.size(); ++j)
            if (!std::isfinite(m.normals[j])) bad_move(i, "normals has a non-finite value");
        // The instance's triangles use its vertices only (flat: its 3 corners each, in order).
        for (size_t t = m.triangle_start; t < m.triangle_start + m.triangle_count; ++t)
            for (int c = 0; c < 3; ++c) {
                const size_t v = size_t(tris_[3 * t + c]);
                const bool ok = m.flat ? v == m.vertex_start + 3 * (t - m.triangle_start) + c
                                       : v >= m.vertex_start && v < m.vertex_start + k;
                if (!ok)
                    bad_move(i, "triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                    (m.flat ? ", not its own corner" : ", outside the instance's vertices"));
            }
        if (m.flat && k != 3 * m.triangle_count) bad_move(i, "a flat instance has 3 vertices per triangle");
        if (k > 0) vranges.push_back({m.vertex_start, m.vertex_start + k});   // (empty ranges overlap nothing)
        if (m.triangle_count > 0) tranges.push_back({m.triangle_start, m.triangle_start + m.triangle_count});
    }
    if (!disjoint(vranges) || !disjoint(tranges)) throw std::invalid_argument("two moves share vertices or triangles");
    // No other triangle may use a moved vertex: its corners would be left behind.
    // (Most corners lie outside the span of the moved vertices: one comparison each.)
    const size_t span_lo = vranges.empty() ? 0 : vranges.front().begin;
    const size_t span_hi = vranges.empty() ? 0 : vranges.back().end;
    size_t next_range = 0;
    for (size_t t = 0; t < nt; ++t) {
        while (next_range < tranges.size() && tranges[next_range].end <= t) ++next_range;
        if (next_range < tranges.size() && t >= tranges[next_range].begin) {
            t = tranges[next_range].end - 1;
            continue;
        }
        for (int c = 0; c < 3; ++c)
            if (size_t(tris_[3 * t + c]) >= span_lo && size_t(tris_[3 * t + c]) < span_hi &&
                inside(vranges, size_t(tris_[3 * t + c])))
                throw std::invalid_argument("triangle " + std::to_string(t) + " uses vertex " +
                                            std::to_string(tris_[3 * t + c]) + ", which a move moves");
    }

    auto out = std::make_shared<Scene>(*this);
    out->id_ = next_id();
    out->ancestors_ = ancestors_after(moves);
    out->instances_ = instances_after(moves);
    for (size_t i = 0; i < moves.size(); ++i) {
        out->apply(moves[i], i);
        out->update_tangents(moves[i].triangle_start, moves[i].triangle_count);
    }
    out->compute_bounds(bounds_of(out->tri_verts_.data(), 3 * nt));
    // Emissive triangles are picked in proportion to their areas, which a move
    // changes (by rounding if it is rigid): weighed again, as a scene built
    // from these arrays weighs them, so that the two render the same image to
    // the bit. (The copied weights rendered up to 2e-8 off it.)
    if (!emitters_.empty()) out->emitters_ = Emitters(out->tri_verts_, out->tri_mat_, out->materials_);
    return out;
}

// The declared instances (set_instances) of the scene after `moves`: one that a
// move moves whole takes the move's matrix, where it now is; one that a move
// cuts into is forgotten. (Each is checked against its mesh again where it is
// used: instanced_grid.cpp.)
std::vector<SceneInstance> Scene::instances_after(const std::vector<RigidMove>& moves) const {
    std::vector<std::pair<size_t, size_t>> starts;   // (triangle_start, move), by start
    for (size_t i = 0; i < moves.size(); ++i)
        if (moves[i].triangle_count > 0) starts.emplace_back(moves[i].triangle_start, i);
    std::sort(starts.begin(), starts.end());
    std::vector<SceneInstance> out;
    out.reserve(instances_.size());
    for (SceneInstance in : instances_) {
        const size_t b = in.triangle_start, e = b + in.triangle_count;
        // The moves are disjoint: those meeting [b, e) follow the last one starting at or before b.
        auto it = std::upper_bound(starts.begin(), starts.end(), std::make_pair(b, moves.size()));
        if (it != starts.begin()) --it;
        bool keep = true;
        for (; it != starts.end() && it->first < e && keep; ++it) {
            const RigidMove& m = moves[it->second];
            if (m.triangle_start + m.triangle_count <= b) continue;
            if (m.triangle_start == b && m.triangle_count == in.triangle_count)
                std::copy(&m.matrix[0][0], &m.matrix[0][0] + 16, &in.matrix[0][0]);
            else
                keep = false;
        }
        if (keep) out.push_back(in);
    }
    return out;
}

// Whether the move's previous matrix maps its positions onto the instance's
// vertices in this scene (checked on up to 64 of them, to a few ulps): a grid
// followed through a wrong map would miss the instance.
bool Scene::where_it_was(const RigidMove& m) const {
    const size_t k = m.positions.size() / 3, step = std::max<size_t>(1, k / 64);
    for (size_t v = 0; v < k; v += step) {
        const Vec3d p = Affine::from_rows(m.previous_matrix).point(point_at(m.positions, v));
        for (int a = 0; a < 3; ++a) {
            const double here = verts_[3 * (m.vertex_start + v) + a];
            if (!(std::abs(p[a] - here) <= 4.0 * 0x1p-23 * std::max(std::abs(p[a]), std::abs(here)) + 1e-30))
                return false;
        }
    }
    return true;
}

uint64_t Scene::next_id() {
    static std::atomic<uint64_t> counter{0};
    return ++counter;
}

namespace {
// Composes one step (a move's previous world -> new world) into `moved`, the
// instances moved since some ancestor; false when the move straddles an
// instance moved before (then that ancestor cannot serve).
bool compose(std::vector<InstanceDelta>& moved, size_t b, size_t e, const Affine& step) {
    auto it = std::find_if(moved.begin(), moved.end(),
                           [&](const InstanceDelta& d) { return d.triangle_start < e && b < d.triangle_end; });
    Affine total = step;
    if (it != moved.end()) {
        if (it->triangle_start != b || it->triangle_end != e) return false;
        total = step.after(Affine::from_rows(it->from_ancestor));
    } else {
        it = moved.insert(moved.end(), InstanceDelta{b, e, {}});
    }
    std::copy(&total.m[0][0], &total.m[0][0] + 12, &it->from_ancestor[0][0]);
    return true;
}
}  // namespace

// This scene's ancestors, and this scene, followed by `moves`. None when a move
// has no previous matrix or its map cannot be inverted (the moved scene is then
// as if built from arrays); an ancestor is dropped when a move straddles one
// of its moved instances or more than kMaxMovedInstances have moved since it.
std::vector<SceneAncestor> Scene::ancestors_after(const std::vector<RigidMove>& moves) const {
    std::vector<std::pair<Range, Affine>> steps;
    for (const RigidMove& m : moves) {
        Affine back;
        if (!m.has_previous || !Affine::from_rows(m.previous_matrix).inverse(back)) return {};
        if (!where_it_was(m)) return {};   // a previous matrix that does not put the instance where it is
        if (m.triangle_count == 0) continue;
        steps.push_back({{m.triangle_start, m.triangle_start + m.triangle_count},
                         Affine::from_rows(m.matrix).after(back)});
    }
    std::vector<SceneAncestor> out;
    std::vector<SceneAncestor> candidates{SceneAncestor{id_, {}}};
    candidates.insert(candidates.end(), ancestors_.begin(), ancestors_.end());
    for (SceneAncestor& a : candidates) {
        bool ok = true;
        for (const auto& [range, step] : steps) ok = ok && compose(a.moved, range.begin, range.end, step);
        if (!ok || a.moved.size() > kMaxMovedInstances) continue;
        std::sort(a.moved.begin(), a.moved.end(),
                  [](const InstanceDelta& x, const InstanceDelta& y) { return x.triangle_start < y.triangle_start; });
        out.push_back(std::move(a));
        if (out.size() == kMaxAncestors) break;
    }
    return out;
}

void Scene::apply(const RigidMove& m, size_t index) {
    const size_t k = m.positions.size() / 3;
    const Affine to_world = Affine::from_rows(m.matrix);
    float* verts = verts_.data() + 3 * m.vertex_start;
    for (size_t v = 0; v < k; ++v) {
        const Vec3d w = to_world.point(point_at(m.positions, v));
        for (int a = 0; a < 3; ++a) verts[3 * v + a] = float(w[a]);
    }
    for (size_t j = 0; j < 3 * k; ++j)
        if (!std::isfinite(verts[j]))
            bad_move(index, "vertex " + std::to_string(m.vertex_start + j / 3) + " is not finite in world space");
    if (m.flat) {
        // Face normals from the corners in double, before their rounding (as the exporter does).
        float* normals = normals_.data() + 3 * m.vertex_start;
        for (size_t t = 0; t < m.triangle_count; ++t) {
            const Vec3d a = to_world.point(point_at(m.positions, 3 * t)),
                        b = to_world.point(point_at(m.positions, 3 * t + 1)),
                        c = to_world.point(point_at(m.positions, 3 * t + 2));
            const Vec3d n = cross(b - a, c - a);
            for (int j = 0; j < 3; ++j) store_unit(n, normals + 9 * t + 3 * j);
        }
    } else if (!m.normals.empty()) {
        const Affine to_world_normal = normal_map(to_world);
        float* normals = normals_.data() + 3 * m.vertex_start;
        for (size_t v = 0; v < k; ++v) store_unit(to_world_normal.vector(point_at(m.normals, v)), normals + 3 * v);
    }
    if (!normals_.empty())
        for (size_t j = 3 * m.vertex_start; j < 3 * (m.vertex_start + k); ++j)
            if (!std::isfinite(normals_[j]))
                bad_move(index, "normal " + std::to_string(j / 3) + " is not finite in world space");
    for (size_t i = 3 * m.triangle_start; i < 3 * (m.triangle_start + m.triangle_count); ++i)
        tri_verts_[i] = vert(tris_[i]);
}

}  // namespace gw
