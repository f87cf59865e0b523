#!/usr/bin/env bash
# Regular grid vs conforming periodic mesh for the six structures of thesis
# Table 5.2 (their unstructured-mesh parameters; our p2 is the chirality
# shift fraction, see doc/laminate.md): E and nu on a P2 triangle mesh,
# the grid's p4 that matches E, and nu(grid) - nu(mesh) there.
#
#   bash contrib/benchmarks/table_5_2.sh [cells along height] [element size]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-laminate
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ny=${1:-148}
size=${2:-0.02}

echo "| type | p1 | p2 | p3 | p4 (mesh) | E mesh | nu mesh | p4 grid | nu grid | nu(grid) - nu(mesh) |"
echo "|---|---|---|---|---|---|---|---|---|---|"
while read -r type p1 p2 p3 p4; do
  cat > "$work/c.prm" <<PRM
set Output directory = $work/c
set Mode = compare meshes
subsection Grid
  set Cells along height = $ny
end
subsection Structure
  set Type = $type
  set p1 = $p1
  set p2 = $p2
  set p3 = $p3
  set p4 = $p4
end
subsection Conforming mesh
  set Element size = $size
end
subsection Output
  set Write vtu = false
end
PRM
  "$app" "$work/c.prm" > /dev/null
  python3 - "$work/c/summary.json" "$type" "$p1" "$p2" "$p3" "$p4" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
m, g = s["conforming_mesh"]["result"], s["matched_grid"]
print("| %s | %s | %s | %s | %s | %.4f | %.4f | %.4f | %.4f | %.4f |" % (
    *sys.argv[2:7], m["E"], m["nu"], g["value"], g["nu"], g["nu_difference"]))
PY
done <<ROWS
hexagon 0.75 0.1 1.0 0.74
hexagon 0.74 0.2 1.0 0.526
hexagon 0.88 0.1 1.0 0.642
triangle 0.73 0.2 0.7 0.787
triangle 0.84 0.2 0.65 0.769
triangle 0.93 0.2 0.9 0.812
ROWS
