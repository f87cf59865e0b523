#!/usr/bin/env bash
# IPC contact cost in 3D: two stacked Neo-Hookean blocks (P1 tetrahedra from
# hexahedra split into 24) resting on a floor plane, with a 1e-3 gap under
# each, dropped under gravity for a few BDF2 steps (CG + AMG). Every step has
# body-body (point-triangle, edge-edge) and body-plane pairs in contact.
# Sizes N = 4 8 12 16 (N^3 hexahedra, 24 N^3 tetrahedra: about 1.5k, 12k,
# 41k and 98k). Per run: DoFs, tetrahedra, mean active pairs, mean Newton
# iterations, mean step time and its split (elasticity assembly, contact
# assembly, broad phase, CCD, linear solver), contact time per active pair.
# Writes results/ipc_scaling.csv. Machine-dependent: compare within one run.
#
#   bash contrib/benchmarks/ipc_scaling.sh [sizes...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$root/contrib/benchmarks/stack_scene.sh"
app=$root/build/bin/forma-transient-ipc
sizes=${*:-4 8 12 16}
work=$(mktemp -d)
out=$root/contrib/benchmarks/results/ipc_scaling.csv
mkdir -p "$(dirname "$out")"
echo "N,tets,dofs,steps,active_pairs,newton_its,step_s,assembly_s,contact_s,broad_s,ccd_s,solver_s,contact_us_per_pair,min_distance,inverted" > "$out"
for n in $sizes; do
  python3 "$root/contrib/meshes/make_ipc_meshes.py" --stack "$n" "$work/stack$n.msh"
  stack_scene_prm "$work/stack$n.msh" "$work/out$n" 0.05 "cg-amg" > "$work/run$n.prm"
  "$app" "$work/run$n.prm" > "$work/run$n.log"
  python3 - "$work/out$n/summary.json" "$n" >> "$out" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
steps = [x for x in s["steps"] if x["step"] > 0]
m = lambda f: sum(f(x) for x in steps) / len(steps)
sec = lambda k: m(lambda x: x["contact"]["seconds"][k])
pairs = m(lambda x: x["contact"]["active_pairs"])
print(",".join(str(v) for v in [
    sys.argv[2], s["n_cells"], s["n_dofs"], len(steps), round(pairs),
    round(m(lambda x: x["newton_iterations"]), 1),
    round(sec("step"), 3), round(sec("assembly") - sec("contact_assembly"), 3),
    round(sec("contact_assembly"), 3), round(sec("broad_phase"), 3),
    round(sec("ccd"), 4), round(sec("linear_solver"), 3),
    round(1e6 * sec("contact_assembly") / max(pairs, 1)
          / m(lambda x: x["newton_iterations"] + 1), 1),
    s["ipc"]["min_distance"], s["ipc"]["inverted_elements"]]))
PY
  tail -1 "$out"
done
rm -rf "$work"
echo "written $out"
