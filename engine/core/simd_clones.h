#pragma once
// DASH_SIMD_CLONES before a function that loops over the lanes of a batch (engine/robots/batch_kinematics.h,
// engine/collision/cover_kernels.h): g++ compiles it for AVX-512, AVX2 and plain x86-64 (SSE2) and
// picks the clone the CPU runs at load time (target_clones, an ifunc), so the build needs no -mavx2.
// None of the clones enables FMA, and ISO C++ mode keeps -ffp-contract=off, so every clone rounds the
// same way. Elsewhere (another compiler or CPU family) it is empty: the plain loops stay.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define DASH_SIMD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define DASH_SIMD_CLONES
#endif
