#pragma once
// GRANPACK_SIMD_CLONES before a (non-template) function compiles it once per x86-64 level
// (AVX-512, AVX2, baseline) and picks the best at load time (GCC target_clones): the default
// build stays portable and still runs its hot loops 4 or 8 doubles wide where the CPU can.
// Elsewhere (other compilers or architectures) it expands to nothing.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GRANPACK_SIMD_CLONES                                                                       \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define GRANPACK_SIMD_CLONES
#endif
