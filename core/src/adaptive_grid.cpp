// The adaptive grid: build, and the traversal compiled per instruction set.
// See adaptive_grid.h.
#include "adaptive_grid.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "brute_force.h"
#include "dda.h"
#include "empty_box.h"
#include "ordered_tasks.h"
#include "overlap.h"

namespace gw {

// --- traversal, once per instruction set ------------------------------------

namespace walk_portable {   // 4 lanes: SSE on x86-64, NEON on aarch64 (GCC vector extensions)
#include "adaptive_walk.inc"
// (Out of line, as the AVX2 copy's are: inlined into AdaptiveGrid::closest / occluded,
// the walk's register saves and stack frame were paid by every ray there, also by the
// AVX2 walk's and the one-leaf root's.)
__attribute__((noinline)) bool closest(const AdaptiveGridData& g, const Scene& sc, const Vec3* tv, const RayPre& r,
                                       Hit& hit, TraceContext& ctx) {
    return walk<4, false>(g, sc, tv, r, hit, ctx);
}
__attribute__((noinline)) bool occluded(const AdaptiveGridData& g, const Scene& sc, const Vec3* tv, const RayPre& r,
                                        Hit& hit, TraceContext& ctx) {
    return walk<4, true>(g, sc, tv, r, hit, ctx);
}
}  // namespace walk_portable

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GW_HAVE_AVX2_WALK 1
#pragma GCC push_options
#pragma GCC target("avx2")
#define GW_WALK_AVX2 1
namespace walk_avx2 {   // 8 lanes
#include "adaptive_walk.inc"
bool closest(const AdaptiveGridData& g, const Scene& sc, const Vec3* tv, const RayPre& r, Hit& hit, TraceContext& ctx) {
    return walk<8, false>(g, sc, tv, r, hit, ctx);
}
bool occluded(const AdaptiveGridData& g, const Scene& sc, const Vec3* tv, const RayPre& r, Hit& hit, TraceContext& ctx) {
    return walk<8, true>(g, sc, tv, r, hit, ctx);
}

}  // namespace walk_avx2
#undef GW_WALK_AVX2
#pragma GCC pop_options
#endif

namespace {

// The rounding of an absolute coordinate that cells are padded by, relative
// to the coordinates' magnitude (2^-21: about 4 float spacings; cell_range).
constexpr double kCoordinateRounding = 4.8e-7;
// A scene narrower than this many such paddings: the padding leaves no
// resolution that separates its primitives (AdaptiveGrid::too_few_spacings).
constexpr double kTooFewSpacings = 64.0;

bool cpu_has_avx2() {
#ifdef GW_HAVE_AVX2_WALK
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

// --- build ---------------------------------------------------------------------

constexpr int kMaxResolution = 1024;
constexpr uint64_t kQuadricCost = 4;   // a quadric's test, in triangle tests (when refining)

struct Box {   // in double: sizes and cell boundaries are exact enough for any float scene
    double lo[3], hi[3];
};

// What every builder of one structure reads.
struct BuildInput {
    const Scene& sc;
    const AdaptiveParams& p;
    const CancelToken* cancel;
    std::vector<Bounds> bounds;   // per primitive
    int threads;                  // for the root's refined cells
};

// The box a refined cell's grid covers: the cell's box (c of the grid (box,
// cell, n)), shrunk to what its primitives `ids` occupy, padded by a little of
// the cell and rounded outwards to float.
// 1e-4 of the longest of a grid's cell sides: what a child box, and a node's
// large primitives' clip box, grow by on every axis (as the root grows by its
// longest extent, padded_box), so that a flat box is not thinner than the
// float tests' rounding of t.
double box_pad(const double cell[3]) { return 1e-4 * std::max(std::max(cell[0], cell[1]), cell[2]); }

// [lo - pad, hi + pad] in double, rounded outwards to float (far from the
// origin the pad may be below a float spacing).
void grow_outwards(const double lo[3], const double hi[3], double pad, Vec3& out_lo, Vec3& out_hi) {
    for (int a = 0; a < 3; ++a) {
        out_lo[a] = next_down(float(lo[a] - pad));
        out_hi[a] = next_up(float(hi[a] + pad));
    }
}

Box child_box(const std::vector<Bounds>& bounds, const Box& box, const double cell[3], const int n[3], uint64_t c,
              const uint32_t* ids, size_t count) {
    const int idx[3] = {int(c % uint64_t(n[0])), int((c / uint64_t(n[0])) % uint64_t(n[1])),
                        int(c / (uint64_t(n[0]) * n[1]))};
    Box cb;
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a] + idx[a] * cell[a], hi = box.lo[a] + (idx[a] + 1) * cell[a];
        cb.lo[a] = hi;
        cb.hi[a] = lo;
        for (size_t i = 0; i < count; ++i) {
            cb.lo[a] = std::min(cb.lo[a], std::max(lo, double(bounds[ids[i]].lo[a])));
            cb.hi[a] = std::max(cb.hi[a], std::min(hi, double(bounds[ids[i]].hi[a])));
        }
        if (cb.lo[a] > cb.hi[a]) { cb.lo[a] = lo; cb.hi[a] = hi; }   // primitives only in the padding
    }
    // (box_pad: the flat child of a floor's cell, padded by its own thickness, was too
    // thin for the float triangle test's rounding of t near a ray's origin, relative to
    // the triangle's size, not to t, and a ray from 1e-6 above the floor whose tmax lay
    // just past the hit missed it: 76 of 10,047; test34)
    Vec3 lo, hi;
    grow_outwards(cb.lo, cb.hi, box_pad(cell), lo, hi);
    for (int a = 0; a < 3; ++a) {
        cb.lo[a] = lo[a];
        cb.hi[a] = hi[a];
    }
    return cb;
}

// Where a refined cell's structure, built on its own, goes in the whole: its
// first node, cell and reference there.
struct Place {
    uint32_t node, cell, ref;
};

// Copies `part` into g at `at` (g already holds the room), its indices moved
// there. (`at` by value: the stores below may alias a reference's target.)
void copy_part(AdaptiveGridData& g, const AdaptiveGridData& part, const Place at, const CancelToken* cancel,
               uint64_t& step) {
    for (size_t i = 0; i < part.nodes.size(); ++i) {
        AdaptiveGridData::Node nd = part.nodes[i];
        nd.first += at.cell;
        if (nd.big_count) nd.big += at.ref;
        g.nodes[at.node + i] = nd;
    }
    for (size_t i = 0; i < part.cells.size(); ++i) {
        check_cancel(cancel, step);
        AdaptiveGridData::Cell c = part.cells[i];
        if (c.b == AdaptiveGridData::kChild) c.a += at.node;
        else if (c.b != 0) c.a += at.ref;
        g.cells[at.cell + i] = c;
    }
    constexpr size_t kSlice = size_t(1) << 16;
    for (size_t i = 0; i < part.refs.size(); i += kSlice) {
        const size_t end = std::min(part.refs.size(), i + kSlice);
        check_cancel(cancel, step, end - i);
        std::copy(part.refs.begin() + i, part.refs.begin() + end, g.refs.begin() + at.ref + i);
    }
}

// A leaf's list of the primitives ids[0 .. count): the number of triangles,
// then the triangles, then the quadrics (count + 1 values from out).
void fill_leaf(const uint32_t* ids, uint32_t count, uint32_t nt, uint32_t* out) {
    uint32_t k = 1;
    for (uint32_t i = 0; i < count; ++i)
        if (ids[i] < nt) out[k++] = ids[i];
    out[0] = k - 1;
    for (uint32_t i = 0; i < count; ++i)
        if (ids[i] >= nt) out[k++] = ids[i];
}

class Builder {
public:
    // Builds into g, within max_cells cells and max_refs references in g.
    Builder(const BuildInput& in, AdaptiveGridData& g, uint64_t max_cells, uint64_t max_refs)
        : in_(in), sc_(in.sc), p_(in.p), g_(g), cancel_(in.cancel), bounds_(in.bounds),
          max_cells_(max_cells), max_refs_(max_refs) {}

