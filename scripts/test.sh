#!/usr/bin/env bash
# Sets up and builds splitgrid (scripts/setup.sh, with ParaView for the real-client test of
# sg-export), then runs the whole test suite through ctest. Tests that need ../shared/meshes
# skip when it is absent. Arguments are passed on to setup.sh (e.g. --werror).
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${root_dir}/scripts/setup.sh" --with-paraview "$@"
ctest --test-dir "${root_dir}/build" --output-on-failure -j2
