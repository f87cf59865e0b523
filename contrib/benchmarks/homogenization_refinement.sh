#!/usr/bin/env bash
# Adaptive refinement of a periodic cell with corners against uniform grids
# (issue 46, items 5 and 6d): builds homogenization_refinement.cc in build/
# (a target outside 'all') and writes
# contrib/benchmarks/results/homogenization_refinement.csv (about 2 minutes).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
make -C "$root/build" homogenization_refinement_benchmark > /dev/null
"$root/build/bin/homogenization_refinement_benchmark" |
  tee "$root/contrib/benchmarks/results/homogenization_refinement.csv"
