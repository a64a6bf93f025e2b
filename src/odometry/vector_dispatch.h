#pragma once
// Hot loops marked VOCAL_VECTOR_CLONES are compiled twice on x86-64 with GCC and picked when the
// library loads: AVX2 + FMA where the CPU has them, SSE2 (every x86-64) otherwise. The default build
// thus runs on any x86-64 without -march=native. Elsewhere (arm64: NEON) the baseline build is used.

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define VOCAL_VECTOR_CLONES __attribute__((target_clones("arch=haswell", "default")))
#else
#define VOCAL_VECTOR_CLONES
#endif

// Hand-written AVX2 passes (functions marked __attribute__((target("avx2")))), where this build can
// have them; handAvx2Available() says whether this CPU runs them (asked once).
#if defined(__GNUC__) && defined(__x86_64__)
#define VOCAL_HAND_AVX2 1
#define VOCAL_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
#include <immintrin.h>
#endif

inline bool handAvx2Available() {
#ifdef VOCAL_HAND_AVX2
  static const bool available = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return available;
#else
  return false;
#endif
}
