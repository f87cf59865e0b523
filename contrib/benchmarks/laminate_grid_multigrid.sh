#!/usr/bin/env bash
# forma-laminate's grid solvers side by side (issue 41, item 4), one rank:
# the direct solver (CHOLMOD) on the symmetric cells (auto, the default),
# the direct solver on the whole rectangle, and the matrix-free multigrid
# (whole rectangle) at relative residuals 1e-10 (the default; exact
# derivatives) and 1e-6 (C^H to 1e-10). Three kinds of grid:
#   random  random two-phase images (55% stiff pixels, contrast 1e-3)
#   blobs   the same white noise blurred over 9 x 9 pixels and cut at 55%
#           stiff: grains of about 8 pixels, as in scanned microstructures
#   hexagon the Hexagon structure p1 = 0.8, p3 = 0.1, p4 = 0.8 (void 1e-6)
# Prints one CSV row per run: seconds of the homogenization (its log line),
# the process's peak memory, and |C - C_ref| / |C| against the first run on
# that grid (the direct solver up to DIRECT_LIMIT, beyond it multigrid at
# 1e-10).
#
#   bash contrib/benchmarks/laminate_grid_multigrid.sh > results/laminate_grid_multigrid.csv
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-laminate
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
RANDOM_SIZES=${RANDOM_SIZES:-"100 200 400 800 2000"}
HEXAGON_NY=${HEXAGON_NY:-"116 232 400 578 1155"}
DIRECT_LIMIT=${DIRECT_LIMIT:-400} # no direct runs beyond this many cells along the height

image() { # kind n -> an n x n binary PGM (fixed seed)
  python3 - "$1" "$2" "$work/$1_$2.pgm" <<'PY'
import random, sys
kind, n, path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
rng = random.Random(1)
noise = [rng.random() for _ in range(n * n)]
if kind == "blobs":  # periodic 9 x 9 box blur, separable
    r = 4
    for step in (1, n):
        out = []
        for k in range(n * n):
            i, j = k % n, k // n
            if step == 1:
                out.append(sum(noise[(i + d) % n + n * j] for d in range(-r, r + 1)))
            else:
                out.append(sum(noise[i + n * ((j + d) % n)] for d in range(-r, r + 1)))
        noise = out
    cut = sorted(noise)[int(0.45 * n * n)]
    stiff = [v >= cut for v in noise]
else:
    stiff = [v < 0.55 for v in noise]
with open(path, "wb") as f:
    f.write(b"P5\n%d %d\n255\n" % (n, n))
    f.write(bytes(255 if s else 0 for s in stiff))
PY
}

run() { # kind size solver symmetry tolerance -> csv row
  local kind=$1 size=$2 solver=$3 symmetry=$4 tol=$5 out=$work/run
  rm -rf "$out"
  {
    echo "set Output directory = $out"
    echo "set Mode = homogenize"
    echo "subsection Base material"
    [ "$kind" != hexagon ] && echo "  set Void stiffness ratio = 1e-3"
    echo "end"
    echo "subsection Grid"
    [ "$kind" = hexagon ] && echo "  set Cells along height = $size"
    echo "  set Solver = $solver"
    echo "  set Solver tolerance = $tol"
    echo "  set Use symmetry = $symmetry"
    echo "end"
    echo "subsection Structure"
    if [ "$kind" != hexagon ]; then
      echo "  set Type = image"
      echo "  set Image file = $work/${kind}_$size.pgm"
    else
      echo "  set p1 = 0.8"
      echo "  set p3 = 0.1"
      echo "  set p4 = 0.8"
    fi
    echo "end"
    echo "subsection Output"
    echo "  set Write vtu = false"
    echo "end"
  } > "$work/run.prm"
  /usr/bin/time -f "%M" -o "$work/rss" "$app" "$work/run.prm" > /dev/null
  local seconds rss
  seconds=$(sed -n 's/homogenization: \([0-9.e+-]*\) s wall/\1/p' "$out/log.txt")
  rss=$(( $(cat "$work/rss") / 1024 ))
  python3 - "$out/summary.json" "$work/reference.json" "$kind" "$size" \
    "$solver" "$symmetry" "$tol" "$seconds" "$rss" <<'PY'
import json, math, os, shutil, sys
summary, reference = sys.argv[1], sys.argv[2]
kind, size, solver, symmetry, tol, seconds, rss = sys.argv[3:]
s = json.load(open(summary))
C = [x for row in s["result"]["C_voigt"] for x in row]
if not os.path.exists(reference):
    shutil.copy(summary, reference)
    diff = "0"
else:
    R = [x for row in json.load(open(reference))["result"]["C_voigt"] for x in row]
    diff = "%.1e" % (math.sqrt(sum((a - b) ** 2 for a, b in zip(C, R)))
                     / math.sqrt(sum(b * b for b in R)))
cells = s["grid"]["cells"]
print(f"{kind},{size},{cells},{solver},{symmetry},{tol},{seconds},{rss},{diff},"
      f"{s['result']['E']:.6g},{s['result']['nu']:.6g}")
PY
}

echo "kind,size,cells,solver,symmetry,tolerance,seconds,peak_rss_MB,rel_diff_C,E,nu"
for kind in random blobs; do
  sizes=$RANDOM_SIZES
  [ "$kind" = blobs ] && sizes=${BLOBS_SIZES:-"200 400 800"}
  for n in $sizes; do
    image "$kind" "$n"
    rm -f "$work/reference.json"
    if [ "$n" -le "$DIRECT_LIMIT" ]; then
      run "$kind" "$n" direct false 1e-10
    fi
    run "$kind" "$n" multigrid false 1e-10
    run "$kind" "$n" multigrid false 1e-6
  done
done
for ny in $HEXAGON_NY; do
  rm -f "$work/reference.json"
  if [ "$ny" -le "$DIRECT_LIMIT" ]; then
    run hexagon "$ny" direct true 1e-10
    run hexagon "$ny" direct false 1e-10
  fi
  run hexagon "$ny" multigrid false 1e-10
  run hexagon "$ny" multigrid false 1e-6
done
