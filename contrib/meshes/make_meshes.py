#!/usr/bin/env python3
"""Write the structured meshes of the shipped forma-transient-ipc examples
as Gmsh 2.2 ASCII files (physical tags: cells -> material id 0, boundary
elements -> boundary ids). Run from the repository root:
    python3 contrib/meshes/make_meshes.py
"""
import math
import os

OUT = "parameter_files/transient_ipc/meshes"


def write_msh(path, nodes, cells, cell_type, faces, face_type):
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for i, p in enumerate(nodes):
            f.write("%d %.12g %.12g %.12g\n" % ((i + 1,) + tuple(p)))
        f.write("$EndNodes\n$Elements\n%d\n" % (len(cells) + len(faces)))
        k = 1
        for tag, vs in faces:
            f.write("%d %d 2 %d %d %s\n" % (k, face_type, tag, tag,
                                            " ".join(str(v + 1) for v in vs)))
            k += 1
        for vs in cells:
            f.write("%d %d 2 0 0 %s\n" % (k, cell_type,
                                          " ".join(str(v + 1) for v in vs)))
            k += 1
        f.write("$EndElements\n")


def bridge(path, nx=24, ny=4, L=6.0, H=1.5, w=0.75, rise=1.0):
    """A deck on two legs over an arch (thesis Figs. 3.3, 3.4, 3.14).
    Boundary ids: 0 leg feet (supports), 1 outer sides, 2 deck top,
    3 arch underside, 4/5/6 three load patches on the deck top."""
    def bottom(x):
        if x <= w + 1e-12 or x >= L - w - 1e-12:
            return 0.0
        return rise * math.sin(math.pi * (x - w) / (L - 2 * w))

    nodes = []
    for j in range(ny + 1):
        for i in range(nx + 1):
            x = L * i / nx
            yb = bottom(x)
            nodes.append((x, yb + (H - yb) * j / ny, 0.0))
    n = lambda i, j: j * (nx + 1) + i
    cells = [(n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1))
             for j in range(ny) for i in range(nx)]
    faces = []
    for i in range(nx):
        xm = L * (i + 0.5) / nx
        faces.append((0 if bottom(xm) == 0 else 3, (n(i, 0), n(i + 1, 0))))
        top = 2
        for tag, c in ((4, 1.5), (5, 3.0), (6, 4.5)):
            if abs(xm - c) < 0.25 + 1e-9:
                top = tag
        faces.append((top, (n(i, ny), n(i + 1, ny))))
    for j in range(ny):
        faces.append((1, (n(0, j), n(0, j + 1))))
        faces.append((1, (n(nx, j), n(nx, j + 1))))
    write_msh(path, nodes, cells, 3, faces, 1)


def beam(path, nx=12, ny=2, nz=4, L=6.0, B=1.0, H=1.0):
    """A beam standing on a central support (thesis Fig. 3.5). Boundary
    ids: 0 left end, 1 right end, 4 support patch |x| <= 0.5 at the bottom,
    5 all other faces."""
    nodes = [(-L / 2 + L * i / nx, -B / 2 + B * j / ny, H * k / nz)
             for k in range(nz + 1) for j in range(ny + 1)
             for i in range(nx + 1)]
    n = lambda i, j, k: (k * (ny + 1) + j) * (nx + 1) + i
    cells = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                cells.append((n(i, j, k), n(i + 1, j, k), n(i + 1, j + 1, k),
                              n(i, j + 1, k), n(i, j, k + 1),
                              n(i + 1, j, k + 1), n(i + 1, j + 1, k + 1),
                              n(i, j + 1, k + 1)))
    faces = []
    for j in range(ny):
        for k in range(nz):
            faces.append((0, (n(0, j, k), n(0, j + 1, k), n(0, j + 1, k + 1),
                              n(0, j, k + 1))))
            faces.append((1, (n(nx, j, k), n(nx, j + 1, k),
                              n(nx, j + 1, k + 1), n(nx, j, k + 1))))
    for i in range(nx):
        xm = -L / 2 + L * (i + 0.5) / nx
        for j in range(ny):
            faces.append((4 if abs(xm) < 0.5 else 5,
                          (n(i, j, 0), n(i + 1, j, 0), n(i + 1, j + 1, 0),
                           n(i, j + 1, 0))))
            faces.append((5, (n(i, j, nz), n(i + 1, j, nz),
                              n(i + 1, j + 1, nz), n(i, j + 1, nz))))
        for k in range(nz):
            faces.append((5, (n(i, 0, k), n(i + 1, 0, k), n(i + 1, 0, k + 1),
                              n(i, 0, k + 1))))
            faces.append((5, (n(i, ny, k), n(i + 1, ny, k),
                              n(i + 1, ny, k + 1), n(i, ny, k + 1))))
    write_msh(path, nodes, cells, 5, faces, 3)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    bridge(os.path.join(OUT, "bridge.msh"))
    beam(os.path.join(OUT, "beam_on_support.msh"))
