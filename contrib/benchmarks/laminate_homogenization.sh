#!/usr/bin/env bash
# Time of one homogenization (Hexagon structure, direct solver, 1 rank) vs
# grid size, and the throughput of a sweep on 1 and 2 ranks. Prints a table;
# the times come from each run's log.txt.
#
#   bash contrib/benchmarks/laminate_homogenization.sh [max cells along height]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-laminate
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
max=${1:-578}

# Symmetry on (default: primitive half cell, odd fluctuations) and off
# (the whole rectangle); "off" stops at 462 cells (memory).
run() { # ny symmetry -> seconds
  cat > "$work/h.prm" <<PRM
set Output directory = $work/h
set Mode = homogenize
subsection Grid
  set Cells along height = $1
  set Use symmetry = $2
end
subsection Structure
  set p1 = 0.8
  set p3 = 0.1
  set p4 = 0.8
end
subsection Output
  set Write vtu = false
end
PRM
  "$app" "$work/h.prm" > "$work/h.out"
  sed -n 's/homogenization: \([0-9.e-]*\) s wall/\1/p' "$work/h/log.txt"
}
echo "grid         rectangle unknowns   s (symmetry)   s (whole rectangle)"
for ny in 58 116 148 232 346 462 578; do
  [ "$ny" -le "$max" ] || break
  nx=$(python3 -c "print(2 * round(3**0.5 * $ny / 2))")
  on=$(run "$ny" true)
  off=-
  [ "$ny" -le 462 ] && off=$(run "$ny" false)
  printf "%4d x %-4d %12d %14s %18s\n" "$nx" "$ny" $((2 * (nx + 1) * (ny + 1))) "$on" "$off"
done

# Sweep throughput: 24 structures on the 256 x 148 grid.
cat > "$work/s.prm" <<PRM
set Output directory = $work/s
set Mode = sweep
subsection Sweep
  set Families = hexagon, triangle
  set p1 = 0.7, 0.8, 0.9
  set p2 = 0, 0.5
  set p3 = 0.2
  set p4 = 0.6, 0.9
end
PRM
for ranks in 1 2; do
  start=$(date +%s.%N)
  mpirun -np $ranks "$app" "$work/s.prm" > /dev/null
  end=$(date +%s.%N)
  python3 -c "print('sweep, $ranks rank(s): %.2f structures/s' % (24 / ($end - $start)))"
done
