#!/usr/bin/env python3
"""Adaptive against fixed-step BDF2 (issue 45, item 3).

For each problem: a reference run (fixed BDF2, a step `ref_factor` times
smaller than the finest fixed run), fixed BDF2 runs at several steps and
adaptive runs at several tolerances. The error of a run is the largest
distance, over its own time levels, between its point displacement and the
reference's (linearly interpolated in time), and the distance at the end.
Writes results/adaptive_time.csv and prints a Markdown table.

Usage: contrib/benchmarks/adaptive_time.py [build/bin/forma-transient-ipc]
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
APP = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    ROOT, "build", "bin", "forma-transient-ipc")

PROBLEMS = [
    # name, prm, extra settings, fixed steps, adaptive tolerances,
    # first adaptive step, reference step, displacement scale (absolute
    # tolerance = tolerance * scale)
    ("swinging strip (Neo-Hookean, damped, gravity)",
     os.path.join(ROOT, "tests", "transient_ipc", "neo_hookean_dynamic.prm"),
     ["Time/End time=2", "Output/Write vtu=false"],
     [0.02, 0.01, 0.005], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.005, 2.5e-4, 5),
    ("swinging strip, BDF damping rate",
     os.path.join(ROOT, "tests", "transient_ipc", "neo_hookean_dynamic.prm"),
     ["Time/End time=2", "Output/Write vtu=false",
      "Material/Damping rate=bdf"],
     [0.02, 0.01, 0.005], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.005, 2.5e-4, 5),
    ("damped oscillator (linear, Kelvin-Voigt)",
     os.path.join(HERE, "damped_oscillator.prm"),
     [],
     [0.2, 0.1, 0.05], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.01, 2.5e-3, 1),
    ("damped oscillator, BDF damping rate",
     os.path.join(HERE, "damped_oscillator.prm"),
     ["Material/Damping rate=bdf"],
     [0.2, 0.1, 0.05], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.01, 2.5e-3, 1),
    ("struck cantilever (pulse, then free vibration)",
     os.path.join(HERE, "struck_cantilever.prm"),
     [],
     [0.04, 0.02, 0.01], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.001, 5e-4, 1),
    ("struck cantilever, BDF damping rate",
     os.path.join(HERE, "struck_cantilever.prm"),
     ["Material/Damping rate=bdf"],
     [0.04, 0.02, 0.01], [1e-3, 3e-4, 1e-4, 3e-5, 1e-5], 0.001, 5e-4, 1),
]


# Adaptive integrators: name, settings.
INTEGRATORS = [
    ("adaptive BDF2", ["Time/BDF order=2"]),
    ("adaptive BDF1-3", ["Time/BDF order=3", "Time/Variable order=true"]),
    ("adaptive BDF1-5", ["Time/BDF order=5", "Time/Variable order=true"]),
]


def run(prm, settings, directory):
    cmd = [APP, prm, "--set", "Output directory=" + directory]
    for s in settings:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(directory, "summary.json")) as f:
        s = json.load(f)
    times = [r["time"] for r in s["steps"]]
    points = [r["point_displacements"][0] for r in s["steps"]]
    info = s.get("time_integration", {})
    return times, points, info.get("rejected_steps", 0)


def interpolate(times, points, t):
    lo, hi = 0, len(times) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if times[mid] <= t:
            lo = mid
        else:
            hi = mid
    a = (t - times[lo]) / (times[hi] - times[lo])
    return [(1 - a) * x + a * y for x, y in zip(points[lo], points[hi])]


def errors(run_, ref):
    times, points, _ = run_
    worst = 0.
    for t, p in zip(times, points):
        r = interpolate(ref[0], ref[1], t)
        worst = max(worst, math.dist(p, r))
    return worst, math.dist(points[-1], ref[1][-1])


def main():
    rows = []
    only = os.environ.get("PROBLEMS")  # e.g. "0,1": a subset, for trials
    problems = [PROBLEMS[int(k)] for k in only.split(",")] if only \
        else PROBLEMS
    with tempfile.TemporaryDirectory() as tmp:
        for name, prm, extra, steps, tols, first, ref_step, scale in \
                problems:
            ref = run(prm, extra + ["Time/Time step=%g" % ref_step],
                      os.path.join(tmp, "ref"))
            for dt in steps:
                r = run(prm, extra + ["Time/Time step=%g" % dt],
                        os.path.join(tmp, "fixed"))
                e = errors(r, ref)
                rows.append([name, "fixed BDF2", "dt = %g" % dt,
                             len(r[0]) - 1, 0, e[0], e[1]])
            for integrator, settings in INTEGRATORS:
                for tol in tols:
                    r = run(prm, extra + settings + [
                        "Time/Integrator=adaptive",
                        "Time/Tolerance=%g" % tol,
                        "Time/Absolute tolerance=%g" % (tol * scale),
                        "Time/Time step=%g" % first],
                        os.path.join(tmp, "adaptive"))
                    e = errors(r, ref)
                    rows.append([name, integrator, "tol = %g" % tol,
                                 len(r[0]) - 1, r[2], e[0], e[1]])
    header = ["problem", "integrator", "setting", "steps", "rejected",
              "max error", "final error"]
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "adaptive_time.csv"), "w",
              newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| %s | %s | %s | %d | %d | %.3g | %.3g |" % tuple(r))


if __name__ == "__main__":
    main()
