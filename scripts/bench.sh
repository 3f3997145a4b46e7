#!/usr/bin/env bash
# The documented full run of sg-bench (docs/BENCH.md): every mesh of ../shared/meshes (but
# tricky/, which Assimp misreads), the CAD model 2CylinderEngine.glb of assimp-testmodels,
# arena scenes of 2.5 and 10 million triangles made from the Stanford dragon, and the memory
# series from 10^3 to 10^7 triangles; then the charts and docs/RESULTS.md with its images in
# docs/images/bench_*.png, and the run's results.json as docs/results.json (the "before" of
# the next run).
#
# Usage: scripts/bench.sh [--quick] [more sg-bench flags]
#   SG_BENCH_OUT   output folder (default build/bench-full, or build/bench-quick with --quick)
#   SG_MESHES      the meshes folder (default ../shared/meshes beside the clone)
# With --quick the same pipeline runs on small workloads and small scenes in a few minutes,
# and the report goes to the output folder instead of docs/ (quick figures are no results).
# Builds the project first if needed (scripts/setup.sh). Run it on an otherwise idle machine:
# every figure is a wall-clock time.
set -euo pipefail

root_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
meshes="${SG_MESHES:-${root_dir}/../shared/meshes}"
quick=false
for arg in "$@"; do
    if [[ "${arg}" == "--quick" ]]; then quick=true; fi
done
if [[ ! -d "${meshes}" ]]; then
    echo "bench.sh: ${meshes} not found (set SG_MESHES to the folder of benchmark meshes)" >&2
    exit 2
fi
if [[ ! -x "${root_dir}/build/apps/sg-bench" ]]; then
    bash "${root_dir}/scripts/setup.sh"
fi
# CGAL (GPL, optional: SG_WITH_CGAL) is the reference of the point workloads: make sure this
# tree's sg-bench has it, whatever the tree was configured with before.
cmake -S "${root_dir}" -B "${root_dir}/build" -DSG_WITH_CGAL=ON > /dev/null
cmake --build "${root_dir}/build" --target sg-bench

scenes=(
    scanned/stanford_dragon_vrip.ply
    scanned/stanford_dragon_vrip_res2.ply
    scanned/stanford_dragon_vrip_res4.ply
    scanned/igea_triangles.ply
    scanned/nefertiti.obj
    scanned/stanford_bunny.obj
    scanned/lionstatue.obj
    scanned/bunny_npm.obj
    scenes/bmw_m6.ply
    scenes/crytek_sponza_columns_shrubbery_part.obj
    scenes/mountain.obj
    models/tachikoma.obj
    models/teapot.obj
    gltf/balloon/scene.gltf
    gltf/smallpine/scene.gltf
)
# The CAD model: Assimp's 2CylinderEngine from Debian's assimp-testmodels (scripts/setup.sh
# installs it), the scene where the Split Grid reaches its depth limit.
cad_model=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
args=()
if [[ "${quick}" == true ]]; then
    out="${SG_BENCH_OUT:-${root_dir}/build/bench-quick}"
    scenes=(scanned/stanford_dragon_vrip_res2.ply scanned/bunny_npm.obj models/teapot.obj)
    args+=(--arena-sizes 1e6 --scale-sizes 1e3,1e4,1e5,1e6)
else
    out="${SG_BENCH_OUT:-${root_dir}/build/bench-full}"
    args+=(--arena-sizes 2.5e6,1e7 --scale-sizes 1e3,1e4,1e5,1e6,1e7)
fi
paths=()
for s in "${scenes[@]}"; do paths+=("${meshes}/${s}"); done
if [[ "${quick}" != true ]]; then paths+=("${cad_model}"); fi

# The sweep runs on the first scene; the scale series and the arenas use the dragon. The point
# sets go to points/ for Open3D's inside tests below.
mkdir -p "${out}"
"${root_dir}/build/apps/sg-bench" -o "${out}" --save-points "${out}/points" \
    --scale-model "${meshes}/scanned/stanford_dragon_vrip.ply" "${args[@]}" "$@" "${paths[@]}"

# Open3D (python3-open3d) on the inside tests' points: its wrong answers, into
# inside_open3d.json, inside_open3d.md and inside_tests.png.
if PYTHONPATH="${root_dir}/build/python" /usr/bin/python3 -c "import open3d, splitgrid" \
    2>/dev/null; then
    /usr/bin/python3 "${root_dir}/scripts/bench_inside_open3d.py" "${out}/results.json" \
        "${out}/points" > "${out}/inside_open3d.md"
else
    echo "bench.sh: no python3-open3d or splitgrid package: Open3D's inside tests left out" >&2
fi

# The dynamic workload, a run of its own: copies of the Stanford bunny (at least 1M triangles)
# moving rigidly, and the dragon deforming.
if [[ "${quick}" == true ]]; then
    dynamic_args=(--dynamic-frames 4 --dynamic-rays 1e3,1e4 --dynamic-triangles 100000
                  --dynamic-rigid "${meshes}/scanned/bunny_npm.obj"
                  --dynamic-deform "${meshes}/scanned/stanford_dragon_vrip_res4.ply")
else
    dynamic_args=(--dynamic-frames 30 --dynamic-rays 1e4,1e5,1e6 --dynamic-triangles 1000000
                  --dynamic-rigid "${meshes}/scanned/stanford_bunny.obj"
                  --dynamic-deform "${meshes}/scanned/stanford_dragon_vrip.ply")
fi
"${root_dir}/build/apps/sg-bench" -o "${out}/dynamic" "${dynamic_args[@]}" "$@"

if [[ "${quick}" == true ]]; then
    cp "${out}/dynamic/dynamic.png" "${out}/dynamic.png" 2>/dev/null || true
    /usr/bin/python3 "${root_dir}/scripts/bench_report.py" "${out}/results.json" "${out}" "" \
        "${out}/dynamic/results.json" > "${out}/RESULTS.md"
    echo "bench.sh: report in ${out}/RESULTS.md"
else
    cp "${out}/dynamic/dynamic.png" "${out}/dynamic.png" 2>/dev/null || true
    for chart in figure3 speed_vs_accuracy sweep_build_vs_trace memory_scaling dynamic \
        point_workloads inside_tests; do
        if [[ -f "${out}/${chart}.png" ]]; then
            cp "${out}/${chart}.png" "${root_dir}/docs/images/bench_${chart}.png"
        fi
    done
    /usr/bin/python3 "${root_dir}/scripts/bench_report.py" "${out}/results.json" "${out}" \
        "images/bench_" "${out}/dynamic/results.json" > "${root_dir}/docs/RESULTS.md.tmp"
    mv "${root_dir}/docs/RESULTS.md.tmp" "${root_dir}/docs/RESULTS.md"
    # The same JSONs with the scene files named relative to the meshes folder, as the report
    # names them: no machine's absolute path in docs/.
    for pair in "results.json:results.json" "dynamic/results.json:dynamic.json"; do
        /usr/bin/python3 - "${out}/${pair%%:*}" "${meshes}/" > "${root_dir}/docs/${pair##*:}" <<'EOF'
import json, sys
text = open(sys.argv[1]).read().replace(json.dumps(sys.argv[2])[1:-1], "")
json.dump(json.loads(text), sys.stdout, indent=1)
EOF
    done
    echo "bench.sh: report in docs/RESULTS.md, charts in docs/images/bench_*.png"
fi
