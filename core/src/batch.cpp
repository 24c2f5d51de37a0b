// Batched ray queries. See batch.h.
#include "batch.h"

#include <exception>
#include <mutex>
#include <thread>

#include "offset.h"
#include "threads.h"

namespace gw {
namespace {

// Runs body(i, ctx) for i in [0, n) on fixed chunks, one per thread. An
// exception in any chunk (e.g. bad_alloc for the mailbox) is caught in its
// thread and rethrown here after every thread has been joined, so it reaches
// Python as an exception instead of terminating the process.
template <class F>
Stats parallel_rays(const Accel& accel, size_t n, const RenderSettings& s, F&& body) {
    const int nt = int(std::min<size_t>(size_t(resolve_threads(s.threads)), std::max<size_t>(1, n / 4096 + 1)));
    Stats total;
    std::mutex mu;
    std::exception_ptr error;
    auto run = [&](int k) {
        try {
            TraceContext ctx = make_trace_context(accel, s);
            const size_t lo = n * size_t(k) / size_t(nt), hi = n * size_t(k + 1) / size_t(nt);
            for (size_t i = lo; i < hi; ++i) body(i, ctx);
            std::lock_guard<std::mutex> lock(mu);
            total.add(ctx.stats);
        } catch (...) {
            std::lock_guard<std::mutex> lock(mu);
            if (!error) error = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    try {
        for (int k = 1; k < nt; ++k) pool.emplace_back(run, k);
    } catch (...) {   // could not start a thread: the chunks it would have run are run here
        std::lock_guard<std::mutex> lock(mu);
        if (!error) error = std::current_exception();
    }
    if (!error) run(0);
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
    return total;
}

Ray make_ray(const RayBatch& b, size_t i) {
    Ray r;
    r.spawned = b.spawned;
    r.o = {b.o[3 * i], b.o[3 * i + 1], b.o[3 * i + 2]};
    r.d = {b.d[3 * i], b.d[3 * i + 1], b.d[3 * i + 2]};
    r.tmin = b.tmin[i];
    r.tmax = b.tmax[i];
    return r;
}

}  // namespace

Stats intersect_batch(const Accel& accel, const RayBatch& rays, const RenderSettings& s, const BatchOut& out) {
    const Scene& sc = accel.scene();
    return parallel_rays(accel, rays.n, s, [&](size_t i, TraceContext& ctx) {
        const RayPre r(make_ray(rays, i));
        ++ctx.stats.rays[int(RayType::Primary)];
        Hit hit;
        hit.t = r.ray.tmax;
        if (accel.closest(r, hit, ctx)) {
            const Vec3 n = sc.geometric_normal(r, hit);
            out.t[i] = hit.t;
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
    return parallel_rays(accel, rays.n, s, [&](size_t i, TraceContext& ctx) {
        ++ctx.stats.rays[int(RayType::Shadow)];
        out[i] = accel.occluded(RayPre(make_ray(rays, i)), ctx) ? 1 : 0;
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
