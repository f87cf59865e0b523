#!/usr/bin/env bash
# The four two-scale design examples (disk, bar, ghost, pliers) on a
# material map (default: the wide one), the family only: the macro design's
# J / J0 (J0: the uniform start without the coverage penalty) and the
# fine-scale error on the compared boundary. One CSV row per example.
#
#   bash contrib/benchmarks/rhombic_two_scale_maps.sh [map file] [csv]
#   (defaults: contrib/rhombic/map_wide.json,
#    contrib/benchmarks/results/rhombic_two_scale_<map>.csv; about 5 minutes)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=${FORMA_RHOMBIC:-$root/build/bin/forma-rhombic}
map=$(realpath "${1:-$root/contrib/rhombic/map_wide.json}")
out=${2:-$root/contrib/benchmarks/results/rhombic_two_scale_$(basename "$map" .json).csv}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$root/parameter_files/rhombic"
echo "example,J0,J,J_over_J0,fine_error_mean,fine_error_max,clamped_quads" > "$out"
for ex in disk bar ghost pliers; do
  "$app" ${ex}_design.prm --set "Map/Map file=$map" \
    --set "Two-scale/Baselines=" --set "Output directory=$work/$ex" \
    > "$work/$ex.log" 2>&1 || { tail -5 "$work/$ex.log"; exit 1; }
  # J0 without the coverage penalty: one evaluation of the uniform start.
  "$app" ${ex}_design.prm --set "Map/Map file=$map" \
    --set "Two-scale/Baselines=" --set "Two-scale/Coverage weight=0" \
    --set "Two-scale/Macro settings=Optimization/Max iterations=1" \
    --set "Two-scale/Fine-scale check=false" \
    --set "Output directory=$work/${ex}_j0" > "$work/${ex}_j0.log" 2>&1 ||
    { tail -5 "$work/${ex}_j0.log"; exit 1; }
  python3 - "$work" "$ex" >> "$out" <<'PY'
import json, re, sys
work, ex = sys.argv[1], sys.argv[2]
J = json.load(open("%s/%s/summary.json" % (work, ex)))["final_objective"]
J0 = float(re.search(r"\[iteration 0/1\] J = (\S+)",
                     open("%s/%s_j0.log" % (work, ex)).read()).group(1))
log = open("%s/%s.log" % (work, ex)).read()
fine = re.search(r"fine scale, family: on boundary \d+ .*mean (\S+), max (\S+)",
                 log)
clamped = re.search(r"(\d+) quads sharper than the map's range", log)
print("%s,%.6g,%.6g,%.4g,%s,%s,%s" % (ex, J0, J, J / J0, fine.group(1),
      fine.group(2), clamped.group(1) if clamped else 0))
PY
done
column -s, -t "$out"
