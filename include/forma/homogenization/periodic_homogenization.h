#ifndef forma_homogenization_periodic_homogenization_h
#define forma_homogenization_periodic_homogenization_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * Periodic homogenization of a box-shaped cell Y (thesis eqs. 5.4-5.7,
   * 4.2-4.3). For each unit test strain A (Voigt basis: e11, e22, ..., and
   * engineering shears 2 e_ij = 1) it solves for the Y-periodic fluctuation
   * w with
   *   int_Y eps(v) : C : (A + eps(w)) = 0   for all periodic v,
   * fixing w at one vertex, and returns the mutual energies
   *   C^H_ab = 1/|Y| int_Y (A_a + eps(w_a)) : C : (A_b + eps(w_b)),
   * which make C^H symmetric and positive definite by construction.
   *
   * The mesh (regular grid, or any conforming mesh of the box, e.g. a
   * periodic Gmsh mesh) and its periodic constraints, sparsity pattern and
   * solver set-up are built once; homogenize() may be called for many
   * materials (sweeps). All load cases share one matrix factorization or AMG
   * hierarchy. Runs on any number of MPI ranks (p4est for grids).
   */
  template <int dim>
  class PeriodicHomogenization
  {
  public:
    struct SolverParameters
    {
      /// direct (CHOLMOD on one process, Amesos KLU on several) | cg-amg |
      /// auto (direct up to `direct_limit` unknowns left by the
      /// constraints, cg-amg beyond) | multigrid (regular 2D Q1 grids
      /// without lattice symmetries: GridMultigridHomogenization, no mesh
      /// or matrix; every process solves the whole grid;
      /// vertex_shape_gradient() unavailable; on meshes it means auto).
      std::string  type         = "auto";
      unsigned int direct_limit = 400000;
      double       tolerance    = 1e-10;
    };

    /// The material at a cell: center and material id -> elasticity tensor.
    using MaterialFunction = std::function<
      dealii::SymmetricTensor<4, dim>(const dealii::Point<dim> &center,
                                      const dealii::types::material_id)>;

    struct Result
    {
      dealii::SymmetricTensor<4, dim> C;
      std::vector<unsigned int>       linear_iterations; ///< per load case
      std::string                     solver;            ///< the one used
    };

    /// Symmetries of the structures a regular grid will homogenize.
    struct GridLattice
    {
      /**
       * Across direction 0, a multiple of the cell size: the side
       * x_0 = size_0 continues at x_0 = 0 moved by `shift` (wrapped), so
       * the box is a primitive cell of the sheared lattice spanned by
       * size_0 e_0 + shift and size_d e_d. For hexagonal structures: half
       * the sqrt(3) x 1 rectangle with shift (0, 1/2), the rectangle's C^H
       * with half the unknowns.
       */
      dealii::Tensor<1, dim> shift;
      /**
       * Every material homogenized is symmetric under the point inversion
       * x -> 2c - x about this grid vertex (2D: rotation by pi), so the
       * fluctuations are odd about it: w(2c - x) = -w(x). Imposed as
       * constraints on one process, this halves the unknowns again; the
       * result is wrong for materials without the symmetry.
       */
      bool               inversion = false;
      dealii::Point<dim> inversion_center;
    };

    /// A regular grid of n_cells[d] Q`degree` elements on [0, size].
    PeriodicHomogenization(const MPI_Comm                       comm,
                           const dealii::Point<dim>            &size,
                           const std::array<unsigned int, dim> &n_cells,
                           const SolverParameters              &solver,
                           const unsigned int                   degree  = 1,
                           const GridLattice                   &lattice = {});

    /**
     * Any conforming mesh of the box [0, size] (quads or simplices) whose
     * faces on opposite sides match; boundary ids are set here. Distributed
     * as a shared triangulation.
     */
    PeriodicHomogenization(const MPI_Comm                         comm,
                           const dealii::Triangulation<dim, dim> &mesh,
                           const SolverParameters                &solver,
                           const unsigned int                     degree = 1);

    /**
     * A conforming mesh of the solid part of the box [0, box] of a
     * perforated cell (holes are not meshed, e.g. periodic_level_set_mesh):
     * |Y| is the box's volume. The solid must be one piece across the
     * periodic sides (a floating piece makes the problem singular).
     *
     * With `inversion_symmetric`, the mesh and every material homogenized
     * are symmetric under x -> box - x (2D: the rotation by pi about the
     * center; e.g. periodic_level_set_mesh with `centrally_symmetric`): the
     * fluctuations are odd, imposed as constraints on one process, which
     * halves the unknowns (the factorization costs about a third); every
     * node needs a node at its image (checked there). On several
     * processes the symmetry is not used (nor checked).
     */
    PeriodicHomogenization(const MPI_Comm                         comm,
                           const dealii::Triangulation<dim, dim> &mesh,
                           const dealii::Point<dim>              &box,
                           const SolverParameters                &solver,
                           const unsigned int                     degree = 1,
                           const bool inversion_symmetric = false);

    ~PeriodicHomogenization();

    Result
    homogenize(const MaterialFunction &material);

    /// Derivatives of the cell tensor at a cell: dC/dq_m, m = 0..n-1.
    using MaterialDerivativeFunction =
      std::function<std::vector<dealii::SymmetricTensor<4, dim>>(
        const dealii::Point<dim> &center,
        const dealii::types::material_id)>;

    /**
     * Derivatives of the last homogenize()'s C^H with respect to n
     * parameters of the material (the mesh fixed), given the cell tensors'
     * derivatives: with chi_a = A_a x + w_a,
     *   dC_ab / dq_m = 1/|Y| int eps(chi_a) : dC/dq_m : eps(chi_b),
     * exact for the discrete mutual energies because the cell problems are
     * self-adjoint and w_a stationary (no adjoint solve): after direct
     * solves; after cg-amg its error follows the solver tolerance. The
     * perturbed material must keep any symmetry the constraints impose
     * (GridLattice).
     */
    std::vector<dealii::SymmetricTensor<4, dim>>
    material_gradient(const MaterialDerivativeFunction &material_derivative,
                      const unsigned int                n_parameters) const;

    /**
     * Shape derivative of the last homogenize()'s C^H with respect to the
     * mesh's vertex positions (cell meshes; the box stays fixed): entry
     * [v][k] is dC^H / dX_vk, so a vertex velocity field theta gives
     * dC^H = sum_v,k theta_vk [v][k] (indices of the triangulation's
     * vertices). With chi_a = A_a x + w_a and sigma_a = C eps(chi_a),
     *   dC_ab = 1/|Y| int eps_a : C : eps_b div theta
     *           - (grad w_a grad theta) : sigma_b - sigma_a : (grad w_b grad
     *           theta),
     * the derivative of the discrete mutual energies along the mesh motion
     * (the cell problems are self-adjoint and their solutions stationary,
     * so no adjoint solve is needed). Periodic partners must move alike.
     */
    std::vector<std::array<dealii::SymmetricTensor<4, dim>, dim>>
    vertex_shape_gradient() const;

    /**
     * Write the last homogenize()'s fluctuations w_a (as point data) and the
     * given cell data to `file_stem`.vtu (serial) or .pvtu + pieces.
     */
    void
    write_vtu(
      const std::string              &file_stem,
      const std::vector<std::string> &cell_data_names,
      const std::function<std::vector<double>(const dealii::Point<dim> &,
                                              const dealii::types::material_id)>
        &cell_data) const;

    /**
     * The same for a cell homogenized through a reference cell (see
     * ParallelogramCell): points are written at F x and the fluctuations,
     * computed in the basis of the cell's sides, as F^-T w.
     */
    void
    write_vtu(
      const std::string              &file_stem,
      const std::vector<std::string> &cell_data_names,
      const std::function<std::vector<double>(const dealii::Point<dim> &,
                                              const dealii::types::material_id)>
                                   &cell_data,
      const dealii::Tensor<2, dim> &F) const;

    /**
     * Adaptive refinement of a regular grid (the first constructor, solver
     * not multigrid, no inversion symmetry): refine the `fraction` of the
     * cells with the largest stress-jump indicators of the last
     * homogenize() (material as given there), the energy-norm error of the
     * cell problems, which is C^H's own error (C^H_h - C^H = the energy of
     * w - w_h for each diagonal entry). Periodicity is kept with hanging
     * nodes; the next homogenize() solves on the new grid. Returns the
     * number of cells refined.
     */
    unsigned int
    refine(const MaterialFunction &material, const double fraction);

    dealii::types::global_dof_index
    n_dofs() const;

    /// Degrees of freedom left by the periodicity and symmetry
    /// constraints: the size of the system actually solved.
    dealii::types::global_dof_index
    n_unknowns() const;

    dealii::types::global_cell_index
    n_cells() const;

    /// |Y|
    double
    volume() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
