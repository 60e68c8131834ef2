#pragma once
// HULLMAP_AVX2_CLONES before a function: GCC and Clang build it twice, for AVX2 and for any x86-64,
// and the loader picks one for the machine it runs on (target_clones, an ifunc). For loops over
// whole rows that the compiler vectorises; nothing elsewhere (other CPUs, compilers without it).
// A white-box header for the libraries' own sources, not installed.

#if defined(__x86_64__) && defined(__linux__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define HULLMAP_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef HULLMAP_AVX2_CLONES
#define HULLMAP_AVX2_CLONES
#endif
