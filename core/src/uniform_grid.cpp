// The uniform grid: build (the seed's resolution formula, compact CSR storage)
// and Amanatides & Woo 3D-DDA traversal with optional per-thread mailboxes.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "uniform_grid.h"

#include "dda.h"
#include "empty_space.h"

namespace gw {

// Largest exact empty-block radius stored per cell; farther cells store cap + 1
// (a jump then crosses up to 2 * cap + 1 cells).
constexpr int kEmptyCap = 16;

GridBudget uniform_grid_budget(uint64_t prims, double density, uint64_t max_cells, uint64_t max_refs) {
    const double n = double(prims);
    const double cap_cells = double(std::min<uint64_t>(std::max<uint64_t>(max_cells, 1), 1ull << 31));
    const double side = density * std::cbrt(n) + 1.0;   // cells along an axis of a cube-shaped box
    const double cells = std::min(cap_cells, 2.0 * std::ceil(side * side * side) + 64.0);
    const double refs = std::ceil(n * std::pow(density + 1.0, 3) + 4.0 * side * side) + 64.0;
    const uint64_t cap_refs = std::min<uint64_t>(std::max<uint64_t>(max_refs, prims), 0xFFFFFFF0ull);
    return {uint64_t(cells), std::max<uint64_t>(prims, refs >= double(cap_refs) ? cap_refs : uint64_t(refs))};
}

namespace {
// The number of cells in the inclusive range c0..c1.
uint64_t cells_in(const int c0[3], const int c1[3]) {
    return uint64_t(c1[0] - c0[0] + 1) * uint64_t(c1[1] - c0[1] + 1) * uint64_t(c1[2] - c0[2] + 1);
}

// A primitive's cell range in 60 bits (10 per bound), for grids of at most
// 1024 cells per axis: the count pass keeps it so that the fill pass need not
// recompute the primitive's bounds and cells.
constexpr int kPackBits = 10;
uint64_t pack_range(const int c0[3], const int c1[3]) {
    uint64_t p = 0;
    for (int a = 0; a < 3; ++a) p = (p << (2 * kPackBits)) | (uint64_t(c0[a]) << kPackBits) | uint64_t(c1[a]);
    return p;
}
void unpack_range(uint64_t p, int c0[3], int c1[3]) {
    constexpr uint64_t mask = (1u << kPackBits) - 1;
    for (int a = 2; a >= 0; --a, p >>= 2 * kPackBits) {
        c1[a] = int(p & mask);
        c0[a] = int((p >> kPackBits) & mask);
    }
}
}  // namespace

UniformGrid::UniformGrid(std::shared_ptr<const Scene> s, const GridParams& p, const CancelToken* cancel)
    : Accel(std::move(s)) {
    uint64_t step = 0;
    const auto t_start = std::chrono::steady_clock::now();
    if (!(p.density > 0) || !std::isfinite(p.density)) throw std::invalid_argument("grid_density must be > 0");
    if (!(p.margin >= 0 && p.margin <= 1)) throw std::invalid_argument("the grid margin must be in [0, 1]");
    const Scene& sc = *scene_;
    const size_t np = sc.num_prims();
    const Bounds b = sc.bounds();
    // Box arithmetic in double: a scene may be a single point, a subnormal
    // speck, or (up to the scene's +-1e30 limit) huge.
    double ext[3], maxext = 0, mag = 0;
    for (int a = 0; a < 3; ++a) {
        ext[a] = double(b.hi[a]) - double(b.lo[a]);
        maxext = std::max(maxext, ext[a]);
        mag = std::max(mag, std::max(std::abs(double(b.lo[a])), std::abs(double(b.hi[a]))));
    }
    // The box needs a size the DDA can divide by, even for a point scene.
    const double scale = std::max(std::max(maxext, mag * 1e-6), 1e-12);
    // Pad the box a little on every side; give flat axes a thickness so the DDA
    // has a non-empty slab. An axis is flat when its extent is below 1e-4 of
    // the scale: it gets one cell and is left out of the cell-size formula.
    bool flat[3];
    Vec3 tight_lo, tight_hi;
    for (int a = 0; a < 3; ++a) {
        flat[a] = !(ext[a] > 1e-4 * scale);
        const double pad = (flat[a] ? 1e-3 : 1e-5) * scale;
        tight_lo[a] = next_down(float(double(b.lo[a]) - pad - std::abs(double(b.lo[a])) * 1e-6));
        tight_hi[a] = next_up(float(double(b.hi[a]) + pad + std::abs(double(b.hi[a])) * 1e-6));
    }
    // N_ax = floor(M * dim_ax / cbrt(V / N)) + 1, generalised to k non-flat axes.
    int k = 0;
    double vol = 1;
    for (int a = 0; a < 3; ++a)
        if (!flat[a]) { ++k; vol *= double(tight_hi[a] - tight_lo[a]); }
    const double side = k ? std::pow(vol / double(np), 1.0 / k) : 1.0;
    if (uint64_t(np) > 0xFFFFFFF0ull)   // offsets and primitive indices are 32-bit
        throw std::invalid_argument("the uniform grid holds at most 4,294,967,280 primitives, got " +
                                    std::to_string(np));
    const GridBudget budget = uniform_grid_budget(np, p.density, p.max_cells, p.max_refs);
    const uint64_t max_cells = budget.cells, max_refs = budget.refs;
    max_refs_ = max_refs;
    double m = p.density;
    info_.density_requested = p.density;
    std::vector<uint32_t> counts;
    std::vector<uint64_t> ranges;   // packed cell ranges, when the grid allows (pack_range)
    bool margin_on = p.margin > 0;
    for (int attempt = 0;; ++attempt) {
        uint64_t cells = 1, tight_cells = 1;
        for (int a = 0; a < 3; ++a) {
            const double na = flat[a] ? 1.0 : std::floor(m * double(tight_hi[a] - tight_lo[a]) / side) + 1.0;
            n_[a] = int(std::min(na, double(1 << 20)));
            // The margin: extra + 1/2 cells of the same size on both sides, so that
            // the scene's sides fall inside cells, not on the faces between them
            // (a floor would be listed in the cells below it too). None on a flat
            // axis or below 1 / margin cells, and dropped when even one cell
            // inside it is too many (so the loop below still ends, at one cell).
            tight_cells *= uint64_t(n_[a]);
            const int extra = flat[a] || !margin_on ? 0
                            : int(std::min(std::floor(p.margin * double(n_[a])), double(1 << 19)));
            if (extra > 0) {
                const double size = (double(tight_hi[a]) - double(tight_lo[a])) / double(n_[a]);
                lo_[a] = next_down(float(double(tight_lo[a]) - (extra + 0.5) * size));
                hi_[a] = next_up(float(double(tight_hi[a]) + (extra + 0.5) * size));
                n_[a] += 2 * extra + 1;
            } else {
                lo_[a] = tight_lo[a];
                hi_[a] = tight_hi[a];
            }
            cells *= uint64_t(n_[a]);
        }
        if (cells > max_cells && tight_cells == 1) {
            margin_on = false;
            continue;
        }
        if (cells > max_cells) {   // shrink M towards the cap and try again
            m *= std::pow(double(max_cells) / double(cells), 1.0 / std::max(k, 1)) * 0.999;
            info_.reduced = true;
            continue;
        }
        for (int a = 0; a < 3; ++a) {
            cell_[a] = (hi_[a] - lo_[a]) / float(n_[a]);
            inv_cell_[a] = float(n_[a]) / (hi_[a] - lo_[a]);
        }
        // Pass 1: count references per cell.
        assign_checked(counts, cells, 0u, cancel, step);
        const bool pack = std::max(n_[0], std::max(n_[1], n_[2])) <= (1 << kPackBits);
        ranges.clear();
        if (pack) ranges.reserve(np);
        uint64_t refs = 0;
        for (size_t i = 0; i < np && refs <= max_refs; ++i) {
            int c0[3], c1[3];
            cell_range(sc.prim_bounds(i), c0, c1);
            if (pack) ranges.push_back(pack_range(c0, c1));
            const uint64_t covered = cells_in(c0, c1);
            check_cancel(cancel, step, covered);
            for_cells(c0, c1, [&](uint64_t c) { ++counts[c]; });
            refs += covered;
        }
        if (refs > max_refs && cells > 1) {
            if (tight_cells == 1) margin_on = false;
            else m *= 0.7;
            info_.reduced = true;
            continue;
        }
        if (refs > max_refs) throw std::invalid_argument("scene has too many primitive references for the grid");
        info_.cells = cells;
        info_.refs = refs;
        break;
    }
    info_.density_used = m;
    info_.kind = "uniform grid";
    info_.grids = 1;
    // Prefix sums, then pass 2: fill.
    assign_checked(offsets_, info_.cells + 1, 0u, cancel, step);
    for (uint64_t c = 0; c < info_.cells; ++c) {
        check_cancel(cancel, step);
        offsets_[c + 1] = offsets_[c] + counts[c];
        counts[c] = offsets_[c];
    }
    assign_checked(prims_, info_.refs, 0u, cancel, step);
    const bool packed = ranges.size() == np;
    for (size_t i = 0; i < np; ++i) {
        int c0[3], c1[3];
        if (packed) {
            unpack_range(ranges[i], c0, c1);
        } else {
            cell_range(sc.prim_bounds(i), c0, c1);
        }
        check_cancel(cancel, step, cells_in(c0, c1));
        for_cells(c0, c1, [&](uint64_t c) { prims_[counts[c]++] = uint32_t(i); });
    }
    for (int a = 0; a < 3; ++a) info_.n[a] = n_[a];
    std::vector<uint32_t>().swap(counts);   // free before the distance field's scratch
    std::vector<uint64_t>().swap(ranges);
    empty_ = empty_distance(offsets_, n_, kEmptyCap, cancel);
    info_.bytes = offsets_.size() * 4 + prims_.size() * 4 + empty_.size();
    info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    if (info_.reduced)
        info_.note = "grid density reduced from " + std::to_string(p.density) + " to " + std::to_string(m) +
                     " to respect the cap of " + std::to_string(max_cells) + " cells / " +
                     std::to_string(max_refs) + " references";
}

namespace {
// Primitives whose bounds may differ between two scenes of the same counts
// (ascending): triangles whose corners differ, quadrics whose bounds do.
// Null when more than `limit` do.
bool changed_prims(const Scene& a, const Scene& b, size_t limit, std::vector<uint32_t>& out,
                   const CancelToken* cancel, uint64_t& step) {
    const size_t nt = a.num_triangles(), np = a.num_prims();
    const Vec3 *va = a.triangle_vertices(), *vb = b.triangle_vertices();
    constexpr size_t kBlock = 64;   // triangles compared at once: one memcmp per unchanged block
    for (size_t i = 0; i < nt; i += kBlock) {
        const size_t e = std::min(nt, i + kBlock);
        check_cancel(cancel, step, e - i);
        if (std::memcmp(va + 3 * i, vb + 3 * i, (e - i) * 3 * sizeof(Vec3)) == 0) continue;
        for (size_t t = i; t < e; ++t)
            if (std::memcmp(va + 3 * t, vb + 3 * t, 3 * sizeof(Vec3)) != 0) out.push_back(uint32_t(t));
        if (out.size() > limit) return false;
    }
    for (size_t i = nt; i < np; ++i) {
        const Bounds x = a.prim_bounds(i), y = b.prim_bounds(i);
        bool same = true;
        for (int k = 0; k < 3; ++k) same &= x.lo[k] == y.lo[k] && x.hi[k] == y.hi[k];
        if (!same) out.push_back(uint32_t(i));
        if (out.size() > limit) return false;
    }
    return true;
}

struct Move {   // one primitive entering or leaving one cell
    uint64_t cell;
    uint32_t prim;
    bool operator<(const Move& o) const { return cell != o.cell ? cell < o.cell : prim < o.prim; }
};
}  // namespace

std::shared_ptr<const UniformGrid> UniformGrid::update(const UniformGrid& prev, std::shared_ptr<const Scene> s,
                                                       const CancelToken* cancel) {
    const Scene &old_sc = prev.scene(), &sc = *s;
    if (old_sc.num_triangles() != sc.num_triangles() || old_sc.num_spheres() != sc.num_spheres() ||
        old_sc.num_cones() != sc.num_cones())
        return nullptr;
    // Every primitive must lie inside the box, with at least half the room a
    // fresh build leaves (it pads the scene's box by 1e-5 of its largest side).
    const Bounds& b = sc.bounds();
    double scale = 1e-12;
    for (int a = 0; a < 3; ++a) scale = std::max(scale, double(b.hi[a]) - double(b.lo[a]));
    for (int a = 0; a < 3; ++a)
        if (!(double(b.lo[a]) - 0.5e-5 * scale >= double(prev.lo_[a]) &&
              double(b.hi[a]) + 0.5e-5 * scale <= double(prev.hi_[a])))
            return nullptr;
    uint64_t step = 0;
    std::vector<uint32_t> changed;
    // Past a quarter of the primitives a fresh build costs about the same.
    if (!changed_prims(old_sc, sc, sc.num_prims() / 4, changed, cancel, step)) return nullptr;
    // The cells each changed primitive leaves and enters; nothing is listed
    // until the totals are known to fit: the references within the build's
    // budget, and the moves within the previous grid's references (a fresh
    // build costs about that; a primitive grown over the box would otherwise
    // list millions of moves).
    std::vector<CellChange> moves;
    uint64_t gone = 0, added = 0;
    for (const uint32_t i : changed) {
        CellChange m{i, {}, {}, {}, {}};
        prev.cell_range(old_sc.prim_bounds(i), m.a0, m.a1);
        prev.cell_range(sc.prim_bounds(i), m.b0, m.b1);
        if (std::equal(m.a0, m.a0 + 3, m.b0) && std::equal(m.a1, m.a1 + 3, m.b1)) continue;   // the same cells
        gone += cells_in(m.a0, m.a1);
        added += cells_in(m.b0, m.b1);
        if (gone + added > prev.prims_.size() + 64) return nullptr;
        moves.push_back(m);
    }
    if (prev.prims_.size() - gone + added > prev.max_refs_) return nullptr;
    return std::shared_ptr<const UniformGrid>(new UniformGrid(prev, std::move(s), moves, cancel));
}

UniformGrid::UniformGrid(const UniformGrid& prev, std::shared_ptr<const Scene> s, const std::vector<CellChange>& moves,
                         const CancelToken* cancel)
    : Accel(std::move(s)), lo_(prev.lo_), hi_(prev.hi_), cell_(prev.cell_), inv_cell_(prev.inv_cell_),
      max_refs_(prev.max_refs_), info_(prev.info_) {
    const auto t_start = std::chrono::steady_clock::now();
    uint64_t step = 0;
    for (int a = 0; a < 3; ++a) n_[a] = prev.n_[a];
    std::vector<Move> gone, added;   // (cell, primitive) leaving and entering
    for (const CellChange& m : moves) {
        check_cancel(cancel, step, cells_in(m.a0, m.a1) + cells_in(m.b0, m.b1));
        for_cells(m.a0, m.a1, [&](uint64_t c) { gone.push_back({c, m.prim}); });
        for_cells(m.b0, m.b1, [&](uint64_t c) { added.push_back({c, m.prim}); });
    }
    std::sort(gone.begin(), gone.end());
    std::sort(added.begin(), added.end());
    const uint64_t refs = prev.prims_.size() - gone.size() + added.size();   // (within max_refs_: update() checked)
    // Offsets: the previous counts, less what left, plus what entered.
    const uint64_t cells = info_.cells;
    assign_checked(offsets_, cells + 1, 0u, cancel, step);
    size_t g = 0, d = 0;
    bool emptiness_changed = false;
    for (uint64_t c = 0; c < cells; ++c) {
        check_cancel(cancel, step);
        const uint32_t before = prev.offsets_[c + 1] - prev.offsets_[c];
        uint32_t count = before;
        for (; g < gone.size() && gone[g].cell == c; ++g) --count;
        for (; d < added.size() && added[d].cell == c; ++d) ++count;
        emptiness_changed |= (before == 0) != (count == 0);
        offsets_[c + 1] = offsets_[c] + count;
    }
    // Lists: untouched cells' runs copied whole; a touched cell's list merged
    // in ascending primitive order, as a fresh build's fill pass leaves it.
    prims_.resize(refs);
    uint64_t copied_to = 0;   // cells before this one are in place
    auto copy_until = [&](uint64_t c) {   // the untouched cells [copied_to, c)
        const uint32_t from = prev.offsets_[copied_to], to = prev.offsets_[c];
        check_cancel(cancel, step, to - from);
        std::copy(prev.prims_.begin() + from, prev.prims_.begin() + to, prims_.begin() + offsets_[copied_to]);
    };
    g = d = 0;
    while (g < gone.size() || d < added.size()) {
        const uint64_t c = std::min(g < gone.size() ? gone[g].cell : cells, d < added.size() ? added[d].cell : cells);
        copy_until(c);
        uint32_t out = offsets_[c];
        const size_t g_end = std::find_if(gone.begin() + g, gone.end(), [&](const Move& m) { return m.cell != c; }) -
                             gone.begin();
        for (uint32_t k = prev.offsets_[c]; k < prev.offsets_[c + 1]; ++k) {
            const uint32_t prim = prev.prims_[k];
            if (g < g_end && gone[g].prim == prim) { ++g; continue; }   // (both ascending)
            for (; d < added.size() && added[d].cell == c && added[d].prim < prim; ++d) prims_[out++] = added[d].prim;
            prims_[out++] = prim;
        }
        for (; d < added.size() && added[d].cell == c; ++d) prims_[out++] = added[d].prim;
        g = g_end;
        copied_to = c + 1;
    }
    copy_until(cells);
    empty_ = emptiness_changed ? empty_distance(offsets_, n_, kEmptyCap, cancel) : prev.empty_;
    info_.refs = refs;
    info_.bytes = offsets_.size() * 4 + prims_.size() * 4 + empty_.size();
    info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    info_.note = "updated from the previous scene version: " + std::to_string(moves.size()) +
                 " primitives changed cells";
}

// Cells overlapped by a box (in double: the difference of two floats is
// exact). The box is inflated by 1/1000 of a cell plus the float rounding of
// a cell coordinate at this resolution, so that a primitive touching a cell
// face within rounding error is listed on both sides. (The adaptive grid also
// pads by the rounding of an absolute coordinate; here the scene box's own
// padding, 1e-6 of its magnitude, keeps cells coarser than that rounding, and
// test34's features smaller than the coordinates' spacing are found without it.)
void UniformGrid::cell_range(const Bounds& b, int c0[3], int c1[3]) const {
    for (int a = 0; a < 3; ++a) {
        const double top = double(n_[a] - 1), pad = 1e-3 + 4e-7 * double(n_[a]);
        double x0 = (double(b.lo[a]) - double(lo_[a])) * double(inv_cell_[a]) - pad;
        double x1 = (double(b.hi[a]) - double(lo_[a])) * double(inv_cell_[a]) + pad;
        x0 = std::min(std::max(x0, 0.0), top);
        x1 = std::min(std::max(x1, 0.0), top);
        c0[a] = int(x0);
        c1[a] = int(x1);
    }
}

// The cell holding the point at parameter t, located in double so a far-away
// origin does not shift it by a cell.
int UniformGrid::cell_at(const Ray& ray, double t, int a) const {
    const double x = (double(ray.o[a]) - double(lo_[a]) + double(ray.d[a]) * t) * double(inv_cell_[a]);
    return int(std::min(std::max(x, 0.0), double(n_[a] - 1)));
}

template <bool AnyHit, bool Filtered>
bool UniformGrid::traverse(const RayPre& r, Hit& hit, TraceContext& ctx, const PrimFilter* filter) const {
    if (!r.valid) return false;
    const Ray& ray = r.ray;
    // The walk's ray parameters are doubles, as in the adaptive grid's walk
    // (adaptive_walk.inc): a float t moves the ray's point by 2^-24 of its
    // distance from the origin, which for a ray from 10^4 scene sizes away is
    // more than the cells' padding, and the walk would miss hits.
    const Vec3 dir = dda_d(ray.d);
    double inv[3];
    dda_inverse(dir, inv);
    double t0 = ray.tmin, t1 = reach(hit.t);   // t1: where the ray leaves the grid (or its tmax)
    if (!clip_to_box_d(lo_, hi_, ray, dir, inv, t0, t1)) return false;
    if (!(t0 <= double(std::numeric_limits<float>::max()))) return false;   // the box lies beyond float range along this ray
    const bool mailboxes = ctx.mailbox.enabled();
    if (mailboxes) ctx.mailbox.next_ray();
    int cell[3], step[3], out[3];
    double tnext[3], tdelta[3];
    // t where the ray crosses face `face` (a cell index) along axis a. (The
    // face's coordinate in double too: far from the origin, rounded to float
    // it can be off by most of a cell.)
    auto face_t = [&](int a, int face) {
        return (double(lo_[a]) + double(face) * double(cell_[a]) - double(ray.o[a])) * inv[a];
    };
    // t where the ray leaves cell[a] along axis a (the face in the step direction).
    auto exit_t = [&](int a) { return face_t(a, step[a] > 0 ? cell[a] + 1 : cell[a]); };
    for (int a = 0; a < 3; ++a) {
        cell[a] = cell_at(ray, t0, a);
        if (dir[a] > 0) {
            step[a] = 1; out[a] = n_[a];
            tnext[a] = exit_t(a);
            tdelta[a] = double(cell_[a]) * inv[a];
        } else if (dir[a] < 0) {
            step[a] = -1; out[a] = -1;
            tnext[a] = exit_t(a);
            tdelta[a] = -double(cell_[a]) * inv[a];
        } else {
            step[a] = 0; out[a] = -1;
            tnext[a] = tdelta[a] = kInf;
        }
    }
    // Linear cell index, stepped incrementally. tnext advances by tdelta: the
    // accumulated rounding only decides when a hit is accepted (a hit is kept
    // until the walk passes it), never which cells are visited.
    const int64_t stride[3] = {1, n_[0], int64_t(n_[0]) * n_[1]};
    int64_t c = (int64_t(cell[2]) * n_[1] + cell[1]) * n_[0] + cell[0];
    bool found = false;
    const Scene& sc = *scene_;
    double t_jump = t0;   // entry t of the last jump: every jump must move beyond it
    for (;;) {
        ++ctx.stats.cells;
        const int k = ctx.skip_empty ? empty_[c] : 0;
        if (k >= 2) {
            // Cells within k - 1 of this one are all empty: leave that block in one jump.
            double t_exit = kInf;
            for (int a = 0; a < 3; ++a) {
                if (step[a] == 0) continue;
                const int face = step[a] > 0 ? cell[a] + k : cell[a] - (k - 1);
                t_exit = std::min(t_exit, face_t(a, face));
            }
            if (reach(hit.t) < t_exit || t_exit >= t1) break;   // no hit can lie in empty cells
            if (t_exit > t_jump) {
                t_jump = t_exit;
                for (int a = 0; a < 3; ++a) {
                    cell[a] = cell_at(ray, t_exit, a);
                    if (step[a] != 0) tnext[a] = exit_t(a);
                }
                c = (int64_t(cell[2]) * n_[1] + cell[1]) * n_[0] + cell[0];
                continue;
            }
            // Rounding left us where the last jump started: take a normal DDA step.
        }
        for (uint32_t k = offsets_[c], e = offsets_[c + 1]; k < e; ++k) {
            const uint32_t prim = prims_[k];
            if (Filtered && filter->skip(prim)) continue;
            if (mailboxes && ctx.mailbox.seen(prim)) { ++ctx.stats.mailbox_skips; continue; }
            ++ctx.stats.prim_tests;
            if (sc.intersect(prim, r, hit)) {
                if (AnyHit) return true;
                found = true;
            }
        }
        // Accept the nearest hit once it lies inside this cell: a hit beyond the
        // cell's exit may hide a nearer one in a later cell, so keep walking,
        // but keep the candidate (it may belong to no later cell at all).
        const int axis = tnext[0] < tnext[1] ? (tnext[0] < tnext[2] ? 0 : 2) : (tnext[1] < tnext[2] ? 1 : 2);
        if (reach(hit.t) < tnext[axis]) break;
        cell[axis] += step[axis];
        if (cell[axis] == out[axis]) break;
        c += step[axis] * stride[axis];
        tnext[axis] += tdelta[axis];
    }
    return found;
}

bool UniformGrid::closest(const RayPre& r, Hit& hit, TraceContext& ctx) const {
    return traverse<false, false>(r, hit, ctx, nullptr);
}

bool UniformGrid::occluded(const RayPre& r, TraceContext& ctx) const {
    Hit hit;
    hit.t = r.ray.tmax;
    return traverse<true, false>(r, hit, ctx, nullptr);
}

bool UniformGrid::closest_filtered(const RayPre& r, Hit& hit, TraceContext& ctx, const PrimFilter& f) const {
    return traverse<false, true>(r, hit, ctx, &f);
}

bool UniformGrid::occluded_filtered(const RayPre& r, TraceContext& ctx, const PrimFilter& f) const {
    Hit hit;
    hit.t = r.ray.tmax;
    return traverse<true, true>(r, hit, ctx, &f);
}

}  // namespace gw
