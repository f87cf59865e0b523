#!/bin/bash
# Table 2.2's "Post vol. min." (Optimization/Volume minimization
# iterations): the 3D pipe assemblies as shipped (60 iterations of stress
# minimization with the volume held; the tent with its assembly terms, the
# thesis's "Tent (baseline)"), then 40 iterations minimizing the volume of
# the whole assembly with the stress held within 2% of where the stress
# stage left it: its peak (Volume minimization stress bound = peak, the
# default) or its L^20 norm (norm; BOUNDS="peak norm" runs both). Reports
# per example: the max stress initial -> after the stress stage -> final,
# the volume after the stress stage and at the end, and the wall time. Writes results/volume_minimization.csv (about 25
# minutes per bound on one core; doc/contact_assembly.md). A failed run is reported
# as such.
#   contrib/benchmarks/volume_minimization.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" volume_minimization "$@"
echo "example,bound,stress_iterations,volume_iterations,initial_stress,stress_after_stage,final_stress,volume_after_stage,final_volume,volume_change_percent,seconds" > "$out"
cd "$examples"
for bound in ${BOUNDS:-peak}; do
for name in dodecahedron_3d tent_sockets_3d truss_3d; do
  rm -rf "$work/out" # a failed run must not report the last one
  "$app" "$name.prm" --set "Output directory=$work/out" \
    --set "Output/Write vtu=false" \
    --set "Optimization/Volume minimization stress bound=$bound" \
    --set "Optimization/Volume minimization iterations=40" > "$work/log" 2>&1 || true
  if python3 - "$name,$bound" "$work/out/summary.json" >> "$out" <<'EOPY'
import json, sys
name, summary = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
v = o["volume_minimization"]
mid = v["start_state"]
print("%s,%d,%d,%.4g,%.4g,%.4g,%.5g,%.5g,%.2f,%.0f" % (
    name, v["iteration"], o["iterations"] - v["iteration"],
    s["initial_max_stress"], mid["max_stress"], s["final_max_stress"],
    mid["volume"], s["final_volume"],
    100 * (s["final_volume"] / mid["volume"] - 1), s["timing"]["total_seconds"]))
EOPY
  then :; else echo "$name,$bound,failed" >> "$out"; fi
  tail -1 "$out"
done
done
