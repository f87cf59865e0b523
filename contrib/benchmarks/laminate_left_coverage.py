#!/usr/bin/env python3
"""The auxetic side at E/E_b = 0.5 on conforming meshes (thesis Delta_L,
ch. 5.5): for forma's `hexagon` family (the thesis's Triangle, see
doc/laminate.md "Table 5.2 row by row") at given tile size p1, beam width
p4 and beams per joint n, the beam shift p2 is bisected until E/E_b = 0.5
on a conforming P2 mesh (forma-laminate `compare meshes`, resolved by
construction), and nu there gives Delta_L = nu / (-0.5).

  python3 contrib/benchmarks/laminate_left_coverage.py [element size] \
      > contrib/benchmarks/results/laminate_left_coverage.csv
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
APP = os.path.join(ROOT, "build", "bin", "forma-laminate")

# p1, p4, beams per joint
CASES = [(0.90, 0.80, 6), (0.90, 0.80, 10), (0.90, 0.90, 6), (0.90, 0.90, 10),
         (0.95, 0.80, 6), (0.95, 0.80, 10), (0.95, 0.90, 10), (0.95, 0.90, 20)]


def mesh(work, p1, p2, p3, p4, size):
    prm = os.path.join(work, "c.prm")
    with open(prm, "w") as f:
        f.write("""set Output directory = %s
set Mode = compare meshes
subsection Base material
  set Poisson's ratio = 0
end
subsection Grid
  set Cells along height = 12
end
subsection Structure
  set Type = hexagon
  set p1 = %r
  set p2 = %r
  set p3 = %r
  set p4 = %r
end
subsection Conforming mesh
  set Element size = %r
end
subsection Output
  set Write vtu = false
end
""" % (os.path.join(work, "c"), p1, p2, p3, p4, size))
    p = subprocess.run([APP, prm], capture_output=True, text=True)
    if p.returncode != 0:
        return None, p.stderr.strip().splitlines()[-1]
    with open(os.path.join(work, "c", "summary.json")) as f:
        return json.load(f)["conforming_mesh"]["result"], None


def main():
    size = float(sys.argv[1]) if len(sys.argv) > 1 else 0.012
    print("p1,p4,n_beams,element_size,shift_p2,E,nu,phi,Delta_L,error")
    with tempfile.TemporaryDirectory() as work:
        for p1, p4, n in CASES:
            # E falls from about 0.9 (straight beams) to below 0.5 well before
            # a shift of 0.3 at these p1.
            lo, hi, x = 0.0, 0.3, 0.14
            r, error = None, None
            for _ in range(16):
                r, error = mesh(work, p1, x, 1.0 / n, p4, size)
                if r is None or abs(r["E"] - 0.5) < 2e-3:
                    break
                if r["E"] > 0.5:
                    lo = x
                else:
                    hi = x
                x = 0.5 * (lo + hi)
            if r is None:
                print("%g,%g,%d,%g,%.4f,,,,,%s" % (p1, p4, n, size, x,
                                                  error.replace(",", ";")))
            else:
                print("%g,%g,%d,%g,%.4f,%.4f,%.4f,%.4f,%.3f," % (
                    p1, p4, n, size, x, r["E"], r["nu"],
                    r["volume_fraction"], -r["nu"] / 0.5))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
