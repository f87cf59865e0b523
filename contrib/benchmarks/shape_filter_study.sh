#!/bin/bash
# What the shape filter (Design/Shape filter radius, vertex morphing) and
# boundary resampling (Design/Remesh boundary = resample) do to the 2D
# examples of thesis Table 2.2 (doc/contact_assembly.md, "Shape filter and
# boundary resampling"): each run is the shipped example with the settings
# of its row, everything else as shipped (the lever and the bridge ship
# with radius 0.2 now, and the lever's wall face slides along the wall:
# the rows marked "before" are their old set-ups). Reports iterations,
# remeshes, holds of blocked vertices, max stress initial -> final and its
# ratio, the volume, the wall time and thesis Table 2.2's columns (outer
# iterations = meshes, relative gradient norm, the last outer iteration's
# reduction of J in % of J0).
# Writes results/shape_filter_study.csv (about 25 minutes on one core).
#   contrib/benchmarks/shape_filter_study.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" shape_filter_study "$@"
echo "example,setting,iterations,remeshes,holds,initial_max_stress,final_max_stress,reduction,final_volume,seconds,outer_iterations,relative_gradient_norm,last_outer_reduction_percent,stop" > "$out"
cd "$examples"
# Rows: example | setting (the CSV's label) | --set overrides of the
# shipped file, '|'-separated.
old_lever="Design/Fixed boundaries=1, 2, 3|Design/Symmetry planes="
while IFS='|' read -r example setting rest; do
  args=()
  IFS='|' read -ra sets <<< "$rest"
  for x in "${sets[@]}"; do [ -n "$x" ] && args+=(--set "$x"); done
  "$app" "$example.prm" --set "Output directory=$work/out" \
    --set "Output/Write vtu=false" "${args[@]}" > "$work/log" 2>&1 || true
  python3 - "$example" "$setting" "$work/out/summary.json" "$work/log" >> "$out" <<'EOPY'
import json, sys
example, setting, summary, log = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
text = open(log).read()
stop = [l for l in text.splitlines() if l.startswith("stopped after")]
print("%s,\"%s\",%d,%d,%d,%.3g,%.3g,%.2f,%.4g,%.0f,%d,%.2g,%.2g,%s" % (
    example, setting, s["history"][-1]["iteration"], len(o["remeshes"]),
    text.count("holding "), s["initial_max_stress"], s["final_max_stress"],
    s["initial_max_stress"] / s["final_max_stress"], s["final_volume"],
    s["timing"]["total_seconds"], o["outer_iterations"],
    o["relative_gradient_norm"], o["last_outer_reduction_percent"],
    stop[0].split(": ", 1)[1] if stop else "-"))
EOPY
  tail -1 "$out"
done <<ROWS
lever|wall fixed, no filter (before)|$old_lever|Design/Shape filter radius=0
lever|wall fixed, no filter, resample|$old_lever|Design/Shape filter radius=0|Design/Remesh boundary=resample
lever|wall fixed, filter 0.2|$old_lever
lever|wall fixed, filter 0.2, resample|$old_lever|Design/Remesh boundary=resample
lever|wall fixed, filter 0.3|$old_lever|Design/Shape filter radius=0.3
lever|wall slides, filter 0.2 (shipped)|
lever|wall slides, filter 0.15|Design/Shape filter radius=0.15
bridge|no filter (before)|Design/Shape filter radius=0
bridge|filter 0.2 (shipped)|
bridge|filter 0.25|Design/Shape filter radius=0.25
connector_stress|no filter (shipped)|
connector_stress|filter 0.25|Design/Shape filter radius=0.25
hook|no filter (shipped)|
hook|no filter, resample|Design/Remesh boundary=resample
hook|filter 0.1|Design/Shape filter radius=0.1
hook|filter 0.1, resample|Design/Shape filter radius=0.1|Design/Remesh boundary=resample
hook|filter 0.15|Design/Shape filter radius=0.15
ROWS
