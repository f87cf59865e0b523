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
    Impl                &m     = *impl;
    typename Impl::Loads loads = m.assemble(material);
    Result               result;
    result.solver = m.solver_parameters.type;
    const FullMatrix<double> load_work =
      m.solve_cell_problems(loads, result.linear_iterations);
    // Unstructured meshes, whose kernels are per cell: as w_c is
    // stationary, a(chi_c, chi_d) = a(A_c x, chi_d) = int V_cd - f_c . w_d
    // (f_c the condensed right-hand side): no second pass over the cells.
    // Exact at stationarity, so only after direct solves.
    if (!m.congruent_cells && m.solver_parameters.type == "direct")
      m.energies_at_stationarity(loads.average, load_work, result.C);
    else
      m.energies_by_cells(result.C);
    return result;
  }



  template <int dim>
  typename PeriodicHomogenization<dim>::Impl::Loads
  PeriodicHomogenization<dim>::Impl::assemble(const MaterialFunction &material)
  {
    const unsigned int n = fe->n_dofs_per_cell();
    Loads              loads;
    loads.average.reinit(nv, nv);
    if (serial_direct)
      {
        cholesky.set_zero();
        loads.free_rhs.assign(nv, Vector<double>(cholesky.size()));
      }
    else
      {
        matrix = 0;
        loads.rhs.assign(nv, TrilinosWrappers::MPI::Vector(owned, comm));
      }
    FullMatrix<double>                   K(n, n);
    std::vector<Vector<double>>          F(nv, Vector<double>(n));
    std::vector<types::global_dof_index> local(n);
    cell_tensors.clear();
    cell_tensors.reserve(tria->n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
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
          cell_tensors.push_back(V);
          const double measure = congruent_cells ? shared_cell_system(V, K, F) :
                                                   cell_system(cell, V, K, F);
          for (unsigned int a = 0; a < nv; ++a)
            for (unsigned int b = 0; b < nv; ++b)
              loads.average(a, b) += measure * V[a][b];
          cell->get_dof_indices(local);
          if (serial_direct)
            add_reduced(K, F, local, loads.free_rhs);
          else
            {
              constraints.distribute_local_to_global(K, local, matrix);
              for (unsigned int c = 0; c < nv; ++c)
                constraints.distribute_local_to_global(F[c],
                                                       local,
                                                       loads.rhs[c]);
            }
        }
    if (!serial_direct)
      matrix.compress(VectorOperation::add);
    for (auto &r : loads.rhs)
      r.compress(VectorOperation::add);
    return loads;
  }



  template <int dim>
  double
  PeriodicHomogenization<dim>::Impl::shared_cell_system(
    const Tensor<2, nv>         &V,
    FullMatrix<double>          &K,
    std::vector<Vector<double>> &F) const
  {
    const auto  &kernel = shared_kernel;
    unsigned int p      = 0;
    K                   = 0;
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
    return kernel.measure;
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::add_reduced(
    const FullMatrix<double>                   &K,
    const std::vector<Vector<double>>          &F,
    const std::vector<types::global_dof_index> &local,
    std::vector<Vector<double>>                &free_rhs)
  {
    // (local dof, free dof, weight) for the cell's rows of T.
    auto &cell_T = reduction_scratch;
    cell_T.clear();
    for (unsigned int i = 0; i < local.size(); ++i)
      for (unsigned int k = reduction_start[local[i]];
           k < reduction_start[local[i] + 1];
           ++k)
        cell_T.emplace_back(i,
                            reduction_entries[k].first,
                            reduction_entries[k].second);
    for (const auto &[i, r, t_i] : cell_T)
      {
        // Entries (r, c <= r): the half SparseCholesky keeps.
        row_columns.clear();
        row_values.clear();
        for (const auto &[j, c, t_j] : cell_T)
          if (c <= r)
            {
              row_columns.push_back(c);
              row_values.push_back(t_i * t_j * K(i, j));
            }
        // A free dof met twice (a cell holding a dof and its image) adds
        // up.
        cholesky.add_row(r,
                         row_columns.size(),
                         row_columns.data(),
                         row_values.data());
        for (unsigned int c = 0; c < nv; ++c)
          free_rhs[c](r) += t_i * F[c](i);
      }
  }



  template <int dim>
  FullMatrix<double>
  PeriodicHomogenization<dim>::Impl::solve_cell_problems(
    Loads                     &loads,
    std::vector<unsigned int> &iterations)
  {
    fluctuation.resize(nv);
    // f_c . w_d (f_c the condensed right-hand side, w_d the solution).
    FullMatrix<double> load_work(nv, nv);
    if (serial_direct)
      {
        cholesky.factorize();
        std::vector<Vector<double>> x = loads.free_rhs;
        Vector<double>              u(dof_handler.n_dofs());
        for (unsigned int c = 0; c < nv; ++c)
          {
            cholesky.solve(x[c]);
            for (types::global_dof_index i = 0; i < u.size(); ++i)
              {
                double value = 0;
                for (unsigned int k = reduction_start[i];
                     k < reduction_start[i + 1];
                     ++k)
                  value += reduction_entries[k].second *
                           x[c](reduction_entries[k].first);
                u(i) = value;
              }
            fluctuation[c].reinit(owned, relevant, comm);
            fluctuation[c] = u;
            iterations.push_back(1);
          }
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            load_work(c, d) = loads.free_rhs[c] * x[d];
        return load_work;
      }
    LinearSolver::Parameters lp;
    lp.type               = solver_parameters.type;
    lp.relative_tolerance = solver_parameters.tolerance;
    lp.max_iterations     = 5000;
    LinearSolver solver(lp);
    solver.set_null_space(translation_modes);
    std::vector<TrilinosWrappers::MPI::Vector> w(
      nv, TrilinosWrappers::MPI::Vector(owned, comm));
    for (unsigned int c = 0; c < nv; ++c)
      iterations.push_back(c == 0 ?
                             solver.solve(matrix, w[c], loads.rhs[c], false) :
                             solver.solve_reusing(matrix, w[c], loads.rhs[c]));
    for (unsigned int c = 0; c < nv; ++c) // u = T x needs none of it
      {
        for (unsigned int d = 0; d < nv; ++d)
          load_work(d, c) = loads.rhs[d] * w[c];
        constraints.distribute(w[c]);
        fluctuation[c].reinit(owned, relevant, comm);
        fluctuation[c] = w[c];
      }
    return load_work;
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::energies_at_stationarity(
    const FullMatrix<double> &average,
    const FullMatrix<double> &load_work,
    SymmetricTensor<4, dim>  &C) const
  {
    FullMatrix<double> energy(nv, nv);
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int d = 0; d < nv; ++d)
        energy(c, d) =
          Utilities::MPI::sum(average(c, d), comm) - load_work(c, d);
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int d = 0; d < nv; ++d)
        {
          const double e    = 0.5 * (energy(c, d) + energy(d, c));
          const auto [i, j] = voigt_pair<dim>(c);
          const auto [k, l] = voigt_pair<dim>(d);
          C[i][j][k][l]     = e / box_volume;
        }
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::energies_by_cells(
    SymmetricTensor<4, dim> &C) const
  {
    // Grids (shared kernels): mutual energies cell by cell, symmetric and
    // positive definite by construction.
    const unsigned int                   n = fe->n_dofs_per_cell();
    FullMatrix<double>                   energy(nv, nv);
    std::vector<Vector<double>>          w_local(nv, Vector<double>(n));
    std::vector<types::global_dof_index> local(n);
    Kernel                               own_kernel;
    unsigned int                         index = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const Tensor<2, nv> &V = cell_tensors[index++];
          if (!congruent_cells)
            compute_kernel(cell, own_kernel);
          const auto &kernel = congruent_cells ? shared_kernel : own_kernel;
          cell->get_dof_indices(local);
          for (unsigned int c = 0; c < nv; ++c)
            for (unsigned int i = 0; i < n; ++i)
              w_local[c](i) = fluctuation[c](local[i]);
          add_mutual_energies(kernel, V, w_local, energy);
        }
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int d = 0; d < nv; ++d)
        {
          // Mutual energies of engineering unit strains are the Voigt
          // entries; symmetrize the round-off away (SymmetricTensor<4>
          // stores both C_ijkl and C_klij).
          const double e =
            Utilities::MPI::sum(0.5 * (energy(c, d) + energy(d, c)), comm);
          const auto [i, j] = voigt_pair<dim>(c);
          const auto [k, l] = voigt_pair<dim>(d);
          C[i][j][k][l]     = e / box_volume;
        }
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



  template PeriodicHomogenization<2>::Impl::Loads
  PeriodicHomogenization<2>::Impl::assemble(const MaterialFunction &);
  template double
  PeriodicHomogenization<2>::Impl::shared_cell_system(
    const Tensor<2, nv> &,
    FullMatrix<double> &,
    std::vector<Vector<double>> &) const;
  template void
  PeriodicHomogenization<2>::Impl::add_reduced(
    const FullMatrix<double> &,
    const std::vector<Vector<double>> &,
    const std::vector<types::global_dof_index> &,
    std::vector<Vector<double>> &);
  template FullMatrix<double>
  PeriodicHomogenization<2>::Impl::solve_cell_problems(
    Loads &,
    std::vector<unsigned int> &);
  template void
  PeriodicHomogenization<2>::Impl::energies_at_stationarity(
    const FullMatrix<double> &,
    const FullMatrix<double> &,
    SymmetricTensor<4, 2> &) const;
  template void
  PeriodicHomogenization<2>::Impl::energies_by_cells(
    SymmetricTensor<4, 2> &) const;
  template PeriodicHomogenization<3>::Impl::Loads
  PeriodicHomogenization<3>::Impl::assemble(const MaterialFunction &);
  template double
  PeriodicHomogenization<3>::Impl::shared_cell_system(
    const Tensor<2, nv> &,
    FullMatrix<double> &,
    std::vector<Vector<double>> &) const;
  template void
  PeriodicHomogenization<3>::Impl::add_reduced(
    const FullMatrix<double> &,
    const std::vector<Vector<double>> &,
    const std::vector<types::global_dof_index> &,
    std::vector<Vector<double>> &);
  template FullMatrix<double>
  PeriodicHomogenization<3>::Impl::solve_cell_problems(
    Loads &,
    std::vector<unsigned int> &);
  template void
  PeriodicHomogenization<3>::Impl::energies_at_stationarity(
    const FullMatrix<double> &,
    const FullMatrix<double> &,
    SymmetricTensor<4, 3> &) const;
  template void
  PeriodicHomogenization<3>::Impl::energies_by_cells(
    SymmetricTensor<4, 3> &) const;
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
