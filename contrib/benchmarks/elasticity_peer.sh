#!/usr/bin/env bash
# forma against FEniCSx on the 3D Q2 cantilever of
# ../shared/benchmarks/elasticity_peer.md (beam 4 x 1 x 1, 4n x n x n hexes,
# E 1e5, nu 0.3, clamped at x = 0, traction (0, 0, -1) at x = 4, CG to
# ||r|| <= 1e-8 ||b||), whole process, runs made in turn on one machine:
# forma with cg-mg (matrix-free p-multigrid) and cg-amg (assembled, ML AMG),
# FEniCSx 0.5 (Debian python3-dolfinx) with PETSc CG + GAMG. Reports DoFs,
# wall time, CG iterations, peak memory (summed over ranks), u_z(4, .5, .5),
# and forma's split of setup (mesh, DoFs, assembly) and solve. Writes
# contrib/benchmarks/results/elasticity_peer.csv.
#
#   bash contrib/benchmarks/elasticity_peer.sh ["n:ranks:solvers ..."]
#
# solvers: any of mg, amg, peer joined by '+'; default: the sizes below.
# Sizes n divisible by 2 or 4 are built from a coarse mesh refined once or
# twice (the same hexahedra).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-transient-ipc
peer=$root/contrib/benchmarks/elasticity_peer_fenicsx.py
out=$root/contrib/benchmarks/results
work=$(mktemp -d)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
# REPEAT=k: each forma case k times, the run of median wall time reported
# (the spread on a 2-core virtual machine is 20-40%).
repeat=${REPEAT:-1}
cases=${1:-"7:1:mg+amg+peer 12:1:mg+amg+peer 18:1:mg+amg+peer 18:2:mg+amg+peer 28:1:mg 28:2:mg"}

# peak resident memory of every rank, summed (MB), from /usr/bin/time -f %M
sum_memory() { awk '/^peak_kb / { s += $2 } END { printf "%.0f", s / 1024 }' "$1"; }

forma() { # n ranks solver
  local n=$1 np=$2 solver=$3 dir=$work/forma_$1_$2_$3
  # The same 4n x n x n hexahedra from a coarse mesh refined r times: p4est
  # keeps the coarse mesh on every rank, and building it is serial work.
  local r=0
  while [ $r -lt 2 ] && [ $((n % (2 << r))) -eq 0 ]; do r=$((r + 1)); done
  local c=$((n >> r))
  cat > "$work/run.prm" <<PRM
set Dimension = 3
set Output directory = $dir
subsection Mesh
  set Generator = subdivided_hyper_rectangle
  set Generator arguments = $((4 * c)), $c, $c : 0, 0, 0 : 4, 1, 1 : true
  set Initial refinement = $r
end
subsection Finite element
  set Degree = 2
end
subsection Material
  set Bodies = * : E = 1e5, nu = 0.3
end
subsection Boundary conditions
  set Dirichlet = 0 : xyz : 0, 0, 0
  set Traction = 1 : 0, 0, -1
end
subsection Solver
  set Linear solver = cg-$solver
  set Linear tolerance = 1e-8
  set Newton relative tolerance = 1e-7
end
subsection Output
  set Write vtu = false
  set Points = 4, 0.5, 0.5
end
PRM
  local t0 t1 k
  for k in $(seq "$repeat"); do
    t0=$(date +%s.%N)
    mpirun -np "$np" /usr/bin/time -f "peak_kb %M" "$app" "$work/run.prm" \
      > /dev/null 2> "$work/time.txt"
    t1=$(date +%s.%N)
    forma_row "$dir" "$t0" "$t1" "$n" "$np" "forma cg-$solver" \
      "$(sum_memory "$work/time.txt")"
  done | sort -t, -k5 -g | sed -n "$(((repeat + 1) / 2))p" # the median wall
}

forma_row() { # output directory, start, end, n, ranks, code, memory
  python3 - "$@" <<'PY'
import json, re, sys
d, t0, t1, n, np, code, mem = sys.argv[1:]
s = json.load(open(d + "/summary.json"))
step = s["steps"][-1]
log = open(d + "/log.txt").read()
solve = float(re.search(r"linear solver wall time ([\d.e+-]+) s", log).group(1))
wall = float(t1) - float(t0)
uz = step["point_displacements"][0][2]
print(f"{n},{np},{code},{s['n_dofs']},{wall:.2f},{wall - solve:.2f},{solve:.2f},"
      f"{step['linear_iterations']},{mem},{uz:.10e}")
PY
}

fenicsx() { # n ranks
  local n=$1 np=$2 t0 t1 line
  # forms compiled in an untimed warm-up (FFCx caches them)
  [ -f "$work/warm" ] || { /usr/bin/python3 "$peer" 2 > /dev/null 2>&1; touch "$work/warm"; }
  t0=$(date +%s.%N)
  line=$(mpirun -np "$np" /usr/bin/time -f "peak_kb %M" /usr/bin/python3 \
    "$peer" "$n" 2> "$work/time.txt")
  t1=$(date +%s.%N)
  read -r dofs its uz <<< "$line"
  python3 -c "print(f'$n,$np,fenicsx cg-gamg,$dofs,{$t1 - $t0:.2f},,,$its,$(sum_memory "$work/time.txt"),$uz')"
}

echo "n,ranks,code,dofs,wall_s,setup_s,solve_s,cg_iterations,peak_mb,u_z" \
  > "$out/elasticity_peer.csv"
for c in $cases; do
  IFS=: read -r n np solvers <<< "$c"
  for s in ${solvers//+/ }; do
    case $s in
      peer) fenicsx "$n" "$np" ;;
      *) forma "$n" "$np" "$s" ;;
    esac | tee -a "$out/elasticity_peer.csv"
  done
done
rm -rf "$work"
