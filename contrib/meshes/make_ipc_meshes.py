#!/usr/bin/env python3
"""Write the multi-body meshes of the IPC examples and tests as Gmsh 2.2
ASCII files: structured quads (2D) or hexahedra (3D) per body, cell tag =
the body's material id, boundary tag = 10 * body + side (sides: 0 left,
1 right, 2 bottom, 3 top, 4 front, 5 back), and obstacle surfaces. Run from
the repository root:
    python3 contrib/meshes/make_ipc_meshes.py
The benchmark contrib/benchmarks/ipc_scaling.sh writes its meshes with
    python3 contrib/meshes/make_ipc_meshes.py --stack N FILE
(two stacked blocks of N x N x N/2 hexahedra each).
"""
import math
import os
import random

OUT = "parameter_files/transient_ipc/meshes"


class Mesh:
    def __init__(self, dim):
        self.dim = dim
        self.nodes, self.cells, self.faces = [], [], []
        self.at = {}  # (body, rounded position) -> node: blocks of a body join

    def block(self, lo, hi, n, body, angle=0.0, tilt=0.0):
        """A box [lo, hi] with n cells per direction, material id `body`,
        turned by `angle` (radians, about z through its center), then in 3D
        tilted by `tilt` (about x through its center)."""
        d = self.dim
        base = len(self.nodes)
        nz = n[2] if d == 3 else 0
        idx = {}
        for k in range(nz + 1):
            for j in range(n[1] + 1):
                for i in range(n[0] + 1):
                    p = [lo[0] + (hi[0] - lo[0]) * i / n[0],
                         lo[1] + (hi[1] - lo[1]) * j / n[1],
                         lo[2] + (hi[2] - lo[2]) * k / nz if d == 3 else 0.0]
                    if angle:
                        cx, cy = 0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])
                        x, y = p[0] - cx, p[1] - cy
                        p[0] = cx + math.cos(angle) * x - math.sin(angle) * y
                        p[1] = cy + math.sin(angle) * x + math.cos(angle) * y
                    if tilt:
                        cy, cz = 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])
                        y, z = p[1] - cy, p[2] - cz
                        p[1] = cy + math.cos(tilt) * y - math.sin(tilt) * z
                        p[2] = cz + math.sin(tilt) * y + math.cos(tilt) * z
                    key = (body,) + tuple(round(c, 9) for c in p)
                    if key not in self.at:
                        self.at[key] = len(self.nodes)
                        self.nodes.append(p)
                    idx[(i, j, k)] = self.at[key]
        v = lambda i, j, k=0: idx[(i, j, k)]
        if d == 2:
            for j in range(n[1]):
                for i in range(n[0]):
                    self.cells.append((body, (v(i, j), v(i + 1, j),
                                              v(i + 1, j + 1), v(i, j + 1))))
            for j in range(n[1]):
                self.faces.append((10 * body + 0, (v(0, j), v(0, j + 1))))
                self.faces.append((10 * body + 1, (v(n[0], j), v(n[0], j + 1))))
            for i in range(n[0]):
                self.faces.append((10 * body + 2, (v(i, 0), v(i + 1, 0))))
                self.faces.append((10 * body + 3, (v(i, n[1]), v(i + 1, n[1]))))
        else:
            for k in range(nz):
                for j in range(n[1]):
                    for i in range(n[0]):
                        self.cells.append((body, (
                            v(i, j, k), v(i + 1, j, k), v(i + 1, j + 1, k),
                            v(i, j + 1, k), v(i, j, k + 1), v(i + 1, j, k + 1),
                            v(i + 1, j + 1, k + 1), v(i, j + 1, k + 1))))
            quad = lambda a, b, c, e: (a, b, c, e)
            for k in range(nz):
                for j in range(n[1]):
                    self.faces.append((10 * body + 0, quad(
                        v(0, j, k), v(0, j + 1, k), v(0, j + 1, k + 1), v(0, j, k + 1))))
                    self.faces.append((10 * body + 1, quad(
                        v(n[0], j, k), v(n[0], j + 1, k), v(n[0], j + 1, k + 1),
                        v(n[0], j, k + 1))))
            for k in range(nz):
                for i in range(n[0]):
                    self.faces.append((10 * body + 2, quad(
                        v(i, 0, k), v(i + 1, 0, k), v(i + 1, 0, k + 1), v(i, 0, k + 1))))
                    self.faces.append((10 * body + 3, quad(
                        v(i, n[1], k), v(i + 1, n[1], k), v(i + 1, n[1], k + 1),
                        v(i, n[1], k + 1))))
            for j in range(n[1]):
                for i in range(n[0]):
                    self.faces.append((10 * body + 4, quad(
                        v(i, j, 0), v(i + 1, j, 0), v(i + 1, j + 1, 0), v(i, j + 1, 0))))
                    self.faces.append((10 * body + 5, quad(
                        v(i, j, nz), v(i + 1, j, nz), v(i + 1, j + 1, nz),
                        v(i, j + 1, nz))))

    def union(self, body, boxes, h):
        """A body made of axis-aligned boxes (lo, hi) meshed with cells of
        size about h; boxes that share a side must subdivide it alike."""
        for lo, hi in boxes:
            n = [max(1, round((hi[d] - lo[d]) / h)) for d in range(self.dim)]
            self.block(lo, hi, n, body)

    def write(self, name, tagger=None):
        """Write the mesh; faces shared by two blocks of a body are interior
        and dropped. tagger(body, center) may replace a face's tag."""
        count = {}
        for tag, vs in self.faces:
            key = tuple(sorted(vs))
            count[key] = count.get(key, 0) + 1
        owner = {}
        for body, vs in self.cells:
            for v in vs:
                owner[v] = body
        faces = []
        for tag, vs in self.faces:
            if count[tuple(sorted(vs))] > 1:
                continue
            if tagger:
                c = [sum(self.nodes[v][d] for v in vs) / len(vs)
                     for d in range(3)]
                t = tagger(owner[vs[0]], c)
                tag = tag if t is None else t
            faces.append((tag, vs))
        self.faces = faces
        cell_type, face_type = (3, 1) if self.dim == 2 else (5, 3)
        path = name if os.path.isabs(name) else os.path.join(OUT, name)
        with open(path, "w") as f:
            f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n"
                    % len(self.nodes))
            for i, p in enumerate(self.nodes):
                f.write("%d %.12g %.12g %.12g\n" % ((i + 1,) + tuple(p)))
            f.write("$EndNodes\n$Elements\n%d\n"
                    % (len(self.cells) + len(self.faces)))
            k = 1
            for tag, vs in self.faces:
                f.write("%d %d 2 %d %d %s\n" % (k, face_type, tag, tag,
                                                " ".join(str(v + 1) for v in vs)))
                k += 1
            for tag, vs in self.cells:
                f.write("%d %d 2 %d %d %s\n" % (k, cell_type, tag, tag,
                                                " ".join(str(v + 1) for v in vs)))
                k += 1
            f.write("$EndElements\n")


