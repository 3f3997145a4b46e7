// The traversal kernels for x86-64-v4 processors (AVX-512 F, VL, BW, DQ, CD; Intel Skylake-SP,
// AMD Zen 4 and later): the 8-wide code of the AVX2 kernels with mask registers.
#include "kernel_deps.hpp"

#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma,bmi,bmi2,lzcnt,popcnt,f16c,movbe")
#define SG_KERNEL_ISA avx512
#define SG_KERNEL_ISA_LEVEL 4
#define SG_KERNEL_TABLE avx512_kernels
#include "kernels_isa.inc"
#pragma GCC pop_options
