#!/bin/bash
# The thesis's tent variants (Table 2.2: "Tent (baseline)" with the
# assembly term J^a = 10, "(disassembly)" adding J^d = 1, "(parallel)"
# adding the parallel alignment J^p = 0.1): tent_sockets_3d.prm (an id per
# socket, J^a on each) as shipped, then with a disassembly term on each
# socket's pipe side (the pipe must not move out of its ball along its
# axis beyond u_tol = 1e-3), then also an alignment term on each socket's
# ball side (target: half its wall parallel to the pipe; epsilon 0.3, since
# the flat facets of a meshed cylinder tilt by up to about 0.05 from its
# axis, which epsilon 0.1 would count as about half parallel). 60 iterations
# each; tent_3d (no J^a) is in pipe_assemblies.sh. Reports iterations,
# holds, J/J0, the max stress initial -> final and its factor, the volume
# ratio, the summed assembly, disassembly and alignment terms at the end,
# and the wall time. Writes results/tent_variants.csv (about 15 minutes on
# one core; doc/contact_assembly.md, "3D pipe assemblies from graphs"). A
# failed run is reported as such.
#   contrib/benchmarks/tent_variants.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" tent_variants "$@"
echo "variant,iterations,holds,J_over_J0,initial_stress,final_stress,factor,volume_ratio,assembly,disassembly,alignment,seconds" > "$out"
cd "$examples"
# The variants' Terms: the shipped ones, plus a record per assembly record.
terms() {
  python3 - "$1" <<'EOPY'
import re, sys
line = [l for l in open("tent_sockets_3d.prm") if "set Terms" in l][0]
terms = line.split("=", 1)[1].strip()
extra = []
for r in terms.split(";"):
    r = r.strip()
    if not r.startswith("assembly"):
        continue
    b, m = re.search(r"boundary=(\d+)", r).group(1), re.search(r"material=(\d+)", r).group(1)
    xyz = re.search(r"(x=[^,]+, y=[^,]+, z=[^,]+)", r).group(1)
    # The pipe of socket 20 + 2e or 21 + 2e is material 11 + e.
    pipe = 11 + (int(b) - 20) // 2
    extra.append("disassembly : boundary=%s, material=%d, %s, tolerance=1e-3, weight=1" % (b, pipe, xyz))
    if sys.argv[1] == "parallel":
        extra.append("alignment : boundary=%s, material=%s, %s, target=0.5, epsilon=0.3, beta=1, weight=0.1" % (b, m, xyz))
print(" ; ".join([terms] + extra))
EOPY
}
for variant in baseline disassembly parallel; do
  rm -rf "$work/out" # a failed run must not report the last one
  args=(--set "Output directory=$work/out" --set "Output/Write vtu=false")
  if [ "$variant" != baseline ]; then
    args+=(--set "Objective/Terms=$(terms "$variant")")
  fi
  "$app" tent_sockets_3d.prm "${args[@]}" > "$work/log" 2>&1 || true
  if python3 - "$variant" "$work/out/summary.json" "$work/log" >> "$out" <<'EOPY'
import json, sys
variant, summary, log = sys.argv[1:]
s = json.load(open(summary))
o = s["optimization"]
t = s["history"][-1]["terms"]
print("%s,%d,%d,%.4f,%.4g,%.4g,%.2f,%.4f,%.3g,%.3g,%.3g,%.0f" % (
    variant, s["history"][-1]["iteration"], open(log).read().count("holding "),
    o["ratio"], s["initial_max_stress"], s["final_max_stress"],
    s["initial_max_stress"] / s["final_max_stress"],
    s["final_volume"] / s["initial_volume"], t.get("assembly", 0),
    t.get("disassembly", 0), t.get("alignment", 0), s["timing"]["total_seconds"]))
EOPY
  then :; else echo "$variant,failed" >> "$out"; fi
  tail -1 "$out"
done
