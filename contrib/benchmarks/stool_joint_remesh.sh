#!/bin/bash
# What 3D boundary remeshing (Design/Remesh boundary = resample, CGAL) does
# to the stool joint of thesis Table 2.2 (doc/contact_assembly.md): the
# shipped run (no remesh) against runs that remesh when the mesh quality
# falls below 0.2, keeping the surface or resampling it. Reports
# iterations, remeshes, holds, J/J0, the connector's (material 1) peak
# stress initial -> final and its ratio, its volume, the first remesh's
# quality before -> after, and the wall time.
# Writes results/stool_joint_remesh.csv (about 6 minutes on one core).
#   contrib/benchmarks/stool_joint_remesh.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" stool_joint_remesh "$@"
echo "setting,iterations,remeshes,holds,J_over_J0,connector_initial,connector_final,reduction,connector_volume,first_remesh,seconds" > "$out"
cd "$examples"
while IFS='|' read -r setting rest; do
  args=()
  IFS='|' read -ra sets <<< "$rest"
  for x in "${sets[@]}"; do [ -n "$x" ] && args+=(--set "$x"); done
  "$app" stool_joint_3d.prm --set "Output directory=$work/out" \
    --set "Output/Write vtu=false" "${args[@]}" > "$work/log" 2>&1 || true
  python3 - "$setting" "$work/out/summary.json" "$work/log" >> "$out" <<'EOPY'
import json, re, sys
setting, summary, log = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
text = open(log).read()
first = re.search(r"remeshed \(min scaled Jacobian ([0-9.]+)\).*min scaled Jacobian ([0-9.]+)", text)
c0 = o["initial_state"]["max_stress_by_material"]["1"]
c1 = o["final_state"]["max_stress_by_material"]["1"]
print("\"%s\",%d,%d,%d,%.3f,%.3g,%.3g,%.2f,%.4g,%s,%.0f" % (
    setting, s["history"][-1]["iteration"], len(o["remeshes"]),
    text.count("holding "), o["ratio"], c0, c1, c0 / c1,
    o["final_state"]["volume_by_material"]["1"],
    "%s -> %s" % first.groups() if first else "-",
    s["timing"]["total_seconds"]))
EOPY
  tail -1 "$out"
done <<ROWS
no remesh (shipped)|
remesh quality 0.2, surface kept|Optimization/Remesh quality=0.2
remesh quality 0.2, surface resampled|Optimization/Remesh quality=0.2|Design/Remesh boundary=resample
ROWS
