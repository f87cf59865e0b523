#!/bin/bash
# Thesis Algorithm 1 as Table 2.2 runs it (doc/contact_assembly.md,
# "Algorithm 1"): the shipped 2D examples once as shipped (one L-BFGS run,
# remeshed when the mesh quality falls below Remesh quality) and once with
# 10 outer iterations (a stagnated run is followed by a remesh and a fresh
# L-BFGS run) and the volume bound's weight ramped 10^2 -> 10^3 over them.
# Reports per run: outer iterations oi/max_oi, iterations, J/J0, max stress
# initial -> final and its reduction, volume, the relative gradient norm
# and the last outer iteration's reduction of J (% of J0), as the thesis's
# table does, and the wall time.
# Writes results/algorithm1_examples.csv (about 15 minutes on one core).
#   contrib/benchmarks/algorithm1_examples.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" algorithm1_examples "$@"
echo "example,setting,outer,iterations,J_over_J0,initial_max_stress,final_max_stress,reduction,initial_volume,final_volume,relative_gradient_norm,last_outer_reduction_percent,seconds" > "$out"
cd "$examples"
while IFS='|' read -r example terms; do
  for setting in shipped algorithm1; do
    args=()
    if [ "$setting" = algorithm1 ]; then
      args=(--set "Optimization/Max iterations=300"
            --set "Optimization/Outer iterations=10"
            --set "Objective/Terms=$terms")
    fi
    "$app" "$example.prm" --set "Output directory=$work/out" \
      --set "Output/Write vtu=false" "${args[@]}" > "$work/log" 2>&1 || true
    python3 - "$example" "$setting" "$work/out/summary.json" >> "$out" <<'EOPY'
import json, sys
example, setting, summary = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
print("%s,%s,%d/%d,%d,%.4f,%.4g,%.4g,%.2f,%.5g,%.5g,%.3g,%.3g,%.0f" % (
    example, setting, o["outer_iterations"], o["max_outer_iterations"],
    o["iterations"], o["ratio"], s["initial_max_stress"],
    s["final_max_stress"], s["initial_max_stress"] / s["final_max_stress"],
    s["initial_volume"], s["final_volume"], o["relative_gradient_norm"],
    o["last_outer_reduction_percent"], s["timing"]["total_seconds"]))
EOPY
    tail -1 "$out"
  done
done <<ROWS
connector_stress|stress : p=20 ; volume bound : bound=4, weight=100, final weight=1000
lever|stress : p=20 ; volume bound : bound=3.7, weight=100, final weight=1000
bridge|stress : p=20 ; volume bound : bound=3.9, weight=100, final weight=1000
hook|stress : p=20 ; volume bound : bound=1.9503, weight=100, final weight=1000
ROWS
