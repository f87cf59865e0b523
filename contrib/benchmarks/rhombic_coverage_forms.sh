#!/usr/bin/env bash
# The covered region D(alpha) of a material map in three forms, refitted
# from the same samples (no inverse solves, seconds each): one convex
# polygon in (E, nu) (the thesis's), one in (log E, nu), and two stacked in
# E on the log axis (Map/Coverage axis, Map/Coverage pieces). Per
# construction angle: the covered nodes, how many of them each form holds,
# and its E/E_b and nu extents. Writes a CSV and prints a table.
#
#   bash contrib/benchmarks/rhombic_coverage_forms.sh [map file] [csv]
#   (defaults: contrib/rhombic/map_wide.json,
#    contrib/benchmarks/results/rhombic_coverage_forms.csv)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=${FORMA_RHOMBIC:-$root/build/bin/forma-rhombic}
map=$(realpath "${1:-$root/contrib/rhombic/map_wide.json}")
out=${2:-$root/contrib/benchmarks/results/rhombic_coverage_forms.csv}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$root/parameter_files/rhombic"
for form in "linear 1" "logarithmic 1" "logarithmic 2"; do
  set -- $form
  "$app" build_map_wide.prm --set "Map/Initial map=file" \
    --set "Map/Initial map file=$map" --set "Map/Angles=" \
    --set "Map/Coverage axis=$1" --set "Map/Coverage pieces=$2" \
    --set "Output directory=$work/$1_$2" > "$work/$1_$2.log" 2>&1 ||
    { cat "$work/$1_$2.log"; exit 1; }
done
python3 - "$work" "$out" <<'PY'
import csv, json, math, sys
work, out = sys.argv[1], sys.argv[2]
forms = [("linear", 1), ("logarithmic", 1), ("logarithmic", 2)]
maps = {f: json.load(open("%s/%s_%d/map.json" % (work, *f))) for f in forms}
m0 = maps[forms[0]]
E, nu, angles = m0["grid"]["E"], m0["grid"]["nu"], m0["grid"]["angles"]

def pieces(m, a):
    if "coverage_pieces" in m:
        return [p[a] for p in m["coverage_pieces"]]
    return [m["coverage_polygons"][a]]

def inside(c, x, x0, x1, n):
    left = c[4] + (c[5] - c[4]) * (x - x0) / (x1 - x0)
    right = c[6] + (c[7] - c[6]) * (x - x0) / (x1 - x0)
    return (c[0] - 1e-9 <= x <= c[1] + 1e-9 and c[2] - 1e-9 <= n <= c[3] + 1e-9
            and n >= left - 1e-9 and n <= right + 1e-9)

rows = []
for a, angle in enumerate(angles):
    cov = m0["covered"][a]
    row = {"angle": angle, "covered": sum(cov)}
    for f in forms:
        m = maps[f]
        log = m.get("coverage_axis") == "log E/E_b"
        X = [math.log(e) if log else e for e in E]
        held, Es, nus = 0, [], []
        for i, e in enumerate(E):
            for j, n in enumerate(nu):
                if any(c[0] < c[1] and inside(c, X[i], X[0], X[-1], n)
                       for c in pieces(m, a)):
                    held += cov[i * len(nu) + j]
                    Es.append(e); nus.append(round(n, 9) + 0.0)
        key = "%s_%d" % f
        row[key + "_nodes"] = held
        row[key + "_E"] = "%g-%g" % (min(Es), max(Es)) if Es else "-"
        row[key + "_nu"] = "%g..%g" % (min(nus), max(nus)) if nus else "-"
    rows.append(row)
with open(out, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader(); w.writerows(rows)
print("| angle | covered nodes | one polygon in E | one in log E | two in log E |")
print("|---|---|---|---|---|")
for r in rows:
    cells = ["%d (E %s, nu %s)" % (r[k + "_nodes"], r[k + "_E"], r[k + "_nu"])
             for k in ("linear_1", "logarithmic_1", "logarithmic_2")]
    print("| %g | %d | %s |" % (r["angle"], r["covered"], " | ".join(cells)))
PY
