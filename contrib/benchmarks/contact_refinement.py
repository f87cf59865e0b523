#!/usr/bin/env python3
"""Contact-aware refinement on a Hertz contact (issue 46, items 3 and 6c).

parameter_files/contact_assembly/hertz_ring.prm: a thick ring squeezed
between rigid planes, by its quarter. For two squeezes delta, three
strategies refine the same coarse mesh: uniform (Refine fraction = 1),
Kelly alone (Contact residual = false) and Kelly plus the contact faces'
traction residual. Every cycle's peak contact pressure p_max (the largest
penalty traction at the contact faces' quadrature points) is compared with
a reference: the Kelly + contact run with more cycles. Reports, per
strategy, the DoFs from which p_max stays within 2% (and 0.5%) of the
reference, and the reference against Hertz's p0 = sqrt(P E* / (pi R)) for
its own force P. Writes results/contact_refinement.csv and prints Markdown.

Usage: contrib/benchmarks/contact_refinement.py [build/bin/forma-contact-assembly]
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
    ROOT, "build", "bin", "forma-contact-assembly")
PRM = os.path.join(ROOT, "parameter_files", "contact_assembly",
                   "hertz_ring.prm")
E, NU, R = 1.0, 0.3, 1.0
DELTAS = (0.002, 0.005)
STRATEGIES = {
    "uniform": (["Finite element/Refine fraction=1"], 5),
    "kelly": (["Finite element/Contact residual=false"], 9),
    "kelly + contact": (["Finite element/Contact residual=true"], 9),
}
REFERENCE_CYCLES = 11
TARGETS = (0.02, 0.005)


def run(delta, settings, cycles):
    with tempfile.TemporaryDirectory() as out:
        cmd = [APP, PRM, "--set", "Output directory=" + out,
               "--set", "Boundary conditions/Dirichlet=2 : x : %g ; 3 : y : 0"
               % delta,
               "--set", "Finite element/Adaptive cycles=%d" % cycles]
        for s in settings:
            cmd += ["--set", s]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(os.path.join(out, "summary.json")) as f:
            rows = []
            for c in json.load(f)["cycles"]:
                k = c["contact"][0]
                # The quarter carries half the contact: P and 2a of the ring.
                rows.append({"n_dofs": c["n_dofs"],
                             "force": -2 * k["force"][0],
                             "half_width": k["active_area"],
                             "max_pressure": k["max_pressure"]})
            return rows


def dofs_to_stay_within(cycles, reference, target):
    """DoFs of the first cycle from which |p_max / ref - 1| <= target."""
    need = float("nan")
    for c in reversed(cycles):
        if abs(c["max_pressure"] / reference - 1) > target:
            break
        need = c["n_dofs"]
    return need


def main():
    rows = []
    e_star = E / (1 - NU * NU)
    for delta in DELTAS:
        ref = run(delta, STRATEGIES["kelly + contact"][0],
                  REFERENCE_CYCLES)[-1]
        p_ref = ref["max_pressure"]
        hertz_p0 = math.sqrt(ref["force"] * e_star / (math.pi * R))
        hertz_a = math.sqrt(4 * ref["force"] * R / (math.pi * e_star))
        print("\n### delta = %g\n\nreference (Kelly + contact, %d cycles, %d "
              "DoFs): P = %.6g, a = %.5g (Hertz %.5g), p_max = %.6g (Hertz "
              "p0 %.6g, %+.2f%%)\n" % (
                  delta, REFERENCE_CYCLES, ref["n_dofs"], ref["force"],
                  ref["half_width"], hertz_a, p_ref, hertz_p0,
                  100 * (p_ref / hertz_p0 - 1)))
        rows.append([delta, "reference", REFERENCE_CYCLES, ref["n_dofs"],
                     ref["force"], ref["half_width"], p_ref, 0.0])
        rows.append([delta, "hertz", "", "", ref["force"], hertz_a,
                     hertz_p0, p_ref / hertz_p0 - 1])
        print("| strategy | cycle | DoFs | P | a | p_max | error |\n"
              "|---|---|---|---|---|---|---|")
        need = {}
        for name, (settings, cycles) in STRATEGIES.items():
            history = run(delta, settings, cycles)
            for k, c in enumerate(history):
                error = c["max_pressure"] / p_ref - 1
                rows.append([delta, name, k, c["n_dofs"], c["force"],
                             c["half_width"], c["max_pressure"], error])
                print("| %s | %d | %d | %.5g | %.4g | %.5g | %+.2f%% |" % (
                    name, k, c["n_dofs"], c["force"], c["half_width"],
                    c["max_pressure"], 100 * error))
            need[name] = [dofs_to_stay_within(history, p_ref, t)
                          for t in TARGETS]
        print("\nDoFs from which p_max stays within the reference's:")
        for name, n in need.items():
            print("- %s: %s" % (name, ", ".join(
                "%g%%: %s" % (100 * t, "not reached" if math.isnan(d) else
                              "%d" % d) for t, d in zip(TARGETS, n))))
            rows.append([delta, "DoFs to stay within %s: %s" % (
                "/".join("%g%%" % (100 * t) for t in TARGETS), name), "",
                "", "", "", n[0], n[1]])
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "contact_refinement.csv"), "w",
              newline="") as f:
        w = csv.writer(f)
        w.writerow(["delta", "strategy", "cycle", "n_dofs", "force",
                    "half_width", "max_pressure", "relative_error"])
        w.writerows(rows)


if __name__ == "__main__":
    main()
