// The seed's uniform grid: one resolution for the whole scene box (the
// seed's formula in M), compact CSR storage, Amanatides & Woo 3D-DDA
// traversal with per-thread mailboxes and empty-space jumps.
#pragma once
#include <vector>

#include "accel.h"

namespace gw {

struct GridParams {
    double density = 2.0;              // the seed's M
    uint64_t max_cells = 1ull << 24;   // cap on nx*ny*nz
    uint64_t max_refs = 1ull << 27;    // cap on primitive references (4 bytes each)
};

class UniformGrid final : public Accel {
public:
    UniformGrid(std::shared_ptr<const Scene> s, const GridParams& p, const CancelToken* cancel = nullptr);
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    AccelInfo info() const override { return info_; }
    bool uses_mailboxes() const override { return true; }

private:
    template <class F>
    void for_cells(const int c0[3], const int c1[3], F&& f) const {   // f(linear cell index)
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) f((uint64_t(z) * n_[1] + y) * n_[0] + x);
    }
    template <bool AnyHit>
    bool traverse(const RayPre& r, Hit& hit, TraceContext& ctx) const;
    void cell_range(const Bounds& b, int lo[3], int hi[3]) const;
    int cell_at(const Ray& ray, float t, int axis) const;

    Vec3 lo_, hi_, cell_, inv_cell_;
    int n_[3] = {1, 1, 1};
    std::vector<uint32_t> offsets_;   // per cell: start in prims_ (size cells + 1)
    std::vector<uint32_t> prims_;     // flat primitive index list
    std::vector<uint8_t> empty_;      // per cell: Chebyshev distance to the nearest non-empty cell
    AccelInfo info_;
};

}  // namespace gw
