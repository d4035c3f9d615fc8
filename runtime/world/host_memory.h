// Optional host allocator for the world's large buffers (images, flare
// images, coefficient arrays, decoded U copies): a game engine can route them
// into its own heap. Small bookkeeping and the package reader's buffers (the
// compressed sections and FrameFactors) use the C++ heap.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

namespace firelook::runtime {

struct MemoryHooks {
    // Both set or both null (null: malloc/free). alloc returns memory aligned
    // to at least 16 bytes or null on failure.
    void* (*alloc)(size_t size, void* user) = nullptr;
    void (*free)(void* pointer, void* user) = nullptr;
    void* user = nullptr;
};

// A standard allocator over MemoryHooks (which must outlive every container using it).
template <typename T>
struct HostAllocator {
    using value_type = T;
    const MemoryHooks* hooks = nullptr;

    HostAllocator() = default;
    explicit HostAllocator(const MemoryHooks* h) : hooks(h) {}
    template <typename U>
    HostAllocator(const HostAllocator<U>& other) : hooks(other.hooks) {}

    T* allocate(size_t n) {
        if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_alloc();
        void* p = hooks && hooks->alloc ? hooks->alloc(n * sizeof(T), hooks->user) : std::malloc(n * sizeof(T));
        if (!p) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t) {
        if (hooks && hooks->free)
            hooks->free(p, hooks->user);
        else
            std::free(p);
    }
    template <typename U>
    bool operator==(const HostAllocator<U>& o) const {
        return hooks == o.hooks;
    }
};

}  // namespace firelook::runtime
