#include <deal.II/lac/trilinos_vector.h>

#include <forma/homogenization/periodic_homogenization.h>
#include <forma/solvers/linear_solver.h>

#include "periodic_homogenization_impl.h"

#include <algorithm>
#include <cmath>

// PeriodicHomogenization::homogenize(): the cell problems of the unit test
// strains and their mutual energies.

namespace forma
{
  using namespace dealii;

  template <int dim>
  typename PeriodicHomogenization<dim>::Result
  PeriodicHomogenization<dim>::homogenize(const MaterialFunction &material)
  {
    if (impl->grid)
      return impl->homogenize_on_grid(material);
    Impl              &m  = *impl;
    constexpr unsigned nv = Impl::nv;
    const unsigned int n  = m.fe->n_dofs_per_cell();

    // One pass: the matrix and the right-hand sides of all test strains.
    if (m.serial_direct)
      m.cholesky.set_zero();
    else
      m.matrix = 0;
    // The right-hand sides: T^T F on the free dofs (serial direct) or the
    // condensed F.
    const unsigned int n_free = m.serial_direct ? m.cholesky.size() : 0;
    std::vector<Vector<double>> free_rhs(m.serial_direct ? nv : 0,
                                         Vector<double>(n_free));
    std::vector<TrilinosWrappers::MPI::Vector> rhs;
    if (!m.serial_direct)
      rhs.assign(nv, TrilinosWrappers::MPI::Vector(m.owned, m.comm));
    // Adds the cell's K and F to T^T K T and T^T F: (local dof, free dof,
    // weight) for the cell's rows of T.
    std::vector<std::tuple<unsigned int, unsigned int, double>> cell_T;
    std::vector<unsigned int>                                   columns;
    std::vector<double>                                         values;
    const auto                                                  add_reduced =
      [&](const FullMatrix<double>                   &K,
          const std::vector<Vector<double>>          &F,
          const std::vector<types::global_dof_index> &local) {
        cell_T.clear();
        for (unsigned int i = 0; i < local.size(); ++i)
          for (unsigned int k = m.reduction_start[local[i]];
               k < m.reduction_start[local[i] + 1];
               ++k)
            cell_T.emplace_back(i,
                                m.reduction_entries[k].first,
                                m.reduction_entries[k].second);
        for (const auto &[i, r, t_i] : cell_T)
          {
            // Entries (r, c <= r): the half SparseCholesky keeps.
            columns.clear();
            values.clear();
            for (const auto &[j, c, t_j] : cell_T)
              if (c <= r)
                {
                  columns.push_back(c);
                  values.push_back(t_i * t_j * K(i, j));
                }
            // A free dof met twice (a cell holding a dof and its image)
            // adds up.
            m.cholesky.add_row(r,
                               columns.size(),
                               columns.data(),
                               values.data());
            for (unsigned int c = 0; c < nv; ++c)
              free_rhs[c](r) += t_i * F[c](i);
          }
      };
    FullMatrix<double>                   average(nv, nv); // int_Y V
    FullMatrix<double>                   K(n, n);
    std::vector<Vector<double>>          F(nv, Vector<double>(n));
    std::vector<types::global_dof_index> local(n);
    typename Impl::Kernel                own_kernel;
    std::vector<Tensor<2, nv>>          &cell_tensor = m.cell_tensors;
    cell_tensor.clear();
    cell_tensor.reserve(m.tria->n_active_cells());
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const SymmetricTensor<4, dim> C =
            material(cell->center(), cell->material_id());
          Tensor<2, nv> V;
          for (unsigned int a = 0; a < nv; ++a)
            for (unsigned int b = 0; b < nv; ++b)
              {
                const auto [i, j] = voigt_pair<dim>(a);
                const auto [k, l] = voigt_pair<dim>(b);
                V[a][b]           = C[i][j][k][l];
              }
          cell_tensor.push_back(V);
          double measure;
          if (m.congruent_cells)
            {
              const auto &kernel = m.shared_kernel;
              measure            = kernel.measure;
              K                  = 0;
              unsigned int p     = 0;
              for (unsigned int a = 0; a < nv; ++a)
                for (unsigned int b = a; b < nv; ++b, ++p)
                  K.add(V[a][b], kernel.pair[p]);
              // f_c = -int B^T C A_c = -sum_a V_ac int B_a
              for (unsigned int c = 0; c < nv; ++c)
                {
                  F[c] = 0;
                  for (unsigned int a = 0; a < nv; ++a)
                    F[c].add(-V[a][c], kernel.integral[a]);
                }
            }
          else
            measure = m.cell_system(cell, V, K, F);
          for (unsigned int a = 0; a < nv; ++a)
            for (unsigned int b = 0; b < nv; ++b)
              average(a, b) += measure * V[a][b];
          cell->get_dof_indices(local);
          if (m.serial_direct)
            add_reduced(K, F, local);
          else
            {
              m.constraints.distribute_local_to_global(K, local, m.matrix);
              for (unsigned int c = 0; c < nv; ++c)
                m.constraints.distribute_local_to_global(F[c], local, rhs[c]);
            }
        }
    if (!m.serial_direct)
      m.matrix.compress(VectorOperation::add);
    for (auto &r : rhs)
      r.compress(VectorOperation::add);

