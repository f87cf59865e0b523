#ifndef forma_homogenization_periodic_homogenization_h
#define forma_homogenization_periodic_homogenization_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
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
      /// direct (Amesos KLU) | cg-amg | auto (direct up to `direct_limit`
      /// unknowns, cg-amg beyond).
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

    /// A regular grid of n_cells[d] Q`degree` elements on [0, size].
    PeriodicHomogenization(const MPI_Comm                       comm,
                           const dealii::Point<dim>            &size,
                           const std::array<unsigned int, dim> &n_cells,
                           const SolverParameters              &solver,
                           const unsigned int                   degree = 1);

    /**
     * Any conforming mesh of the box [0, size] (quads or simplices) whose
     * faces on opposite sides match; boundary ids are set here. Distributed
     * as a shared triangulation.
     */
    PeriodicHomogenization(const MPI_Comm                         comm,
                           const dealii::Triangulation<dim, dim> &mesh,
                           const SolverParameters                &solver,
                           const unsigned int                     degree = 1);

    ~PeriodicHomogenization();

    Result
    homogenize(const MaterialFunction &material);

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

    dealii::types::global_dof_index
    n_dofs() const;

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