    void build() {
        const Bounds sb = sc_.bounds();
        Box box;
        double maxext = 0, mag = 0;
        for (int a = 0; a < 3; ++a) {
            maxext = std::max(maxext, double(sb.hi[a]) - double(sb.lo[a]));
            mag = std::max(mag, std::max(std::abs(double(sb.lo[a])), std::abs(double(sb.hi[a]))));
        }
        // A size the DDA can divide by, even for a point scene; padding on every
        // side (padded_box, which the batch guard uses too), rounded outwards.
        padded_box(sb, box.lo, box.hi);
        for (int a = 0; a < 3; ++a) {
            box.lo[a] = next_down(float(box.lo[a]));
            box.hi[a] = next_up(float(box.hi[a]));
        }
        std::vector<uint32_t> all(sc_.num_prims());
        for (size_t i = 0; i < all.size(); ++i) all[i] = uint32_t(i);
        g_.nodes.reserve(64);
        if (node(box, all, 0) != 0) throw std::logic_error("adaptive grid: the root must be node 0");
        // (whether the root refined or not: a 2 m terrain 1e5 from the origin refined its root,
        // and its leaves held hundreds of triangles each, 270-570 tests a ray against the uniform
        // grid's 18, at 1e6 tens of thousands)
        too_few_spacings_ = all.size() > 2 * size_t(std::max(p_.leaf_size, 1)) && maxext > 0 &&
                            maxext < kTooFewSpacings * kCoordinateRounding * mag;
    }
    bool too_few_spacings() const { return too_few_spacings_; }
    int build_threads() const { return build_threads_; }

    uint64_t refs() const { return g_.refs.size(); }
    double root_density() const { return root_density_; }

private:
    // Resolution of a grid over `box` for n primitives at `density` cells per
    // primitive: cells as cubic as the box allows; axes thinner than 1e-4 of
    // the box's largest side get one cell and stay out of the count, and so do
    // axes left out of `axes` (bit a set: axis a is divided). With
    // drop_short, so do axes shorter than half a cell (below).
    static void resolution(const Box& box, size_t n, double density, int res[3], unsigned axes = 7,
                           bool drop_short = false) {
        double ext[3], maxext = 0;
        for (int a = 0; a < 3; ++a) maxext = std::max(maxext, ext[a] = box.hi[a] - box.lo[a]);
        bool divided[3];
        int k = 0;
        double vol = 1;
        for (int a = 0; a < 3; ++a)
            if ((divided[a] = ext[a] > 1e-4 * maxext && (axes >> a & 1u))) { ++k; vol *= ext[a]; }
        const double wanted = std::max(1.0, density * double(n));
        double side = k ? std::pow(vol / wanted, 1.0 / k) : 1.0;
        // An axis shorter than half a cell gets one cell: left out of the
        // count, it no longer swells the others' share (a slab of a stack,
        // 1/1000 as high as it is wide, had 45 cells per primitive for 2).
        // (Refining grids only: a root of a few primitives, such as the seed's
        // Distant, stays the one cell that brute force's loop traces fastest.)
        for (int a = 0; a < 3 && k > 1 && drop_short; ++a)
            if (divided[a] && ext[a] < 0.5 * side) {
                divided[a] = false;
                vol /= ext[a];
                side = std::pow(vol / wanted, 1.0 / --k);
                a = -1;   // (the others again, against the new side)
            }
        for (int a = 0; a < 3; ++a)
            res[a] = divided[a] && side > 0
                         ? int(std::min(std::max(std::floor(ext[a] / side + 0.5), 1.0), double(kMaxResolution)))
                         : 1;
    }

    // Whether b spans over `fraction` of the box along axis a.
    static bool spans(const Bounds& b, const Box& box, int a, double fraction) {
        return double(b.hi[a]) - double(b.lo[a]) > fraction * (box.hi[a] - box.lo[a]);
    }
    // Whether b is long: spans over a quarter of the box along some axis.
    static bool is_long(const Bounds& b, const Box& box) {
        return spans(b, box, 0, 0.25) || spans(b, box, 1, 0.25) || spans(b, box, 2, 0.25);
    }

    // The axes across a stack: where many primitives are long along some
    // axis (their bounds spanning over a quarter of the box), the axes along
    // which fewer than an eighth as many span even an eighth of it. A stack
    // of floors, shelves or slats gives the axis across them: a grid divided
    // along it alone lists each primitive once, where cubic cells list each
    // in a whole layer of cells. 7 (all axes) where there is no such axis.
    // (An eighth, not a quarter: the small grids refining a terrain are
    // thin boxes its triangles cross, each a sixth of such a box wide;
    // searching them for layers, which would list each triangle in every
    // layer, cost the build of SPD's mount size 8 a third more time.)
    unsigned thin_axes(const Box& box, const std::vector<uint32_t>& prims) const {
        uint64_t longer[3] = {0, 0, 0}, wider[3] = {0, 0, 0};
        uint64_t step = 0;
        for (uint32_t prim : prims) {
            check_cancel(cancel_, step);
            for (int a = 0; a < 3; ++a) {
                longer[a] += spans(bounds_[prim], box, a, 0.25);
                wider[a] += spans(bounds_[prim], box, a, 0.125);
            }
        }
        const uint64_t most = std::max(longer[0], std::max(longer[1], longer[2]));
        unsigned axes = 0;
        for (int a = 0; a < 3; ++a)
            if (8 * wider[a] < most) axes |= 1u << a;
        return axes ? axes : 7u;
    }

