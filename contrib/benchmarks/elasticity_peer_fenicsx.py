"""The FEniCSx side of elasticity_peer.sh: the 3D Q2 cantilever of
../shared/benchmarks/elasticity_peer.md with PETSc CG + GAMG (rigid-body
near null space, Chebyshev/Jacobi smoothing), run with Debian's dolfinx 0.5:

    mpirun -np P /usr/bin/python3 elasticity_peer_fenicsx.py n

Prints one line: dofs, CG iterations, u_z(4, 0.5, 0.5).
"""
import sys

import numpy as np
import ufl
from dolfinx import fem, geometry, mesh
from dolfinx.fem import petsc as fem_petsc
from mpi4py import MPI
from petsc4py import PETSc


def rigid_body_modes(V):
    """The six rigid motions as a PETSc near null space of V."""
    x = V.tabulate_dof_coordinates()
    n_local = V.dofmap.index_map.size_local
    bs = V.dofmap.index_map_bs
    modes = [fem.Function(V) for _ in range(6)]
    arrays = [m.x.array.reshape(-1, bs) for m in modes]
    for d in range(3):
        arrays[d][:n_local, d] = 1.0
    X, Y, Z = (x[:n_local, k] for k in range(3))
    arrays[3][:n_local, 0], arrays[3][:n_local, 1] = -Y, X
    arrays[4][:n_local, 1], arrays[4][:n_local, 2] = -Z, Y
    arrays[5][:n_local, 0], arrays[5][:n_local, 2] = Z, -X
    # Copies: a Function's PETSc vector wraps the Function's own memory,
    # which is freed with `modes` when this returns, while the null space
    # keeps the vectors (a dangling near null space made GAMG take 84-683
    # iterations, different from run to run, instead of 33).
    vectors = [m.vector.copy() for m in modes]
    for i, v in enumerate(vectors):  # Gram-Schmidt: PETSc wants them orthonormal
        for w in vectors[:i]:
            v.axpy(-v.dot(w), w)
        v.normalize()
    return PETSc.NullSpace().create(vectors=vectors)


def main(n):
    comm = MPI.COMM_WORLD
    msh = mesh.create_box(comm, [np.array([0.0, 0.0, 0.0]),
                                 np.array([4.0, 1.0, 1.0])],
                          [4 * n, n, n], mesh.CellType.hexahedron)
    V = fem.VectorFunctionSpace(msh, ("Lagrange", 2))
    fdim = msh.topology.dim - 1
    clamped = mesh.locate_entities_boundary(
        msh, fdim, lambda x: np.isclose(x[0], 0.0))
    loaded = mesh.locate_entities_boundary(
        msh, fdim, lambda x: np.isclose(x[0], 4.0))
    tags = mesh.meshtags(msh, fdim, loaded, np.full(len(loaded), 1,
                                                    dtype=np.int32))
    bc = fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType),
                         fem.locate_dofs_topological(V, fdim, clamped), V)

    E, nu = 1e5, 0.3
    mu, lmbda = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def eps(w):
        return ufl.sym(ufl.grad(w))

    dx = ufl.dx(metadata={"quadrature_degree": 4})  # 3^3 Gauss points
    ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
    a = fem.form(ufl.inner(2 * mu * eps(u) + lmbda * ufl.tr(eps(u)) *
                           ufl.Identity(3), eps(v)) * dx)
    t = fem.Constant(msh, PETSc.ScalarType((0.0, 0.0, -1.0)))
    L = fem.form(ufl.inner(t, v) * ds(1))

    A = fem_petsc.assemble_matrix(a, bcs=[bc])
    A.assemble()
    A.setNearNullSpace(rigid_body_modes(V))
    b = fem_petsc.assemble_vector(L)
    fem_petsc.apply_lifting(b, [a], bcs=[[bc]])
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    fem_petsc.set_bc(b, [bc])

    opts = PETSc.Options()
    opts["ksp_type"] = "cg"
    opts["ksp_rtol"] = 1e-8
    opts["ksp_norm_type"] = "unpreconditioned"
    opts["pc_type"] = "gamg"
    opts["mg_levels_ksp_type"] = "chebyshev"
    opts["mg_levels_pc_type"] = "jacobi"
    opts["mg_levels_ksp_chebyshev_esteig_steps"] = 20
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setFromOptions()
    uh = fem.Function(V)
    ksp.solve(b, uh.vector)
    uh.x.scatter_forward()

    point = np.array([[4.0, 0.5, 0.5]])
    tree = geometry.BoundingBoxTree(msh, msh.topology.dim)
    cells = geometry.compute_colliding_cells(
        msh, geometry.compute_collisions(tree, point), point)
    uz = None
    if len(cells.links(0)) > 0:
        uz = uh.eval(point, cells.links(0)[:1])[2]
    uz = [z for z in comm.allgather(uz) if z is not None][0]
    dofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
    if comm.rank == 0:
        print(f"{dofs} {ksp.getIterationNumber()} {uz:.10e}")


if __name__ == "__main__":
    main(int(sys.argv[1]))
