// The runtime's one SIMD prelude (internal; not installed): GCC vector-extension types and the
// two attributes every kernel uses. Kernels are written once on these types; the compiler builds
// each FIRELOOK_KERNEL_CLONES function twice, AVX2 + FMA (x86-64-v3) and the baseline, and the
// loader picks one by the CPU (function multi-versioning). Helpers that take vectors are
// FIRELOOK_ALWAYS_INLINE and take them by reference, so no vector crosses a call boundary and the
// psABI of 32-byte vectors never matters.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FIRELOOK_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define FIRELOOK_KERNEL_CLONES
#endif
#define FIRELOOK_ALWAYS_INLINE inline __attribute__((always_inline))

namespace firelook::basis::simd {

typedef float v4f __attribute__((vector_size(16)));
typedef float v8f __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));  // one AVX-512 register
typedef int32_t v8i __attribute__((vector_size(32)));
typedef int16_t v8s __attribute__((vector_size(16)));   // 8 int16 lanes (one SSE register)
typedef uint16_t v8u __attribute__((vector_size(16)));
typedef uint8_t v8b __attribute__((vector_size(8)));
typedef int16_t v16s __attribute__((vector_size(32)));  // 16 int16 lanes (one AVX2 register)
typedef uint16_t v16u __attribute__((vector_size(32)));
typedef uint8_t v16b __attribute__((vector_size(16)));

// Unaligned loads and stores (memcpy compiles to one move).
template <typename V, typename T>
FIRELOOK_ALWAYS_INLINE void load(V& v, const T* p) {
    std::memcpy(&v, p, sizeof v);
}
template <typename V, typename T>
FIRELOOK_ALWAYS_INLINE void store(T* p, const V& v) {
    std::memcpy(p, &v, sizeof v);
}

}  // namespace firelook::basis::simd
