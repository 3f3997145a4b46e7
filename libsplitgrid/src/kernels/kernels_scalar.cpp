// The traversal kernels without SIMD: one triangle, one box, one cell at a time, in plain C++
// (no intrinsics, no vector types). They are the poster's conditions ("without SIMD"), the
// reference the SIMD kernels are compared with, and the only kernels of a processor that is
// not x86-64. libsplitgrid/CMakeLists.txt compiles this file with -fno-tree-vectorize and
// -fno-tree-slp-vectorize, so that the compiler does not vectorise them either;
// scripts/check_scalar_kernels.sh checks the object code for packed instructions.
#include "kernel_deps.hpp"

#define SG_KERNEL_ISA scalar
#define SG_KERNEL_ISA_LEVEL 0
#define SG_KERNEL_TABLE scalar_kernels
#include "kernels_isa.inc"