def write_polyline(name, points):
    """A 2D obstacle: a polyline as Gmsh line elements (type 1)."""
    with open(os.path.join(OUT, name), "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n"
                % len(points))
        for i, p in enumerate(points):
            f.write("%d %.12g %.12g 0\n" % (i + 1, p[0], p[1]))
        f.write("$EndNodes\n$Elements\n%d\n" % (len(points) - 1))
        for i in range(len(points) - 1):
            f.write("%d 1 2 1 1 %d %d\n" % (i + 1, i + 1, i + 2))
        f.write("$EndElements\n")


def write_polylines(name, lines):
    """A 2D obstacle of several polylines as Gmsh line elements."""
    nodes, elements = [], []
    for line in lines:
        base = len(nodes)
        nodes += line
        elements += [(base + i, base + i + 1) for i in range(len(line) - 1)]
    with open(os.path.join(OUT, name), "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n"
                % len(nodes))
        for i, p in enumerate(nodes):
            f.write("%d %.12g %.12g 0\n" % (i + 1, p[0], p[1]))
        f.write("$EndNodes\n$Elements\n%d\n" % len(elements))
        for k, (a, b) in enumerate(elements):
            f.write("%d 1 2 1 1 %d %d\n" % (k + 1, a + 1, b + 1))
        f.write("$EndElements\n")


