// See instanced_grid.h.
#include "instanced_grid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <unordered_map>

#include "bounds.h"
#include "dda.h"
#include "ordered_tasks.h"

namespace gw {

namespace {

// A copy's map may scale by at most this either way: the walks assume
// directions within 2^+-64 (dda.h), and the mapped ray's rounding grows with
// the scale (as for MovedGrid).
constexpr double kMaxScale = 0x1p20;
// How far a copy's corners may lie from its mesh's first copy's under the
// map, relative to their magnitudes: 8 times the host's rounding of each to
// float (half a float spacing, 2^-24 of the magnitude), far below any real
// difference of shape. (2^-18 accepted a 1 mm triangle at 100 with a corner
// moved by 0.7 mm.)
constexpr double kCornerTolerance = 0x1p-21;
// Cells of the grid over the copies, per copy, and the caps on its cells and
// references (its resolution is lowered past them).
constexpr double kCellsPerCopy = 2.0;
constexpr uint64_t kMaxTopCells = uint64_t(1) << 22, kMaxTopRefs = uint64_t(1) << 26;
// A cell of the grid over the copies that lists more than this many is
// crowded: the copies cluster within a few of its cells (a forest with one
// tree 1e5 away), every ray into the cluster would clip them all (4,999
// copies in one cell: 27 us a ray against 0.7 for the flat grid), and the
// flat adaptive grid, which refines where primitives crowd, is built instead.
constexpr uint32_t kCrowdedCell = 256;

double magnitude(const Vec3d& v) { return std::max(std::max(std::abs(v.x), std::abs(v.y)), std::abs(v.z)); }

// The corners of triangles [start, start + count) that first show each of
// their vertices (ids), as offsets from the range's first corner, in order:
// where a copy's triangles list its vertices as its mesh's first copy lists
// its own, shifted by one offset, checking these corners checks them all (a
// corner is its vertex: Scene's triangle_vertices() is vertices[triangles[k]]).
// One pass with a table over the ids' range; empty where that range is more
// than a few times the corners (ids spread out: every corner is checked).
std::vector<uint32_t> first_corners(const int32_t* ids, size_t start, size_t count, const CancelToken* cancel,
                                    uint64_t& step) {
    const int32_t* c = ids + 3 * start;
    const size_t n = 3 * count;
    int32_t lo = c[0], hi = c[0];
    for (size_t k = 1; k < n; ++k) lo = std::min(lo, c[k]), hi = std::max(hi, c[k]);
    check_cancel(cancel, step, n);
    const uint64_t range = uint64_t(int64_t(hi) - int64_t(lo)) + 1;
    std::vector<uint32_t> out;
    if (range > 4 * uint64_t(n) + 64) return out;
    std::vector<uint8_t> seen(range, 0);
    for (size_t k = 0; k < n; ++k) {
        check_cancel(cancel, step);
        uint8_t& s = seen[size_t(int64_t(c[k]) - lo)];
        if (!s) s = 1, out.push_back(uint32_t(k));
    }
    return out;
}

// Whether triangles [start, start + count) are, corner for corner, triangles
// [mesh_start, ...) moved by `to_mesh`'s inverse (to_mesh maps them onto those).
// ids: the scene's vertex ids per corner, or null; corners: first_corners() of
// the mesh's first copy (empty: none). A copy whose ids are its mesh's first
// copy's shifted by one offset (how exporters lay copies out) is checked at
// those corners alone: the same answer, a sixth of the work for a closed mesh.
bool is_copy(const Vec3* tv, const int32_t* ids, const std::vector<uint32_t>& corners, size_t start,
             size_t mesh_start, size_t count, const Affine& to_mesh, const CancelToken* cancel, uint64_t& step) {
    const double scale = to_mesh.norm();
    auto corner_matches = [&](size_t k) {
        const Vec3d here(tv[3 * start + k]), there(tv[3 * mesh_start + k]);
        const Vec3d mapped = to_mesh.point(here);
        const double tol = kCornerTolerance * (magnitude(there) + scale * magnitude(here)) + 1e-30;
        return magnitude(mapped - there) <= tol;
    };
    if (ids && !corners.empty()) {
        const int32_t* a = ids + 3 * start;
        const int32_t* b = ids + 3 * mesh_start;
        const int64_t offset = int64_t(a[0]) - int64_t(b[0]);
        bool shifted = true;
        for (size_t k = 0; k < 3 * count; ++k) shifted &= int64_t(a[k]) - int64_t(b[k]) == offset;
        check_cancel(cancel, step, 3 * uint64_t(count));
        if (shifted) {
            for (uint32_t k : corners) {
                check_cancel(cancel, step);
                if (!corner_matches(k)) return false;
            }
            return true;
        }
    }
    for (size_t k = 0; k < 3 * count; ++k) {
        check_cancel(cancel, step);
        if (!corner_matches(k)) return false;
    }
    return true;
}

// Whether copies of `copied` triangles make the instanced grid worth it in a
// scene of `prims` primitives (InstancedGrid::build).
bool pays(size_t copied, size_t prims, bool always) {
    return copied > 0 && (always || (2 * copied >= prims && copied >= InstancedGrid::kAutoTriangles));
}

// Ray::after in a part's own numbering, whose primitive k is the scene's first + k (k < count).
int32_t after_in(int32_t after, uint32_t first, uint32_t count) {
    if (after < int32_t(first)) return -1;   // (none, or every primitive of the part comes after it)
    return uint32_t(after) - first >= count ? int32_t(count) : int32_t(uint32_t(after) - first);
}

}  // namespace

std::shared_ptr<const Accel> InstancedGrid::build(std::shared_ptr<const Scene> scene, const AdaptiveParams& p,
                                                  const CancelToken* cancel, bool always) {
    const auto t_start = std::chrono::steady_clock::now();
    const std::vector<SceneInstance>& declared = scene->instances();
    if (declared.size() < 2) return nullptr;
    std::shared_ptr<InstancedGrid> g(new InstancedGrid(scene));
    const Vec3* tv = scene->triangle_vertices();
    uint64_t step = 0;

    // Each mesh's first copy (in declaration order) stays in the rest; the
    // others that check out become copies (checked on p.threads threads).
    // (Mesh ids are any non-negative int32: hashed, not indexed.)
    std::unordered_map<int32_t, size_t> first_of;   // declared mesh id -> its first copy's index in declared
    std::unordered_map<int32_t, size_t> grid_of;    // declared mesh id -> index into meshes_
    std::vector<int32_t> mesh_ids;                  // per meshes_ entry: its declared id
    std::vector<std::pair<size_t, Affine>> candidates;   // (declared index, map to its mesh's first copy)
    size_t copied = 0, refused = 0;
    for (size_t i = 0; i < declared.size(); ++i) {
        const SceneInstance& in = declared[i];
        if (in.triangle_count == 0) continue;
        const auto known = first_of.emplace(in.mesh, i);
        if (known.second) continue;
        const SceneInstance& first = declared[known.first->second];
        Affine back, to_mesh, inv;
        if (first.triangle_count == in.triangle_count && Affine::from_rows(in.matrix).inverse(back) &&
            (to_mesh = Affine::from_rows(first.matrix).after(back)).inverse(inv) && to_mesh.norm() <= kMaxScale &&
            inv.norm() <= kMaxScale)
            candidates.emplace_back(i, to_mesh);
        else
            ++refused;
    }
    // Copies that pass are among these: a scene that would not pay is known
    // before any corner is checked.
    size_t offered = 0;
    for (const auto& cand : candidates) offered += declared[cand.first].triangle_count;
    if (!pays(offered, scene->num_prims(), always)) return nullptr;
    // (The vertex ids, where the scene keeps them for every triangle; each mesh's
    // first copy's corners that first show its vertices.)
    const Scene::Geometry geometry = scene->geometry();
    const int32_t* ids = geometry.triangles->size() == 3 * scene->num_triangles() && !geometry.vertices->empty()
                             ? geometry.triangles->data() : nullptr;
    std::unordered_map<int32_t, std::vector<uint32_t>> corners_of;
    if (ids)
        for (const auto& cand : candidates) {
            const int32_t mesh = declared[cand.first].mesh;
            if (corners_of.count(mesh)) continue;
            const SceneInstance& first = declared[first_of.at(mesh)];
            corners_of[mesh] = first_corners(ids, first.triangle_start, first.triangle_count, cancel, step);
        }
    const std::vector<uint32_t> none;
    std::vector<uint8_t> matches(candidates.size());
    for_each_range(candidates.size(), p.threads, 256, [&](size_t b, size_t e) {
        uint64_t steps = 0;
        for (size_t k = b; k < e; ++k) {
            const SceneInstance& in = declared[candidates[k].first];
            const SceneInstance& first = declared[first_of.at(in.mesh)];
            const auto corners = corners_of.find(in.mesh);
            matches[k] = is_copy(tv, ids, corners == corners_of.end() ? none : corners->second, in.triangle_start,
                                 first.triangle_start, in.triangle_count, candidates[k].second, cancel, steps);
        }
    }, "gridwalk-build");
    for (size_t k = 0; k < candidates.size(); ++k) {
        if (!matches[k]) {
            ++refused;
            continue;
        }
        const SceneInstance& in = declared[candidates[k].first];
        Copy c;
        c.start = uint32_t(in.triangle_start);
        c.count = uint32_t(in.triangle_count);
        c.to_mesh = candidates[k].second;
        c.scale = c.to_mesh.norm();
        const auto grid = grid_of.emplace(in.mesh, g->meshes_.size());
        if (grid.second) g->meshes_.push_back(nullptr), mesh_ids.push_back(in.mesh);
        c.mesh = uint32_t(grid.first->second);
        g->copies_.push_back(c);
        copied += in.triangle_count;
    }
    if (!pays(copied, scene->num_prims(), always)) return nullptr;

    // The copies' boxes: their own triangles' bounds, padded by the map's
    // rounding (a hit is the first copy's triangle mapped back, which may lie
    // beside the copy's own by that much) and as the grids pad their boxes.
    for_each_range(g->copies_.size(), p.threads, 256, [&](size_t b, size_t e) {
        uint64_t steps = 0;
        for (size_t i = b; i < e; ++i) {
            Copy& c = g->copies_[i];
            Bounds box;
            for (size_t k = 3 * size_t(c.start); k < 3 * (size_t(c.start) + c.count); ++k) box.grow(tv[k]);
            check_cancel(cancel, steps, 3 * uint64_t(c.count));
            double lo[3], hi[3];
            padded_box(box, lo, hi);
            const double mag = std::max(magnitude(Vec3d(box.lo)), magnitude(Vec3d(box.hi)));
            for (int a = 0; a < 3; ++a) {
                const double pad = 4 * kCornerTolerance * mag;
                c.lo[a] = next_down(float(lo[a] - pad));
                c.hi[a] = next_up(float(hi[a] + pad));
            }
        }
    }, "gridwalk-build");
    Bounds all;
    for (const Copy& c : g->copies_) {
        all.grow(c.lo);
        all.grow(c.hi);
    }
    g->lo_ = all.lo;
    g->hi_ = all.hi;

    // The grid over them: cells as cubic as the box allows, about
    // kCellsPerCopy per copy, fewer past the caps.
    double ext[3], maxext = 0;
    for (int a = 0; a < 3; ++a) maxext = std::max(maxext, ext[a] = double(all.hi[a]) - double(all.lo[a]));
    double wanted = std::min(kCellsPerCopy * double(g->copies_.size()), double(kMaxTopCells));
    for (;;) {
        int k = 0;
        double vol = 1;
        for (int a = 0; a < 3; ++a)
            if (ext[a] > 1e-4 * maxext) ++k, vol *= ext[a];
        const double side = k ? std::pow(vol / std::max(wanted, 1.0), 1.0 / k) : 1.0;
        for (int a = 0; a < 3; ++a) {
            g->n_[a] = ext[a] > 1e-4 * maxext && side > 0
                           ? int(std::min(std::max(std::floor(ext[a] / side + 0.5), 1.0), 1024.0))
                           : 1;
            g->cell_[a] = ext[a] > 0 ? ext[a] / g->n_[a] : 1.0;
            g->inv_cell_[a] = 1.0 / g->cell_[a];
        }
        uint64_t refs = 0;
        for (const Copy& c : g->copies_) {
            int c0[3], c1[3];
            g->cell_range(c, c0, c1);
            refs += uint64_t(c1[0] - c0[0] + 1) * uint64_t(c1[1] - c0[1] + 1) * uint64_t(c1[2] - c0[2] + 1);
        }
        if (refs <= kMaxTopRefs || wanted <= 1) break;
        wanted = std::floor(wanted / 2);
    }
    const uint64_t cells = uint64_t(g->n_[0]) * uint64_t(g->n_[1]) * uint64_t(g->n_[2]);
    g->first_.assign(cells + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            if (*std::max_element(g->first_.begin(), g->first_.end()) > kCrowdedCell) return nullptr;
            for (uint64_t c = 0; c < cells; ++c) g->first_[c + 1] += g->first_[c];
            g->ids_.resize(g->first_[cells]);
        }
        std::vector<uint32_t> fill;
        if (pass == 1) fill.assign(g->first_.begin(), g->first_.end() - 1);
        for (uint32_t i = 0; i < g->copies_.size(); ++i) {
            int c0[3], c1[3];
            g->cell_range(g->copies_[i], c0, c1);
            for (int z = c0[2]; z <= c1[2]; ++z)
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x) {
                        check_cancel(cancel, step);
                        const uint64_t c = (uint64_t(z) * uint64_t(g->n_[1]) + uint64_t(y)) * uint64_t(g->n_[0]) + uint64_t(x);
                        if (pass == 0) ++g->first_[c + 1];
                        else g->ids_[fill[c]++] = i;
                    }
        }
    }

    // The rest: every primitive outside the copies. (Built after the grid over
    // the copies, which may give up.)
    {
        std::vector<std::pair<uint32_t, uint32_t>> ranges;
        for (const Copy& c : g->copies_) ranges.emplace_back(c.start, c.start + c.count);
        std::sort(ranges.begin(), ranges.end());
        g->rest_ids_.reserve(scene->num_prims() - copied);
        uint32_t at = 0;
        for (const auto& r : ranges) {
            for (; at < r.first; ++at) g->rest_ids_.push_back(at), check_cancel(cancel, step);
            at = r.second;
        }
        for (; at < scene->num_prims(); ++at) g->rest_ids_.push_back(at), check_cancel(cancel, step);
    }
    AccelInfo sum;
    size_t part_corners = 0;   // the part scenes' copies of triangle corners
    auto add = [&](const AdaptiveGrid& a) {
        sum.grids += a.info().grids;
        sum.cells += a.info().cells;
        sum.refs += a.info().refs;
        sum.bytes += a.info().bytes;
    };
    if (!g->rest_ids_.empty()) {
        auto rest = std::make_shared<AdaptiveGrid>(scene->part(g->rest_ids_), p, cancel);
        part_corners += 3 * rest->scene().num_triangles();
        if (rest->too_few_spacings()) return nullptr;
        add(*rest);
        sum.build_threads = rest->info().build_threads;
        g->rest_ = std::move(rest);
    }
    // Each copied mesh's grid, over its first copy's triangles.
    // Each is built around its first copy's centre (shift): the mapped rays'
    // rounding, and the skip of spawned rays (to_mesh), then scale with the
    // mesh, not with where its first copy happens to lie.
    std::vector<Vec3d> shift(g->meshes_.size());
    for (size_t k = 0; k < g->meshes_.size(); ++k) {
        const SceneInstance& first = declared[first_of.at(mesh_ids[k])];
        std::vector<uint32_t> ids(first.triangle_count);
        Bounds box;
        for (size_t j = 0; j < ids.size(); ++j) {
            ids[j] = uint32_t(first.triangle_start + j);
            for (int c = 0; c < 3; ++c) box.grow(tv[3 * (first.triangle_start + j) + size_t(c)]);
        }
        shift[k] = (Vec3d(box.lo) + Vec3d(box.hi)) * 0.5;
        AdaptiveParams mp = p;
        mp.threads = 1;   // (small grids, one after another)
        // (The meshes share one crowded root's allowance: gridwalk.memory counts two.)
        mp.crowded_refs = p.crowded_refs / g->meshes_.size();
        auto grid = std::make_shared<AdaptiveGrid>(scene->part(ids, shift[k]), mp, cancel);
        if (grid->too_few_spacings()) return nullptr;
        add(*grid);
        part_corners += 3 * ids.size();
        g->meshes_[k] = std::move(grid);
    }
    for (Copy& c : g->copies_)
        for (int r = 0; r < 3; ++r) c.to_mesh.m[r][3] -= shift[c.mesh][r];

    AccelInfo& info = g->info_;
    info.kind = "instanced adaptive grid";
    for (int a = 0; a < 3; ++a) info.n[a] = g->n_[a];
    info.grids = sum.grids + 1;
    info.cells = sum.cells + cells;
    info.refs = sum.refs + g->ids_.size();
    info.bytes = sum.bytes + (g->first_.size() + g->ids_.size() + g->rest_ids_.size()) * sizeof(uint32_t) +
                 g->copies_.size() * sizeof(Copy) + part_corners * sizeof(Vec3);
    info.build_threads = std::max(sum.build_threads, 1);
    info.density_requested = p.root_density;
    info.density_used = p.root_density;
    info.note = std::to_string(g->copies_.size()) + " copies of " + std::to_string(g->meshes_.size()) +
                " meshes traced through one grid per mesh, placed by a grid over their boxes";
    if (refused)
        info.note += "; " + std::to_string(refused) +
                     " declared instances did not match their mesh's first instance and are traced as triangles";
    info.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    return g;
}

