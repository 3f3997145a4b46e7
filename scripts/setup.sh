#!/usr/bin/env bash
# Installs the Debian 12 packages splitgrid needs (only if one is missing), then configures and
# builds the project in build/ (Release, Ninja). Safe to run again: a second run installs
# nothing and rebuilds only what changed.
#
# Usage: scripts/setup.sh [--werror] [--with-paraview] [--with-python-tests]
#   --werror          treat compiler warnings as errors (also on when the environment has CI=true)
#   --with-paraview   also install ParaView and a virtual X server for the real-client test of
#                     sg-export (tests/paraview/), and unpack ParaView's Python modules into
#                     build/paraview-python (scripts/test.sh passes this). With CI=true the
#                     configure step then fails if that test cannot be registered.
#   --with-python-tests  also install what the Python package's tests use (pytest, hypothesis,
#                     Dask, Open3D; scripts/test.sh passes this). The package itself (python/,
#                     pybind11 and numpy) is always built; with CI=true the configure step fails
#                     if it or its tests cannot be.
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${root_dir}/build"

werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
with_paraview=false
with_python_tests=false
for arg in "$@"; do
    case "${arg}" in
        --werror) werror=ON ;;
        --with-paraview) with_paraview=true ;;
        --with-python-tests) with_python_tests=true ;;
        *) echo "setup.sh: unknown argument: ${arg}" >&2; exit 1 ;;
    esac
done

packages=(
    cmake ninja-build g++
    libcli11-dev libspdlog-dev nlohmann-json3-dev
    libassimp-dev assimp-utils assimp-testmodels zlib1g-dev
    libtbb-dev libgtest-dev libboost-dev
    libembree-dev libvtk9-dev
    python3-matplotlib python3-numpy  # charts (sg-bench), the numpy lines of docs/FORMAT.md
    pybind11-dev python3-dev  # the Python package (python/, docs/PYTHON.md)
    libcgal-dev  # CGAL, sg-bench's reference for point queries (GPL, sg-bench only: SG_WITH_CGAL)
    clang-14 libclang-rt-14-dev  # libFuzzer for tests/fuzz (scripts/test.sh)
)
if [[ "${with_paraview}" == true ]]; then
    # pvbatch, and Xvfb to give it a display: Debian's ParaView renders only through X.
    packages+=(paraview xvfb xauth)
fi
if [[ "${with_python_tests}" == true ]]; then
    # The Python package's tests: pytest and hypothesis; Dask for splitgrid.dask; Open3D, the
    # interface the package follows (tests/python/).
    packages+=(python3-pytest python3-hypothesis python3-dask python3-distributed python3-open3d)
fi

missing=()
for package in "${packages[@]}"; do
    status="$(dpkg-query -W -f='${Status}' "${package}" 2>/dev/null || true)"
    if [[ "${status}" != "install ok installed" ]]; then missing+=("${package}"); fi
done

sudo_cmd=()
if [[ "$(id -u)" != 0 ]]; then sudo_cmd=(sudo); fi

if ((${#missing[@]} > 0)); then
    echo "setup.sh: installing ${missing[*]}"
    if ((${#sudo_cmd[@]} > 0)) && ! command -v sudo >/dev/null; then
        echo "setup.sh: need root or sudo to install: ${missing[*]}" >&2
        exit 1
    fi
    "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
    "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${missing[@]}"
fi

# CGAL is off by default in CMake (GPL, optional); the tree this script makes, which CI tests
# and scripts/bench.sh runs, measures it.
cmake_args=(-DSG_WARNINGS_AS_ERRORS="${werror}" -DSG_WITH_CGAL=ON)
require_paraview=OFF
if [[ "${with_paraview}" == true ]]; then
    # ParaView's Python modules live in python3-paraview, which conflicts with python3-vtk9
    # (needed by libvtk9-dev), so installing it would remove VTK's development files. The
    # package is unpacked into a folder of its own instead, at the version of the installed
    # paraview, and pvbatch finds it through PYTHONPATH (tests/CMakeLists.txt).
    paraview_python="${build_dir}/paraview-python"
    paraview_modules="${paraview_python}/usr/lib/python3/dist-packages"
    if [[ ! -f "${paraview_modules}/paraview/simple.py" ]]; then
        version="$(dpkg-query -W -f='${Version}' paraview)"
        echo "setup.sh: unpacking python3-paraview ${version} into ${paraview_python}"
        download_dir="$(mktemp -d)"
        trap 'rm -rf "${download_dir}"' EXIT
        # apt-get download writes into the current folder; as root it warns that the download
        # is not sandboxed, which is harmless here.
        if ! (cd "${download_dir}" && apt-get download "python3-paraview=${version}"); then
            "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
            (cd "${download_dir}" && apt-get download "python3-paraview=${version}")
        fi
        rm -rf "${paraview_python}"
        mkdir -p "${paraview_python}"
        dpkg-deb -x "${download_dir}"/python3-paraview_*.deb "${paraview_python}"
    fi
    cmake_args+=(-DSG_PARAVIEW_PYTHONPATH="${paraview_modules}")
    if [[ "${CI:-}" == "true" ]]; then require_paraview=ON; fi
fi
cmake_args+=(-DSG_REQUIRE_PARAVIEW="${require_paraview}")
# CI: the Python package and its tests may not silently vanish (python/CMakeLists.txt).
require_python=OFF
if [[ "${CI:-}" == "true" ]]; then require_python=ON; fi
cmake_args+=(-DSG_REQUIRE_PYTHON="${require_python}")

# Options are passed every time so that a CI build never inherits a cached OFF.
cmake -S "${root_dir}" -B "${build_dir}" -G Ninja -DCMAKE_BUILD_TYPE=Release "${cmake_args[@]}"
cmake --build "${build_dir}"