    Result result;
    result.solver = m.solver_parameters.type;
    m.fluctuation.resize(nv);
    std::vector<TrilinosWrappers::MPI::Vector> w;
    if (!m.serial_direct)
      w.assign(nv, TrilinosWrappers::MPI::Vector(m.owned, m.comm));
    // f_c . w_d (f_c the condensed right-hand side, w_d the solution).
    FullMatrix<double> load_work(nv, nv);
    if (m.serial_direct)
      {
        m.cholesky.factorize();
        std::vector<Vector<double>> x = free_rhs;
        Vector<double>              u(m.dof_handler.n_dofs());
        for (unsigned int c = 0; c < nv; ++c)
          {
            m.cholesky.solve(x[c]);
            for (types::global_dof_index i = 0; i < u.size(); ++i)
              {
                double value = 0;
                for (unsigned int k = m.reduction_start[i];
                     k < m.reduction_start[i + 1];
                     ++k)
                  value += m.reduction_entries[k].second *
                           x[c](m.reduction_entries[k].first);
                u(i) = value;
              }
            m.fluctuation[c].reinit(m.owned, m.relevant, m.comm);
            m.fluctuation[c] = u;
            result.linear_iterations.push_back(1);
          }
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            load_work(c, d) = free_rhs[c] * x[d];
      }
    else
      {
        LinearSolver::Parameters lp;
        lp.type               = m.solver_parameters.type;
        lp.relative_tolerance = m.solver_parameters.tolerance;
        lp.max_iterations     = 5000;
        LinearSolver solver(lp);
        solver.set_null_space(m.translation_modes);
        for (unsigned int c = 0; c < nv; ++c)
          result.linear_iterations.push_back(
            c == 0 ? solver.solve(m.matrix, w[c], rhs[c], false) :
                     solver.solve_reusing(m.matrix, w[c], rhs[c]));
      }
    for (unsigned int c = 0; c < w.size(); ++c) // u = T x needs none of it
      {
        for (unsigned int d = 0; d < nv; ++d)
          load_work(d, c) = rhs[d] * w[c];
        m.constraints.distribute(w[c]);
        m.fluctuation[c].reinit(m.owned, m.relevant, m.comm);
        m.fluctuation[c] = w[c];
      }

