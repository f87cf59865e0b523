"""forma-laminate's `compare meshes` mode from Python, shared by the
laminate benchmark scripts."""
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
APP = os.path.join(ROOT, "build", "bin", "forma-laminate")


def run(work, mode, family, p1, p2, p3, p4, grid, extra=""):
    """forma-laminate in `mode` on one structure (base E = 1, nu = 0), with
    the Grid subsection's `grid` lines and further top-level `extra`
    settings. Returns (summary, None), or (None, the error line) if the
    run fails."""
    prm = os.path.join(work, "c.prm")
    with open(prm, "w") as f:
        f.write("""set Output directory = %s
set Mode = %s
subsection Base material
  set Young's modulus = 1
  set Poisson's ratio = 0
end
subsection Grid
%s
end
subsection Structure
  set Type = %s
  set p1 = %r
  set p2 = %r
  set p3 = %r
  set p4 = %r
end
subsection Output
  set Write vtu = false
end
%s""" % (os.path.join(work, "c"), mode, grid, family, p1, p2, p3, p4, extra))
    p = subprocess.run([APP, prm], capture_output=True, text=True)
    if p.returncode != 0:
        lines = p.stderr.strip().splitlines()
        return None, lines[-1] if lines else "exit code %d" % p.returncode
    with open(os.path.join(work, "c", "summary.json")) as f:
        return json.load(f), None


def compare_meshes(work, family, p1, p2, p3, p4, size, cells=12,
                   gray="hashin-shtrikman"):
    """One structure on a conforming P2 mesh of element size `size` and on
    the grid of `cells` along height. Returns (summary, None), or (None,
    the error line) if the run fails."""
    return run(work, "compare meshes", family, p1, p2, p3, p4,
               "  set Cells along height = %d\n  set Gray pixels = %s"
               % (cells, gray),
               "subsection Conforming mesh\n  set Element size = %r\nend\n"
               % size)
