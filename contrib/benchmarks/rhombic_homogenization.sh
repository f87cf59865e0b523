#!/usr/bin/env bash
# forma-rhombic performance (thesis ch. 4.5: "under 1 s for about 4000
# vertices"; target 0.25 s on one core):
#  1. one cell homogenization (60 degree cell, P2, direct solver) against
#     the mesh sizes: vertices, dofs, seconds for meshing, set-up and
#     solve, and the error of E1 against the finest mesh; at about 4700
#     vertices also with the whole cell meshed (Mesh/Symmetric mesh =
#     false: no half mesh, no odd constraints), as a ratio in this run;
#  2. the shape gradient (8 parameters) against one forward evaluation
#     (inverse mode's log);
#  3. sweep throughput on 1 and 2 ranks.
#
#   bash contrib/benchmarks/rhombic_homogenization.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-rhombic
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

structure="  set Angle = 60
  set Parameters = 0.2, 0.15, 0.3, 0.7, 0.25, 0.08, 0.1, 0.08"
run() { # element size, boundary size[, symmetric mesh] -> "vertices dofs mesh setup solve E1"
  cat > "$work/h.prm" <<PRM
set Output directory = $work/h
subsection Structure
$structure
end
subsection Mesh
  set Element size = $1
  set Boundary element size = $2
  set Symmetric mesh = ${3:-true}
end
subsection Output
  set Write vtu = false
end
PRM
  "$app" "$work/h.prm" > "$work/h.out"
  v=$(sed -n 's/^mesh: \([0-9]*\) vertices.*P2: \([0-9]*\) dofs.*/\1 \2/p' "$work/h.out")
  t=$(sed -n 's/seconds: mesh \([0-9.e-]*\), set-up \([0-9.e-]*\), solve \([0-9.e-]*\)/\1 \2 \3/p' "$work/h/log.txt")
  e=$(sed -n 's/^E1 = \([0-9.e-]*\),.*/\1/p' "$work/h.out")
  echo "$v $t $e"
}
reference=$(run 0.00625 0.003125 | awk '{print $6}')
echo "element  boundary  vertices    dofs   mesh s  set-up s  solve s  total s  E1 error"
for hs in "0.1 0.025" "0.05 0.025" "0.05 0.0125" "0.025 0.0125" "0.025 0.00625" "0.0125 0.00625"; do
  set -- $hs
  read -r v d m s o e <<< "$(run "$1" "$2")"
  awk -v a="$1" -v b="$2" -v v="$v" -v d="$d" -v m="$m" -v s="$s" -v o="$o" \
      -v e="$e" -v r="$reference" 'BEGIN {
    printf "%7s %9s %9d %7d %8.3f %9.3f %8.3f %8.3f %8.2f%%\n",
           a, b, v, d, m, s, o, m + s + o, 100 * (e / r - 1) }'
done
echo "(E1 error against element size 0.00625, boundary 0.003125)"
# Symmetric half against the whole cell, the same sizes, best of 3 each.
best() { # element size, boundary size, symmetric -> fastest "total" of 3
  for k in 1 2 3; do run "$1" "$2" "$3" | awk '{print $3 + $4 + $5}'; done | sort -g | head -1
}
half=$(best 0.025 0.0125 true)
whole=$(best 0.025 0.0125 false)
awk -v h="$half" -v w="$whole" 'BEGIN {
  printf "element 0.025, boundary 0.0125 (best of 3): symmetric half %.3f s, whole cell %.3f s, ratio %.2f\n", h, w, h / w }'

# Gradient against forward: inverse mode logs both per design.
cat > "$work/i.prm" <<PRM
set Output directory = $work/i
set Mode = inverse
subsection Structure
  set Angle = 60
  set Parameters = 0.25, 0.25, 0.5, 0.5, 0.2, 0.1, 0.1, 0.1
end
subsection Inverse
  set Max iterations = 5
end
PRM
"$app" "$work/i.prm" > /dev/null
awk '/gradient/ { gsub(",", ""); n++; f += $3 + $5 + $7; g += $9 }
     END { printf "shape gradient (8 parameters): %.3f s, forward (mesh + solve): %.3f s, ratio %.2f (%d designs)\n", g / n, f / n, g / f, n }' \
  "$work/i/log.txt"

# Sweep throughput with the default mesh: 24 structures (start-up counts)
# and 120 (closer to a real sweep's rate), on 1 and 2 ranks. Each sweep:
# p3, p4, p6 values and angles (the counts are the products).
small=("0.3:0.7:4" "0.5" "0.08, 0.14" "90, 75, 60")                # 4 x 1 x 2 x 3
large=("0.3:0.7:5" "0.5, 0.7" "0.08, 0.11, 0.14" "90, 80, 70, 60") # 5 x 2 x 3 x 4
sweep_prm() { # p3 values, p4 values, p6 values, angles
  cat > "$work/s.prm" <<PRM
set Output directory = $work/s
set Mode = sweep
subsection Sweep
  set p3 = $1
  set p4 = $2
  set p6 = $3
  set Angles = $4
end
PRM
}
seconds=()
for size in 24 120; do
  if [ $size = 24 ]; then sweep_prm "${small[@]}"; else sweep_prm "${large[@]}"; fi
  for np in 1 2; do
    start=$(date +%s.%N)
    mpirun -np $np "$app" "$work/s.prm" > /dev/null
    end=$(date +%s.%N)
    seconds[$np]=$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')
    awk -v t="${seconds[$np]}" -v np="$np" -v n="$size" \
      'BEGIN { printf "sweep on %d rank(s): %d structures in %.1f s, %.2f structures/s\n", np, n, t, n / t }'
  done
  awk -v a="${seconds[1]}" -v b="${seconds[2]}" -v n="$size" \
    'BEGIN { printf "sweep of %d: 2 ranks against 1, speed-up %.2f\n", n, a / b }'
done
sweep_prm "${small[@]}"

# The same sweep at about 4700 vertices on one rank, symmetric half
# against the whole cell.
for symmetric in true false; do
  start=$(date +%s.%N)
  "$app" "$work/s.prm" --set "Mesh/Element size=0.025" \
    --set "Mesh/Boundary element size=0.0125" \
    --set "Mesh/Symmetric mesh=$symmetric" > /dev/null
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" -v s="$symmetric" \
    'BEGIN { printf "sweep at element 0.025, boundary 0.0125, symmetric mesh %s: %.3f s per structure\n", s, (b - a) / 24 }'
done
