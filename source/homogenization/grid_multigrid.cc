#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include <forma/homogenization/grid_multigrid.h>

#include "grid_multigrid_impl.h"

#include <cmath>
#include <sstream>
#include <string>

// GridMultigridHomogenization: the hierarchy, the V-cycle, the CG solves of
// the test strains and their mutual energies.

namespace forma
{
  using namespace dealii;
  using namespace internal::grid_multigrid;

  namespace
  {
    Voigt
    voigt_of(const SymmetricTensor<4, 2> &T)
    {
      return {{T[0][0][0][0],
               T[0][0][1][1],
               T[0][0][0][1],
               T[1][1][1][1],
               T[1][1][0][1],
               T[0][1][0][1]}};
    }

    SymmetricTensor<4, 2>
    tensor_of(const double V[3][3])
    {
      SymmetricTensor<4, 2> T;
      T[0][0][0][0] = V[0][0];
      T[0][0][1][1] = T[1][1][0][0] = V[0][1];
      T[0][0][0][1] = T[0][1][0][0] = V[0][2];
      T[1][1][1][1]                 = V[1][1];
      T[1][1][0][1] = T[0][1][1][1] = V[1][2];
      T[0][1][0][1]                 = V[2][2];
      return T;
    }

    /// a . C b for Voigt vectors
    double
    energy(const Voigt &C, const double a[3], const double b[3])
    {
      return a[0] * (C[0] * b[0] + C[1] * b[1] + C[2] * b[2]) +
             a[1] * (C[1] * b[0] + C[3] * b[1] + C[4] * b[2]) +
             a[2] * (C[2] * b[0] + C[4] * b[1] + C[5] * b[2]);
    }

  } // namespace



  void
  GridMultigridHomogenization::Impl::build_hierarchy()
  {
    smoothers.clear(); // they watch the levels
    fine.compute_diagonal();
    levels.clear();
    levels.push_back(single_precision(fine));
    while (std::size_t(levels.back().nx) * levels.back().ny >
             parameters.coarsest_nodes &&
           (levels.back().nx > 1 || levels.back().ny > 1))
      levels.push_back(coarsen(levels.back(), parameters.operator_dependent));

    residual.resize(levels.size());
    coarse_rhs.resize(levels.size());
    correction.resize(levels.size());
    for (unsigned int l = 0; l + 1 < levels.size(); ++l)
      {
        residual[l].reinit(levels[l].m());
        coarse_rhs[l].reinit(levels[l + 1].m());
        correction[l].reinit(levels[l + 1].m());
      }
    for (unsigned int l = 0; l + 1 < levels.size(); ++l)
      {
        Smoother::AdditionalData data;
        data.degree = parameters.smoothing_degree;
        // Smooth the upper 1/15 of the spectrum (the rest is the coarse
        // grid's); 12 Lanczos steps bound the top eigenvalue well enough.
        data.smoothing_range     = 15;
        data.eig_cg_n_iterations = 12;
        data.preconditioner = std::make_shared<DiagonalMatrix<Vector<float>>>();
        data.preconditioner->get_vector().reinit(levels[l].m());
        for (std::size_t i = 0; i < levels[l].m(); ++i)
          data.preconditioner->get_vector()(i) = 1. / levels[l].el(i, i);
        smoothers.push_back(std::make_unique<Smoother>());
        smoothers.back()->initialize(levels[l], data);
      }
    factorize_coarsest();
  }



  void
  GridMultigridHomogenization::Impl::factorize_coarsest()
  {
    const Level<float> &level = levels.back();
    const auto          n     = level.block_size();
    const auto          N     = level.n_nodes();
    FullMatrix<double>  A(n, n);
    double              K[64];
    for (unsigned int j = 0; j < level.ny; ++j)
      for (unsigned int i = 0; i < level.nx; ++i)
        {
          level.cell_matrix(i + level.nx * std::size_t(j), K);
          const auto node = cell_nodes(level, i, j);
          for (unsigned int r = 0; r < 8; ++r)
            for (unsigned int k = 0; k < 8; ++k)
              A(node[r / 2] + (r % 2) * N, node[k / 2] + (k % 2) * N) +=
                K[8 * r + k];
        }
    // The translations are the null space: fix node 0 (v_cycle() makes the
    // right-hand sides orthogonal to them, so this solves exactly).
    for (const std::size_t d : {std::size_t(0), std::size_t(N)})
      for (std::size_t k = 0; k < n; ++k)
        A(d, k) = A(k, d) = (k == d) ? 1. : 0.;
    coarsest.reinit(n);
    coarsest = A;
    coarsest.compute_lu_factorization();
  }