    // A grid of resolution n over box, with what cell_range asks of every
    // primitive worked out once per axis.
    struct Frame {
        const Box& box;
        const int* n;
        double cell[3];
        double reach_lo[3], reach_hi[3];   // bounds beyond these miss the grid
        double pad[3];                     // cell_range's inflation, in cells
        double top[3];                     // the last cell's index
        Frame(const Box& b, const int res[3]) : box(b), n(res) {
            for (int a = 0; a < 3; ++a) {
                cell[a] = (b.hi[a] - b.lo[a]) / res[a];
                reach_lo[a] = b.lo[a] - 1e-3 * cell[a];
                reach_hi[a] = b.hi[a] + 1e-3 * cell[a];
                const double magnitude = std::max(std::abs(b.lo[a]), std::abs(b.hi[a]));
                pad[a] = 1e-3 + 4e-7 * double(res[a]) + kCoordinateRounding * magnitude / cell[a];
                top[a] = double(res[a] - 1);
            }
        }
    };

    // Cells overlapped by b (clipped to the node), inflated by 1/1000 of a
    // cell plus the float rounding of a cell coordinate and of the absolute
    // coordinate (a few float spacings at the box's magnitude, which far from
    // the origin can be a good part of a small cell), so that a primitive
    // touching a cell face within rounding error is listed on both sides.
    static bool cell_range(const Bounds& b, const Frame& f, int c0[3], int c1[3], double pad_out[3] = nullptr,
                           bool* inside = nullptr) {
        if (inside) *inside = true;
        for (int a = 0; a < 3; ++a) {
            if (double(b.hi[a]) < f.reach_lo[a] || double(b.lo[a]) > f.reach_hi[a]) return false;
            const double x0 = (double(b.lo[a]) - f.box.lo[a]) / f.cell[a] - f.pad[a];
            const double x1 = (double(b.hi[a]) - f.box.lo[a]) / f.cell[a] + f.pad[a];
            c0[a] = int(std::min(std::max(x0, 0.0), f.top[a]));
            c1[a] = int(std::min(std::max(x1, 0.0), f.top[a]));
            if (pad_out) pad_out[a] = f.pad[a] * f.cell[a];
            if (inside && (x0 < 0 || x1 >= double(f.n[a]))) *inside = false;   // clipped to the grid
        }
        return true;
    }

    // The cells each of a node's primitives meets (for_cells), recorded once
    // and read by both passes that fill the node's lists: one part per range
    // of the primitives (several where threads found them).
    struct CellLists {
        size_t begin = 0;              // the part's first primitive (position in the node's list)
        std::vector<uint32_t> first;   // per primitive of the part: start in cells (and the end)
        std::vector<uint32_t> cells;   // linear cell indices
    };
    static constexpr size_t kPrimsPerPart = size_t(1) << 14;   // (fewer: found on the calling thread alone)
    // find_cells' parts: a primitive's cells cost about 30 times its bounds'
    // cell range (the passes above), so its parts are that much smaller.
    static constexpr size_t kFoundPrimsPerPart = size_t(1) << 9;
    static constexpr size_t kBoundPrims = 4096;   // fewer: no fewest_cells pass (node())
    static constexpr size_t kSamplePrims = 16;    // a refining grid's sample (sampled_refs), from twice as many
    static constexpr size_t kSmallGrid = 32;      // fewer primitives: a refining grid starts at one cell per primitive

    // Records the cells of a grid of resolution n over box that each
    // primitive meets; returns their total, or stops (returning more than
    // limit, with out incomplete) once past limit. A node that may fan out
    // (the root, mostly) and has many primitives has them found in parts by
    // in_.threads threads: the same cells, in the same order.
    uint64_t find_cells(const Box& box, const std::vector<uint32_t>& prims, const int n[3], uint64_t limit,
                        std::vector<CellLists>& out) {
        const Frame frame(box, n);
        const size_t parts = may_fan_out_ && in_.threads > 1 && prims.size() >= 2 * kFoundPrimsPerPart
                                 ? std::min<size_t>(size_t(in_.threads) * 8, prims.size() / kFoundPrimsPerPart)
                                 : 1;
        out.assign(parts, CellLists());
        std::atomic<uint64_t> found{0};   // cells recorded by finished parts
        auto find = [&](size_t k, uint64_t& step) {
            CellLists part;   // (filled here, then moved into out: parts side by side in out share cache lines)
            part.begin = prims.size() * k / parts;
            const size_t end = prims.size() * (k + 1) / parts;
            part.first.reserve(end - part.begin + 1);
            part.first.push_back(0);
            for (size_t i = part.begin; i < end; ++i) {
                for_cells(prims[i], frame, step, [&](uint64_t c) { part.cells.push_back(uint32_t(c)); });
                part.first.push_back(uint32_t(part.cells.size()));
                if (part.cells.size() + found.load(std::memory_order_relaxed) > limit) break;
            }
            found += part.cells.size();
            out[k] = std::move(part);
        };
        if (parts == 1) {
            find(0, step_);
            return out[0].cells.size();
        }
        OrderedTasks tasks(parts, in_.threads, [&](size_t k) { uint64_t step = 0; find(k, step); }, "gridwalk-build");
        build_threads_ = std::max(build_threads_, tasks.threads());
        uint64_t total = 0;
        for (size_t k = 0; k < parts; ++k) {
            tasks.wait(k);
            total += out[k].cells.size();
        }
        return total;
    }

    // A lower bound on the cells of a grid of resolution n over box that the
    // primitives meet (on what find_cells would count), or a number above
    // limit once past it: a connected primitive whose bounds lie inside the
    // grid meets a cell in every slab its bounds span along each axis (the
    // cell holding its point in that slab, whose padded box meets it). Asked
    // before find_cells, it turns a grid far too fine for its primitives down
    // in one cheap pass, where find_cells would walk every cell of their
    // bounds (a million long thin triangles across the scene: 6 times
    // Embree's build, one failed resolution after the other).
    // (On `threads` threads, each adding up a range of the primitives.)
    uint64_t fewest_cells(const Box& box, const std::vector<uint32_t>& prims, const int n[3], uint64_t limit,
                          int threads) {
        const Frame frame(box, n);
        std::atomic<uint64_t> sum{0};   // of the ranges finished
        for_each_range(prims.size(), threads, kPrimsPerPart, [&](size_t i0, size_t i1) {
            uint64_t step = 0, total = 0;
            for (size_t i = i0; i < i1; ++i) {
                check_cancel(cancel_, step);
                int c0[3], c1[3];
                bool inside;
                if (!cell_range(bounds_[prims[i]], frame, c0, c1, nullptr, &inside) || !inside) continue;
                total += uint64_t(std::max(std::max(c1[0] - c0[0], c1[1] - c0[1]), c1[2] - c0[2]) + 1);
                if (total + sum.load(std::memory_order_relaxed) > limit) break;
            }
            sum += total;
        }, "gridwalk-build");
        return sum.load();
    }

