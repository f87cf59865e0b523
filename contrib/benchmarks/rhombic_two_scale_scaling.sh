#!/usr/bin/env bash
# forma-rhombic two-scale pipeline against the number of cells (thesis Fig.
# 4.31: "running time scales linearly with the number of cells"): the bar
# of parameter_files/rhombic/bar_design.prm with its quad mesh refined 0,
# 1 and 2 times (63, 252, 1008 cells), one material everywhere (no
# optimization: its iteration count would not be a property of the
# pipeline), the tiled geometry meshed but not simulated. Seconds per stage
# from summary.json: rhombic mesh, map queries, fine mesh; seconds per cell.
#
#   bash contrib/benchmarks/rhombic_two_scale_scaling.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-rhombic
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "refinement  cells  triangles  rhombic mesh s  map s  fine mesh s  total s  total s / cell"
for r in 0 1 2; do
  "$app" "$root/parameter_files/rhombic/bar_mesh_independence.prm" \
    --set "Output directory=$work/r$r" --set "Quad mesh/Refinement=$r" \
    --set "Two-scale/Fine-scale simulation=false" > "$work/r$r.out"
  python3 - "$work/r$r/summary.json" "$r" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["seconds"]
cells = s["two_scale"]["cells"]
fine = t["fine mesh, family"] + t["fine mesh, remapped_square"]
total = t["rhombic mesh"] + t["map"] + fine
print("%10s %6d %10d %15.2f %6.2f %12.2f %8.2f %15.4f" % (
    sys.argv[2], cells, s["fine_scale"]["family"]["triangles"],
    t["rhombic mesh"], t["map"], fine, total, total / cells))
PY
done
