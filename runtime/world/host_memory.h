// Optional host allocator for the world's large buffers (images, flare
// images, coefficient arrays, resident frames): a game engine can route them
// into its own heap. Small bookkeeping and the package reader's buffers (the
// compressed sections and their decode buffers) use the C++ heap.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory_resource>
#include <new>

namespace firelook::world {

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

// The same hooks as a std::pmr::memory_resource, for the resident frames (basis/resident_frame.h).
// Alignments up to 16 bytes, as the hooks promise.
class HostMemoryResource final : public std::pmr::memory_resource {
  public:
    explicit HostMemoryResource(const MemoryHooks* hooks) : hooks_(hooks) {}

  private:
    void* do_allocate(size_t bytes, size_t alignment) override {
        if (alignment > 16) throw std::bad_alloc();
        return HostAllocator<std::byte>(hooks_).allocate(bytes == 0 ? 1 : bytes);
    }
    void do_deallocate(void* p, size_t bytes, size_t) override {
        HostAllocator<std::byte>(hooks_).deallocate(static_cast<std::byte*>(p), bytes);
    }
    bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override { return this == &other; }
    const MemoryHooks* hooks_;
};

}  // namespace firelook::world
