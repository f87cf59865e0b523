#!/usr/bin/env bash
# forma-laminate's inverse design with exact structure gradients against
# the same runs with central differences (an older forma whose bin/ and
# lib/ are in $BEFORE): wall time, L-BFGS iterations and the misfit reached,
# for targets of a Hexagon, a chiral Triangle and a limit structure on the
# default grid. Writes results/laminate_inverse_gradient.csv.
#
#   BEFORE=/path/to/old/prefix bash contrib/benchmarks/laminate_inverse_gradient.sh [cells along height]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ny=${1:-74}
out=$root/contrib/benchmarks/results/laminate_inverse_gradient.csv

# name | structure section | sweep section (the inverse mode's table)
targets=(
  "hexagon|set Type = hexagon\n set p1 = 0.83\n set p2 = 0.6\n set p3 = 0.5\n set p4 = 0.66|set Families = hexagon\n set p1 = 0.7:0.9:3\n set p2 = 0, 1\n set p3 = 0.5\n set p4 = 0.5:0.9:3"
  "triangle|set Type = triangle\n set p1 = 0.82\n set p2 = 0.5\n set p3 = 0.5\n set p4 = 0.72|set Families = triangle\n set p1 = 0.7:0.9:3\n set p2 = 0, 1\n set p3 = 0.5\n set p4 = 0.5:0.9:3"
  "limit|set Type = hexagon\n set Limit structure = true\n set p1 = 0.73\n set theta = 0.85\n set alpha = 6|set Families = hexagon\n set Limit structures = true\n set p1 = 0.65:0.85:3\n set theta = 0.7:0.9:3\n set alpha = 0, 20"
)

common() {
  printf 'subsection Grid\n set Cells along height = %s\nend\n' "$ny"
  printf 'subsection Output\n set Write vtu = false\nend\n'
}

run() { # binary-dir lib-dir name structure sweep -> "seconds,iterations,misfit"
  local bin=$1 lib=$2 name=$3 dir=$work/$3-$(basename "$(dirname "$1")")
  { common; printf "set Output directory = %s/target\nset Mode = homogenize\n" "$dir"
    printf "subsection Structure\n $4\nend\n"; } > "$dir.h.prm"
  mkdir -p "$dir"
  LD_LIBRARY_PATH=$lib "$bin/forma-laminate" "$dir.h.prm" > /dev/null
  read -r E nu < <(python3 -c "import json; s = json.load(open('$dir/target/summary.json')); print(repr(s['result']['E']), repr(s['result']['nu']))")
  { common; printf "set Output directory = %s/inverse\nset Mode = inverse\n" "$dir"
    printf "subsection Sweep\n $5\nend\n"
    printf "subsection Inverse\n set Target Young's modulus = %s\n set Target Poisson's ratio = %s\n set Tolerance = 1e-5\n set Max iterations = 100\n set Table cells along height = 16\nend\n" "$E" "$nu"; } > "$dir.i.prm"
  local start end
  start=$(date +%s.%N)
  LD_LIBRARY_PATH=$lib "$bin/forma-laminate" "$dir.i.prm" > /dev/null
  end=$(date +%s.%N)
  python3 -c "import json; s = json.load(open('$dir/inverse/summary.json')); c = s['candidates']; n = sum(x['iterations'] for x in c); print('%.2f,%d,%d,%.2e,%.3f' % ($end - $start, n, len(c), s['misfit'], ($end - $start) / max(n, 1)))"
}

echo "target,grid_ny,gradient,seconds,iterations,candidates,misfit,seconds_per_iteration" > "$out"
for t in "${targets[@]}"; do
  IFS='|' read -r name structure sweep <<< "$t"
  structure=$(printf '%b' "$structure"); sweep=$(printf '%b' "$sweep")
  if [ -n "${BEFORE:-}" ]; then
    echo "$name,$ny,central differences,$(run "$BEFORE/bin" "$BEFORE/lib" "$name" "$structure" "$sweep")" >> "$out"
  fi
  echo "$name,$ny,exact,$(run "$root/build/bin" "$root/build/lib" "$name" "$structure" "$sweep")" >> "$out"
done
column -s, -t "$out"
