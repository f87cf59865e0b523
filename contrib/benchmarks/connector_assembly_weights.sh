#!/bin/bash
# The assembly/disassembly trade-off of thesis Fig. 2.15 and Table 2.1 on
# the shipped connector (forma-contact-assembly, connector_disassembly.prm):
# the disassembly weight stays at 1e4 while the assembly weight goes
# 1e4, 1e3, 100, 10 (the thesis's 100, 10, 1, 0.1 against 100: our terms
# are smaller, see doc/contact_assembly.md); a first run without either term (weights 1e-6: they
# are measured, not optimized) is the baseline of Fig. 2.14. For each run
# it reports the final unweighted assembly (eq. 2.17), disassembly (eq.
# 2.18) and stress (L^20) terms, the max stress and the volume.
# Writes results/connector_assembly_weights.csv.
#   contrib/benchmarks/connector_assembly_weights.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" connector_assembly_weights "$@"
echo "assembly_weight,disassembly_weight,iterations,assembly,disassembly,stress,initial_max_stress,final_max_stress,final_volume" > "$out"
cd "$examples"
for weights in "1e-6 1e-6" "1e4 1e4" "1e3 1e4" "100 1e4" "10 1e4"; do
  set -- $weights
  terms="stress : p=20 ; volume bound : bound=4, weight=100"
  terms="$terms ; assembly : boundary=10, material=1, x=0, y=1, weight=$1"
  terms="$terms ; disassembly : boundary=10, material=2, x=0, y=1, tolerance=1e-3, weight=$2"
  "$app" connector_disassembly.prm --set "Output directory=$work/out" \
    --set "Objective/Terms=$terms" --set "Output/Write vtu=false" > /dev/null
  python3 - "$1" "$2" "$work/out/summary.json" >> "$out" <<'EOPY'
import json, sys
wa, wd = float(sys.argv[1]), float(sys.argv[2])
s = json.load(open(sys.argv[3]))
last = s["history"][-1]
t = last["terms"]
print("%s,%s,%d,%.4g,%.4g,%.4g,%.3g,%.3g,%.4g" % (
    sys.argv[1], sys.argv[2], last["iteration"], t["assembly"] / wa,
    t["disassembly"] / wd, t["stress"], s["initial_max_stress"],
    s["final_max_stress"], s["final_volume"]))
EOPY
  tail -1 "$out"
done
