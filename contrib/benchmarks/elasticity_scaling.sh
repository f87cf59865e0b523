#!/usr/bin/env bash
# Scaling of the static elasticity solve (CG + ML AMG with rigid-body null
# space) for 2D Q2 and 3D Q2 from ~1e4 to ~1e6 DoFs: wall time of assembly and
# linear solve, CG iterations, the fitted exponent of time vs DoFs, and the
# np=2 / np=1 speedup at the largest size. Writes contrib/benchmarks/results/
# elasticity_scaling.csv and prints a table. Needs python3 and a build in build/.
#
#   bash contrib/benchmarks/elasticity_scaling.sh [max_refinement_2d] [max_refinement_3d]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-transient-ipc
out=$root/contrib/benchmarks/results
work=$(mktemp -d)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
max2=${1:-8}; max3=${2:-5}

run() { # dim refinement np
  local dim=$1 r=$2 np=$3 args bc
  if [ "$dim" = 2 ]; then args="0, 0 : 1, 1 : true"; bc="0 : xy : 0, 0"; tr="1 : 0, -1"
  else args="0, 0, 0 : 1, 1, 1 : true"; bc="0 : xyz : 0, 0, 0"; tr="1 : 0, 0, -1"; fi
  cat > "$work/run.prm" <<PRM
set Dimension = $dim
set Output directory = $work/out_${dim}_${r}_${np}
subsection Mesh
  set Generator = hyper_rectangle
  set Generator arguments = $args
  set Initial refinement = $r
end
subsection Finite element
  set Degree = 2
end
subsection Material
  set Bodies = * : E = 1, nu = 0.3
end
subsection Boundary conditions
  set Dirichlet = $bc
  set Traction = $tr
end
subsection Solver
  set Linear solver = cg-amg
  set Linear tolerance = 1e-8
end
subsection Output
  set Write vtu = false
end
PRM
  local t0=$(date +%s.%N)
  mpirun -np "$np" "$app" "$work/run.prm" > /dev/null
  local t1=$(date +%s.%N)
  python3 - "$work/out_${dim}_${r}_${np}" "$t0" "$t1" "$dim" "$r" "$np" <<'PY'
import json, re, sys
d, t0, t1, dim, r, np = sys.argv[1:]
s = json.load(open(d + "/summary.json"))
log = open(d + "/log.txt").read()
a, l = map(float, re.search(r"assembly wall time ([\d.e+-]+) s, linear solver wall time ([\d.e+-]+) s", log).groups())
print(f"{dim},{r},{np},{s['n_dofs']},{s['steps'][-1]['linear_iterations']},{a:.3f},{l:.3f},{float(t1)-float(t0):.3f}")
PY
}

csv=$out/elasticity_scaling.csv
echo "dim,refinement,np,dofs,cg_iterations,assembly_s,solver_s,total_s" > "$csv"
for r in $(seq 5 "$max2"); do run 2 "$r" 1 | tee -a "$csv"; done
run 2 "$max2" 2 | tee -a "$csv"
for r in $(seq 2 "$max3"); do run 3 "$r" 1 | tee -a "$csv"; done
run 3 "$max3" 2 | tee -a "$csv"

python3 - "$csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for dim in ("2", "3"):
    serial = [r for r in rows if r["dim"] == dim and r["np"] == "1"]
    big = serial[-2:] if len(serial) >= 2 else serial
    # exponent of (assembly + solve) time vs DoFs over the two largest sizes
    t = [float(r["assembly_s"]) + float(r["solver_s"]) for r in big]
    n = [float(r["dofs"]) for r in big]
    expo = math.log(t[1] / t[0]) / math.log(n[1] / n[0]) if len(big) == 2 else float("nan")
    share = float(big[-1]["assembly_s"]) / t[-1]
    par = [r for r in rows if r["dim"] == dim and r["np"] == "2"][-1]
    speedup = t[-1] / (float(par["assembly_s"]) + float(par["solver_s"]))
    print(f"{dim}D Q2: time ~ DoFs^{expo:.2f} (largest two sizes), assembly share {share:.0%}, "
          f"CG iterations {[r['cg_iterations'] for r in serial]}, np=2 speedup {speedup:.2f} at {par['dofs']} DoFs")
PY
rm -rf "$work"
