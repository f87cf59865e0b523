#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <forma/mesh/harmonic_extension.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  HarmonicExtension<dim>::HarmonicExtension(
    const DoFHandler<dim>           &dof_handler,
    const AffineConstraints<double> &constraints,
    const Mapping<dim>              &mapping,
    const MPI_Comm                   comm)
    : dof_handler(dof_handler)
    , constraints(constraints)
    , mapping(mapping)
    , comm(comm)
  {
    setup(); // collective: now, not inside a per-rank loop later
  }



  template <int dim>
  void
  HarmonicExtension<dim>::setup()
  {
    owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    boundary_constraints.clear();
    boundary_constraints.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, boundary_constraints);
    for (const auto i : DoFTools::extract_boundary_dofs(dof_handler))
      if (relevant.is_element(i) && !boundary_constraints.is_constrained(i))
        boundary_constraints.add_line(i);
    boundary_constraints.make_consistent_in_parallel(owned, relevant, comm);
    boundary_constraints.close();

    TrilinosWrappers::SparsityPattern sp(owned, owned, relevant, comm);
    DoFTools::make_sparsity_pattern(dof_handler,
                                    sp,
                                    boundary_constraints,
                                    false,
                                    Utilities::MPI::this_mpi_process(comm));
    sp.compress();
    matrix.reinit(sp);
    for_each_cell_laplacian(
      [&](const FullMatrix<double>                   &K,
          const std::vector<types::global_dof_index> &dofs) {
        boundary_constraints.distribute_local_to_global(K, dofs, matrix);
      });
    matrix.compress(VectorOperation::add);
    ready = true;
  }



  template <int dim>
  void
  HarmonicExtension<dim>::for_each_cell_laplacian(
    const std::function<void(const FullMatrix<double> &,
                             const std::vector<types::global_dof_index> &)> &f)
    const
  {
    const auto           &fe = dof_handler.get_fe();
    const Quadrature<dim> q  = dof_handler.get_triangulation()
                                .get_reference_cells()[0]
                                .template get_gauss_type_quadrature<dim>(2);
    FEValues<dim>      fv(mapping, fe, q, update_gradients | update_JxW_values);
    const unsigned int n = fe.n_dofs_per_cell();
    FullMatrix<double> K(n, n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          K = 0;
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              if (fe.system_to_component_index(a).first ==
                  fe.system_to_component_index(b).first)
                for (unsigned int k = 0; k < q.size(); ++k)
                  K(a, b) +=
                    fv.shape_grad(a, k) * fv.shape_grad(b, k) * fv.JxW(k);
          cell->get_dof_indices(dofs);
          f(K, dofs);
        }
  }



  template <int dim>
  typename HarmonicExtension<dim>::Vector
  HarmonicExtension<dim>::laplacian_times(const Vector                    &x,
                                          const AffineConstraints<double> &c)
  {
    Vector x_ghost(owned, relevant, comm);
    x_ghost = x;
    Vector                 result(owned, comm);
    dealii::Vector<double> x_local, local;
    for_each_cell_laplacian(
      [&](const FullMatrix<double>                   &K,
          const std::vector<types::global_dof_index> &dofs) {
        x_local.reinit(dofs.size());
        local.reinit(dofs.size());
        for (unsigned int b = 0; b < dofs.size(); ++b)
          x_local(b) = x_ghost(dofs[b]);
        K.vmult(local, x_local);
        c.distribute_local_to_global(local, dofs, result);
      });
    result.compress(VectorOperation::add);
    return result;
  }



  template <int dim>
  void
  HarmonicExtension<dim>::extend(Vector &x)
  {
    if (!ready)
      setup();
    // x_B: the boundary entries (fixed and hanging ones follow from the
    // field's constraints); interior entries solve
    //   A_II x_I = -A_IB x_B.
    Vector boundary_part(x);
    for (const auto i : owned)
      if (!boundary_constraints.is_constrained(i))
        boundary_part(i) = 0;
    boundary_part.compress(VectorOperation::insert);
    constraints.distribute(boundary_part);
    Vector rhs = laplacian_times(boundary_part, boundary_constraints);
    rhs *= -1.;
    Vector interior(owned, comm);
    solver.solve_reusing(matrix, interior, rhs);
    boundary_constraints.set_zero(interior);
    x = boundary_part;
    x += interior;
  }



  template <int dim>
  void
  HarmonicExtension<dim>::extend_transpose(Vector &g)
  {
    if (!ready)
      setup();
    // g_B - A_BI A_II^-1 g_I (A symmetric); interior entries become zero.
    Vector g_interior(g);
    boundary_constraints.set_zero(g_interior);
    Vector w(owned, comm);
    solver.solve_reusing(matrix, w, g_interior);
    boundary_constraints.set_zero(w);
    boundary_constraints.distribute(w); // hanging interior values
    const Vector r = laplacian_times(w, constraints);
    for (const auto i : owned)
      g(i) = boundary_constraints.is_constrained(i) ? g(i) - r(i) : 0.;
    g.compress(VectorOperation::insert);
  }

  template <int dim>
  bool
  HarmonicExtension<dim>::is_boundary(const types::global_dof_index i)
  {
    if (!ready)
      setup();
    const auto *e = boundary_constraints.get_constraint_entries(i);
    return e && e->empty();
  }



  template class HarmonicExtension<2>;
  template class HarmonicExtension<3>;
} // namespace forma
