// Batched ray queries. See batch.h.
#include "batch.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

#include "offset.h"
#include "threads.h"

namespace gw {
namespace {

inline double sq(double x) { return x * x; }

// Runs body(i, ctx) for i in [0, n) on as many threads as the batch's cost
// warrants, in fixed chunks. The calling thread first traces up to
// kProbeRays rays (stopping early after kProbeSeconds) and times them; the
// rest of the batch is split among nt threads, the calling thread taking the
// first chunk: one thread per kThreadWorth seconds of estimated work, and at
// least one per 4096 rays (a batch whose first rays are cheap misses, the
// sky before the scene, would otherwise be judged cheap), at most the
// settings' threads and one per kProbeRays rays. Starting and joining a
// thread cost up to a few hundred microseconds on a 2-core VM (4000 rays
// through a grid at 5 Mrays/s took 0.82 ms on 2 threads against 0.71 ms on
// one), so a batch under about 2 ms of work stays on one thread, while a few
// thousand brute-force rays over 10^4 primitives (milliseconds each) use
// every core. (With only the bound of one thread per 4096 rays, those ran on
// one.) The answers do not depend on the split. An exception in any chunk
// (e.g. bad_alloc for the mailbox) is caught in its thread and rethrown here
// after every thread has been joined, so it reaches Python as an exception
// instead of terminating the process.
constexpr size_t kProbeRays = 128;
constexpr double kProbeSeconds = 1e-3;
constexpr double kThreadWorth = 1e-3;

template <class F>
Stats parallel_rays(const Accel& accel, size_t n, const RenderSettings& s, F&& body) {
    const size_t most = size_t(resolve_threads(s.threads));
    TraceContext first_ctx = make_trace_context(accel, s);
    const size_t probe_max = most > 1 ? std::min(n, kProbeRays) : n;
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    size_t probe = 0;
    while (probe < probe_max) {
        body(probe, first_ctx);
        ++probe;
        if (most > 1 && probe % 8 == 0 && elapsed() > kProbeSeconds) break;
    }
    const double probe_seconds = elapsed();
    const size_t rest = n - probe;
    const double estimate = probe ? probe_seconds * double(rest) / double(probe) : 0.0;
    const size_t by_cost = std::max(size_t(estimate / kThreadWorth), rest / 4096 + 1);
    const size_t nt = std::max<size_t>(1, std::min({most, by_cost, rest / kProbeRays}));
    Stats total;
    std::mutex mu;
    std::exception_ptr error;
    // Chunk k of the rest, traced with ctx; its stats join the total.
    auto chunk = [&](size_t k, TraceContext& ctx) {
        const size_t lo = probe + rest * k / nt, hi = probe + rest * (k + 1) / nt;
        for (size_t i = lo; i < hi; ++i) body(i, ctx);
        std::lock_guard<std::mutex> lock(mu);
        total.add(ctx.stats);
    };
    auto guarded = [&](auto&& f) {
        try {
            f();
        } catch (...) {
            std::lock_guard<std::mutex> lock(mu);
            if (!error) error = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(nt - 1);   // (no reallocation below: emplace_back throws only system_error)
    try {
        for (size_t k = 1; k < nt; ++k) {
            pool.emplace_back([&, k] {
                guarded([&] {
                    TraceContext ctx = make_trace_context(accel, s);
                    chunk(k, ctx);
                });
            });
            name_thread(pool.back(), "gridwalk-rays");
        }
    } catch (const std::system_error& e) {   // could not start a thread: stop, report
        std::lock_guard<std::mutex> lock(mu);
        if (!error) error = std::make_exception_ptr(thread_start_error(int(pool.size()) + 1, int(nt), e));
    }
    if (!error) guarded([&] { chunk(0, first_ctx); });
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
    return total;
}

// The scene's box in double, with its squared diagonal: computed once per batch.
struct SceneBox {
    double lo[3], hi[3], diagonal2;
    bool moderate;        // the diagonal lies in [2^-60, 2^60] (may_hit's fast path)
    // The box grown by 2^16 diagonals on every side (may_hit's fast path),
    // for a structure that clips rays to its box; else the box itself, so that
    // brute force tests no primitive for a ray that misses the box.
    double near_lo[3], near_hi[3];
    SceneBox(const Bounds& b, bool clipped) {
        diagonal2 = 0;
        for (int a = 0; a < 3; ++a) {
            lo[a] = b.lo[a];
            hi[a] = b.hi[a];
            diagonal2 += sq(hi[a] - lo[a]);
        }
        moderate = diagonal2 >= 0x1p-120 && diagonal2 <= 0x1p120;
        // Padded as the adaptive grid pads its root (padded_box), so that a ray
        // grazing the box, which the float triangle test may hit within its
        // rounding, reaches every structure's tests alike: on the exact box
        // brute force missed 1,767 of 30,000 rays aimed at a lone triangle's
        // corners that the grids and Embree hit (and with brute force alone
        // padded, the grids missed such rays where this test is taken for
        // every ray: scenes beyond 2^60 or under 2^-60, rays from far away).
        padded_box(b, lo, hi);
        const double margin = clipped ? 0x1p16 * std::sqrt(diagonal2) : 0.0;
        for (int a = 0; a < 3; ++a) {
            near_lo[a] = lo[a] - margin;
            near_hi[a] = hi[a] + margin;
        }
    }
};

// Ray i of the batch, with its direction rescaled by a power of two (exactly)
// into [1, 2) when its largest component lies outside [2^-64, 2^64], and its
// tmin, tmax by the inverse: the walks' reciprocals then stay finite.
// scale_exp receives e such that the caller's t = ldexp(the rescaled ray's t, e).
//
// Whether the ray can meet the scene at all, in double: false when its
// [tmin, tmax] misses the scene's (conservative) box, and false when float t
// cannot tell the scene's points apart along it (one float step of t there
// moves the ray by more than a quarter of the box's diagonal). Such a ray is
// a documented miss for every structure alike: its hits could only be ordered
// by rounding (origin (0, 1e30, 2), direction (1, -1e30, -2): everything it
// meets is "at t = 1"), and far outside the box the quadratic shapes' tests
// lose all their digits and may report hits that are not there.
bool may_hit(const Ray& r, const SceneBox& box) {
    // A ray with tmin >= 0 that starts near the box (within 2^16 diagonals D
    // of it on every axis: shadow rays, most secondary and random rays, and
    // camera rays; inside it for brute force) passes without divisions when D lies in [2^-60, 2^60]
    // (box.moderate). Every point of the box then lies within sqrt(3) 2^16 D
    // + D < 2^17 D of the origin. make_ray leaves the direction's largest
    // component in [2^-64, 2^64] (or the ray invalid: a miss for every
    // structure alike), so the part of the segment inside the box lies within
    // t <= 2^17 D / |d| (finite), where a float step of t moves the ray by at
    // most max(2^-23 2^17 D, 2^-149 |d|) <= D / 64: float t tells the scene's
    // points apart. A segment that misses the box holds no hit for any structure.
    if (box.moderate && r.tmin >= 0 && r.o.x >= box.near_lo[0] && r.o.x <= box.near_hi[0] &&
        r.o.y >= box.near_lo[1] && r.o.y <= box.near_hi[1] && r.o.z >= box.near_lo[2] && r.o.z <= box.near_hi[2])
        return true;
    double t0 = r.tmin, t1 = r.tmax;
    for (int a = 0; a < 3; ++a) {
        const double o = r.o[a], d = r.d[a];
        if (d == 0) {
            if (o < box.lo[a] || o > box.hi[a]) return false;
            continue;
        }
        const double inv = 1.0 / d;   // finite: |d| >= the smallest float subnormal
        const double ta = (box.lo[a] - o) * inv, tb = (box.hi[a] - o) * inv;
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    // Multiplying by the reciprocal rounds twice where dividing rounded once.
    // Every rounding here is met with slack far above it (and far below a float
    // step), always in the direction that lets more rays through: the test may
    // pass a ray that division and square roots would refuse, never the reverse.
    // The far end of the segment, shrunk so that it cannot round up into the next binade.
    const double reach = std::max(std::abs(t0), std::abs(t1)) * (1 - 0x1p-48);
    t0 -= std::abs(t0) * 0x1p-48;
    t1 += std::abs(t1) * 0x1p-48;
    if (!(t0 <= t1)) return false;
    // One float step of t at the far end, times |d|, at most a quarter of the diagonal (squared).
    const float far = float(reach);
    const double step = double(next_up(far)) - double(far);
    const double d2 = double(r.d.x) * r.d.x + double(r.d.y) * r.d.y + double(r.d.z) * r.d.z;
    return 16.0 * step * step * d2 <= box.diagonal2 * (1 + 0x1p-44);
}

Ray make_ray(const RayBatch& b, size_t i, int& scale_exp) {
    Ray r;
    r.spawned = b.spawned;
    r.o = {b.o[3 * i], b.o[3 * i + 1], b.o[3 * i + 2]};
    r.d = {b.d[3 * i], b.d[3 * i + 1], b.d[3 * i + 2]};
    r.tmin = b.tmin[i];
    r.tmax = b.tmax[i];
    scale_exp = 0;
    const float m = std::max(std::abs(r.d.x), std::max(std::abs(r.d.y), std::abs(r.d.z)));
    if (m > 0 && std::isfinite(m) && (m < 0x1p-64f || m > 0x1p64f)) {
        const int e = -std::ilogb(m);   // d * 2^e has its largest component in [1, 2)
        for (int a = 0; a < 3; ++a) r.d[a] = std::ldexp(r.d[a], e);
        r.tmin = std::ldexp(r.tmin, -e);
        // Hits beyond float range along the caller's ray are misses, for
        // occlusion queries too: the segment ends where t would overflow.
        r.tmax = std::min(std::ldexp(r.tmax, -e), std::ldexp(std::numeric_limits<float>::max(), -e));
        scale_exp = e;
    }
    return r;
}

// make_ray; false for a ray that may_hit() turns into a miss.
bool traceable_ray(const RayBatch& b, size_t i, const SceneBox& box, Ray& r, int& scale_exp) {
    r = make_ray(b, i, scale_exp);
    return may_hit(r, box);
}

}  // namespace

Stats intersect_batch(const Accel& accel, const RayBatch& rays, const RenderSettings& s, const BatchOut& out) {
    const Scene& sc = accel.scene();
    const SceneBox box(sc.bounds(), accel.clips_to_box());
    return parallel_rays(accel, rays.n, s, [&](size_t i, TraceContext& ctx) {
        int scale_exp;
        Ray ray;
        const bool traceable = traceable_ray(rays, i, box, ray, scale_exp);
        const RayPre r(ray);
        ++ctx.stats.rays[int(RayType::Primary)];
        Hit hit;
        hit.t = r.ray.tmax;
        const bool found = traceable && accel.closest(r, hit, ctx);
        // The caller's t (overflow: beyond float range, a miss).
        const float t = scale_exp == 0 ? hit.t : std::ldexp(hit.t, scale_exp);
        if (found && std::isfinite(t)) {
            const Vec3 n = sc.geometric_normal(r, hit);
            out.t[i] = t;
            out.prim[i] = int32_t(sc.local_index(size_t(hit.prim)));
            out.kind[i] = int32_t(sc.kind_of(size_t(hit.prim)));
            out.u[i] = hit.u;
            out.v[i] = hit.v;
            out.normal[3 * i] = n.x; out.normal[3 * i + 1] = n.y; out.normal[3 * i + 2] = n.z;
        } else {
            out.t[i] = kInf;
            out.prim[i] = -1;
            out.kind[i] = int32_t(PrimKind::Miss);
            out.u[i] = out.v[i] = 0;
            out.normal[3 * i] = out.normal[3 * i + 1] = out.normal[3 * i + 2] = 0;
        }
    });
}

Stats occluded_batch(const Accel& accel, const RayBatch& rays, const RenderSettings& s, uint8_t* out) {
    const SceneBox box(accel.scene().bounds(), accel.clips_to_box());
    return parallel_rays(accel, rays.n, s, [&](size_t i, TraceContext& ctx) {
        ++ctx.stats.rays[int(RayType::Shadow)];
        int scale_exp;
        Ray ray;
        out[i] = traceable_ray(rays, i, box, ray, scale_exp) && accel.occluded(RayPre(ray), ctx)
                     ? 1 : 0;
    });
}

void spawn_batch(const Accel& accel, const float* o, const float* d, const float* t, const int32_t* prim,
                 const float* u, const float* v, const float* new_d, size_t n, float* out) {
    const Scene& sc = accel.scene();
    for (size_t i = 0; i < n; ++i) {
        Ray ray;
        ray.o = {o[3 * i], o[3 * i + 1], o[3 * i + 2]};
        ray.d = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
        const Vec3 w{new_d[3 * i], new_d[3 * i + 1], new_d[3 * i + 2]};
        Vec3 p = ray.o;
        if (prim[i] >= 0 && size_t(prim[i]) < sc.num_prims() && std::isfinite(t[i])) {
            Hit h;
            h.t = t[i];
            h.prim = prim[i];
            h.u = u[i];
            h.v = v[i];
            const SurfacePoint sp = sc.surface(RayPre(ray), h);
            p = offset_origin(sp.p, sp.p_err, sp.ng, w);
        }
        out[3 * i] = p.x; out[3 * i + 1] = p.y; out[3 * i + 2] = p.z;
    }
}

}  // namespace gw
