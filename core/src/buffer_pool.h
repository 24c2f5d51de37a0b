// Large buffers kept for reuse while a viewport is open.
//
// The viewport builds a new Scene on every edit, with arrays of the same sizes
// as the version before. Fresh memory from the kernel arrives unmapped: every
// page is faulted in and zeroed on first touch, which was more than half of a
// 1M-triangle Scene's construction (35 of 60 ms). While a BufferPoolUse is
// alive (one per viewport renderer), large buffers that are freed are kept and
// handed back, already mapped, to the next request of exactly the same size.
// Without one, PoolAllocator allocates and frees as malloc does.
//
// What the pool keeps is bounded: never more bytes than the pooled buffers in
// use (a scene version's worth, as the previous version's buffers wait for the
// next one), and nothing kept longer than kPoolSeconds.
#pragma once
#include <cstddef>
#include <new>
#include <vector>

namespace gw {

void* pool_allocate(std::size_t bytes);
void pool_free(void* p, std::size_t bytes) noexcept;

// While any exists, freed buffers of at least 1 MiB are kept (within the
// bounds above, oldest dropped first); the last one's end frees them all.
class BufferPoolUse {
public:
    BufferPoolUse();
    ~BufferPoolUse();
    BufferPoolUse(const BufferPoolUse&) = delete;
    BufferPoolUse& operator=(const BufferPoolUse&) = delete;
};
constexpr double kPoolSeconds = 30.0;

// The bytes the pool holds now (for tests).
std::size_t pool_bytes();
// Drops what the bounds no longer allow (the age limit passes without any
// allocation; an idle viewport calls this now and then).
void pool_trim();

template <class T>
struct PoolAllocator {
    using value_type = T;
    PoolAllocator() = default;
    template <class U>
    PoolAllocator(const PoolAllocator<U>&) {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        return static_cast<T*>(pool_allocate(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { pool_free(p, n * sizeof(T)); }
    template <class U>
    bool operator==(const PoolAllocator<U>&) const { return true; }
    template <class U>
    bool operator!=(const PoolAllocator<U>&) const { return false; }
};

template <class T>
using PooledVector = std::vector<T, PoolAllocator<T>>;

}  // namespace gw
