#!/usr/bin/env bash
# Cost of an adjoint gradient through IPC contact and friction relative to
# the forward simulation of the same run (issue 7; thesis: at most 2x, its
# follow-up under 1.1x), with the memory of the stored trajectory:
#  - ball2d-rK: the bouncing ball of ball_material_recovery.prm (friction
#    on an incline, 60 BDF2 steps), Q2, refinements K = 2 3 4;
#  - stack3d-N: two stacked P1 blocks (make_ipc_meshes.py --stack N, 24 N^3
#    tetrahedra) dropped on a floor with friction, 5 BDF2 steps, N = 4 8.
# Mode = optimize with 0 iterations: one forward solve and one gradient;
# every number comes from one run's summary.json (adjoint statistics).
# Writes results/ipc_gradient_cost.csv. Machine-dependent: compare ratios.
#
#   bash contrib/benchmarks/ipc_gradient_cost.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-transient-ipc
work=$(mktemp -d)
out=$root/contrib/benchmarks/results/ipc_gradient_cost.csv
source "$root/contrib/benchmarks/stack_scene.sh"
mkdir -p "$(dirname "$out")"
echo "case,n_dofs,steps,seconds_per_forward_solve,seconds_per_gradient,ratio,stored_MB,stored_kB_per_step" > "$out"

collect() { # name summary.json
  python3 - "$2" "$1" >> "$out" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
a = s["adjoint"]
t = s["parameters"]["Time"]
n = round(float(t["End time"]["value"]) /
          float(t["Time step"]["value"]))
mb = a["stored_state_bytes"] / 1e6
print(f'{sys.argv[2]},{a["n_dofs"]},{n},{a["seconds_per_forward_solve"]:.3f},'
      f'{a["seconds_per_gradient"]:.3f},'
      f'{a["seconds_per_gradient"] / a["seconds_per_forward_solve"]:.3f},'
      f'{mb:.2f},{1e3 * mb / (n + 1):.1f}')
PY
}

for k in 2 3 4; do
  "$app" "$root/parameter_files/transient_ipc/ball_material_recovery.prm" \
    --set "Output directory=$work/ball$k" \
    --set "Mesh/Initial refinement=$k" \
    --set "Optimization/Max iterations=0" \
    --set "Output/Write vtu=false" > "$work/ball$k.log"
  collect "ball2d-r$k" "$work/ball$k/summary.json"
done

for n in 4 8; do
  python3 "$root/contrib/meshes/make_ipc_meshes.py" --stack "$n" "$work/stack$n.msh"
  # The scene of stack_scene.sh, pushed sideways, with friction; one
  # forward solve and one gradient of a center-of-mass objective.
  stack_scene_prm "$work/stack$n.msh" "$work/stack$n" 0.05 direct > "$work/stack$n.prm"
  "$app" "$work/stack$n.prm" --set "Mode=optimize" \
    --set "Loads/Gravity=1, 0, -9.81" \
    --set "Solver/Newton relative tolerance=1e-10" \
    --set "IPC/Friction coefficient=0.3" \
    --set "Design/Parameters=material, friction" \
    --set "Objective/Terms=center of mass : x=0.5, y=0.5, z=0.3" \
    --set "Optimization/Max iterations=0" > "$work/stack$n.log"
  collect "stack3d-$n" "$work/stack$n/summary.json"
done
column -s, -t "$out"
