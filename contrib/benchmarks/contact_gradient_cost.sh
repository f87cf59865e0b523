#!/bin/bash
# Cost of the adjoint shape gradient against the forward (Newton) solve of
# the same run for the 2D connector with frictionless and frictional DD
# contact (forma-contact-assembly), over meshes from Gmsh at element sizes
# 0.1, 0.05, 0.025 (P2). Mode = optimize with 0 iterations: one forward
# solve and one gradient; the numbers come from summary.json (adjoint
# statistics). Writes results/contact_gradient_cost.csv.
#   contrib/benchmarks/contact_gradient_cost.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" contact_gradient_cost "$@"
echo "case,element_size,n_dofs,seconds_per_forward_solve,seconds_per_gradient,ratio" > "$out"
cd "$work"
for h in 0.1 0.05 0.025; do
  gmsh -2 -format msh2 -setnumber h "$h" "$examples/meshes/connector_2d.geo" \
    -o "connector_$h.msh" > /dev/null
  for law in frictionless friction; do
    extra=""
    [ "$law" = friction ] && extra="--set Contact/Deformable-deformable=10:alpha=1e-4,eta=1e-5,mu=1,eta_n=1e-4"
    "$app" "$examples/connector_stress.prm" \
      --set "Output directory=out" --set "Mesh/File=$work/connector_$h.msh" \
      --set "Optimization/Max iterations=0" --set "Output/Write vtu=false" \
      $extra > /dev/null
    python3 - "$law" "$h" >> "$out" <<'EOPY'
import json, sys
a = json.load(open("out/summary.json"))["adjoint"]
f, g = a["seconds_per_forward_solve"], a["seconds_per_gradient"]
print("%s,%s,%d,%.4g,%.4g,%.3f" % (sys.argv[1], sys.argv[2], a["n_dofs"], f, g, g / f))
EOPY
    tail -1 "$out"
  done
done
