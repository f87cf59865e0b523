#!/bin/bash
# Cost of an adjoint gradient relative to the forward solve of the same run
# (issue 3): static Neo-Hookean (2D and 3D, Q2) over growing meshes, and a
# transient BDF2 run over growing numbers of steps (memory of the stored
# states). Mode = optimize with 0 iterations: one forward solve and one
# gradient at the default tolerances; every number comes
# from one run's summary.json (adjoint statistics).
#   contrib/benchmarks/gradient_cost.sh [build/bin/forma-transient-ipc]
set -e
app=$(realpath "${1:-build/bin/forma-transient-ipc}")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
out="$here/results/gradient_cost.csv"
mkdir -p "$here/results"
echo "case,n_dofs,steps,seconds_per_forward_solve,seconds_per_gradient,ratio,stored_state_MB" > "$out"
cd "$work"

run() { # name dim mesh-arguments problem steps bdf
  local name=$1 dim=$2 mesh=$3 problem=$4 steps=$5
  local dirichlet="0 : xy : 0, 0" traction="1 : 0, -5" gravity="0, -9.81"
  if [ "$dim" = 3 ]; then
    dirichlet="0 : xyz : 0, 0, 0"; traction="1 : 0, -5, 0"; gravity="0, 0, -9.81"
  fi
  cat > run.prm <<EOT
set Dimension = $dim
set Output directory = out
set Mode = optimize
subsection Mesh
  set Generator = subdivided_hyper_rectangle
  set Generator arguments = $mesh
end
subsection Finite element
  set Degree = 2
end
subsection Material
  set Model = neo-hookean
  set Bodies = * : E = 1e4, nu = 0.3, density = $([ "$problem" = static ] && echo 1 || echo 10), damping shear = 20, damping bulk = 10
end
subsection Boundary conditions
  set Dirichlet = $dirichlet
  set Traction = $traction
end
subsection Loads
  set Gravity = $gravity
end
subsection Time
  set Problem = $problem
  set End time = $(python3 -c "print($steps * 0.01)")
  set Time step = 0.01
  set BDF order = 2
end
subsection Design
  set Parameters = shape, material
  set Fixed boundaries = 0
end
subsection Objective
  set Terms = von mises : p=4 ; target
end
subsection Optimization
  set Max iterations = 0
end
EOT
  "$app" run.prm > /dev/null
  python3 - "$name" "$steps" >> "$out" <<'EOPY'
import json, sys
a = json.load(open("out/summary.json"))["adjoint"]
f, g = a["seconds_per_forward_solve"], a["seconds_per_gradient"]
print("%s,%d,%s,%.4g,%.4g,%.3f,%.3f" % (sys.argv[1], a["n_dofs"], sys.argv[2],
      f, g, g / f, a["stored_state_bytes"] / 1e6))
EOPY
  tail -1 "$out"
}

cases=${CASES:-"static-2d static-3d transient-2d"}
[[ $cases == *static-2d* ]] && for n in 16 32 64 128; do
  run static-2d 2 "$n, $((n / 4)) : 0, 0 : 4, 1 : true" static 1
done
[[ $cases == *static-3d* ]] && for n in 8 16 24; do
  run static-3d 3 "$n, $((n / 4)), $((n / 4)) : 0, 0, 0 : 4, 1, 1 : true" static 1
done
[[ $cases == *transient-2d* ]] && for s in 10 20 40 80; do
  run transient-2d 2 "32, 8 : 0, 0 : 4, 1 : true" transient $s
done
rm -rf "$work"
echo "written: $out"
