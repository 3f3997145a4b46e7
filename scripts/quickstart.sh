#!/usr/bin/env bash
# Sets up and builds splitgrid (scripts/setup.sh), then builds the Split Grid of a real model
# that every Debian machine with assimp-testmodels has, saves it to build/engine.sg and prints
# its statistics. Arguments are passed on to setup.sh (e.g. --werror).
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${root_dir}/scripts/setup.sh" "$@"

model=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
"${root_dir}/build/apps/sg-build" "${model}" -o "${root_dir}/build/engine.sg"
echo
"${root_dir}/build/apps/sg-stats" "${root_dir}/build/engine.sg"
