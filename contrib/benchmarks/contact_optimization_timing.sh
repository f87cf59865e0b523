#!/bin/bash
# The 2D connector optimization (forma-contact-assembly, connector_stress.prm)
# end to end, its wall time split into forward Newton solves, adjoint linear
# solves, derivative products (objective partials and shape derivative),
# remeshing and the rest (optimizer, line-search checks, output), with the
# max stress at the start and the end, for the
# shipped mesh (h = 0.1) and a finer one (h = 0.05, needs the gmsh command:
# apt-get install gmsh). Numbers from summary.json ("timing", "adjoint").
# Writes results/contact_optimization_timing.csv.
#   contrib/benchmarks/contact_optimization_timing.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" contact_optimization_timing "$@"
echo "element_size,n_dofs,iterations,remeshes,forward_solves,gradients,total_s,forward_s,adjoint_solve_s,derivative_products_s,remesh_s,other_s,gradient_per_forward_solve,initial_max_stress,final_max_stress" > "$out"
cd "$work"
for h in 0.1 0.05; do
  mesh="$examples/meshes/connector_2d.msh"
  if [ "$h" != 0.1 ]; then
    command -v gmsh > /dev/null || { echo "gmsh not found: skipping h = $h"; continue; }
    gmsh -2 -format msh2 -setnumber h "$h" "$examples/meshes/connector_2d.geo" \
      -o "connector_$h.msh" > /dev/null
    mesh="$work/connector_$h.msh"
  fi
  "$app" "$examples/connector_stress.prm" --set "Output directory=out_$h" \
    --set "Mesh/File=$mesh" --set "Output/Write vtu=false" > /dev/null
  python3 - "$h" "out_$h/summary.json" >> "$out" <<'EOPY'
import json, sys
s = json.load(open(sys.argv[2]))
a, t, o = s["adjoint"], s["timing"], s["optimization"]
per_solve = a["forward_seconds"] / a["forward_solves"]
per_gradient = a["adjoint_seconds"] / a["gradients"]
print("%s,%d,%d,%d,%d,%d,%.3g,%.3g,%.3g,%.3g,%.3g,%.3g,%.3f,%.3g,%.3g" % (
    sys.argv[1], a["n_dofs"], o["iterations"], len(o["remeshes"]),
    a["forward_solves"], a["gradients"], t["total_seconds"],
    t["forward_seconds"], t["adjoint_solve_seconds"],
    t["derivative_products_seconds"], t["remesh_seconds"],
    t["other_seconds"], per_gradient / per_solve,
    s["initial_max_stress"], s["final_max_stress"]))
EOPY
  tail -1 "$out"
done