    // The references of kSamplePrims primitives spread evenly over prims
    // (every prims.size() / kSamplePrims-th) in the grid (box, n), scaled to
    // all of prims: a guess at what find_cells would count, from a sixteenth
    // of its work where prims holds 256.
    uint64_t sampled_refs(const Box& box, const std::vector<uint32_t>& prims, const int n[3]) {
        const Frame frame(box, n);
        uint64_t found = 0;
        for (size_t k = 0; k < kSamplePrims; ++k)
            for_cells(prims[k * prims.size() / kSamplePrims], frame, step_, [&](uint64_t) { ++found; });
        return found * prims.size() / kSamplePrims;
    }

    // Whether the long primitives (bounds spanning over a quarter of the box
    // along some axis) lie spread across the cells of a grid dividing the
    // stack (cells_of: the cells each of prims meets): no cell meets more
    // than a quarter of them. Floors in a thin band amid small clutter fail
    // it: there the layers would hold the band in one or two cells while rays
    // cross hundreds of layers of the clutter (0.07 s -> 0.43 s for 20,000
    // random rays, with 2,000 quads within 0.1% of the box's height among
    // 20,000 small triangles, where the cubic grid's tests of the band were
    // the lesser cost).
    bool spread_across(const Box& box, const std::vector<uint32_t>& prims, const std::vector<CellLists>& cells_of,
                       uint64_t ncells) const {
        std::vector<uint32_t> count(ncells, 0);
        uint64_t longs = 0, most = 0, step = 0;
        for (const CellLists& part : cells_of)
            for (size_t j = 0; j + 1 < part.first.size(); ++j) {
                check_cancel(cancel_, step, 1 + part.first[j + 1] - part.first[j]);
                if (!is_long(bounds_[prims[part.begin + j]], box)) continue;
                ++longs;
                for (uint32_t k = part.first[j]; k < part.first[j + 1]; ++k)
                    most = std::max<uint64_t>(most, ++count[part.cells[k]]);
            }
        return 4 * most <= longs;
    }

