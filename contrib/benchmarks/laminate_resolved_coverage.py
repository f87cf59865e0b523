#!/usr/bin/env python3
"""Coverage at E/E_b = 0.5 on conforming meshes (thesis Delta_L, Delta_R,
ch. 5.5), resolved by construction (forma-laminate `compare meshes`, P2).

left:  forma's `hexagon` family (the thesis's Triangle, see doc/laminate.md
       "Table 5.2 row by row") at tile size p1, beam width p4 and n beams
       per joint; the beam shift p2 is bisected until E/E_b = 0.5, and
       Delta_L = nu / (-0.5).
right: forma's `triangle` family (the thesis's Hexagon) with straight beams
       at p1 and n; the beam width p4 is bisected until E/E_b = 0.5, and
       Delta_R = nu / 0.5.
envelope: the left side's lowest nu at E/E_b = 0.1 ... 0.8 over a few left
       structures, and eq. 5.10's constants c1, c2, c3 fitted to it (linear
       least squares), beside the thesis's 3.477, 3.098, 0.988.

  python3 contrib/benchmarks/laminate_resolved_coverage.py left|right \
      [element size [case...]] > contrib/benchmarks/results/laminate_resolved_coverage_SIDE.csv

A case is p1:p4:n (left) or p1:n (right), optionally followed by the
bisection's bracket and start, lo:hi:start (default: the lists below).
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from laminate_compare_meshes import compare_meshes  # noqa: E402

# p1, p4, beams per joint
LEFT = [(0.90, 0.80, 6), (0.90, 0.80, 10), (0.90, 0.90, 6), (0.90, 0.90, 10),
         (0.95, 0.80, 6), (0.95, 0.80, 10), (0.95, 0.90, 10), (0.95, 0.90, 20)]
# p1, beams per joint
RIGHT = [(0.8, 10), (0.8, 20), (0.9, 10), (0.9, 20), (0.95, 10), (0.95, 20)]


def mesh(work, family, p1, p2, p3, p4, size):
    summary, error = compare_meshes(work, family, p1, p2, p3, p4, size)
    return (summary["conforming_mesh"]["result"], None) if summary else (
        None, error)


def bisect(evaluate, lo, hi, x, falls, E_target=0.5):
    """x in [lo, hi] with E(x) = E_target; E falls (or grows) with x.
    Returns the last x evaluated with its result; if E jumps across the
    target (the geometry changes topology), an error says so."""
    r, error = None, None
    for _ in range(16):
        r, error = evaluate(x)
        if r is None or abs(r["E"] - E_target) < 4e-3 * E_target:
            return x, r, error
        if (r["E"] > E_target) == falls:
            lo = x
        else:
            hi = x
        if hi - lo < 1e-5:
            break
        x = 0.5 * (lo + hi)
    return x, None, ("E jumps across %g near %.5f, or the bracket misses "
                     "it (last E %.4f)" % (E_target, x, r["E"]))


def own_bound(r, sign):
    """Delta at E/E_b = 0.5 allowed by the HS bound of the sample's own
    volume fraction: E_max(nu) = min(2 kappa_u (1 - nu), 2 mu_u (1 + nu))
    = 0.5 at nu = 1 - 0.25 / kappa_u (right) or 0.25 / mu_u - 1 (left)."""
    hs = r["hashin_shtrikman"]
    nu = 1 - 0.25 / hs["kappa_upper"] if sign > 0 else \
        0.25 / hs["mu_upper"] - 1
    return sign * nu / 0.5


def row(values, x, r, error, sign):
    if r is None:
        return ",".join(values) + ",%.4f,,,,,,%s" % (x,
                                                     error.replace(",", ";"))
    return ",".join(values) + ",%.4f,%.4f,%.4f,%.4f,%.3f,%.3f," % (
        x, r["E"], r["nu"], r["volume_fraction"], sign * r["nu"] / 0.5,
        own_bound(r, sign))


def fit_eq_5_10(points):
    """c1, c2, c3 of E(nu) = 1 + (1 + c1 - c2 + c3) nu + c1 nu^2 + c2 nu^3
    + c3 nu^4 by least squares: E - 1 - nu = c1 (nu + nu^2)
    + c2 (nu^3 - nu) + c3 (nu + nu^4); normal equations, Cramer's rule."""
    rows = [([nu + nu**2, nu**3 - nu, nu + nu**4], E - 1 - nu)
            for E, nu in points]
    M = [[sum(a[i] * a[j] for a, _ in rows) for j in range(3)]
         for i in range(3)]
    v = [sum(a[i] * y for a, y in rows) for i in range(3)]

    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    D = det(M)
    c = []
    for k in range(3):
        Mk = [[v[i] if j == k else M[i][j] for j in range(3)] for i in range(3)]
        c.append(det(Mk) / D)
    return c


