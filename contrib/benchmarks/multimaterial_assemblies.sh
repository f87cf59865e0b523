#!/bin/bash
# The thesis's 3D multimaterial assemblies (Table 2.2: stool, coat rack
# base and hooks): PLA connectors (material 1) optimized for stress among
# fixed wooden parts, the shipped examples as they are, and the stool with
# more material allowed (ch. 2.7.2: "If 10% increase in the volume is
# allowed, the stress decreases to 0.88, and to 0.85 at 20%", against 2.68
# -> 1.12 with the volume held): its connector's volume bound at 1.1 and
# 1.2 times its initial 1.759. Reports tetrahedra, iterations, remeshes,
# holds, the stop reason, J/J0, the connector's peak stress initial ->
# final and its factor, the connector's volume ratio and the wall time.
# Writes results/multimaterial_assemblies.csv (about 30 minutes on one
# core; doc/contact_assembly.md, "Coat rack", and the stool under "Shipped
# examples"). A failed run is reported as such.
#   contrib/benchmarks/multimaterial_assemblies.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" multimaterial_assemblies "$@"
echo "example,volume_factor,tetrahedra,iterations,remeshes,holds,stop_reason,J_over_J0,initial_connector_stress,final_connector_stress,factor,connector_volume_ratio,seconds" > "$out"
cd "$examples"
stool_terms() {
  echo "stress : p=20, material=1 ; volume bound : bound=$(python3 -c "print('%.4f' % (1.759 * $1))"), material=1, weight=100"
}
for run in stool_3d:1.0 stool_3d:1.1 stool_3d:1.2 coat_rack_base_3d:1.0 coat_rack_hooks_3d:1.0; do
  name=${run%%:*}
  factor=${run##*:}
  args=()
  if [ "$factor" != 1.0 ]; then
    args+=(--set "Objective/Terms=$(stool_terms "$factor")")
  fi
  run_with_mesh "$name" "${args[@]}"
  if python3 - "$name" "$factor" "$work/out/summary.json" "$work/log" \
    "$work/mesh/summary.json" >> "$out" <<'EOPY'
import json, sys
name, factor, summary, log, mesh = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
i0, i1 = o["initial_state"], o["final_state"]
i, f = i0["max_stress_by_material"]["1"], i1["max_stress_by_material"]["1"]
text = open(log).read()
cells = json.load(open(mesh))["n_cells"]
print("%s,%s,%d,%d,%d,%d,%s,%.4f,%.4g,%.4g,%.2f,%.4f,%.0f" % (
    name, factor, cells, s["history"][-1]["iteration"], len(o["remeshes"]),
    text.count("holding "), o["stop_reason"].replace(",", ";"), o["ratio"], i, f, i / f,
    i1["volume_by_material"]["1"] / i0["volume_by_material"]["1"],
    s["timing"]["total_seconds"]))
EOPY
  then :; else echo "$name,$factor,failed" >> "$out"; fi
  tail -1 "$out"
done
