// The traversal kernels for the x86-64 baseline (SSE2): the SIMD fallback every x86-64 processor
// can run. They are written with x86 intrinsics (simd.hpp, triangle_test.hpp), so they are
// built for x86-64 only; another processor runs the scalar kernels (kernels_scalar.cpp).
#include "kernel_deps.hpp"

// The 8-wide vectors of simd.hpp are passed between inline functions of this file only, so
// the compilers' note that their calling convention differs from AVX code concerns no
// interface. The pragma silences clang (and GCC where the note has a source location);
// libsplitgrid/CMakeLists.txt also turns it off for GCC, which reports it without one.
#pragma GCC diagnostic ignored "-Wpsabi"
#define SG_KERNEL_ISA sse2
#define SG_KERNEL_ISA_LEVEL 2
#define SG_KERNEL_TABLE sse2_kernels
#include "kernels_isa.inc"
