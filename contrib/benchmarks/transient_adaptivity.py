#!/usr/bin/env python3
"""Transient h adaptivity against uniform meshes (issue 46, item 2).

Lamb's problem (parameter_files/transient_ipc/lamb_impact_adaptive.prm): an
impact on a slab's surface. Runs the uniform meshes of refinement 0..3 and
the adaptive run (coarse mesh 0, at most 2 levels more, so its finest cells
are those of uniform refinement 2), on 1 rank and the adaptive one on 2.
The reference is uniform refinement 3. The error of a run is the largest
distance over the steps between its displacement at the two output points
and the reference's, relative to the reference's largest displacement
there. The cost is the DoFs summed over the steps (and the wall time).
Writes results/transient_adaptivity.csv and prints a Markdown table.

Usage: contrib/benchmarks/transient_adaptivity.py [build/bin/forma-transient-ipc]
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
APP = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    ROOT, "build", "bin", "forma-transient-ipc")
PRM = os.path.join(ROOT, "parameter_files", "transient_ipc",
                   "lamb_impact_adaptive.prm")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def run(settings, directory, ranks=1):
    cmd = ([] if ranks == 1 else ["mpirun", "-np", str(ranks)]) + [
        APP, PRM, "--set", "Output directory=" + directory,
        "--set", "Output/Write vtu=false"]
    for s in settings:
        cmd += ["--set", s]
    start = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=ENV)
    wall = time.time() - start
    with open(os.path.join(directory, "summary.json")) as f:
        s = json.load(f)
    points = [r["point_displacements"] for r in s["steps"]]
    if "mesh_adaptation" in s:
        m = s["mesh_adaptation"]
        cost, peak = m["dof_steps"], m["max_dofs"]
    else:
        cost, peak = s["n_dofs"] * (len(s["steps"]) - 1), s["n_dofs"]
    return points, cost, peak, wall


def error(points, reference):
    scale = max(math.hypot(*p) for step in reference for p in step)
    worst = 0.0
    for a, b in zip(points, reference):
        for p, q in zip(a, b):
            worst = max(worst, math.hypot(p[0] - q[0], p[1] - q[1]))
    return worst / scale


def main():
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        uniform = {}
        for r in range(4):
            uniform[r] = run(["Finite element/Adaptivity=none",
                              "Mesh/Initial refinement=%d" % r],
                             os.path.join(tmp, "uniform%d" % r))
        reference = uniform[3][0]
        for r in range(3):
            points, cost, peak, wall = uniform[r]
            rows.append(("uniform, refinement %d" % r, 1,
                         error(points, reference), cost, peak, wall))
        for ranks in (1, 2):
            points, cost, peak, wall = run([], os.path.join(
                tmp, "adaptive%d" % ranks), ranks)
            rows.append(("adaptive, refinement 0 + up to 2", ranks,
                         error(points, reference), cost, peak, wall))
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "transient_adaptivity.csv"),
              "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["run", "ranks", "relative_error", "dof_steps",
                    "max_dofs", "wall_s"])
        for row in rows:
            w.writerow([row[0], row[1], "%.3g" % row[2], row[3], row[4],
                        "%.1f" % row[5]])
    print("| run | ranks | error vs uniform 3 | DoFs summed over steps "
          "| largest mesh (DoFs) | wall |")
    print("|---|---|---|---|---|---|")
    for name, ranks, err, cost, peak, wall in rows:
        print("| %s | %d | %.3g | %d | %d | %.1f s |" %
              (name, ranks, err, cost, peak, wall))


if __name__ == "__main__":
    main()
