#!/usr/bin/env bash
# Accuracy of a material-to-geometry map away from its samples (thesis
# Fig. 4.33): `query` at the midpoints of the map's (E, nu) grid cells
# (geometric in E where the splines are logarithmic in E) and at the given
# angles (between the construction's, or a construction angle for a map of
# one angle: the midpoints are still off the samples), for every point
# inside D(alpha); the structure the map gives is homogenized and compared
# with the target. Writes one CSV row per point and prints the mean and
# largest errors. With SELECT=covered-cells (construction angles only),
# the points are instead the midpoints of the grid cells whose four nodes
# the construction reached, inside D(alpha) or not: the accuracy over the
# whole covered region, where D(alpha), a convex polygon, is only part of
# it.
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
select=${SELECT:-inside}
# The grid cells' midpoints at angle $1, "E nu" per line.
points() {
  python3 - "$map" "$1" "$select" <<'PY'
import json, math, sys
m = json.load(open(sys.argv[1]))
E, nu, angles = m["grid"]["E"], m["grid"]["nu"], m["grid"]["angles"]
log = m["parameters"][0].get("logarithmic", [False])[0]
mid = lambda a, b: math.sqrt(a * b) if log else (a + b) / 2
covered = None
if sys.argv[3] == "covered-cells":
    a = [k for k, x in enumerate(angles) if abs(x - float(sys.argv[2])) < 1e-9]
    if not a:
        sys.exit("SELECT=covered-cells: %s is not a construction angle"
                 % sys.argv[2])
    covered = m["covered"][a[0]]
for i in range(len(E) - 1):
    for j in range(len(nu) - 1):
        corners = [(i + di) * len(nu) + j + dj for di in (0, 1) for dj in (0, 1)]
        if covered is None or all(covered[c] for c in corners):
            print("%.6g %.6g" % (mid(E[i], E[i + 1]), (nu[j] + nu[j + 1]) / 2))
PY
}
for a in ${angles//,/ }; do
  while read -r E nu; do
    "$app" "$work/q.prm" --set "Query/Young's modulus=$E" \
      --set "Query/Poisson's ratio=$nu" --set "Query/Angle=$a" \
      < /dev/null > /dev/null 2>&1 || continue
    python3 - "$work/q/summary.json" "$a" "$E" "$nu" "$select" >> "$out" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
if s.get("status") == "ok" and (s.get("inside_coverage")
                                or sys.argv[5] == "covered-cells"):
    print("%s,%s,%s,%.6g,%.6g" % (sys.argv[2], sys.argv[3], sys.argv[4],
          abs(s["E_relative_error"]), abs(s["nu_error"])))
PY
  done < <(points "$a")
done
python3 - "$out" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
n = len(rows)
if n == 0:
    sys.exit("no point inside the coverage")
dE = [float(r["E_achieved_rel_error"]) for r in rows]
dn = [float(r["nu_error"]) for r in rows]
print("%d points: |E/E* - 1| mean %.4f, max %.4f; "
      "|nu - nu*| mean %.4f, max %.4f" % (n, sum(dE) / n, max(dE),
                                          sum(dn) / n, max(dn)))
PY
