#!/usr/bin/env bash
# Kill-and-resume (issue 44 item 3): every resumable mode is killed with
# SIGKILL at random moments and resumed until it finishes; the result must
# equal an uninterrupted run's. Run from the repository root after a build:
#
#   bash contrib/fuzz/kill_resume.sh            # all scenarios, 3 kills each
#   KILLS=5 SEED=7 bash contrib/fuzz/kill_resume.sh connector sweep
#
# Each kill falls at a random moment of the uninterrupted run's duration
# (SEED makes the moments repeatable). A killed run is followed by a run with
# its mode's Resume setting; that one may be killed too (up to KILLS times
# per scenario), and then one runs to the end. A resume that finds no
# checkpoint yet (killed before the first) starts afresh. Compared:
#   optimize: the summaries' histories hold the same iterations (a resumed
#     job's from 0 on), J at each, the final stresses, volume and relative
#     gradient norm (relative 1e-10);
#   sweep (forma-rhombic, forma-laminate): samples.csv, byte for byte;
#   build map: every sample of map.json (1e-10).
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$root/build/bin
prm=$root/parameter_files
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
seed=${SEED:-$RANDOM}
RANDOM=$seed
kills=${KILLS:-3}
echo "kill_resume: seed $seed, $kills kills per scenario, in $work"
failures=0

# compare KIND REFERENCE_DIR RESUMED_DIR: exit 0 when equal.
compare() {
  python3 - "$@" << 'EOF'
import csv, json, sys
kind, a, b = sys.argv[1:4]
def rel(x, y):
    return abs(x - y) / max(abs(x), 1e-300)
if kind == "optimize":
    s, t = (json.load(open(d + "/summary.json")) for d in (a, b))
    J = {h["iteration"]: h["objective"] for h in s["history"]}
    if [h["iteration"] for h in s["history"]] != \
            [h["iteration"] for h in t["history"]]:
        print("the histories hold other iterations")
        sys.exit(1)
    worst = max(rel(J[h["iteration"]], h["objective"]) for h in t["history"])
    for key in ("final_max_stress", "final_volume", "final_objective"):
        worst = max(worst, rel(s[key], t[key]))
    worst = max(worst, rel(s["optimization"]["relative_gradient_norm"],
                           t["optimization"]["relative_gradient_norm"]))
    print(f"largest relative difference {worst:.1e}, final J {t['final_objective']:.10g}")
    sys.exit(0 if worst <= 1e-10 else 1)
if kind == "sweep":
    same = open(a + "/samples.csv").read() == open(b + "/samples.csv").read()
    print("samples.csv " + ("identical" if same else "DIFFERS"))
    sys.exit(0 if same else 1)
if kind == "map":
    x, y = (json.load(open(d + "/map.json"))["samples"] for d in (a, b))
    worst = 0 if len(x) == len(y) else float("inf")
    for p, q in zip(x, y):
        worst = max([worst] + [abs(u - v) for u, v in zip(p, q)])
    print(f"{len(y)} samples, largest difference {worst:.1e}")
    sys.exit(0 if worst <= 1e-10 else 1)
EOF
}