    // Builds the node over `box` holding `prims`; returns its index, or -1
    // when refining would not separate the primitives (the caller keeps a leaf).
    int64_t node(const Box& box, const std::vector<uint32_t>& prims, int depth) {
        // The threads of this node's own per-cell passes: all of them above the
        // structures built side by side (where one node runs at a time), one in those.
        const int pass_threads = may_fan_out_ ? in_.threads : 1;
        // The finest resolution up to the density whose references stay within
        // max_refs_per_prim per primitive: primitives as large as the cells
        // would otherwise be listed in many of them.
        // (A small refining grid starts at one cell per primitive: on a
        // mesh's surface, most of them, 9 to 31 triangles crowding a cell,
        // list too many references at sub_density's two, and every such grid
        // paid a full pass over its primitives' cells for nothing. Suzanne
        // PLY: 204 of 272 grids under 32 primitives.)
        double density = depth > 0 && prims.size() < kSmallGrid ? std::min(p_.sub_density, 1.0) : p_.sub_density;
        if (depth == 0)   // (the root's cells stay within root_cells)
            density = std::min(p_.root_density, double(p_.root_cells) / double(std::max<size_t>(prims.size(), 1)));
        // (Also below 2^32: CellLists' offsets are 32-bit. Only a node of
        // over 1.4e9 primitives reaches that, and takes a coarser grid.)
        constexpr uint64_t kMostRefs = 0xFFFFFFFFull - (1ull << 27);
        uint64_t allowed = std::min<uint64_t>(uint64_t(p_.max_refs_per_prim * double(prims.size())), kMostRefs);
        // The finest resolution dividing `axes`, from density d down, whose
        // references stay within `allowed`: into res, with their number into
        // refs (and the cells into cells_of, with `found_cells` set, where
        // they were found); returns its density, 0 where none fitted (res then
        // stays as it was; a grid of one cell lists every primitive once).
        auto search = [&](unsigned axes, double d, int res[3], uint64_t& refs, std::vector<CellLists>& cells_of,
                          bool& found_cells) {
            int last[3] = {0, 0, 0};
            refs = prims.size();
            for (int attempt = 0; attempt < 64; ++attempt, d *= 0.5) {
                int m[3];
                resolution(box, prims.size(), d, m, axes, depth > 0);
                if (uint64_t(m[0]) * m[1] * m[2] <= 1) {
                    std::copy(m, m + 3, res);
                    return d;
                }
                // (One capped at kMaxResolution along an axis can repeat: tried already.)
                const bool same = std::equal(m, m + 3, last);
                std::copy(m, m + 3, last);
                if (same) continue;
                // A refining grid whose sample of primitives already needs more
                // references than allowed takes the next resolution without the
                // full pass. (Of a scene of 90,000 icospheres of 80 triangles
                // scattered on a floor, 89,000 grids refining the root's cells
                // tried 3.2 resolutions each, most failing by 0-50%, and
                // find_cells took 61% of the build.)
                if (depth > 0 && prims.size() >= 2 * kSamplePrims && sampled_refs(box, prims, m) > allowed) {
                    if (d * double(prims.size()) < 1) break;
                    continue;
                }
                // (The bound first only for a grid of many primitives on the top two
                // levels, where a failed resolution costs most: elsewhere its pass
                // would cost more than it saves.)
                if (depth > 1 || prims.size() < kBoundPrims ||
                    fewest_cells(box, prims, m, allowed, pass_threads) <= allowed) {
                    const uint64_t total = find_cells(box, prims, m, allowed, cells_of);
                    if (total <= allowed) {
                        std::copy(m, m + 3, res);
                        refs = total;
                        found_cells = true;
                        return d;
                    }
                }
                if (d * double(prims.size()) < 1) break;   // even one cell per primitive in all is too fine
            }
            return 0.0;
        };
        int n[3] = {1, 1, 1};
        uint64_t refs = 0;
        std::vector<CellLists> met;
        bool recorded = false;   // met holds the cells of resolution n
        double found = search(7, density, n, refs, met, recorded);
        // Cubic cells held back to a quarter of the density or less by the
        // references of long primitives (a stack of floors, shelves or slats
        // lists each in a whole layer of cells): a grid dividing only the
        // axes few of them are long along, where its cells hold a quarter as
        // many primitives or fewer, on average (the layers of a terrain's
        // cells, which its triangles cross, are not taken), and the long
        // primitives lie spread across it (spread_across).
        if (found <= 0.25 * density) {
            const unsigned axes = thin_axes(box, prims);
            if (axes != 7) {
                int m[3] = {1, 1, 1};
                uint64_t m_refs = 0;
                std::vector<CellLists> m_met;
                bool m_recorded = false;
                const double m_found = search(axes, density, m, m_refs, m_met, m_recorded);
                const double cells = double(n[0]) * n[1] * n[2], m_cells = double(m[0]) * m[1] * m[2];
                if (m_recorded && double(m_refs) / m_cells <= 0.25 * double(refs) / cells &&
                    spread_across(box, prims, m_met, uint64_t(m_cells))) {
                    std::copy(m, m + 3, n);
                    met.swap(m_met);
                    recorded = m_recorded;
                    found = m_found;
                    refs = m_refs;
                }
            }
        }
        // A crowded root: the reference cap held it to 1/128 of its density or
        // less, and its cells still average over 4 leaves' worth of references (the
        // triangles of a fan all meeting its centre, a stack of long quads that
        // no axis-aligned cut separates). Refining such cells fails alike, and
        // every ray tests hundreds or thousands of primitives (1,000 quads tilted
        // 45 degrees: a root of one cell, 2,000 tests per ray). It may then list
        // crowded_refs_per_prim references per primitive, within crowded_refs in
        // all (1 MiB of them; gridwalk.memory counts what that may add below),
        // where that at least doubles what it may list.
        // (docs/architecture.md, "Crowded roots", has the measurements.)
        if (depth == 0 && 128 * found <= density && double(refs) > 4.0 * p_.leaf_size * double(n[0]) * n[1] * n[2]) {
            const uint64_t more = std::min<uint64_t>(
                uint64_t(std::min(p_.crowded_refs_per_prim * double(prims.size()), double(p_.crowded_refs))), kMostRefs);
            if (more >= 2 * allowed) {   // (a smaller raise cut tests by a sixth on 60,000 slivers, not time)
                allowed = more;   // (search reads it)
                int m[3] = {1, 1, 1};
                uint64_t m_refs = 0;
                std::vector<CellLists> m_met;
                bool m_recorded = false;
                const double m_found = search(7, density, m, m_refs, m_met, m_recorded);
                if (m_recorded && double(m[0]) * m[1] * m[2] > double(n[0]) * n[1] * n[2]) {
                    std::copy(m, m + 3, n);
                    met.swap(m_met);
                    recorded = m_recorded;
                    found = m_found;
                }
            }
        }
        if (depth == 0) root_density_ = found;
        const uint64_t ncells = uint64_t(n[0]) * n[1] * n[2];
        if (depth > 0 && ncells <= 1) return -1;
        const Frame frame(box, n);
        const double* cell = frame.cell;
        // Large primitives: those covering more cells than big_cells; the node
        // tests them once per ray, at most big_max of them, the widest: a
        // room's walls and a few panels, a ground plane, the glass spheres
        // over SPD's mountain. Where those big_max cover less than half of
        // what all the large ones cover (a building's floors and walls: 468
        // at layouts.md's building's root, about 100 with two floors), only
        // those covering a sixteenth of the cells or more: big_max picked
        // among many alike would be a list every ray tests wherever it is
        // (18 tests per camera ray in the building, 2 without, 1.3x as fast;
        // 20 and 4 with two floors, 1.27x), where 16 of a room's 18 walls and
        // panels hold most of them (without the list, random rays in such a
        // room were 0.80-0.85x as fast).
        std::vector<uint32_t> big;
        {
            std::vector<std::pair<uint64_t, uint32_t>> wide;   // (in any order: sorted below)
            std::mutex wide_mu;
            for_each_range(prims.size(), pass_threads, kPrimsPerPart, [&](size_t i0, size_t i1) {
                uint64_t step = 0;
                std::vector<std::pair<uint64_t, uint32_t>> found;
                for (size_t i = i0; i < i1; ++i) {
                    check_cancel(cancel_, step);
                    int c0[3], c1[3];
                    if (!cell_range(bounds_[prims[i]], frame, c0, c1)) continue;
                    const uint64_t covered =
                        uint64_t(c1[0] - c0[0] + 1) * uint64_t(c1[1] - c0[1] + 1) * uint64_t(c1[2] - c0[2] + 1);
                    if (covered > uint64_t(p_.big_cells)) found.emplace_back(covered, prims[i]);
                }
                std::lock_guard<std::mutex> lock(wide_mu);
                wide.insert(wide.end(), found.begin(), found.end());
            }, "gridwalk-build");
            if (!wide.empty()) {
                std::sort(wide.begin(), wide.end(), [](const auto& x, const auto& y) {
                    return x.first != y.first ? x.first > y.first : x.second < y.second;
                });
                size_t keep = std::min(wide.size(), size_t(p_.big_max));
                uint64_t kept = 0, all = 0;   // cells covered by the widest big_max, and by all of them
                for (size_t i = 0; i < wide.size(); ++i) (i < keep ? kept : all) += wide[i].first;
                all += kept;
                if (2 * kept < all)   // (the widest are a small part of the set)
                    for (keep = 0; keep < size_t(p_.big_max) && 16 * wide[keep].first >= ncells;) ++keep;
                wide.resize(keep);
                for (const auto& w : wide) big.push_back(w.second);
                std::sort(big.begin(), big.end());
            }
        }
        if (g_.cells.size() + ncells > max_cells_) {
            if (depth > 0) return -1;
            throw std::invalid_argument("adaptive grid: the cell cap is too small for the root grid");
        }
        if (!recorded) find_cells(box, prims, n, UINT64_MAX, met);
        // The cells of prims[i] (not a large primitive): part.cells[part.first[j] .. part.first[j + 1]),
        // i = part.begin + j.
        auto each_rest = [&](auto&& f) {
            for (const CellLists& part : met)
                for (size_t j = 0; j + 1 < part.first.size(); ++j) {
                    const uint32_t prim = prims[part.begin + j];
                    check_cancel(cancel_, step_, 1 + part.first[j + 1] - part.first[j]);
                    if (!big.empty() && std::binary_search(big.begin(), big.end(), prim)) continue;
                    for (uint32_t k = part.first[j]; k < part.first[j + 1]; ++k) f(prim, part.cells[k]);
                }
        };
        // Pass 1: count references per cell.
        std::vector<uint32_t> count;
        assign_checked(count, ncells + 1, 0u, cancel_, step_);
        uint64_t total = 0;
        each_rest([&](uint32_t, uint32_t c) { ++count[c]; ++total; });
        uint32_t most = 0;
        for (uint64_t c = 0; c < ncells; ++c) {
            check_cancel(cancel_, step_);
            most = std::max(most, count[c]);
        }
        // Refining is useless when a cell still holds most of the primitives.
        if (depth > 0 && double(most) >= 0.75 * double(prims.size())) return -1;
        if (total + g_.refs.size() > max_refs_) {
            if (depth > 0) return -1;
            throw std::invalid_argument("adaptive grid: too many primitive references for the reference cap");
        }
        // Pass 2: fill per-cell lists (CSR).
        std::vector<uint32_t> start;
        assign_checked(start, ncells + 1, 0u, cancel_, step_);
        for (uint64_t c = 0; c < ncells; ++c) {
            check_cancel(cancel_, step_);
            start[c + 1] = start[c] + count[c];
            count[c] = start[c];
        }
        std::vector<uint32_t> list;
        assign_checked(list, total, 0u, cancel_, step_);
        each_rest([&](uint32_t prim, uint32_t c) { list[count[c]++] = prim; });
        std::vector<CellLists>().swap(met);   // (freed before the children are built)
        // The node, and its cells (filled below; children append after them).
        const uint32_t index = uint32_t(g_.nodes.size());
        AdaptiveGridData::Node nd;
        for (int a = 0; a < 3; ++a) {
            nd.lo[a] = float(box.lo[a]);
            nd.hi[a] = float(box.hi[a]);
            nd.cell[a] = float(box.hi[a] - box.lo[a]) / float(n[a]);
            nd.inv_cell[a] = float(n[a]) / float(box.hi[a] - box.lo[a]);
            nd.n[a] = n[a];
            nd.lo_d[a] = double(nd.lo[a]);
            nd.cell_d[a] = double(nd.cell[a]);
            nd.inv_cell_d[a] = double(nd.inv_cell[a]);
            nd.last_d[a] = double(n[a] - 1);
        }
        nd.stride[0] = 1;
        nd.stride[1] = n[0];
        nd.stride[2] = int64_t(n[0]) * n[1];
        nd.first = uint32_t(g_.cells.size());
        nd.big = nd.big_count = 0;
        nd.big_lo = nd.big_hi = nd.big_clip_lo = nd.big_clip_hi = Vec3(0, 0, 0);
        nd.big_boxed = false;
        if (!big.empty()) {
            const AdaptiveGridData::Cell list_cell = leaf(big.data(), uint32_t(big.size()));
            nd.big = list_cell.a;
            nd.big_count = list_cell.b;
            Bounds all;   // (primitive bounds are rounded outwards: they hold the primitive)
            for (uint32_t prim : big) all.grow(bounds_[prim]);
            nd.big_lo = all.lo;
            nd.big_hi = all.hi;
            const double lo[3] = {all.lo.x, all.lo.y, all.lo.z}, hi[3] = {all.hi.x, all.hi.y, all.hi.z};
            grow_outwards(lo, hi, box_pad(cell), nd.big_clip_lo, nd.big_clip_hi);
            // Worth a box check for closest-hit rays too where the list is
            // costly to test (a quadric, tested in double, or more than 4
            // triangles) and its box is small beside the node's (by surface
            // area: the chance that a ray through the node meets it).
            const uint32_t ntri = g_.refs[list_cell.a];
            auto area = [](const Vec3& lo, const Vec3& hi) {
                const double x = double(hi.x) - lo.x, y = double(hi.y) - lo.y, z = double(hi.z) - lo.z;
                return x * y + y * z + z * x;
            };
            nd.big_boxed = (ntri < list_cell.b || ntri > 4) && area(all.lo, all.hi) < 0.5 * area(nd.lo, nd.hi);
        }
        g_.nodes.push_back(nd);
        grow_checked(g_.cells, g_.cells.size() + ncells, AdaptiveGridData::Cell{0, 0}, cancel_, step_);
        // The occupied cells, and of those the crowded ones to refine: deeper
        // down, only much more crowded ones (leaf_size x 4^depth), since each
        // level multiplies references. A quadric counts as kQuadricCost
        // triangles: it is tested alone, in double, where triangles share SIMD tests.
        std::vector<uint8_t> occupied;
        assign_checked(occupied, ncells, uint8_t(0), cancel_, step_);
        std::vector<uint64_t> refine;   // cells, in order
        uint64_t leaf_refs = 0;         // the references of all occupied cells as leaves
        for (uint64_t c = 0; c < ncells; ++c) {
            check_cancel(cancel_, step_);
            const uint32_t b = start[c], e = start[c + 1];
            if (b == e) continue;
            occupied[c] = 1;
            leaf_refs += 1 + e - b;
            uint64_t cost = 0;
            for (uint32_t k = b; k < e; ++k) cost += list[k] < nt_ ? 1 : kQuadricCost;
            if (cost > (uint64_t(p_.leaf_size) << (2 * depth)) && depth < p_.max_depth) refine.push_back(c);
        }
        // The refined cells of the first node (depth first) with several and
        // none holding 3/4 of their primitives (the root, mostly; else the cell
        // that does, and so on down) are built as structures of their own, on
        // in_.threads threads, each within a share of the caps left after this
        // node proportional to its primitives (this node's cells each keep room
        // for a leaf), then copied in, in cell order: the whole does not depend on the number of
        // threads or on the order the cells finish in. Above that node, and
        // inside each of those structures, cells are refined in place.
        std::vector<AdaptiveGridData> parts;
        uint64_t weight = 0, heaviest = 0;
        for (uint64_t c : refine) {
            weight += start[c + 1] - start[c];
            heaviest = std::max<uint64_t>(heaviest, start[c + 1] - start[c]);
        }
        const bool fan_out = may_fan_out_ && refine.size() >= 2 && 4 * heaviest <= 3 * weight;
        uint64_t cells_left = 0, refs_left = 0;
        auto share = [&](uint64_t left, uint64_t c) {   // refined cell c's share of what is left
            return uint64_t(double(left) * (double(start[c + 1] - start[c]) / double(weight)));
        };
        if (fan_out) {
            may_fan_out_ = false;
            cells_left = max_cells_ - std::min(max_cells_, uint64_t(g_.cells.size()));
            refs_left = max_refs_ - std::min(max_refs_, g_.refs.size() + leaf_refs);
        }
        std::unique_ptr<OrderedTasks> tasks;   // (after all it reads: joined before they go, however this ends)
        if (fan_out && in_.threads > 1) {
            parts.resize(refine.size());
            tasks = std::make_unique<OrderedTasks>(refine.size(), in_.threads, [&](size_t k) {
                const uint64_t c = refine[k], b = start[c], e = start[c + 1];
                AdaptiveGridData built;   // (moved into parts when done: no cache line shared while it grows)
                Builder part(in_, built, share(cells_left, c), share(refs_left, c));
                part.may_fan_out_ = false;
                const std::vector<uint32_t> sub(list.begin() + b, list.begin() + e);
                check_cancel(cancel_, part.step_, 4 * sub.size());   // the copy and the box below
                // (node() < 0 added nothing: refining would not separate them)
                if (part.node(child_box(bounds_, box, cell, n, c, sub.data(), sub.size()), sub, depth + 1) >= 0)
                    parts[k] = std::move(built);
            }, "gridwalk-build");
            build_threads_ = std::max(build_threads_, tasks->threads());
        }
        if (tasks) {
            for (size_t k = 0; k < refine.size(); ++k) tasks->wait(k);   // (the caller's thread helps)
            tasks.reset();
            place_parts(nd.first, occupied, start, list, refine, parts, pass_threads);
        } else {
            std::vector<uint32_t> sub;
            size_t next_refine = 0;
            for (uint64_t c = 0; c < ncells; ++c) {
                check_cancel(cancel_, step_);
                if (!occupied[c]) continue;
                const uint32_t b = start[c], e = start[c + 1];
                AdaptiveGridData::Cell out{0, 0};
                if (next_refine < refine.size() && refine[next_refine] == c) {
                    sub.assign(list.begin() + b, list.begin() + e);
                    check_cancel(cancel_, step_, 4 * sub.size());   // the copy and the box below
                    // (On one thread, a fanned-out cell is built in place within the
                    // same share as on several: the same decisions, the same grid.
                    // Otherwise only a cell holding 3/4 of the primitives may fan out below.)
                    const uint64_t caps[2] = {max_cells_, max_refs_};
                    if (fan_out) {
                        max_cells_ = g_.cells.size() + share(cells_left, c);
                        max_refs_ = g_.refs.size() + share(refs_left, c);
                    }
                    const bool allowed = may_fan_out_, dominant = 4 * uint64_t(e - b) > 3 * weight;
                    may_fan_out_ = allowed && dominant;
                    const int64_t child =
                        node(child_box(bounds_, box, cell, n, c, sub.data(), sub.size()), sub, depth + 1);
                    if (!dominant) may_fan_out_ = allowed;
                    max_cells_ = caps[0];
                    max_refs_ = caps[1];
                    ++next_refine;
                    if (child >= 0) out = AdaptiveGridData::Cell{uint32_t(child), AdaptiveGridData::kChild};
                }
                if (out.b == 0) out = leaf(list.data() + b, e - b);
                g_.cells[nd.first + c] = out;
            }
        }
        // Empty cells: the box of empty cells around each, for jumps.
        const std::vector<uint32_t> boxes = empty_boxes(occupied, n, p_.max_box_cells, cancel_, pass_threads);
        for (uint64_t c = 0; c < ncells; ++c) {
            check_cancel(cancel_, step_);
            if (!occupied[c]) g_.cells[nd.first + c].a = boxes[c];
        }
        return index;
    }

