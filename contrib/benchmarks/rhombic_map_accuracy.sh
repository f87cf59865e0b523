#!/usr/bin/env bash
# Accuracy of a material-to-geometry map away from its samples (thesis
# Fig. 4.33): `query` at the midpoints of the (E, nu) grid cells and at
# angles between the construction's, for every point inside D(alpha); the
# structure the map gives is homogenized and compared with the target.
# Writes one CSV row per point and prints the mean and largest errors.
#
#   bash contrib/benchmarks/rhombic_map_accuracy.sh [map file] [angles] [csv]
#   (two processes on two cores: split the angles, give each its csv)
#   (defaults: contrib/rhombic/map_full.json, 87.5,...,57.5)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=${FORMA_RHOMBIC:-$root/build/bin/forma-rhombic}
map=$(realpath "${1:-$root/contrib/rhombic/map_full.json}")
angles=${2:-87.5,82.5,77.5,72.5,67.5,62.5,57.5}
out=${3:-$root/contrib/benchmarks/results/rhombic_map_accuracy_$(basename "$map" .json).csv}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat > "$work/q.prm" <<PRM
set Dimension = 2
set Mode = query
set Output directory = $work/q
subsection Map
  set Map file = $map
end
subsection Output
  set Write vtu = false
end
PRM
echo "angle,E,nu,E_achieved_rel_error,nu_error" > "$out"
for a in ${angles//,/ }; do
  for E in 0.025 0.035 0.045 0.055 0.065 0.075 0.085 0.095; do
    for nu in 0.025 0.075 0.125 0.175 0.225 0.275 0.325 0.375; do
      "$app" "$work/q.prm" --set "Query/Young's modulus=$E" \
        --set "Query/Poisson's ratio=$nu" --set "Query/Angle=$a" \
        > /dev/null 2>&1 || continue
      python3 - "$work/q/summary.json" "$a" "$E" "$nu" >> "$out" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
if s.get("status") == "ok" and s.get("inside_coverage"):
    print("%s,%s,%s,%.6g,%.6g" % (sys.argv[2], sys.argv[3], sys.argv[4],
          abs(s["E_relative_error"]), abs(s["nu_error"])))
PY
    done
  done
done
python3 - "$out" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
n = len(rows)
if n == 0:
    sys.exit("no point inside the coverage")
dE = [float(r["E_achieved_rel_error"]) for r in rows]
dn = [float(r["nu_error"]) for r in rows]
print("%d points inside D(alpha): |E/E* - 1| mean %.4f, max %.4f; "
      "|nu - nu*| mean %.4f, max %.4f" % (n, sum(dE) / n, max(dE),
                                          sum(dn) / n, max(dn)))
PY
