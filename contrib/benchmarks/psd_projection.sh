#!/usr/bin/env bash
# Per-call time of the PSD projection of IPC pair Hessians: Eigen's fixed-size
# self-adjoint eigensolver (project_to_psd) against the LAPACK SVD it
# replaced. Builds psd_projection.cc in build/ (a target outside 'all'); writes
# contrib/benchmarks/results/psd_projection.csv.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
make -C "$root/build" psd_projection_benchmark > /dev/null
"$root/build/bin/psd_projection_benchmark" |
  tee "$root/contrib/benchmarks/results/psd_projection.csv"