    // Calls f(linear cell index) for each cell of the grid (box, n) that prim
    // meets: the cells its bounds overlap (cell_range), and of those, where
    // there are several, the ones whose padded box the primitive itself meets
    // (overlap.h). The padding is cell_range's, so that a hit found in a cell
    // by the walk's rounded arithmetic is in a cell that lists the primitive.
    // (step: the calling thread's count for check_cancel.)
    template <class F>
    void for_cells(uint32_t prim, const Frame& frame, uint64_t& step, F&& f) const {
        check_cancel(cancel_, step);
        const Box& box = frame.box;
        const double* cell = frame.cell;
        const int* n = frame.n;
        int c0[3], c1[3];
        double pad[3];
        bool inside;
        if (!cell_range(bounds_[prim], frame, c0, c1, pad, &inside)) return;
        auto each = [&](auto&& meets) {
            double m[3];   // a cell's centre
            for (int z = c0[2]; z <= c1[2]; ++z) {
                check_cancel(cancel_, step, 8 * uint64_t(c1[1] - c0[1] + 1) * uint64_t(c1[0] - c0[0] + 1));
                m[2] = box.lo[2] + (z + 0.5) * cell[2];
                for (int y = c0[1]; y <= c1[1]; ++y) {
                    m[1] = box.lo[1] + (y + 0.5) * cell[1];
                    for (int x = c0[0]; x <= c1[0]; ++x) {
                        m[0] = box.lo[0] + (x + 0.5) * cell[0];
                        if (meets(m)) f((uint64_t(z) * n[1] + y) * n[0] + x);
                    }
                }
            }
        };
        double half[3];
        for (int a = 0; a < 3; ++a) half[a] = 0.5 * cell[a] + pad[a];
        // A connected primitive whose bounds, unclipped, are one cell thick
        // along two axes meets every cell of its range (it spans the third
        // axis continuously, within the one cell along the others).
        // (Cones are listed by their bounds.)
        if ((inside && int(c0[0] != c1[0]) + int(c0[1] != c1[1]) + int(c0[2] != c1[2]) <= 1) ||
            sc_.kind_of(prim) == PrimKind::Cone) {
            each([](const double*) { return true; });
        } else if (prim < nt_) {
            const Vec3* v = sc_.triangle_vertices() + 3 * size_t(prim);
            const TriangleBoxTest test(v[0], v[1], v[2], half);
            each([&](const double* m) { return test.meets(m); });
        } else {
            const size_t s = sc_.local_index(prim);
            const Vec3& c = sc_.sphere_center(s);
            const float r = sc_.sphere_radius(s);
            each([&](const double* m) { return sphere_meets_box(c, r, m, half); });
        }
    }

