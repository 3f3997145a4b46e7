#!/usr/bin/env bash
# Cross-builds the library and its tests for 64-bit Arm (aarch64) and runs them under
# qemu-user: the portable build, whose traversal kernels are the scalar ones (SG_ISA=scalar on
# x86-64). Only the library and its own suite are built (SG_WITH_FORMATS off: Assimp, VTK, the
# tools and the Python package have no arm64 packages installed here). Needs Debian's crossbuild-essential-arm64, qemu-user, libtbb-dev:arm64
# and libgtest-dev:arm64 (CONTRIBUTING.md, "Another processor").
#
# Usage: scripts/test_arm64.sh [ctest arguments, e.g. -R Traverse]
#   Builds in build-arm64/ with cmake/toolchain-aarch64-linux-gnu.cmake, then runs ctest
#   there (each test under qemu-aarch64); ctest's exit code is the script's.
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${root_dir}/build-arm64"

for tool in aarch64-linux-gnu-g++ qemu-aarch64; do
    if ! command -v "${tool}" >/dev/null; then
        echo "test_arm64.sh: ${tool} not found: install crossbuild-essential-arm64 and qemu-user" >&2
        exit 1
    fi
done
for package in libtbb-dev:arm64 libgtest-dev:arm64; do
    status="$(dpkg-query -W -f='${Status}' "${package}" 2>/dev/null || true)"
    if [[ "${status}" != "install ok installed" ]]; then
        echo "test_arm64.sh: ${package} is not installed (dpkg --add-architecture arm64," \
             "then apt-get install ${package})" >&2
        exit 1
    fi
done

werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
cmake -S "${root_dir}" -B "${build_dir}" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_TOOLCHAIN_FILE="${root_dir}/cmake/toolchain-aarch64-linux-gnu.cmake" \
    -DSG_WITH_FORMATS=OFF -DSG_BUILD_APPS=OFF -DSG_WITH_VTK=OFF -DSG_BUILD_PYTHON=OFF \
    -DSG_WARNINGS_AS_ERRORS="${werror}"
cmake --build "${build_dir}" -j2 --target libsplitgrid_tests
# The library's own suite, the only one this tree has.
ctest --test-dir "${build_dir}" --output-on-failure -j2 "$@"
