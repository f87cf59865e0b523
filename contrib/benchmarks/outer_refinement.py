#!/usr/bin/env python3
"""Refinement between optimization iterations (issue 46, item 4).

The bridge of thesis Fig. 3.4 (parameter_files/transient_ipc/
bridge_stress.prm: an L^p stress norm with the volume held), optimized on
the coarse mesh (the earlier bridge settings: no outer iterations, no
boundary smoothing), on uniformly refined meshes, with Gmsh remeshes
between 3 outer iterations of at most 12 L-BFGS iterations, and with
Optimization/Outer step = refine (3 outer iterations of at most 12
L-BFGS iterations; the mesh is refined where Kelly's indicator, or the
goal estimate of the stress norm, of the current design is largest, 25%
of the cells). Each final design is then solved on its own mesh and on two
uniform refinements of it (design_on_finer_meshes, the same shape): the
last is the reference. Reported per run: DoFs of the final mesh, J as the
run reports it and its error against the reference, the reference J of the
design over the initial design's (on the coarse mesh refined three times),
the smallest scaled Jacobian at the final design's cell corners, and the
wall time. Every run checks Design/Min scaled Jacobian at the cells' corners
(Design/Check corners) but one: the coarse run checked at the quadrature
points only (Check corners = false), whose design folds cells at their corners (it
cannot be refined, and its J is not that of a valid shape). Runs p = 2 (the
file's) and p = 8 (peaks matter).

Writes results/outer_refinement.csv and prints a Markdown table.

Usage: contrib/benchmarks/outer_refinement.py
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
APP = os.path.join(ROOT, "build", "bin", "forma-transient-ipc")
EVALUATE = os.path.join(ROOT, "build", "bin", "design_on_finer_meshes")
SOURCE = os.path.join(ROOT, "parameter_files", "transient_ipc")

OUTER = """subsection Finite element
  set Adaptivity = h
  set Refine fraction = 0.25
  set Error indicator = {indicator}
end
subsection Optimization
  set Outer iterations = 3
  set Inner iterations = 12
  set Outer step = refine
end
"""
CORNERS = "subsection Design\n  set Check corners = true\nend\n"
RUNS = [
    ("coarse, quadrature points only",
     "subsection Design\n  set Check corners = false\nend\n"),
    ("coarse", CORNERS),
    ("uniform 1", CORNERS +
     "subsection Mesh\n  set Initial refinement = 1\nend\n"),
    ("uniform 2", CORNERS +
     "subsection Mesh\n  set Initial refinement = 2\nend\n"),
    ("remesh (Gmsh)", CORNERS + "subsection Optimization\n"
     "  set Outer iterations = 3\n  set Inner iterations = 12\nend\n"),
    ("refine, kelly", OUTER.format(indicator="kelly")),
    ("refine, goal", OUTER.format(indicator="goal")),
]


def write_prm(work, name, p, extra):
    text = open(os.path.join(SOURCE, "bridge_stress.prm")).read()
    text += ("set Output directory = {}\n"
             "subsection Output\n  set Write vtu = false\nend\n"
             "subsection Objective\n"
             "  set Terms = stress : p={} ; volume bound : bound=6.1425, "
             "weight=1e5\nend\n").format(os.path.join(work, name), p)
    # The bridge as the runs below set it up: no outer iterations, the
    # boundary kept on a remesh (the shipped file remeshes).
    text += ("subsection Optimization\n  set Outer iterations = 0\n"
             "  set Inner iterations = 0\nend\n"
             "subsection Design\n  set Remesh boundary = keep\nend\n")
    file = os.path.join(work, name + ".prm")
    open(file, "w").write(text + extra)
    return file


def evaluate(prm, directory, levels):
    """J on the run's mesh and on `levels` uniform refinements, and the
    smallest scaled Jacobian at the corners of the final design."""
    out = subprocess.run([EVALUATE, prm, directory, str(levels)],
                         capture_output=True, text=True)
    corners = float(out.stderr.split("with corners")[1].split()[0])
    v = [float(x) for x in out.stdout.split()]
    values = list(zip(v[0::2], v[1::2]))
    if out.returncode != 0:
        return values, corners, "folds at a corner: not refinable"
    return values, corners, ""


def main():
    subprocess.run(["make", "-C", os.path.join(ROOT, "build"),
                    "design_on_finer_meshes"], check=True,
                   stdout=subprocess.DEVNULL)
    work = tempfile.mkdtemp(prefix="outer_refinement_")
    shutil.copytree(os.path.join(SOURCE, "meshes"),
                    os.path.join(work, "meshes"))
    rows = []
    for p in (2, 8):
        for name, extra in RUNS:
            stem = "p{}_{}".format(p, name.replace(", ", "_").replace(" ", ""))
            prm = write_prm(work, stem, p, extra)
            start = time.time()
            subprocess.run([APP, prm], check=True, stdout=subprocess.DEVNULL)
            wall = time.time() - start
            s = json.load(open(os.path.join(work, stem, "summary.json")))
            o = s["optimization"]
            values, corners, error = evaluate(prm, os.path.join(work, stem),
                                              2)
            if name.startswith("coarse"):
                # The initial design on the coarse mesh refined 3 times.
                c = json.load(open(os.path.join(
                    work, stem, "optimization.checkpoint.json")))
                c["design"] = [0.0] * len(c["design"])
                initial = os.path.join(work, "initial_" + stem)
                os.makedirs(initial, exist_ok=True)
                json.dump(c, open(os.path.join(
                    initial, "optimization.checkpoint.json"), "w"))
                J0 = evaluate(prm, initial, 3)[0][-1][1]
            J = o["final_objective"]
            row = {"p": p, "run": name, "iterations": o["iterations"],
                   "n_dofs": int(values[0][0]), "J": J, "J_over_J0": J / J0,
                   "corner_quality": corners, "wall_s": round(wall, 1)}
            if not error:
                ref = values[-1][1]
                row.update({"J_reference": ref,
                            "reference_dofs": int(values[-1][0]),
                            "J_error_percent": 100 * abs(J / ref - 1),
                            "J_reference_over_J0": ref / J0})
            else:
                row["note"] = error
            rows.append(row)
            print(row, file=sys.stderr, flush=True)
    keys = ["p", "run", "iterations", "n_dofs", "J", "J_over_J0",
            "J_reference", "reference_dofs", "J_error_percent",
            "J_reference_over_J0", "corner_quality", "wall_s", "note"]
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "outer_refinement.csv"),
              "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    print("| p | run | iterations | final DoFs | J/J0 reported | its error "
          "| J/J0 of the design (reference) | corner quality | wall |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "J_reference" in r:
            print("| {p} | {run} | {iterations} | {n_dofs} | {J_over_J0:.4f} "
                  "| {J_error_percent:.2f}% | {J_reference_over_J0:.4f} | "
                  "{corner_quality:.3f} | {wall_s} s |".format(**r))
        else:
            print("| {p} | {run} | {iterations} | {n_dofs} | {J_over_J0:.4f} "
                  "| {note} | | {corner_quality:.3f} | {wall_s} s |"
                  .format(**r))
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
