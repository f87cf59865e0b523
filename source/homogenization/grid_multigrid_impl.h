#ifndef forma_source_homogenization_grid_multigrid_impl_h
#define forma_source_homogenization_grid_multigrid_impl_h

// GridMultigridHomogenization's state, shared by its files (internal, not
// installed): the hierarchy and solves (grid_multigrid.cc) and the output
// (grid_multigrid_output.cc).

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>

#include <forma/homogenization/grid_multigrid.h>

#include "grid_multigrid_level.h"

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

  using namespace internal::grid_multigrid;

  struct GridMultigridHomogenization::Impl
  {
    using Smoother =
      dealii::PreconditionChebyshev<Level, dealii::Vector<double>>;

    Parameters                             parameters;
    std::vector<Level>                     levels;
    std::vector<std::unique_ptr<Smoother>> smoothers;
    dealii::LAPACKFullMatrix<double>       coarsest;
    /// the fluctuations of the three test strains, one block each
    dealii::Vector<double> solution;
    /// Per level: residual, and the coarse right-hand side and correction.
    mutable std::vector<dealii::Vector<double>> residual, coarse_rhs,
      correction;
    double volume = 0;

    void
    build_hierarchy();

    void
    factorize_coarsest();

    /// x = V-cycle(b) on level l.
    void
    v_cycle(const unsigned int            l,
            dealii::Vector<double>       &x,
            const dealii::Vector<double> &b) const;

    /// The strains at the Gauss points of pixel c under test strain a.
    void
    strains(const unsigned int i,
            const unsigned int j,
            const unsigned int a,
            double             eps[4][3]) const
    {
      double u[8];
      gather(levels[0], i, j, solution.begin() + a * levels[0].block_size(), u);
      pixel_strains(u, test_strain[a], levels[0].hx, levels[0].hy, eps);
    }

    void
    vmult(dealii::Vector<double> &x, const dealii::Vector<double> &b) const
    {
      v_cycle(0, x, b);
    }
  };



} // namespace forma

#endif
