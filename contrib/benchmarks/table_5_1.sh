#!/bin/bash
# Thesis Table 5.1 side by side (doc/laminate.md): runs
# parameter_files/laminate/table_5_1.prm and writes one row per iteration
# (J on the grid, |dJ/dq|, E/Eb, nu and J on the conforming mesh, |dJ/dX|
# on the solid-void interface, its share within one element of a corner)
# to results/table_5_1.csv. About 1.5 minutes on one core.
#   contrib/benchmarks/table_5_1.sh [build/bin/forma-laminate]
set -e
app=$(realpath "${1:-build/bin/forma-laminate}")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$here/../../parameter_files/laminate"
"$app" table_5_1.prm --set "Output directory=$work/out" > "$work/log"
python3 - "$work/out/summary.json" > "$here/results/table_5_1.csv" <<'EOPY'
import json, sys
s = json.load(open(sys.argv[1]))
print("iteration,J_grid,parameter_gradient_norm,E_over_Eb_mesh,nu_mesh,J_mesh,"
      "shape_derivative_norm,corner_share,interface_vertices,p1,p2,p4")
for r in s["shape_derivative"]:
    t = r["structure"]
    print("%d,%.5g,%.4g,%.5g,%.5g,%.5g,%.5g,%.3f,%d,%.5g,%.5g,%.5g" % (
        r["iteration"], r["J"], r["parameter_gradient_norm"],
        r["mesh_E_over_Eb"], r["mesh_nu"], r["mesh_J"],
        r["shape_derivative_norm"], r["corner_share"],
        r["interface_vertices"], t["p1"], t["p2"], t["p4"]))
EOPY
cat "$here/results/table_5_1.csv"
