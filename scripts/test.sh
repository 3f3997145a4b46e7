#!/usr/bin/env bash
# Sets up and builds splitgrid (scripts/setup.sh, with ParaView for the real-client test of
# sg-export), then runs the test suite through ctest in three build trees (docs/HARDENING.md):
#   build/        Release, g++: every test, the ParaView test and the Python package's
#                 (label `python`) included.
#   build-asan/   g++ with AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer
#                 (SG_SANITIZE): every test except those labelled `asan_skip`; the Python
#                 package is not built there (python/CMakeLists.txt), so its tests are absent.
#   build-fuzz/   clang 14 with libFuzzer (SG_FUZZ): each fuzz target for SG_FUZZ_SECONDS
#                 seconds (default 45), on the generated seeds and the kept crash inputs.
# Tests that need ../shared/meshes skip when it is absent. Arguments are passed on to
# setup.sh (e.g. --werror). SG_TEST_TREES chooses the trees (default "release asan fuzz");
# the fuzz tree is skipped with a message when clang++-14 is missing.
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
trees="${SG_TEST_TREES:-release asan fuzz}"
werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
for arg in "$@"; do
    if [[ "${arg}" == "--werror" ]]; then werror=ON; fi
done

bash "${root_dir}/scripts/setup.sh" --with-paraview --with-python-tests "$@"

if [[ " ${trees} " == *" release "* ]]; then
    ctest --test-dir "${root_dir}/build" --output-on-failure -j2
fi

if [[ " ${trees} " == *" asan "* ]]; then
    asan_dir="${root_dir}/build-asan"
    # -O2 keeps the sanitized suite fast; no NDEBUG, so SG_ASSERT checks run too.
    cmake -S "${root_dir}" -B "${asan_dir}" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" -DSG_SANITIZE=ON \
        -DSG_WARNINGS_AS_ERRORS="${werror}"
    cmake --build "${asan_dir}"
    # Exported so that the tools the end-to-end tests start inherit them. halt_on_error and
    # -fno-sanitize-recover make every report fail its test; the suppression file lists only
    # third-party leaks, each with its reason (tests/sanitizer/lsan.supp).
    export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:detect_stack_use_after_return=1"
    export LSAN_OPTIONS="suppressions=${root_dir}/tests/sanitizer/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    ctest --test-dir "${asan_dir}" --output-on-failure -j2 -LE asan_skip
    unset ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS
fi

if [[ " ${trees} " == *" fuzz "* ]]; then
    if command -v clang++-14 >/dev/null; then
        fuzz_dir="${root_dir}/build-fuzz"
        cmake -S "${root_dir}" -B "${fuzz_dir}" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
            -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" -DCMAKE_CXX_COMPILER=clang++-14 \
            -DSG_FUZZ=ON -DSG_BUILD_APPS=OFF -DSG_WITH_VTK=OFF -DSG_WARNINGS_AS_ERRORS="${werror}" \
            -DSG_FUZZ_SECONDS="${SG_FUZZ_SECONDS:-45}"
        cmake --build "${fuzz_dir}"
        ctest --test-dir "${fuzz_dir}" --output-on-failure -j2 -L fuzz
    else
        echo "test.sh: clang++-14 not found, fuzz targets not run (scripts/setup.sh installs it)"
    fi
fi
