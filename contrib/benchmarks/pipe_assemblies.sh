#!/bin/bash
# The thesis's 3D pipe-like assemblies (Table 2.2: tent, truss,
# dodecahedron), made from their graphs (Mesh/Source = pipe graph) and
# optimized for stress with the volume held (doc/contact_assembly.md,
# "3D pipe assemblies from graphs"): the shipped examples with 60
# iterations, and the tent and the truss with 150. Reports tetrahedra,
# iterations, holds, J/J0, the max stress initial -> final and its factor,
# the volume ratio, the relative gradient norm (a column of Table 2.2) and
# the wall time. Writes results/pipe_assemblies.csv (about 30 minutes on
# one core). A failed run is reported as such.
#   contrib/benchmarks/pipe_assemblies.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" pipe_assemblies "$@"
echo "example,iterations_limit,tetrahedra,iterations,holds,J_over_J0,initial_stress,final_stress,factor,volume_ratio,relative_gradient_norm,seconds" > "$out"
cd "$examples"
for run in tent_3d:60 truss_3d:60 dodecahedron_3d:60 tent_3d:150 truss_3d:150; do
  name=${run%%:*}
  limit=${run##*:}
  run_with_mesh "$name" --set "Optimization/Max iterations=$limit"
  if python3 - "$name" "$limit" "$work/out/summary.json" "$work/log" \
    "$work/mesh/summary.json" >> "$out" <<'EOPY'
import json, sys
name, limit, summary, log, mesh = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
print("%s,%s,%d,%d,%d,%.4f,%.4g,%.4g,%.2f,%.4f,%.3g,%.0f" % (
    name, limit, json.load(open(mesh))["n_cells"], s["history"][-1]["iteration"],
    open(log).read().count("holding "), o["ratio"], s["initial_max_stress"],
    s["final_max_stress"], s["initial_max_stress"] / s["final_max_stress"],
    s["final_volume"] / s["initial_volume"], o["relative_gradient_norm"],
    s["timing"]["total_seconds"]))
EOPY
  then :; else echo "$name,$limit,failed" >> "$out"; fi
  tail -1 "$out"
done
