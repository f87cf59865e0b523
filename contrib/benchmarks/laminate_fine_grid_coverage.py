#!/usr/bin/env python3
"""Delta_R (and Delta_L) at E/E_b = 0.5 with many beams per joint, on fine
pixel grids solved by the matrix-free multigrid (Grid/Solver = multigrid),
the best structures then confirmed on conforming P2 meshes (thesis ch. 5.5,
Fig. 5.6C and 5.7A; issue 41 items 2 and 4).

Each evaluation first rasterizes the structure on a 100-cell grid to read
its thinnest feature, then homogenizes it on the grid on which that
feature spans FEATURE_CELLS cells (at most MAX_CELLS along the height;
beyond, the sample is reported unresolved). The bisection is the same as
laminate_resolved_coverage.py's.

  right: forma's `triangle` family (the thesis's Hexagon), straight beams,
         the beam width p4 bisected to E/E_b = 0.5; Delta_R = nu / 0.5
  left:  forma's `hexagon` family (the thesis's Triangle) at beam width p4,
         the beam shift p2 bisected; Delta_L = -nu / 0.5
  confirm SIDE p1 n p4|p2 [p4] SIZE...: one structure on conforming meshes
         of the given element sizes (right: p1 n p4; left: p1 n p2 p4)

  python3 contrib/benchmarks/laminate_fine_grid_coverage.py right [p1:n[:lo:hi:start] ...] \
      > contrib/benchmarks/results/laminate_fine_grid_coverage_right.csv
  python3 contrib/benchmarks/laminate_fine_grid_coverage.py left [p1:p4:n[:lo:hi:start] ...]
"""
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from laminate_compare_meshes import compare_meshes, run  # noqa: E402
from laminate_resolved_coverage import bisect, cases, own_bound  # noqa: E402

FEATURE_CELLS = float(os.environ.get("FEATURE_CELLS", "4"))
MAX_CELLS = int(os.environ.get("MAX_CELLS", "1600"))
# p1, beams per joint
RIGHT = [(0.9, 40), (0.93, 60), (0.95, 80), (0.95, 120)]
# p1, p4, beams per joint
LEFT = [(0.97, 0.95, 20), (0.97, 0.95, 40)]


def homogenize(work, family, p1, p2, p3, p4, cells):
    """(summary, None) of one structure on the grid, or (None, error)."""
    return run(work, "homogenize", family, p1, p2, p3, p4,
               "  set Cells along height = %d\n  set Solver = %s\n"
               "  set Solver tolerance = 1e-6"
               % (cells, "multigrid" if cells > 100 else "direct"))


def resolved(work, family, p1, p2, p3, p4):
    """The result on the grid that resolves the structure, with its cells
    along the height."""
    coarse, error = homogenize(work, family, p1, p2, p3, p4, 100)
    if coarse is None:
        return None, error
    feature = coarse["structure"]["min_feature_cells"] / 100
    cells = int(math.ceil(FEATURE_CELLS / feature))
    if cells > MAX_CELLS:
        return None, "needs %d cells along the height" % cells
    summary, error = homogenize(work, family, p1, p2, p3, p4, max(cells, 100))
    if summary is None:
        return None, error
    r = summary["result"]
    r["cells"] = max(cells, 100)
    return r, None


def row(values, x, r, error, sign):
    if r is None:
        return ",".join(values) + ",%.4f,,,,,,,%s" % (
            x, error.replace(",", ";"))
    return ",".join(values) + ",%.4f,%d,%.4f,%.4f,%.4f,%.3f,%.3f," % (
        x, r["cells"], r["E"], r["nu"], r["volume_fraction"],
        sign * r["nu"] / 0.5, own_bound(r, sign))


def confirm(work, side, args):
    family = "triangle" if side == "right" else "hexagon"
    p1, n = float(args[0]), int(args[1])
    p2, p4 = (0.0, float(args[2])) if side == "right" else \
        (float(args[2]), float(args[3]))
    sizes = args[3:] if side == "right" else args[4:]
    print("side,p1,n_beams,p2,p4,element_size,cells,unknowns,E,nu,phi,"
          "Delta,error")
    for size in sizes:
        s, error = compare_meshes(work, family, p1, p2, 1.0 / n, p4,
                                  float(size))
        if s is None:
            print("%s,%g,%d,%g,%g,%s,,,,,,,%s" % (side, p1, n, p2, p4, size,
                                                  error.replace(",", ";")))
            continue
        m = s["conforming_mesh"]
        r = m["result"]
        sign = 1 if side == "right" else -1
        print("%s,%g,%d,%g,%g,%s,%d,%d,%.4f,%.4f,%.4f,%.3f," % (
            side, p1, n, p2, p4, size, m["cells"], m["unknowns"], r["E"],
            r["nu"], r["volume_fraction"], sign * r["nu"] / 0.5))
        sys.stdout.flush()


def main():
    side = sys.argv[1] if len(sys.argv) > 1 else "right"
    with tempfile.TemporaryDirectory() as work:
        if side == "confirm":
            confirm(work, sys.argv[2], sys.argv[3:])
        elif side == "left":
            print("p1,p4,n_beams,shift_p2,cells,E,nu,phi,Delta_L,"
                  "Delta_L_own_bound,error")
            for p1, p4, n, bracket in cases(LEFT, 3, 2):
                x, r, error = bisect(
                    lambda x: resolved(work, "hexagon", p1, x, 1.0 / n, p4),
                    *(bracket or (0.0, 0.3, 0.1)), True)
                print(row(["%g" % p1, "%g" % p4, "%d" % n], x, r, error, -1))
                sys.stdout.flush()
        else:
            print("p1,n_beams,p4,cells,E,nu,phi,Delta_R,Delta_R_own_bound,"
                  "error")
            for p1, n, bracket in cases(RIGHT, 2, 2):
                x, r, error = bisect(
                    lambda x: resolved(work, "triangle", p1, 0.0, 1.0 / n, x),
                    *(bracket or (0.05, 1.0, 0.5)), False)
                print(row(["%g" % p1, "%d" % n], x, r, error, 1))
                sys.stdout.flush()


if __name__ == "__main__":
    main()
