#ifndef forma_source_homogenization_grid_multigrid_impl_h
#define forma_source_homogenization_grid_multigrid_impl_h

// GridMultigridHomogenization's state, shared by its files (internal, not
// installed): the hierarchy and solves (grid_multigrid.cc) and the output
// (grid_multigrid_output.cc).

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>

#include <forma/homogenization/grid_multigrid.h>

#include "grid_multigrid_level.h"

#include <functional>
#include <memory>
#include <vector>

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      /// The unit test strain a (Voigt, engineering shear).
      inline constexpr double test_strain[3][3] = {{1, 0, 0},
                                                   {0, 1, 0},
                                                   {0, 0, 1}};
    } // namespace grid_multigrid
  }   // namespace internal

  struct GridMultigridHomogenization::Impl
  {
    using Voigt = internal::grid_multigrid::Voigt;
    template <typename Number>
    using Level = internal::grid_multigrid::Level<Number>;
    using Smoother =
      dealii::PreconditionChebyshev<Level<float>, dealii::Vector<float>>;

    Parameters parameters;
    /// The pixels in double precision: the operator CG solves.
    Level<double> fine;
    /// The V-cycle's grids in single precision, the pixels' first.
    std::vector<Level<float>>              levels;
    std::vector<std::unique_ptr<Smoother>> smoothers;
    dealii::LAPACKFullMatrix<double>       coarsest;
    /// the fluctuations of the three test strains, one block each
    dealii::Vector<double> solution;
    /// Per level: residual, and the coarse right-hand side and correction.
    mutable std::vector<dealii::Vector<float>> residual, coarse_rhs, correction;
    double                                     volume = 0;

    /// The pixels' tensors, checked positive definite.
    void
    set_pixels(const std::function<dealii::SymmetricTensor<4, 2>(std::size_t)>
                 &pixel_tensor);

    void
    build_hierarchy();

    /// The loads of the three test strains; returns their norm before the
    /// pixels' contributions cancel.
    double
    assemble_loads(dealii::Vector<double> &b) const;

    /// CG on the three fields; returns its steps.
    unsigned int
    solve(const dealii::Vector<double> &b);

    /// C^H from the solution.
    dealii::SymmetricTensor<4, 2>
    mutual_energies() const;

    /// The last homogenize() succeeded: `solution` is its.
    bool solved = false;

    void
    factorize_coarsest();

    /// x = V-cycle(b) on level l.
    void
    v_cycle(const unsigned int           l,
            dealii::Vector<float>       &x,
            const dealii::Vector<float> &b) const;

    /// The strains at the Gauss points of pixel (i, j) under test strain a.
    void
    strains(const unsigned int i,
            const unsigned int j,
            const unsigned int a,
            double             eps[4][3]) const
    {
      double u[8];
      internal::grid_multigrid::gather(
        fine, i, j, solution.begin() + a * fine.block_size(), u);
      internal::grid_multigrid::pixel_strains(
        u, internal::grid_multigrid::test_strain[a], fine.hx, fine.hy, eps);
    }

    void
    vmult(dealii::Vector<double> &x, const dealii::Vector<double> &b) const
    {
      b_single = b;
      x_single.reinit(b.size(), true);
      v_cycle(0, x_single, b_single);
      x = x_single;
    }

    /// vmult()'s vectors in single precision
    mutable dealii::Vector<float> x_single, b_single;
  };



} // namespace forma

#endif
