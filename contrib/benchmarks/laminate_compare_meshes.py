"""forma-laminate's `compare meshes` mode from Python, shared by the
laminate benchmark scripts."""
import json
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
APP = os.path.join(ROOT, "build", "bin", "forma-laminate")


def compare_meshes(work, family, p1, p2, p3, p4, size, cells=12,
                   gray="hashin-shtrikman"):
    """One structure on a conforming P2 mesh of element size `size` and on
    the grid of `cells` along height, base E = 1, nu = 0. Returns
    (summary, None), or (None, the error line) if the run fails."""
    prm = os.path.join(work, "c.prm")
    with open(prm, "w") as f:
        f.write("""set Output directory = %s
set Mode = compare meshes
subsection Base material
  set Young's modulus = 1
  set Poisson's ratio = 0
end
subsection Grid
  set Cells along height = %d
  set Gray pixels = %s
end
subsection Structure
  set Type = %s
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
""" % (os.path.join(work, "c"), cells, gray, family, p1, p2, p3, p4, size))
    p = subprocess.run([APP, prm], capture_output=True, text=True)
    if p.returncode != 0:
        lines = p.stderr.strip().splitlines()
        return None, lines[-1] if lines else "exit code %d" % p.returncode
    with open(os.path.join(work, "c", "summary.json")) as f:
        return json.load(f), None