def write_obj(name, vertices, faces):
    """A 3D obstacle surface as a Wavefront OBJ file."""
    with open(os.path.join(OUT, name), "w") as f:
        f.write("# forma IPC obstacle (contrib/meshes/make_ipc_meshes.py)\n")
        for v in vertices:
            f.write("v %.12g %.12g %.12g\n" % tuple(v))
        for t in faces:
            f.write("f %s\n" % " ".join(str(i + 1) for i in t))


def main():
    # Two equal blocks 0.1 apart: the left one is thrown at the right one.
    m = Mesh(2)
    m.block((0, 0), (1, 1), (4, 4), 0)
    m.block((1.1, 0.2), (2.1, 1.2), (4, 4), 1)
    m.write("two_blocks_2d.msh")
    # A pile: 16 turned blocks (4 rows of 4) above a box, to be dropped in.
    m = Mesh(2)
    rng = random.Random(3)
    for r in range(4):
        for c in range(4):
            x, y = 0.1 + 1.2 * c + 0.3 * (r % 2), 0.3 + 1.3 * r
            m.block((x, y), (x + 0.8, y + 0.8), (2, 2), 4 * r + c,
                    rng.uniform(-0.6, 0.6))
    m.write("pile_2d.msh")
    # The same in 3D: 27 turned and tilted cubes of side 0.5 (3 layers of
    # 3 x 3, 2 x 2 x 2 hexahedra each) above a box. Centers 0.9 apart, more
    # than a turned cube's diagonal (0.87): no two touch.
    m = Mesh(3)
    rng = random.Random(5)
    for r in range(3):
        for b in range(3):
            for c in range(3):
                shift = 0.1 * (1 if r % 2 else -1)
                x, y, z = 0.55 + 0.9 * c + shift, 0.55 + 0.9 * b - shift, \
                    0.6 + 0.9 * r
                m.block((x - 0.25, y - 0.25, z - 0.25),
                        (x + 0.25, y + 0.25, z + 0.25), (2, 2, 2),
                        9 * r + 3 * b + c, rng.uniform(-0.6, 0.6),
                        rng.uniform(-0.5, 0.5))
    m.write("pile_3d.msh")
    # A curved ramp (a quarter pipe of radius 2 into a flat floor) for a
    # ball rolling down it, and a second block to hit at the bottom.
    ramp = [(-0.5, 2.5), (0.0, 2.0)]
    for k in range(1, 25):
        a = 0.5 * math.pi * k / 24
        ramp.append((2.0 - 2.0 * math.cos(a), 2.0 - 2.0 * math.sin(a)))
    ramp.append((7.0, 0.0))
    write_polyline("ramp_2d.msh", ramp)
    # A 3D bowl (a paraboloid z = 0.25 r^2 on a polar grid) as OBJ.
    verts, faces = [(0.0, 0.0, 0.0)], []
    nr, nt = 8, 24
    for i in range(1, nr + 1):
        r = 2.0 * i / nr
        for j in range(nt):
            t = 2 * math.pi * j / nt
            verts.append((r * math.cos(t), r * math.sin(t), 0.25 * r * r))
    ring = lambda i, j: 1 + (i - 1) * nt + j % nt
    for j in range(nt):
        faces.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, nr):
        for j in range(nt):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j + 1), ring(i + 1, j)
            faces.append((a, d, c))
            faces.append((a, c, b))
    write_obj("bowl_3d.obj", verts, faces)
    # Interlocking parts (static, thesis Fig. 3.6): a holder with inward
    # lips (body 0) and a T-shaped insert whose flange sits under the lips
    # (body 1), 0.005 apart everywhere. Tags: 1 the holder's bottom, 2 the
    # insert's top, 0 elsewhere.
    g, h = 0.005, 0.1
    m = Mesh(2)
    m.union(0, [((0, 0), (0.5, 0.5)), ((0.5, 0), (2.5, 0.5)),
                ((2.5, 0), (3, 0.5)), ((0, 0.5), (0.5, 1.5)),
                ((0, 1.5), (0.5, 2)), ((0.5, 1.5), (1.2, 2)),
                ((2.5, 0.5), (3, 1.5)), ((2.5, 1.5), (3, 2)),
                ((1.8, 1.5), (2.5, 2))], h)
    m.union(1, [((0.5 + g, 0.5 + g), (1.2 + g, 1.5 - g)),
                ((1.2 + g, 0.5 + g), (1.8 - g, 1.5 - g)),
                ((1.8 - g, 0.5 + g), (2.5 - g, 1.5 - g)),
                ((1.2 + g, 1.5 - g), (1.8 - g, 3))], h)
    m.write("interlock_2d.msh",
            lambda b, c: 1 if b == 0 and c[1] < 1e-9 else
            2 if b == 1 and c[1] > 3 - 1e-9 else 0)
    # A hook over the top of a door (static, thesis Fig. 3.7): the door's
    # edge (body 0, held on its whole boundary, tag 1) and a hook of
    # 0.2-thick arms (body 1) around it 0.005 apart: a back lip, a top and
    # a front drop that turns into a U. Tags: 2 the inside of the U's
    # bottom (where the coat hangs), 3 the hook's sides that face the door
    # (kept in shape optimization), 0 the hook's free boundary.
    g, t = 0.005, 0.2
    m = Mesh(2)
    m.union(0, [((0, -1), (0.4, 1))], 0.1)
    x0, x1, x2, x3 = -t - g, -g, 0.4 + g, 0.4 + g + t
    m.union(1, [((x0, 0.6), (x1, 1 + g)), ((x0, 1 + g), (x1, 1 + g + t)),
                ((x1, 1 + g), (x2, 1 + g + t)), ((x2, 1 + g), (x3, 1 + g + t)),
                ((x2, -0.4), (x3, 1 + g)), ((x2, -0.4 - t), (x3, -0.4)),
                ((x3, -0.4 - t), (x3 + 0.6, -0.4)),
                ((x3 + 0.6, -0.4 - t), (x3 + 0.6 + t, -0.4)),
                ((x3 + 0.6, -0.4), (x3 + 0.6 + t, -0.1))], 0.05)
    on = lambda a, b: abs(a - b) < 1e-9
    m.write("hook_2d.msh",
            lambda b, c: 1 if b == 0 else
            2 if on(c[1], -0.4) and x3 < c[0] < x3 + 0.6 else
            3 if (on(c[0], x1) and c[1] < 1 + g) or
                 (on(c[1], 1 + g) and x1 < c[0] < x2) or
                 (on(c[0], x2) and c[1] > -0.4) else 0)
    # A coat hanger joining two posts (static 3D, thesis Fig. 3.8; Tozoni
    # et al. 2021, Fig. 29): a lower and an upper post (bodies 0, 1, square
    # 0.6 x 0.6, held at their far ends, tag 1) 0.2 apart, and a hanger
    # (body 2) 0.005 from both: a sleeve around the joint, a collar between
    # the posts' ends and two arms with upturned tips. Square posts, not
    # round ones: a frictionless sleeve on a round post could spin freely
    # (a singular static problem). Tags: 1 the posts' far ends, 4 the rest
    # of the posts, 2 the arms' tops (the coats), 3 the hanger's sides that
    # face the posts, 0 its free boundary.
    g, t, a = 0.005, 0.15, 0.305
    m = Mesh(3)
    m.union(0, [((-0.3, -0.3, -1.2), (0.3, 0.3, 0))], 0.3)
    m.union(1, [((-0.3, -0.3, 0.2), (0.3, 0.3, 1.4))], 0.3)
    xs = [-a - t, -a, a, a + t]
    zs = [-0.5, g, 0.2 - g, 0.45, 0.6]
    boxes = []
    for k in range(len(zs) - 1):
        for i in range(3):
            for j in range(3):
                if i == 1 and j == 1 and k != 1:
                    continue  # the posts' hole, filled by the collar
                boxes.append(((xs[i], xs[j], zs[k]),
                              (xs[i + 1], xs[j + 1], zs[k + 1])))
    for sign in (-1, 1):
        x = [sign * (a + t), sign * (a + t + 0.7), sign * (a + 2 * t + 0.7)]
        for x0, x1 in ((x[0], x[1]), (x[1], x[2])):
            boxes.append(((min(x0, x1), -a, zs[3]), (max(x0, x1), a, zs[4])))
        boxes.append(((min(x[1], x[2]), -a, zs[4]),
                      (max(x[1], x[2]), a, zs[4] + 0.25)))
    m.union(2, boxes, 0.075)
    inside = lambda c: abs(c[0]) < a + 1e-9 and abs(c[1]) < a + 1e-9
    m.write("hanger_3d.msh",
            lambda b, c: (1 if abs(c[2] - (-1.2 if b == 0 else 1.4)) < 1e-9
                          else 4) if b < 2 else
            2 if abs(c[2] - zs[4]) < 1e-9 and a + t < abs(c[0]) < a + t + 0.7
            else 3 if inside(c) else 0)
    # A plus-shaped puzzle piece, and pegs to bounce among (closed
    # polygons of one line mesh).
    m = Mesh(2)
    m.union(0, [((0.2, 0), (0.4, 0.2)), ((0, 0.2), (0.2, 0.4)),
                ((0.2, 0.2), (0.4, 0.4)), ((0.4, 0.2), (0.6, 0.4)),
                ((0.2, 0.4), (0.4, 0.6))], 0.05)
    m.write("puzzle_piece_2d.msh", lambda b, c: 0)
    pegs = []
    for cx, cy in ((2.0, 0.6), (3.2, 1.4), (4.2, 0.5)):
        pegs.append([(cx + 0.25 * math.cos(2 * math.pi * k / 6 + 0.3),
                      cy + 0.25 * math.sin(2 * math.pi * k / 6 + 0.3))
                     for k in range(7)])
    write_polylines("pegs_2d.msh", pegs)
    # Pool scene (3D): two cubes on a table, 1e-3 above it.
    m = Mesh(3)
    m.block((0, 0, 1e-3), (0.2, 0.2, 0.201), (3, 3, 3), 0)
    m.block((1.0, 0.05, 1e-3), (1.2, 0.25, 0.201), (3, 3, 3), 1)
    m.write("pool_3d.msh")
    # Pool scene (2D, thesis Fig. 3.12): a cue puck (body 0) and a target
    # puck (body 1), 1e-3 above a table.
    m = Mesh(2)
    m.block((0, 1e-3), (0.2, 0.201), (4, 4), 0)
    m.block((0.6, 1e-3), (0.8, 0.201), (4, 4), 1)
    m.write("pool_2d.msh")
    # A stack of three blocks 0.005 apart for a static press (3D): within
    # the barrier distance of each other, so the barrier holds them from
    # the start (a floating block alone would make the static problem
    # singular).
    m = Mesh(3)
    for b in range(3):
        z = 1.005 * b
        m.block((0, 0, z), (1, 1, z + 1), (2, 2, 2), b)
    m.write("stack_3d.msh")


def stack(n, path):
    """Two blocks of n x n x n/2 hexahedra, 1 x 1 x 0.5 each, stacked with
    a 1e-3 gap, above the plane z = 0 (also 1e-3 below)."""
    m = Mesh(3)
    h = max(n // 2, 1)
    m.block((0, 0, 1e-3), (1, 1, 0.501), (n, n, h), 0)
    m.block((0, 0, 0.502), (1, 1, 1.002), (n, n, h), 1)
    m.write(path)


if __name__ == "__main__":
    import sys
    if len(sys.argv) == 4 and sys.argv[1] == "--stack":
        stack(int(sys.argv[2]), os.path.abspath(sys.argv[3]))
    else:
        main()