    // Puts the structures of the refined cells built side by side (parts[k],
    // refined cell refine[k]; an empty one adds nothing: the cell stays a
    // leaf) and the leaves of the node's other occupied cells into g_, in
    // cell order, as building in place does: the offsets first, in one pass,
    // then the copies on `threads` threads, by runs of cells holding equal
    // shares of what is copied; each part is freed once copied.
    // first: the node's cell (0, 0, 0) in g_.cells.
    void place_parts(uint32_t first, const std::vector<uint8_t>& occupied, const std::vector<uint32_t>& start,
                     const std::vector<uint32_t>& list, const std::vector<uint64_t>& refine,
                     std::vector<AdaptiveGridData>& parts, int threads) {
        const uint64_t ncells = occupied.size();
        std::vector<Place> places(parts.size());
        std::vector<uint32_t> leaf_at;   // per leaf cell: its list's place in refs
        assign_checked(leaf_at, ncells, 0u, cancel_, step_);
        // Per occupied cell: the cells and references of the cells up to it
        // (itself included), where the copying is cut into runs.
        std::vector<uint64_t> done_at;
        assign_checked(done_at, ncells, uint64_t(0), cancel_, step_);
        const uint64_t cells0 = g_.cells.size(), refs0 = g_.refs.size();
        uint64_t nodes = g_.nodes.size(), cells = cells0, refs = refs0;
        for (uint64_t c = 0, k = 0; c < ncells; ++c) {
            check_cancel(cancel_, step_);
            if (!occupied[c]) continue;
            const AdaptiveGridData* part = k < refine.size() && refine[k] == c ? &parts[k++] : nullptr;
            if (part && !part->nodes.empty()) {
                places[k - 1] = Place{uint32_t(nodes), uint32_t(cells), uint32_t(refs)};
                nodes += part->nodes.size();
                cells += part->cells.size();
                refs += part->refs.size();
            } else {   // (an empty part: the cell stays a leaf)
                leaf_at[c] = uint32_t(refs);
                refs += 1 + start[c + 1] - start[c];
            }
            done_at[c] = (cells - cells0) + (refs - refs0);
        }
        g_.nodes.resize(nodes);
        grow_checked(g_.cells, cells, AdaptiveGridData::Cell{0, 0}, cancel_, step_);
        grow_checked(g_.refs, refs, 0u, cancel_, step_);
        // Runs of cells with equal shares of the copying (one where it is little).
        const uint64_t work = (cells - cells0) + (refs - refs0);
        const uint64_t runs = threads > 1 ? std::max<uint64_t>(1, std::min<uint64_t>(4 * uint64_t(threads),
                                                                                         work / kCellsPerRange))
                                          : 1;
        std::vector<uint64_t> cuts{0};   // run j: cells cuts[j] .. cuts[j + 1]
        for (uint64_t c = 0; c < ncells && cuts.size() < runs; ++c) {
            check_cancel(cancel_, step_);
            if (occupied[c] && done_at[c] * runs >= work * cuts.size()) cuts.push_back(c + 1);
        }
        if (cuts.back() != ncells) cuts.push_back(ncells);
        for_each_range(cuts.size() - 1, threads, 1, [&](size_t j0, size_t j1) {
            uint64_t step = 0;
            const uint64_t c0 = cuts[j0], c1 = cuts[j1];
            size_t k = size_t(std::lower_bound(refine.begin(), refine.end(), c0) - refine.begin());
            for (uint64_t c = c0; c < c1; ++c) {
                if (!occupied[c]) continue;
                const uint32_t b = start[c], e = start[c + 1];
                check_cancel(cancel_, step, 2 * uint64_t(e - b));
                if (k < refine.size() && refine[k] == c) {
                    AdaptiveGridData& part = parts[k++];
                    if (!part.nodes.empty()) {
                        copy_part(g_, part, places[k - 1], cancel_, step);
                        g_.cells[first + c] = AdaptiveGridData::Cell{places[k - 1].node, AdaptiveGridData::kChild};
                        part = AdaptiveGridData();   // (freed as it goes)
                        continue;
                    }
                }
                fill_leaf(list.data() + b, e - b, nt_, g_.refs.data() + leaf_at[c]);
                g_.cells[first + c] = AdaptiveGridData::Cell{leaf_at[c], e - b};
            }
        }, "gridwalk-build");
    }

