// The buffer pool: see buffer_pool.h.
#include "buffer_pool.h"

#include <chrono>
#include <cstdlib>
#include <deque>
#include <mutex>

namespace gw {
namespace {

constexpr std::size_t kPoolMinBytes = std::size_t(1) << 20;   // smaller buffers come from malloc's own free lists

struct Block {
    void* p;
    std::size_t bytes;
    std::chrono::steady_clock::time_point freed;
};

struct Pool {
    std::mutex mu;
    int users = 0;
    std::size_t held = 0;   // bytes in blocks
    std::size_t live = 0;   // bytes of pooled-size buffers handed out and not yet freed
    std::deque<Block> blocks;   // oldest first

    void drop_front() {
        std::free(blocks.front().p);
        held -= blocks.front().bytes;
        blocks.pop_front();
    }
    // Keeps held <= live, and nothing older than kPoolSeconds.
    void trim() {
        const auto oldest = std::chrono::steady_clock::now() - std::chrono::duration<double>(kPoolSeconds);
        while (!blocks.empty() && (held > live || blocks.front().freed < oldest)) drop_front();
    }
};

Pool& pool() {
    static Pool* p = new Pool();   // never destroyed: buffers may be freed during static destruction
    return *p;
}

}  // namespace

void* pool_allocate(std::size_t bytes) {
    if (bytes < kPoolMinBytes) {
        if (void* p = std::malloc(bytes ? bytes : 1)) return p;
        throw std::bad_alloc();
    }
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    void* p = nullptr;
    for (auto it = pl.blocks.rbegin(); it != pl.blocks.rend(); ++it) {   // the newest first
        if (it->bytes != bytes) continue;
        p = it->p;
        pl.held -= bytes;
        pl.blocks.erase(std::next(it).base());
        break;
    }
    if (!p && !(p = std::malloc(bytes))) throw std::bad_alloc();
    pl.live += bytes;
    pl.trim();
    return p;
}

void pool_free(void* p, std::size_t bytes) noexcept {
    if (!p) return;
    if (bytes < kPoolMinBytes) {
        std::free(p);
        return;
    }
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    pl.live -= bytes;
    bool kept = false;
    if (pl.users > 0) {
        try {
            pl.blocks.push_back({p, bytes, std::chrono::steady_clock::now()});
            pl.held += bytes;
            kept = true;
        } catch (...) {
        }
    }
    if (!kept) std::free(p);
    pl.trim();
}

BufferPoolUse::BufferPoolUse() {
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    ++pl.users;
}

BufferPoolUse::~BufferPoolUse() {
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    if (--pl.users > 0) return;
    while (!pl.blocks.empty()) pl.drop_front();
}

void pool_trim() {
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    pl.trim();
}

std::size_t pool_bytes() {
    Pool& pl = pool();
    std::lock_guard<std::mutex> lock(pl.mu);
    return pl.held;
}

}  // namespace gw
