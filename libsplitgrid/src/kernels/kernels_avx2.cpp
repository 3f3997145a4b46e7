// The traversal kernels for x86-64-v3 processors (AVX2, FMA, BMI2; Intel Haswell, AMD Zen
// and later). FMA is enabled but never contracted (-ffp-contract=off), so results equal the
// SSE2 kernels' bit for bit.
#include "kernel_deps.hpp"

// The point queries' 8-wide doubles are passed between inline functions of this file only, so
// the note that their calling convention differs from AVX-512 code concerns no interface
// (libsplitgrid/CMakeLists.txt turns it off where GCC gives it no source location).
#pragma GCC diagnostic ignored "-Wpsabi"

#pragma GCC push_options
#pragma GCC target("avx2,fma,bmi,bmi2,lzcnt,popcnt,f16c,movbe")
#define SG_KERNEL_ISA avx2
#define SG_KERNEL_ISA_LEVEL 3
#define SG_KERNEL_TABLE avx2_kernels
#include "kernels_isa.inc"
#pragma GCC pop_options
