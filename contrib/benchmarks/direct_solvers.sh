#!/usr/bin/env bash
# Direct solvers for IPC contact under MPI (issue 45, item 2): the scene of
# ipc_scaling.sh (two Neo-Hookean blocks of P1 tetrahedra dropped on a floor
# plane, every step with body-body and body-plane pairs in contact), solved
# with Solver/Linear solver = direct (Amesos KLU: the matrix is gathered on
# one rank) and direct-mumps (MUMPS: the factorization is distributed), on 1
# and 2 ranks. Per run: DoFs, wall time of the whole process, mean linear
# solver time per step, peak memory (sum over ranks), and the final mean
# displacement (the answers must agree). KLU runs up to N = 8 only.
# Writes results/direct_solvers.csv.
#
#   bash contrib/benchmarks/direct_solvers.sh [sizes...]   (default 8 12;
#   results/direct_solvers.csv holds 8 12 16 from two runs)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$root/contrib/benchmarks/stack_scene.sh"
app=$root/build/bin/forma-transient-ipc
sizes=${*:-8 12}
work=$(mktemp -d)
out=$root/contrib/benchmarks/results/direct_solvers.csv
mkdir -p "$(dirname "$out")"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "N,dofs,solver,ranks,wall_s,solver_s_per_step,peak_memory_mb,final_mean_displacement_z" > "$out"
for n in $sizes; do
  python3 "$root/contrib/meshes/make_ipc_meshes.py" --stack "$n" "$work/stack$n.msh"
  # KLU's fill-in on 3D meshes: minutes per step beyond N = 8.
  solvers="direct direct-mumps"
  if [ "$n" -gt 8 ]; then solvers=direct-mumps; fi
  for solver in $solvers; do
    for np in 1 2; do
      dir=$work/out$n-$solver-$np
      stack_scene_prm "$work/stack$n.msh" "$dir" 0.03 "$solver" > "$work/run.prm"
      start=$(date +%s.%N)
      mpirun -np "$np" /usr/bin/time -f "peak_kb %M" "$app" "$work/run.prm" \
        > "$work/run.log" 2> "$work/time.txt"
      wall=$(echo "$(date +%s.%N) - $start" | bc)
      mem=$(awk '/^peak_kb / { s += $2 } END { printf "%.0f", s / 1024 }' "$work/time.txt")
      python3 - "$dir/summary.json" "$n" "$solver" "$np" "$wall" "$mem" >> "$out" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
steps = [x for x in s["steps"] if x["step"] > 0]
solver = sum(x["contact"]["seconds"]["linear_solver"] for x in steps) / len(steps)
print(",".join(str(v) for v in [
    sys.argv[2], s["n_dofs"], sys.argv[3], sys.argv[4],
    round(float(sys.argv[5]), 2), round(solver, 3), sys.argv[6],
    "%.10g" % steps[-1]["mean_displacement"][2]]))
PY
      tail -1 "$out"
    done
  done
done
rm -rf "$work"
echo "written $out"
