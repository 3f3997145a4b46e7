# Cross-compiles splitgrid for 64-bit Arm Linux (aarch64) with Debian's cross tools
# (crossbuild-essential-arm64) against the arm64 packages of oneTBB and GoogleTest
# (libtbb-dev:arm64, libgtest-dev:arm64), and runs what the build runs (the tests' discovery,
# ctest) under qemu-user. Only the scalar traversal kernels are built for such a target.
# Used by scripts/test_arm64.sh; CONTRIBUTING.md, "Another processor".
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Debian's multiarch layout: arm64 libraries and their CMake packages in
# /usr/lib/aarch64-linux-gnu, headers shared in /usr/include, the C library's own files under
# /usr/aarch64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
