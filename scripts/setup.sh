#!/usr/bin/env bash
# Installs the Debian 12 packages splitgrid needs (only if one is missing), then configures and
# builds the project in build/ (Release, Ninja). Safe to run again: a second run installs
# nothing and rebuilds only what changed.
#
# Usage: scripts/setup.sh [--werror]
#   --werror   treat compiler warnings as errors (also on when the environment has CI=true)
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${root_dir}/build"

werror=OFF
if [[ "${CI:-}" == "true" ]]; then werror=ON; fi
for arg in "$@"; do
    case "${arg}" in
        --werror) werror=ON ;;
        *) echo "setup.sh: unknown argument: ${arg}" >&2; exit 1 ;;
    esac
done

packages=(
    cmake ninja-build g++
    libcli11-dev libspdlog-dev nlohmann-json3-dev
    libassimp-dev assimp-utils assimp-testmodels zlib1g-dev
    libtbb-dev libgtest-dev
    libembree-dev libvtk9-dev
    python3-matplotlib
    clang-14 libclang-rt-14-dev  # libFuzzer for tests/fuzz (scripts/test.sh)
)

missing=()
for package in "${packages[@]}"; do
    status="$(dpkg-query -W -f='${Status}' "${package}" 2>/dev/null || true)"
    if [[ "${status}" != "install ok installed" ]]; then missing+=("${package}"); fi
done

if ((${#missing[@]} > 0)); then
    echo "setup.sh: installing ${missing[*]}"
    sudo_cmd=()
    if [[ "$(id -u)" != 0 ]]; then
        if ! command -v sudo >/dev/null; then
            echo "setup.sh: need root or sudo to install: ${missing[*]}" >&2
            exit 1
        fi
        sudo_cmd=(sudo)
    fi
    "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
    "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${missing[@]}"
fi

# The warnings option is passed every time so that a CI build never inherits a cached OFF.
cmake -S "${root_dir}" -B "${build_dir}" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DSG_WARNINGS_AS_ERRORS="${werror}"
cmake --build "${build_dir}"
