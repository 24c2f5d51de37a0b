// Batched ray queries for Python (scene.intersect / scene.occluded),
// split over threads in fixed chunks.
#pragma once
#include "accel.h"

namespace gw {

struct BatchOut {
    float* t; int32_t* prim; int32_t* kind; float* u; float* v; float* normal;   // normal: (N, 3)
};

// A batch of rays: n origins and directions (n x 3), tmin and tmax (n).
struct RayBatch {
    const float *o, *d, *tmin, *tmax;
    size_t n;
    bool spawned;   // the rays leave surfaces (see Ray::spawned)
};

// Closest hits, traced as settings s traces (threads, mailboxes, empty-space
// jumps). prim is the index within its kind (-1 on a miss), t = inf on a miss.
Stats intersect_batch(const Accel& accel, const RayBatch& rays, const RenderSettings& s, const BatchOut& out);
// Any hit in (tmin, tmax).
Stats occluded_batch(const Accel& accel, const RayBatch& rays, const RenderSettings& s, uint8_t* out);

// Origins for secondary rays leaving the given hits in new_d, offset exactly
// as the integrator offsets them (offset.h). prim is the global index.
void spawn_batch(const Accel& accel, const float* o, const float* d, const float* t, const int32_t* prim,
                 const float* u, const float* v, const float* new_d, size_t n, float* out);

}  // namespace gw
