#!/usr/bin/env bash
# The shipped 3D contact assemblies on 1 and 2 MPI ranks (issue 40, item 5):
# each runs ITERATIONS (default 3) optimization iterations on one rank and on
# two, and the objective history, final max stress and volume are compared.
# Writes contrib/benchmarks/results/mpi_3d_examples.csv; about 5 minutes.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app="$root/build/bin/forma-contact-assembly"
iterations=${ITERATIONS:-3}
examples=${EXAMPLES:-"stool_3d stool_joint_3d tent_3d tent_sockets_3d truss_3d dodecahedron_3d coat_rack_hooks_3d coat_rack_base_3d"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$root/contrib/benchmarks/results/mpi_3d_examples.csv"
echo "example,iterations,J_1_rank,J_2_ranks,max_relative_difference_of_J_history,max_stress_1,max_stress_2,volume_1,volume_2" > "$out.tmp"
for e in $examples; do
  prm="$root/parameter_files/contact_assembly/$e.prm"
  for n in 1 2; do
    (cd "$(dirname "$prm")" &&
      mpirun -np $n "$app" "$prm" --set "Output directory=$work/$e-$n" \
        --set "Optimization/Max iterations=$iterations" > "$work/$e-$n.log" 2>&1)
  done
  python3 - "$work/$e-1/summary.json" "$work/$e-2/summary.json" "$e" \
    "$iterations" >> "$out.tmp" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
ja = [h["objective"] for h in a["history"]]
jb = [h["objective"] for h in b["history"]]
diff = max(abs(x - y) / abs(x) for x, y in zip(ja, jb)) if len(ja) == len(jb) \
    else float("inf")
print("%s,%s,%.10g,%.10g,%.2g,%.6g,%.6g,%.6g,%.6g" % (
    sys.argv[3], sys.argv[4], ja[-1], jb[-1], diff, a["final_max_stress"],
    b["final_max_stress"], a["final_volume"], b["final_volume"]))
PY
  tail -1 "$out.tmp"
done
mv "$out.tmp" "$out"
