// Mailboxes (Amanatides & Woo 1987): a primitive remembers the id of the last
// ray that tested it, so a primitive spanning several cells is tested once per
// ray. The seed had to switch them off in parallel because one global ray id
// is not thread-safe; here every worker thread owns its own stamp array and
// ray counter, so stamps are never shared between threads.
#pragma once
#include <cstdint>
#include <algorithm>
#include <vector>

namespace gw {

// Counter is the stamp type: 32 bits in the renderer; the unit tests use 8
// bits to reach the wrap-around after 255 rays.
template <class Counter>
class BasicMailbox {
public:
    void resize(size_t prims) {
        if (stamp_.size() != prims) { stamp_.assign(prims, 0); ray_ = 0; }
    }
    // Start a new ray. On wrap-around (after 2^32 rays for 32-bit stamps) the stamps are cleared.
    void next_ray() {
        if (++ray_ == 0) { std::fill(stamp_.begin(), stamp_.end(), Counter(0)); ray_ = 1; }
    }
    // True if prim was already tested by the current ray; otherwise marks it.
    bool seen(uint32_t prim) {
        if (stamp_[prim] == ray_) return true;
        stamp_[prim] = ray_;
        return false;
    }
    bool enabled() const { return !stamp_.empty(); }

private:
    std::vector<Counter> stamp_;
    Counter ray_ = 0;
};
using Mailbox = BasicMailbox<uint32_t>;

}  // namespace gw
