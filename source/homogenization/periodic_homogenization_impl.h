#ifndef forma_source_homogenization_periodic_homogenization_impl_h
#define forma_source_homogenization_periodic_homogenization_impl_h

// PeriodicHomogenization's state, shared by its files (internal, not
// installed): set-up and constraints (periodic_homogenization.cc), the
// cell problems and mutual energies (periodic_homogenization_solve.cc),
// derivatives of C^H (periodic_homogenization_gradients.cc) and output
// (periodic_homogenization_output.cc).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/homogenization/grid_multigrid.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/solvers/sparse_cholesky.h>

#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace internal
  {
    namespace periodic
    {
      // Voigt index -> tensor indices; shears carry the engineering factor.
      template <int dim>
      inline constexpr unsigned int n_voigt = dim *(dim + 1) / 2;

      template <int dim>
      inline std::pair<unsigned int, unsigned int>
      voigt_pair(const unsigned int a)
      {
        if (a < dim)
          return {a, a};
        if (dim == 2)
          return {0, 1};
        static const unsigned int i[3] = {1, 0, 0}, j[3] = {2, 2, 1};
        return {i[a - dim], j[a - dim]};
      }

      /// The unit test strain of Voigt index a (engineering shear = 1).
      template <int dim>
      inline SymmetricTensor<2, dim>
      test_strain(const unsigned int a)
      {
        SymmetricTensor<2, dim> A;
        const auto [i, j] = voigt_pair<dim>(a);
        A[i][j]           = (i == j) ? 1. : 0.5;
        return A;
      }

      /// Voigt vector (engineering shear) of a symmetric strain.
      template <int dim>
      inline void
      strain_to_voigt(const SymmetricTensor<2, dim> &e, double *v)
      {
        for (unsigned int a = 0; a < n_voigt<dim>; ++a)
          {
            const auto [i, j] = voigt_pair<dim>(a);
            v[a]              = (i == j) ? e[i][j] : 2 * e[i][j];
          }
      }
    } // namespace periodic
  }   // namespace internal

  using namespace internal::periodic;



  template <int dim>
  struct PeriodicHomogenization<dim>::Impl
  {
    static constexpr unsigned int nv = n_voigt<dim>;

    /**
     * The stiffness of a cell is linear in its (constant) tensor:
     * K(V) = sum_ab V_ab int B_a^T B_b, with B the Voigt strain of the shape
     * functions. `pair` holds the symmetrized integrals for a <= b,
     * `integral` int B_a; for congruent cells (regular grids) they are
     * computed once.
     */
    struct Kernel
    {
      std::vector<FullMatrix<double>> pair;
      std::vector<Vector<double>>     integral;
      double                          measure = 0;
    };

    Impl(const MPI_Comm comm, const SolverParameters &solver)
      : comm(comm)
      , solver_parameters(solver)
      , requested_solver(solver)
      , dof_handler()
    {}

    void
    setup(const unsigned int degree, const Point<dim> &box);

    /// Periodicity (and symmetry) constraints, then setup_system().
    void
    make_constraints(const Point<dim> &box);

    /// w = 0 at one interior vertex.
    void
    fix_translations(const Point<dim> &box);

    /**
     * Per active cell: sum over the load cases and the cell's faces of
     * h_F / 2 int_F |[sigma_a n]|^2 / |C|_max^2, sigma_a = C (A_a +
     * eps(w_a)) of the last homogenize() (the energy-norm error's face
     * residual; interior and periodic faces, hanging ones included).
     */
    Vector<float>
    stress_jump_indicators(const MaterialFunction &material) const;

    /// Sparsity, matrix, null space, kernels for the closed constraints.
    void
    setup_system();

    /// The position of the cell's dof i (the mapping is linear).
    Point<dim>
    support_point(const typename DoFHandler<dim>::active_cell_iterator &cell,
                  const unsigned int                                    i) const
    {
      Point<dim> p;
      for (unsigned int v = 0; v < support_weights[i].size(); ++v)
        p += support_weights[i][v] * cell->vertex(v);
      return p;
    }

    void
    compute_kernel(const typename DoFHandler<dim>::active_cell_iterator &cell,
                   Kernel &kernel) const;

    /// Meshes whose cells differ: the cell's K = int B^T V B and loads
    /// F_c = -int B^T V A_c directly (pair kernels pay off only when the
    /// cells share them); returns the cell's measure.
    double
    cell_system(const typename DoFHandler<dim>::active_cell_iterator &cell,
                const Tensor<2, nv>                                  &V,
                FullMatrix<double>                                   &K,
                std::vector<Vector<double>>                          &F) const;

    /// The right-hand sides of the unit test strains' cell problems: T^T F
    /// on the free dofs (serial direct) or the condensed F; and int_Y V
    /// over the locally owned cells.
    struct Loads
    {
      FullMatrix<double>                         average;
      std::vector<Vector<double>>                free_rhs;
      std::vector<TrilinosWrappers::MPI::Vector> rhs;
    };

    /// One pass over the cells: the matrix (in `cholesky` or `matrix`),
    /// the loads of all test strains, and cell_tensors.
    Loads
    assemble(const MaterialFunction &material);

    /// Congruent cells: K and F from the shared kernel; returns the
    /// cell's measure.
    double
    shared_cell_system(const Tensor<2, nv>         &V,
                       FullMatrix<double>          &K,
                       std::vector<Vector<double>> &F) const;

    /// Serial direct: add the cell's K and F to T^T K T and T^T F.
    void
    add_reduced(const FullMatrix<double>                   &K,
                const std::vector<Vector<double>>          &F,
                const std::vector<types::global_dof_index> &local,
                std::vector<Vector<double>>                &free_rhs);

    /// The fluctuations of all test strains (in `fluctuation`), one
    /// iteration count per strain; returns f_c . w_d.
    FullMatrix<double>
    solve_cell_problems(Loads &loads, std::vector<unsigned int> &iterations);

    /// C^H = (int V - f . w) / |Y|: exact for stationary w (direct solves).
    void
    energies_at_stationarity(const FullMatrix<double> &average,
                             const FullMatrix<double> &load_work,
                             SymmetricTensor<4, dim>  &C) const;

    /// C^H from the mutual energies of the fluctuations, cell by cell.
    void
    energies_by_cells(SymmetricTensor<4, dim> &C) const;

    /**
     * Add a cell's int (A_c + B w_c)^T V (A_d + B w_d)
     *   = |K| V_cd + V_c. (int B) w_d + V_d. (int B) w_c + w_c^T K(V) w_d
     * for its local fluctuations w_c to energy(c, d).
     */
    void
    add_mutual_energies(const Kernel                      &kernel,
                        const Tensor<2, nv>               &V,
                        const std::vector<Vector<double>> &w_local,
                        FullMatrix<double>                &energy) const;

    MPI_Comm         comm;
    SolverParameters solver_parameters;
    /// As constructed: `auto` decides again for a refined grid.
    SolverParameters                    requested_solver;
    std::unique_ptr<Triangulation<dim>> tria;
    std::unique_ptr<FiniteElement<dim>> fe;
    std::unique_ptr<Mapping<dim>>       mapping_owner;
    const Mapping<dim>                 *mapping = nullptr;
    std::unique_ptr<Quadrature<dim>>    quadrature;
    /// Vertex weights of the element's support points (linear mapping).
    std::vector<std::vector<double>> support_weights;
    DoFHandler<dim>                  dof_handler;
    AffineConstraints<double>        constraints;
    IndexSet                         owned, relevant;
    TrilinosWrappers::SparseMatrix   matrix;
    // One rank and a direct solver: sparse Cholesky (CHOLMOD, several times
    // faster than KLU), assembled in place, analysis kept across calls.
    // The matrix is T^T K T on the free dofs alone, u = T x: the
    // constraints (periodic ties, odd images, pins; homogeneous) resolve
    // once here instead of per cell, and half the rows of a symmetric
    // cell's matrix are not built at all.
    bool           serial_direct = false;
    SparseCholesky cholesky;
    /// Row i of T: the free dofs (and weights) dof i follows, in
    /// reduction_entries[reduction_start[i], reduction_start[i + 1]).
    std::vector<unsigned int>                    reduction_start;
    std::vector<std::pair<unsigned int, double>> reduction_entries;
    std::vector<TrilinosWrappers::MPI::Vector>   fluctuation; // ghosted
    std::vector<std::vector<double>>             translation_modes;
    bool                                         congruent_cells = false;
    Kernel                                       shared_kernel;
    mutable std::unique_ptr<FEValues<dim>>       fe_values;
    mutable std::vector<std::array<double, nv>>  strains, stresses;
    /// add_reduced()'s rows of T on a cell (local dof, free dof, weight)
    /// and one row of the cell's T^T K T.
    std::vector<std::tuple<unsigned int, unsigned int, double>>
                              reduction_scratch;
    std::vector<unsigned int> row_columns;
    std::vector<double>       row_values;
    /// add_mutual_energies()'s cell matrix and product.
    mutable FullMatrix<double> energy_matrix;
    mutable Vector<double>     energy_vector;
    double                     box_volume = 0;
    Point<dim>                 box_size;
    /// The grid was refined (refine()): hanging nodes, cells not congruent.
    bool refined = false;
    /// The last homogenize()'s cell tensors (Voigt), locally owned cells.
    std::vector<Tensor<2, nv>> cell_tensors;
    /// Grids: the side x_0 = L_0 is the side x_0 = 0 moved by L_0 e_0 +
    /// shift (wrapped into the box), and the inversion symmetry.
    GridLattice lattice;

    /**
     * Solver type "multigrid" (regular 2D grids, Q1, no lattice symmetry):
     * GridMultigridHomogenization replaces the mesh and everything above,
     * in periodic_homogenization_grid.cc.
     */
    std::unique_ptr<GridMultigridHomogenization> grid;
    std::array<unsigned int, dim>                grid_cells{};
    Point<dim>                                   grid_size;

    void
    setup_grid(const Point<dim>                    &size,
               const std::array<unsigned int, dim> &n_cells,
               const unsigned int                   degree);

    /// The center of pixel p of the grid.
    Point<dim>
    pixel_center(const std::size_t p) const;

    Result
    homogenize_on_grid(const MaterialFunction &material);

    std::vector<SymmetricTensor<4, dim>>
    material_gradient_on_grid(
      const MaterialDerivativeFunction &material_derivative,
      const unsigned int                n_parameters) const;

    void
    write_vtu_on_grid(
      const std::string              &file_stem,
      const std::vector<std::string> &cell_data_names,
      const std::function<std::vector<double>(const Point<dim> &,
                                              const types::material_id)>
        &cell_data) const;
  };
} // namespace forma

#endif