void InstancedGrid::cell_range(const Copy& c, int c0[3], int c1[3]) const {
    for (int a = 0; a < 3; ++a) {
        const double l = (double(c.lo[a]) - double(lo_[a])) * inv_cell_[a];
        const double h = (double(c.hi[a]) - double(lo_[a])) * inv_cell_[a];
        c0[a] = std::min(std::max(int(std::floor(l)), 0), n_[a] - 1);
        c1[a] = std::min(std::max(int(std::floor(h)), 0), n_[a] - 1);
    }
}

RayPre InstancedGrid::to_mesh(const RayPre& r, const Copy& c) const {
    Ray ray = r.ray;
    const Vec3d o = c.to_mesh.point(Vec3d(ray.o)), d = c.to_mesh.vector(Vec3d(ray.d));
    ray.o = Vec3(float(o.x), float(o.y), float(o.z));
    ray.d = Vec3(float(d.x), float(d.y), float(d.z));
    if (ray.spawned) {
        // A ray leaving a surface starts a few ulps off it (offset.h); mapped
        // and rounded again, and met by the first copy's triangle (rounded
        // elsewhere), the start may fall on the other side. Skip 8 ulps of the
        // origin's magnitudes here and in the mesh's frame along the ray. (The
        // spawned triangle test already rejected every re-hit of 37,000 rays
        // leaving copies at up to 1/1000 of a right angle without it; 64 ulps,
        // as MovedGrid skips, lost the shadow of a copy 0.5 mm away at 141
        // units from the origin.)
        const double here = magnitude(Vec3d(r.ray.o));
        const double err = 8.0 * 0x1p-23 * (magnitude(o) + c.scale * here);
        const double len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (len > 0) ray.tmin = std::max(ray.tmin, float(err / len));
    }
    return RayPre(ray);
}