  void
  GridMultigridHomogenization::Impl::v_cycle(const unsigned int   l,
                                             Vector<float>       &x,
                                             const Vector<float> &b) const
  {
    if (l + 1 == levels.size())
      {
        const std::size_t B = levels[l].block_size();
        Vector<double>    block(B);
        x.reinit(b.size(), true);
        for (unsigned int r = 0; r < Level<float>::n_cases; ++r)
          {
            std::copy(b.begin() + r * B,
                      b.begin() + (r + 1) * B,
                      block.begin());
            // In exact arithmetic the right-hand side is orthogonal to the
            // translations; remove what float rounding left of them, then
            // pin node 0.
            const std::size_t N = levels[l].n_nodes();
            for (unsigned int c = 0; c < 2; ++c)
              {
                double mean = 0;
                for (std::size_t k = 0; k < N; ++k)
                  mean += block(c * N + k);
                for (std::size_t k = 0; k < N; ++k)
                  block(c * N + k) -= mean / N;
              }
            block(0) = block(N) = 0;
            coarsest.solve(block);
            std::copy(block.begin(), block.end(), x.begin() + r * B);
          }
        return;
      }
    smoothers[l]->vmult(x, b);
    Vector<float> &r = residual[l], &bc = coarse_rhs[l], &xc = correction[l];
    levels[l].vmult(r, x);
    r.sadd(-1., 1., b);
    restrict_to(levels[l], levels[l + 1], r, bc);
    v_cycle(l + 1, xc, bc);
    prolongate_add(levels[l], levels[l + 1], x, xc);
    smoothers[l]->step(x, b);
  }



  GridMultigridHomogenization::GridMultigridHomogenization(
    const Point<2>                    &size,
    const std::array<unsigned int, 2> &n_cells,
    const Parameters                  &parameters)
    : impl(std::make_unique<Impl>())
  {
    AssertThrow(n_cells[0] > 0 && n_cells[1] > 0 && size[0] > 0 && size[1] > 0,
                ExcMessage("the homogenization grid needs cells and a size"));
    AssertThrow(parameters.tolerance > 0 && parameters.max_iterations > 0 &&
                  parameters.smoothing_degree > 0 &&
                  parameters.coarsest_nodes >= 16 &&
                  parameters.coarsest_nodes <= 4096,
                ExcMessage("grid multigrid: the tolerance, iterations and "
                           "smoothing degree must be positive, the coarsest "
                           "grid 16 to 4096 nodes (a dense solve; smaller "
                           "grids are too small to smooth)"));
    impl->parameters = parameters;
    impl->fine       = (pixel_level<double>(
      n_cells[0], n_cells[1], size[0] / n_cells[0], size[1] / n_cells[1]));
    impl->volume     = size[0] * size[1];
  }



  GridMultigridHomogenization::~GridMultigridHomogenization() = default;



  GridMultigridHomogenization::Result
  GridMultigridHomogenization::homogenize(
    const std::vector<SymmetricTensor<4, 2>> &pixel_tensors)
  {
    const std::size_t n_pixels = std::size_t(impl->fine.nx) * impl->fine.ny;
    AssertThrow(pixel_tensors.size() == n_pixels,
                ExcMessage(
                  "homogenize(): " + std::to_string(pixel_tensors.size()) +
                  " pixel tensors for a grid of " + std::to_string(n_pixels) +
                  " pixels"));
    return homogenize(
      [&](const std::size_t pixel) { return pixel_tensors[pixel]; });
  }



  void
  GridMultigridHomogenization::Impl::set_pixels(
    const std::function<SymmetricTensor<4, 2>(std::size_t)> &pixel_tensor)
  {
    const std::size_t n_pixels = fine.n_nodes();
    for (auto &entry : fine.voigt)
      entry.resize(n_pixels);
    for (std::size_t c = 0; c < n_pixels; ++c)
      {
        const Voigt V = voigt_of(pixel_tensor(c));
        // positive definite: the leading minors of the Voigt matrix
        const double m2 = V[0] * V[3] - V[1] * V[1];
        const double m3 = V[0] * (V[3] * V[5] - V[4] * V[4]) -
                          V[1] * (V[1] * V[5] - V[4] * V[2]) +
                          V[2] * (V[1] * V[4] - V[3] * V[2]);
        AssertThrow(V[0] > 0 && m2 > 0 && m3 > 0 && std::isfinite(m3),
                    ExcMessage("grid multigrid: the tensor of pixel (" +
                               std::to_string(c % fine.nx) + ", " +
                               std::to_string(c / fine.nx) +
                               ") is not positive definite (a void needs "
                               "a weak phase)"));
        for (unsigned int l = 0; l < 6; ++l)
          fine.voigt[l][c] = V[l];
      }
  }



