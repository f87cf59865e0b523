#!/usr/bin/env python3
"""Thesis Table 5.2 under the reading that reproduces it (doc/laminate.md,
"Table 5.2 row by row").

The thesis's parameters map to forma's as
  - families are named by the lattice of the laminate joints: the thesis's
    Hexagon is forma's `triangle` (triangular solid tiles whose joints form
    a honeycomb), the thesis's Triangle is forma's `hexagon`;
  - p3 is relative to p2 ("each dimension relative to the previous"): the
    beam period is p2 p3 times the joint width, forma's p3 = p2 * p3
    (n = 1 / (p2 p3) beams: 10, 5, 10, 7.1, 7.7, 5.6);
  - the beams of the Hexagon rows are straight (forma p2 = 0); the
    Triangle rows' inclination is not in Table 5.2, so it is fitted to the
    row's E on the conforming mesh (forma p2 by secant steps) and nu is the
    check.
For each row: the conforming P2 mesh at the thesis's unstructured p4 (E, nu
against the thesis's Unstr. row), then forma's compare-meshes grid match
(the grid p4 that gives the mesh's E, against the thesis's Reg. p4), and
the mesh's p4 that gives the thesis's E with nu there (nu at matched E).

  python3 contrib/benchmarks/table_5_2_thesis_reading.py [element size]
      [cells along height] [gray pixels] > results/table_5_2_thesis_reading.csv
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from laminate_compare_meshes import compare_meshes  # noqa: E402

# type, p1, p2, p3, p4 unstr, E unstr, nu unstr, p4 reg, E reg, nu reg
ROWS = [
    ("Hexagon", 0.75, 0.1, 1.0, 0.74, 0.3554, 0.4873, 0.77, 0.3553, 0.4917),
    ("Hexagon", 0.74, 0.2, 1.0, 0.526, 0.3123, 0.4500, 0.546, 0.3121, 0.4595),
    ("Hexagon", 0.88, 0.1, 1.0, 0.642, 0.6845, 0.1656, 0.657, 0.6846, 0.1734),
    ("Triangle", 0.73, 0.2, 0.7, 0.787, 0.1409, -0.5205, 0.805, 0.1408, -0.5154),
    ("Triangle", 0.84, 0.2, 0.65, 0.769, 0.0759, -0.7375, 0.794, 0.0760, -0.7337),
    ("Triangle", 0.93, 0.2, 0.9, 0.812, 0.7681, 0.0010, 0.846, 0.7685, 0.0112),
]


def compare(work, family, p1, p2, p3, p4, size, cells, gray):
    summary, error = compare_meshes(work, family, p1, p2, p3, p4, size, cells,
                                    gray)
    if summary is None:
        raise RuntimeError(error)
    return summary


def mesh_result(work, family, p1, p2, p3, p4, size):
    r = compare(work, family, p1, p2, p3, p4, size, 12, "hashin-shtrikman")
    return r["conforming_mesh"]["result"]


def fit_inclination(work, p1, p3, p4, E_target, size):
    """forma p2 (beam shift / joint width) giving E_target on the mesh: E
    falls as the beams incline; secant steps inside a bracket."""
    lo, hi = 0.0, 0.6
    E = lambda x: mesh_result(work, "hexagon", p1, x, p3, p4, size)["E"]
    f_lo, f_hi = E(lo) - E_target, E(hi) - E_target
    x = 0.5 * (lo + hi)
    for _ in range(30):
        f = E(x) - E_target
        if abs(f) < 1e-4 * E_target:
            break
        if f > 0:
            lo, f_lo = x, f
        else:
            hi, f_hi = x, f
        x = lo - f_lo * (hi - lo) / (f_hi - f_lo)
        x = min(max(x, lo + 0.02 * (hi - lo)), hi - 0.02 * (hi - lo))
    return x


def fit_p4(work, family, p1, p2, p3, E_target, size, p4):
    """The beam width p4 that gives E_target on the mesh (E grows with it):
    to compare nu at matched E, as Table 5.2 does."""
    lo, hi = max(0.05, p4 - 0.2), min(1.0, p4 + 0.2)
    E = lambda x: mesh_result(work, family, p1, p2, p3, x, size)["E"]
    f_lo, f_hi = E(lo) - E_target, E(hi) - E_target
    x = p4
    for _ in range(30):
        f = E(x) - E_target
        if abs(f) < 1e-4 * E_target:
            break
        if f < 0:
            lo, f_lo = x, f
        else:
            hi, f_hi = x, f
        x = lo - f_lo * (hi - lo) / (f_hi - f_lo)
        x = min(max(x, lo + 0.02 * (hi - lo)), hi - 0.02 * (hi - lo))
    return x, mesh_result(work, family, p1, p2, p3, x, size)["nu"]


def main():
    size = float(sys.argv[1]) if len(sys.argv) > 1 else 0.015
    cells = int(sys.argv[2]) if len(sys.argv) > 2 else 148
    gray = sys.argv[3] if len(sys.argv) > 3 else "hashin-shtrikman"
    print("type,p1,p2,p3,n_beams,forma_family,forma_p2,forma_p3,"
          "thesis_p4_unstr,thesis_E_unstr,thesis_nu_unstr,forma_E_mesh,"
          "forma_nu_mesh,thesis_p4_reg,forma_p4_grid,forma_nu_grid,"
          "thesis_eps,forma_nu_grid_minus_mesh,forma_p4_mesh_at_thesis_E,"
          "forma_nu_mesh_at_thesis_E")
    with tempfile.TemporaryDirectory() as work:
        for (kind, p1, p2, p3, p4, E_u, nu_u, p4_r, E_r, nu_r) in ROWS:
            family = "triangle" if kind == "Hexagon" else "hexagon"
            forma_p3 = p2 * p3
            forma_p2 = 0.0
            if kind == "Triangle":
                forma_p2 = fit_inclination(work, p1, forma_p3, p4, E_u, size)
            s = compare(work, family, p1, forma_p2, forma_p3, p4, size, cells,
                        gray)
            m, g = s["conforming_mesh"]["result"], s["matched_grid"]
            p4_E, nu_E = fit_p4(work, family, p1, forma_p2, forma_p3, E_u,
                                size, p4)
            print("%s,%g,%g,%g,%.2f,%s,%.4f,%.4f,%g,%.4f,%.4f,%.4f,%.4f,%g,"
                  "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f" % (
                      kind, p1, p2, p3, 1 / forma_p3, family, forma_p2,
                      forma_p3, p4, E_u, nu_u, m["E"], m["nu"], p4_r,
                      g["value"], g["nu"], abs(nu_r - nu_u),
                      g["nu_difference"], p4_E, nu_E))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