template <bool kAny>
bool InstancedGrid::test_copy(uint32_t i, const RayPre& r, Hit& hit, TraceContext& ctx) const {
    const Copy& c = copies_[i];
    RayPre m = to_mesh(r, c);
    m.ray.after = after_in(r.ray.after, c.start, c.count);
    const AdaptiveGrid& grid = *meshes_[c.mesh];
    if (kAny) return grid.occluded(m, ctx);
    // The mesh grid's triangle k is this copy's c.start + k; a hit at the same
    // t goes to the lower index (Scene::intersect_with): the local hit's index
    // is the count of this copy's triangles below the current one.
    Hit local = hit;
    local.prim = hit.prim < int32_t(c.start) ? 0 : int32_t(std::min<uint32_t>(uint32_t(hit.prim) - c.start, c.count));
    if (!grid.closest(m, local, ctx)) return false;
    hit.t = local.t;
    hit.u = local.u;
    hit.v = local.v;
    hit.prim = int32_t(c.start + uint32_t(local.prim));
    return true;
}

template <bool kAny>
bool InstancedGrid::walk(const RayPre& r, Hit& hit, TraceContext& ctx) const {
    if (!r.valid) return false;
    const Ray& ray = r.ray;
    const DdaRay w(ray);
    double t0 = ray.tmin, t1 = reach(hit.t);
    if (!w.clip(lo_, hi_, ray, t0, t1)) return false;
    ctx.copies.resize(copies_.size());
    ctx.copies.next_ray();
    int cell[3], step[3];
    double next[3], delta[3];
    for (int a = 0; a < 3; ++a) {
        // (the ray's own direction, as adaptive_walk.inc's locate: a component
        // dda_d dropped still moves a ray from far away, dda.h)
        const double x = (w.o[a] + t0 * w.d[a] - double(lo_[a])) * inv_cell_[a];
        cell[a] = std::min(std::max(int(std::floor(x)), 0), n_[a] - 1);
        if (w.dir[a] > 0) {
            step[a] = 1;
            next[a] = (double(lo_[a]) + (cell[a] + 1) * cell_[a] - w.o[a]) * w.inv[a];
            delta[a] = cell_[a] * w.inv[a];
        } else if (w.dir[a] < 0) {
            step[a] = -1;
            next[a] = (double(lo_[a]) + cell[a] * cell_[a] - w.o[a]) * w.inv[a];
            delta[a] = -cell_[a] * w.inv[a];
        } else {
            step[a] = 0;
            next[a] = delta[a] = kInf;
        }
    }
    bool found = false;
    for (;;) {
        ++ctx.stats.cells;
        const uint64_t c = (uint64_t(cell[2]) * uint64_t(n_[1]) + uint64_t(cell[1])) * uint64_t(n_[0]) + uint64_t(cell[0]);
        for (uint32_t k = first_[c]; k < first_[c + 1]; ++k) {
            const uint32_t i = ids_[k];
            if (ctx.copies.seen(i)) continue;
            double a = ray.tmin, b = reach(hit.t);
            if (!w.clip(copies_[i].lo, copies_[i].hi, ray, a, b)) continue;
            if (test_copy<kAny>(i, r, hit, ctx)) {
                if (kAny) return true;
                found = true;
            }
        }
        const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
        const double exit = next[axis];
        if (exit >= t1 || exit >= reach(hit.t)) break;   // the ray's part (or its nearest hit) ends in this cell
        cell[axis] += step[axis];
        if (cell[axis] < 0 || cell[axis] >= n_[axis]) break;
        next[axis] += delta[axis];
    }
    return found;
}