    FullMatrix<double> energy(nv, nv);
    if (!m.congruent_cells && m.solver_parameters.type == "direct")
      {
        // Unstructured meshes, whose kernels are per cell: as w_c is
        // stationary, a(chi_c, chi_d) = a(A_c x, chi_d) = int V_cd - f_c . w_d
        // (f_c the condensed right-hand side): no second pass over the cells.
        // Exact at stationarity, so only after direct solves.
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            energy(c, d) =
              Utilities::MPI::sum(average(c, d), m.comm) - load_work(c, d);
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            {
              const double e       = 0.5 * (energy(c, d) + energy(d, c));
              const auto [i, j]    = voigt_pair<dim>(c);
              const auto [k, l]    = voigt_pair<dim>(d);
              result.C[i][j][k][l] = e / m.box_volume;
            }
        return result;
      }

    // Grids (shared kernels): mutual energies cell by cell, symmetric and
    // positive definite by construction.
    std::vector<Vector<double>> w_local(nv, Vector<double>(n));
    unsigned int                index = 0;
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const Tensor<2, nv> &V = cell_tensor[index++];
          if (!m.congruent_cells)
            m.compute_kernel(cell, own_kernel);
          const auto &kernel = m.congruent_cells ? m.shared_kernel : own_kernel;
          cell->get_dof_indices(local);
          for (unsigned int c = 0; c < nv; ++c)
            for (unsigned int i = 0; i < n; ++i)
              w_local[c](i) = m.fluctuation[c](local[i]);
          m.add_mutual_energies(kernel, V, w_local, energy);
        }
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int d = 0; d < nv; ++d)
        {
          // Mutual energies of engineering unit strains are the Voigt
          // entries; symmetrize the round-off away (SymmetricTensor<4>
          // stores both C_ijkl and C_klij).
          const double e =
            Utilities::MPI::sum(0.5 * (energy(c, d) + energy(d, c)), m.comm);
          const auto [i, j]    = voigt_pair<dim>(c);
          const auto [k, l]    = voigt_pair<dim>(d);
          result.C[i][j][k][l] = e / m.box_volume;
        }
    return result;
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::add_mutual_energies(
    const Kernel                      &kernel,
    const Tensor<2, nv>               &V,
    const std::vector<Vector<double>> &w_local,
    FullMatrix<double>                &energy) const
  {
    // Scratch kept across cells: this runs once per cell and homogenize().
    const unsigned int  n  = w_local[0].size();
    FullMatrix<double> &K  = energy_matrix;
    Vector<double>     &Kw = energy_vector;
    if (K.m() != n)
      {
        K.reinit(n, n);
        Kw.reinit(n);
      }
    else
      K = 0;
    unsigned int p = 0;
    for (unsigned int a = 0; a < nv; ++a)
      for (unsigned int b = a; b < nv; ++b, ++p)
        K.add(V[a][b], kernel.pair[p]);
    // s_a(w) = int (B w)_a
    std::array<std::array<double, nv>, nv> s;
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int a = 0; a < nv; ++a)
        s[c][a] = kernel.integral[a] * w_local[c];
    for (unsigned int d = 0; d < nv; ++d)
      {
        K.vmult(Kw, w_local[d]);
        for (unsigned int c = 0; c < nv; ++c)
          {
            double e = kernel.measure * V[c][d] + (w_local[c] * Kw);
            for (unsigned int a = 0; a < nv; ++a)
              e += V[c][a] * s[d][a] + V[d][a] * s[c][a];
            energy(c, d) += e;
          }
      }
  }



  template PeriodicHomogenization<2>::Result
  PeriodicHomogenization<2>::homogenize(const MaterialFunction &);
  template void
  PeriodicHomogenization<2>::Impl::add_mutual_energies(
    const Kernel &,
    const Tensor<2, nv> &,
    const std::vector<Vector<double>> &,
    FullMatrix<double> &) const;
  template PeriodicHomogenization<3>::Result
  PeriodicHomogenization<3>::homogenize(const MaterialFunction &);
  template void
  PeriodicHomogenization<3>::Impl::add_mutual_energies(
    const Kernel &,
    const Tensor<2, nv> &,
    const std::vector<Vector<double>> &,
    FullMatrix<double> &) const;
} // namespace forma