def envelope(work, size):
    print("E_target,p1,p4,n_beams,shift_p2,E,nu")
    best = {}
    for E_target in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8):
        for p1, p4, n in [(0.95, 0.9, 10), (0.95, 0.8, 10)]:
            x, r, error = bisect(
                lambda x: mesh(work, "hexagon", p1, x, 1.0 / n, p4, size),
                0.0, 0.4, 0.14, True, E_target)
            if r is None:
                continue
            print("%g,%g,%g,%d,%.4f,%.4f,%.4f" % (E_target, p1, p4, n, x,
                                                  r["E"], r["nu"]))
            sys.stdout.flush()
            if E_target not in best or r["nu"] < best[E_target][1]:
                best[E_target] = (r["E"], r["nu"])
    points = sorted(best.values()) + [(0.0, -1.0), (1.0, 0.0)]
    c = fit_eq_5_10(points)
    print("# eq. 5.10 fitted to the envelope and its end points (0, -1), "
          "(1, 0): c1 = %.3f, c2 = %.3f, c3 = %.3f (thesis 3.477, 3.098, "
          "0.988)" % tuple(c))
    for E, nu in sorted(best.values()):
        thesis = 1 + 2.367 * nu + 3.477 * nu**2 + 3.098 * nu**3 + 0.988 * nu**4
        print("# nu %.4f: E forma %.4f, thesis eq. 5.10 %.4f" % (nu, E, thesis))


def cases(default, n_fields, first=3):
    """The cases named on the command line from argument `first` on
    (fields joined by ':', each optionally followed by the bisection's
    lo:hi:start), or the default list with the default bracket (None)."""
    named = [[float(v) for v in c.split(":")] for c in sys.argv[first:]]
    for c in named:
        if len(c) not in (n_fields, n_fields + 3):
            sys.exit("a case needs %d fields (or %d with lo:hi:start), not %d"
                     % (n_fields, n_fields + 3, len(c)))
    if not named:
        return [tuple(c) + (None,) for c in default]
    return [tuple(c[:n_fields - 1]) + (int(c[n_fields - 1]),) +
            (tuple(c[n_fields:]) if len(c) > n_fields else None,)
            for c in named]


def main():
    side = sys.argv[1] if len(sys.argv) > 1 else "left"
    size = float(sys.argv[2]) if len(sys.argv) > 2 else 0.012
    with tempfile.TemporaryDirectory() as work:
        if side == "left":
            print("p1,p4,n_beams,element_size,shift_p2,E,nu,phi,Delta_L,"
                  "Delta_L_own_bound,error")
            for p1, p4, n, bracket in cases(LEFT, 3):
                # E falls from about 0.9 (straight beams) to below 0.5 well
                # before a shift of 0.3 at these p1.
                x, r, error = bisect(
                    lambda x: mesh(work, "hexagon", p1, x, 1.0 / n, p4, size),
                    *(bracket or (0.0, 0.3, 0.14)), True)
                print(row(["%g" % p1, "%g" % p4, "%d" % n, "%g" % size], x, r,
                          error, -1))
                sys.stdout.flush()
        elif side == "envelope":
            envelope(work, size)
        else:
            print("p1,n_beams,element_size,p4,E,nu,phi,Delta_R,Delta_R_own_bound,"
                  "error")
            for p1, n, bracket in cases(RIGHT, 2):
                x, r, error = bisect(
                    lambda x: mesh(work, "triangle", p1, 0.0, 1.0 / n, x, size),
                    *(bracket or (0.05, 1.0, 0.5)), False)
                print(row(["%g" % p1, "%d" % n, "%g" % size], x, r, error, 1))
                sys.stdout.flush()


if __name__ == "__main__":
    main()