RayPre InstancedGrid::to_rest(const RayPre& r) const {
    RayPre rest = r;
    // (the rest's primitive k is rest_ids_[k], in increasing order: k comes after the hit
    // passed from the first k whose id is above it on)
    if (r.ray.after >= 0)
        rest.ray.after = int32_t(std::upper_bound(rest_ids_.begin(), rest_ids_.end(), uint32_t(r.ray.after)) -
                                 rest_ids_.begin()) - 1;
    return rest;
}

bool InstancedGrid::closest(const RayPre& r, Hit& hit, TraceContext& ctx) const {
    bool found = false;
    if (rest_) {
        // The rest's primitive k is rest_ids_[k]; as in test_copy, the local
        // hit's index is the count of the rest's primitives below the current one.
        Hit local = hit;
        local.prim = hit.prim < 0 ? 0
                                  : int32_t(std::lower_bound(rest_ids_.begin(), rest_ids_.end(), uint32_t(hit.prim)) -
                                            rest_ids_.begin());
        if (r.ray.after < 0 ? rest_->closest(r, local, ctx) : rest_->closest(to_rest(r), local, ctx)) {
            hit = local;
            hit.prim = int32_t(rest_ids_[size_t(local.prim)]);
            found = true;
        }
    }
    return walk<false>(r, hit, ctx) || found;
}

bool InstancedGrid::occluded(const RayPre& r, TraceContext& ctx) const {
    if (rest_ && (r.ray.after < 0 ? rest_->occluded(r, ctx) : rest_->occluded(to_rest(r), ctx))) return true;
    Hit hit;
    hit.t = r.ray.tmax;
    return walk<true>(r, hit, ctx);
}

}  // namespace gw
