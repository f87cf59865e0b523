#!/usr/bin/env python3
"""Goal-oriented against uniform and Kelly refinement (issue 46, item 6).

For each problem and degree: h-refinement cycles driven by uniform
refinement (Refine fraction = 1), the Kelly indicator and the goal
(dual-weighted residual) indicator, every cycle reporting J(u_h) and the
goal estimate eta of J(u) - J(u_h) (Finite element/Goal estimate). The
reference J is a Q3 goal-refined run's last J(u_h) + eta; its uncertainty is
|eta| there plus the change of J(u_h) + eta over its last cycle. Reports
the DoFs each strategy needs to reach the error uniform refinement reaches
on its finest mesh (log-log interpolation between cycles) and the
effectivity eta / (J - J(u_h)) of the goal runs.
Writes results/goal_refinement.csv and prints Markdown tables.

Usage: contrib/benchmarks/goal_refinement.py [build/bin/forma-transient-ipc]
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

# name, prm, cycles (uniform, adaptive, reference)
PROBLEMS = [
    ("(a) cantilever, mean tip deflection",
     os.path.join(HERE, "goal_cantilever.prm"), (5, 10, 10)),
    ("(b) L-bracket notch, stress L2 norm",
     os.path.join(HERE, "goal_notch.prm"), (5, 12, 12)),
]
STRATEGIES = {
    "uniform": ["Finite element/Refine fraction=1"],
    "kelly": ["Finite element/Error indicator=kelly"],
    "goal": ["Finite element/Error indicator=goal"],
}


def run(prm, settings):
    with tempfile.TemporaryDirectory() as out:
        cmd = [APP, prm, "--set", "Output directory=" + out]
        for s in settings:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)["cycles"]


def dofs_to_reach(cycles, J, target):
    """DoFs at which |J - J_h| first falls to `target` (log-log)."""
    prev = None
    for c in cycles:
        e = abs(J - c["objective"])
        if e <= target:
            if prev is None:
                return c["n_dofs"]
            n0, e0 = prev
            s = math.log(target / e0) / math.log(e / e0)
            return math.exp(math.log(n0) + s * math.log(c["n_dofs"] / n0))
        prev = (c["n_dofs"], e)
    return float("nan")


def main():
    rows = []
    for name, prm, (n_uniform, n_adaptive, n_reference) in PROBLEMS:
        ref = run(prm, ["Finite element/Degree=3",
                        "Finite element/Error indicator=goal",
                        "Finite element/Adaptive cycles=%d" % n_reference])
        J = ref[-1]["objective"] + ref[-1]["estimate"]
        J_prev = ref[-2]["objective"] + ref[-2]["estimate"]
        uncertainty = abs(ref[-1]["estimate"]) + abs(J - J_prev)
        print("\n### %s\n\nreference J = %.10g (+- %.2g, Q3 goal, %d DoFs)\n"
              % (name, J, uncertainty, ref[-1]["n_dofs"]))
        print("| degree | strategy | DoFs | J(u_h) | error | estimate | "
              "effectivity |\n|---|---|---|---|---|---|---|")
        for degree in (1, 2):
            histories = {}
            for strategy, settings in STRATEGIES.items():
                n = n_uniform if strategy == "uniform" else n_adaptive
                cycles = run(prm, settings + [
                    "Finite element/Degree=%d" % degree,
                    "Finite element/Adaptive cycles=%d" % n])
                histories[strategy] = cycles
                for c in cycles:
                    error = J - c["objective"]
                    eff = c["estimate"] / error if error != 0 else float("nan")
                    rows.append([name, degree, strategy, c["cycle"],
                                 c["n_dofs"], c["objective"], error,
                                 c["estimate"], eff])
                    print("| Q%d | %s | %d | %.8g | %.3g | %.3g | %.2f |" % (
                        degree, strategy, c["n_dofs"], c["objective"], error,
                        c["estimate"], eff))
            target = abs(J - histories["uniform"][-1]["objective"])
            need = {s: dofs_to_reach(h, J, target)
                    for s, h in histories.items()}
            rows.append([name, degree, "target %.3g: DoFs uniform/kelly/goal"
                         % target, "", need["uniform"], need["kelly"],
                         need["goal"], need["uniform"] / need["goal"],
                         need["kelly"] / need["goal"]])
            print("| Q%d | **to reach %.3g** | uniform %.0f, Kelly %.0f, goal "
                  "%.0f | | uniform/goal %.1fx | Kelly/goal %.1fx | |" % (
                      degree, target, need["uniform"], need["kelly"],
                      need["goal"], need["uniform"] / need["goal"],
                      need["kelly"] / need["goal"]))
        rows.append([name, 3, "reference", len(ref) - 1, ref[-1]["n_dofs"],
                     J, uncertainty, "", ""])
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "goal_refinement.csv"), "w",
              newline="") as f:
        w = csv.writer(f)
        w.writerow(["problem", "degree", "strategy", "cycle", "n_dofs",
                    "objective", "error", "estimate", "effectivity"])
        w.writerows(rows)


if __name__ == "__main__":
    main()