    // A leaf: refs gets [number of triangles, triangles..., quadrics...].
    AdaptiveGridData::Cell leaf(const uint32_t* ids, uint32_t count) {
        const uint32_t at = uint32_t(g_.refs.size());
        check_cancel(cancel_, step_, 2 * uint64_t(count));
        g_.refs.resize(g_.refs.size() + count + 1);
        fill_leaf(ids, count, nt_, g_.refs.data() + at);
        return AdaptiveGridData::Cell{at, count};
    }

    const BuildInput& in_;
    const Scene& sc_;
    const AdaptiveParams& p_;
    AdaptiveGridData& g_;
    const CancelToken* cancel_;
    const std::vector<Bounds>& bounds_;
    uint64_t max_cells_, max_refs_;   // (lowered while a fanned-out cell is built in place)
    uint64_t step_ = 0;   // for check_cancel
    const uint32_t nt_ = uint32_t(sc_.num_triangles());   // primitives below this index are triangles
    bool may_fan_out_ = true;   // no node above has built its refined cells as separate structures
    int build_threads_ = 1;
    double root_density_ = 0;   // cells per primitive the root was built for (0: one cell, no density fitted)
    bool too_few_spacings_ = false;
};

}  // namespace

AdaptiveGrid::AdaptiveGrid(std::shared_ptr<const Scene> s, const AdaptiveParams& p, const CancelToken* cancel)
    : Accel(std::move(s)) {
    const auto t_start = std::chrono::steady_clock::now();
    if (p.max_depth < 0 || p.max_depth > kMaxGridDepth)
        throw std::invalid_argument("adaptive grid: at most " + std::to_string(kMaxGridDepth) + " refining levels");
    BuildInput in{*scene_, p, cancel, {}, std::max(p.threads, 1)};
    const size_t n = scene_->num_prims();
    in.bounds.resize(n);
    uint64_t step = 0;
    for (size_t i = 0; i < n; ++i) {
        check_cancel(cancel, step);
        in.bounds[i] = scene_->prim_bounds(i);
    }
    Builder b(in, g_, p.max_cells, p.max_refs);
    b.build();
    info_.build_threads = b.build_threads();
    too_few_spacings_ = b.too_few_spacings();
    width_ = cpu_has_avx2() ? 8 : 4;
    const AdaptiveGridData::Node& root = g_.nodes[0];
    const AdaptiveGridData::Cell& first = g_.cells[root.first];
    one_leaf_ = root.n[0] == 1 && root.n[1] == 1 && root.n[2] == 1 && root.big_count == 0 &&
                first.b == scene_->num_prims() && first.b != AdaptiveGridData::kChild;
    for (int a = 0; a < 3; ++a) info_.n[a] = root.n[a];
    info_.cells = g_.cells.size();
    info_.refs = g_.refs.size();
    info_.bytes = g_.nodes.size() * sizeof(AdaptiveGridData::Node) + g_.cells.size() * sizeof(AdaptiveGridData::Cell) +
                  g_.refs.size() * sizeof(uint32_t);
    g_.prefetch = info_.bytes >= AdaptiveGridData::kPrefetchBytes;
    info_.density_requested = p.root_density;
    info_.density_used = b.root_density();
    info_.kind = "adaptive grid";
    info_.grids = g_.nodes.size();
    info_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
}

bool AdaptiveGrid::closest(const RayPre& r, Hit& hit, TraceContext& ctx) const {
    if (one_leaf_) {
        ++ctx.stats.cells;
        return closest_of_all(*scene_, r, hit, ctx);
    }
    const Vec3* tv = scene_->triangle_vertices();
#ifdef GW_HAVE_AVX2_WALK
    if (width_ == 8) return walk_avx2::closest(g_, *scene_, tv, r, hit, ctx);
#endif
    return walk_portable::closest(g_, *scene_, tv, r, hit, ctx);
}

bool AdaptiveGrid::occluded(const RayPre& r, TraceContext& ctx) const {
    if (one_leaf_) {
        ++ctx.stats.cells;
        return occluded_by_any(*scene_, r, ctx);
    }
    Hit hit;
    hit.t = r.ray.tmax;
    const Vec3* tv = scene_->triangle_vertices();
#ifdef GW_HAVE_AVX2_WALK
    if (width_ == 8) return walk_avx2::occluded(g_, *scene_, tv, r, hit, ctx);
#endif
    return walk_portable::occluded(g_, *scene_, tv, r, hit, ctx);
}

}  // namespace gw