# scenario NAME KIND RESUME_ARGUMENT COMMAND...: the command takes the
# output directory as its last argument's value (OUT is replaced).
scenario() {
  local name=$1 kind=$2 resume=$3
  shift 3
  [ ${#selected[@]} -eq 0 ] || [[ " ${selected[*]} " == *" $name "* ]] || return 0
  local ref=$work/$name.reference out=$work/$name.killed
  local start end
  start=$(date +%s%N)
  "${@//OUT/$ref}" > "$work/$name.reference.log" 2>&1 ||
    { echo "$name: the uninterrupted run failed"; failures=$((failures + 1)); return; }
  end=$(date +%s%N)
  local duration_ms=$(( (end - start) / 1000000 ))
  local n=0 args=("${@//OUT/$out}") first=1 code=0
  while true; do
    local run=("${args[@]}")
    [ $first -eq 1 ] || run+=(--set "$resume")
    if [ $n -lt "$kills" ]; then
      local at_ms=$(( duration_ms * (5 + RANDOM % 90) / 100 ))
      "${run[@]}" > "$work/$name.run$n.log" 2>&1 &
      local pid=$!
      sleep "$(printf '%d.%03d' $((at_ms / 1000)) $((at_ms % 1000)))"
      if kill -9 $pid 2> /dev/null; then
        echo "$name: killed after $at_ms ms of about $duration_ms"
        wait $pid 2> /dev/null
      else
        wait $pid 2> /dev/null
        echo "$name: ended (exit $?) before the kill at $at_ms ms"
      fi
      n=$((n + 1))
      # Killed before its first checkpoint: the next run starts afresh.
      if grep -q "there is no checkpoint" "$work/$name.run$((n - 1)).log"; then
        first=1
      else
        first=0
      fi
      continue
    fi
    "${run[@]}" > "$work/$name.final.log" 2>&1
    code=$?
    if [ $code -ne 0 ] && grep -q "there is no checkpoint" "$work/$name.final.log"; then
      echo "$name: no checkpoint yet, started afresh"
      "${args[@]}" > "$work/$name.final.log" 2>&1
      code=$?
    fi
    break
  done
  local verdict
  if [ $code -eq 0 ] && verdict=$(compare "$kind" "$ref" "$out"); then
    echo "$name: PASSED ($verdict; $(grep -h -o 'resuming from iteration [0-9]*' "$work/$name.final.log" || true))"
  else
    echo "$name: FAILED (exit $code; ${verdict:-no comparison}); logs in $work"
    trap - EXIT
    failures=$((failures + 1))
  fi
}

selected=("$@")

scenario connector optimize 'Optimization/Resume=true' \
  "$bin/forma-contact-assembly" "$prm/contact_assembly/connector_stress.prm" \
  --set 'Optimization/Max iterations=8' --set 'Output directory=OUT'

scenario transient_ipc optimize 'Optimization/Resume=true' \
  "$bin/forma-transient-ipc" "$prm/transient_ipc/ball_shape_recovery.prm" \
  --set 'Optimization/Max iterations=8' --set 'Output directory=OUT'

cat > "$work/sweep.prm" << 'EOF'
set Mode = sweep
subsection Mesh
  set Element size = 0.1
  set Boundary element size = 0.05
end
subsection Sweep
  set p3 = 0.3, 0.45, 0.6
  set p6 = 0.08, 0.12, 0.16
  set Resume = true
end
EOF
scenario sweep sweep 'Sweep/Resume=true' \
  "$bin/forma-rhombic" "$work/sweep.prm" --set 'Output directory=OUT'

cat > "$work/map.prm" << 'EOF'
set Dimension = 2
set Mode = build map
subsection Mesh
  set Element size = 0.08
  set Boundary element size = 0.04
end
subsection Structure
  set Parameters = 0.3, 0.15, 0.5, 0.7, 0.17, 0.15, 0.1, 0.05
end
subsection Inverse
  set Proximity weight = 0.01
end
subsection Map
  set Young's moduli = 0.04, 0.06
  set Poisson's ratios = 0.2, 0.3
  set Spline control points = 4, 4, 4
  set Accuracy checks = 0
  set Angles = 90, 85, 80
  set Resume = true
end
EOF
scenario build_map map 'Map/Resume=true' \
  "$bin/forma-rhombic" "$work/map.prm" --set 'Output directory=OUT'

cat > "$work/laminate.prm" << 'EOF'
set Mode = sweep
subsection Grid
  set Cells along height = 100
end
subsection Sweep
  set Families        = hexagon, triangle
  set p1              = 0.7, 0.8, 0.9
  set p2              = 0, 0.3, 0.6
  set Beams per joint = 3
  set p4              = 0.6, 0.75, 0.9
  set Resume          = true
end
EOF
scenario laminate_sweep sweep 'Sweep/Resume=true' \
  "$bin/forma-laminate" "$work/laminate.prm" --set 'Output directory=OUT'

if [ $failures -gt 0 ]; then
  echo "kill_resume: $failures scenario(s) FAILED"
  exit 1
fi
echo "kill_resume: every scenario resumed to the uninterrupted result"