  double
  GridMultigridHomogenization::Impl::assemble_loads(Vector<double> &b) const
  {
    // b = -int B^T C A_a for the three test strains; returns its norm
    // before the pixels' loads cancel (exactly, in a uniform material).
    const std::size_t B = fine.block_size();
    b.reinit(fine.m());
    double f[8], scale = 0;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int j = 0; j < fine.ny; ++j)
        for (unsigned int i = 0; i < fine.nx; ++i)
          {
            pixel_load(fine, i + fine.nx * std::size_t(j), test_strain[a], f);
            for (double &v : f)
              {
                v = -v;
                scale += v * v;
              }
            scatter_add(fine, i, j, f, b.begin() + a * B);
          }
    return std::sqrt(scale);
  }



  unsigned int
  GridMultigridHomogenization::Impl::solve(const Vector<double> &b)
  {
    // Single-precision rounding makes the V-cycle vary slightly from call
    // to call: flexible CG keeps its steps conjugate anyway.
    SolverControl                    control(parameters.max_iterations,
                          parameters.tolerance * b.l2_norm(),
                          false,
                          false);
    SolverFlexibleCG<Vector<double>> cg(control);
    try
      {
        cg.solve(fine, solution, b, *this);
      }
    catch (const SolverControl::NoConvergence &e)
      {
        std::ostringstream message;
        message << "grid multigrid: CG reached the relative residual "
                << e.last_residual / b.l2_norm() << ", not "
                << parameters.tolerance << ", in " << e.last_step
                << " steps (strongly anisotropic pixels? use the direct "
                   "solver)";
        AssertThrow(false, ExcMessage(message.str()));
      }
    return control.last_step();
  }



  SymmetricTensor<4, 2>
  GridMultigridHomogenization::Impl::mutual_energies() const
  {
    double V[3][3] = {};
    for (unsigned int j = 0; j < fine.ny; ++j)
      for (unsigned int i = 0; i < fine.nx; ++i)
        {
          double eps[3][4][3];
          for (unsigned int a = 0; a < 3; ++a)
            strains(i, j, a, eps[a]);
          const Voigt C = fine.pixel(i + fine.nx * std::size_t(j));
          for (unsigned int q = 0; q < 4; ++q)
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = a; b < 3; ++b)
                V[a][b] += energy(C, eps[a][q], eps[b][q]);
        }
    const double w = fine.hx * fine.hy / 4 / volume;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = a; b < 3; ++b)
        V[b][a] = V[a][b] = V[a][b] * w;
    return tensor_of(V);
  }



  GridMultigridHomogenization::Result
  GridMultigridHomogenization::homogenize(
    const std::function<SymmetricTensor<4, 2>(std::size_t)> &pixel_tensor)
  {
    Impl &m  = *impl;
    m.solved = false;
    m.smoothers.clear(); // they watch the levels
    m.levels.clear();
    m.set_pixels(pixel_tensor);
    m.build_hierarchy();
    Vector<double> b;
    const double   scale = m.assemble_loads(b);
    m.solution.reinit(m.fine.m());
    Result result;
    if (b.l2_norm() > 1e-12 * scale)
      result.iterations = m.solve(b);
    m.solved = true;
    result.C = m.mutual_energies();
    return result;
  }



  std::vector<SymmetricTensor<4, 2>>
  GridMultigridHomogenization::material_gradient(
    const std::vector<std::vector<SymmetricTensor<4, 2>>> &derivative) const
  {
    const Impl          &m    = *impl;
    const Level<double> &fine = m.fine;
    AssertThrow(m.solved,
                ExcMessage("material_gradient() needs a homogenize() first"));
    AssertThrow(derivative.size() == fine.voigt[0].size(),
                ExcMessage("material_gradient(): one derivative per pixel"));
    const std::size_t n = derivative.empty() ? 0 : derivative[0].size();
    std::vector<std::array<std::array<double, 3>, 3>> V(n);
    for (auto &v : V)
      for (auto &row : v)
        row.fill(0.);
    for (unsigned int j = 0; j < fine.ny; ++j)
      for (unsigned int i = 0; i < fine.nx; ++i)
        {
          const std::size_t c = i + fine.nx * std::size_t(j);
          AssertThrow(derivative[c].size() == n,
                      ExcMessage("material_gradient(): pixels differ in "
                                 "their number of parameters"));
          double eps[3][4][3];
          for (unsigned int a = 0; a < 3; ++a)
            m.strains(i, j, a, eps[a]);
          for (std::size_t k = 0; k < n; ++k)
            {
              const Voigt dC = voigt_of(derivative[c][k]);
              for (unsigned int q = 0; q < 4; ++q)
                for (unsigned int a = 0; a < 3; ++a)
                  for (unsigned int b = a; b < 3; ++b)
                    V[k][a][b] += energy(dC, eps[a][q], eps[b][q]);
            }
        }
    const double                       w = fine.hx * fine.hy / 4 / m.volume;
    std::vector<SymmetricTensor<4, 2>> result(n);
    for (std::size_t k = 0; k < n; ++k)
      {
        double S[3][3];
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = a; b < 3; ++b)
            S[b][a] = S[a][b] = V[k][a][b] * w;
        result[k] = tensor_of(S);
      }
    return result;
  }



  std::vector<std::array<unsigned int, 2>>
  GridMultigridHomogenization::levels() const
  {
    std::vector<std::array<unsigned int, 2>> l;
    for (const Level<float> &level : impl->levels)
      l.push_back({{level.nx, level.ny}});
    return l;
  }
} // namespace forma
