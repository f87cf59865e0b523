// Goal-oriented error estimation (dual-weighted residual, Becker and
// Rannacher 2001): for a goal J,
//   J(u) - J(u_h) ~ 1/2 rho(u_h)(z - I_h z) + 1/2 rho*(z_h)(u - I_h u),
// rho(u_h)(v) = F(v) - a(u_h, v) the primal residual, rho*(z_h)(v) =
// J'(u_h) v - a'(u_h)(v, z_h) the adjoint residual, z the adjoint of J. The
// adjoint half makes the estimate exact to third order for nonlinear goals
// (a stress norm, whose error is mostly the quadratic term a linear
// estimate misses). The residuals vanish on the discrete space (Galerkin
// orthogonality), so z and u are approximated one degree higher on the same
// mesh, z+ and u+, with the simulator's own forms, objective partials and
// solvers, and the discrete z_h, u_h stand for I_h z, I_h u. In that space
// the residuals are vectors and the products are sums over DoFs; each cell
// takes the DoF's share among the cells at the DoF.

#include <deal.II/fe/fe_tools.h>
#include <deal.II/lac/full_matrix.h>

#include "simulator_impl.h"

#include <map>
#include <set>

namespace forma
{
  namespace
  {
    // The DoF values of the ghosted `v` on the locally owned cells, by
    // active cell index.
    template <int dim>
    std::vector<dealii::Vector<double>>
    cell_values(const DoFHandler<dim> &dof_handler, const Vector_t &v)
    {
      std::vector<dealii::Vector<double>> values(
        dof_handler.get_triangulation().n_active_cells());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            auto &local = values[cell->active_cell_index()];
            local.reinit(cell->get_fe().n_dofs_per_cell());
            cell->get_dof_values(v, local);
          }
      return values;
    }

    // Each cell's space (FE index k) in the one a degree higher (k + 1):
    // the embedding, and the difference I - I_h there.
    template <int dim>
    struct NestedSpaces
    {
      NestedSpaces(const hp::FECollection<dim>     &fe,
                   const std::vector<unsigned int> &index)
        : index(index)
      {
        for (const unsigned int k :
             std::set<unsigned int>(index.begin(), index.end()))
          {
            embedding[k].reinit(fe[k + 1].n_dofs_per_cell(),
                                fe[k].n_dofs_per_cell());
            FETools::get_interpolation_matrix(fe[k], fe[k + 1], embedding[k]);
            difference[k].reinit(fe[k + 1].n_dofs_per_cell(),
                                 fe[k + 1].n_dofs_per_cell());
            FETools::get_interpolation_difference_matrix(fe[k + 1],
                                                         fe[k],
                                                         difference[k]);
          }
      }

      // The function of the cells' lower-degree values `low` in the
      // higher space (the spaces are nested: exact).
      Vector_t
      embed(const DoFHandler<dim>                     &dof_handler,
            const IndexSet                            &owned,
            const MPI_Comm                             comm,
            const std::vector<dealii::Vector<double>> &low) const
      {
        Vector_t                             high(owned, comm);
        std::vector<types::global_dof_index> dofs;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int     i = cell->active_cell_index();
              dealii::Vector<double> local(cell->get_fe().n_dofs_per_cell());
              embedding.at(index[i]).vmult(local, low[i]);
              dofs.resize(local.size());
              cell->get_dof_indices(dofs);
              for (unsigned int k = 0; k < dofs.size(); ++k)
                if (owned.is_element(dofs[k]))
                  high(dofs[k]) = local(k);
            }
        high.compress(VectorOperation::insert);
        return high;
      }

      const std::vector<unsigned int>            index;
      std::map<unsigned int, FullMatrix<double>> embedding, difference;
    };
  } // namespace



  template <int dim>
  std::vector<std::vector<double>>
  ElasticitySimulator<dim>::Impl::goal_weights(const Objective<dim> &J,
                                               double               &value)
  {
    // Regularization terms (functions of the design alone) cancel in
    // J(u) - J(u_h): J here is the sum of the integral terms.
    const auto                       I = objective_integrals(J, 0);
    std::vector<std::vector<double>> w;
    value = 0;
    for (unsigned int t = 0; t < J.terms().size(); ++t)
      {
        const auto         &term = *J.terms()[t];
        std::vector<double> d(term.integrals().size(), 0.);
        if (!term.integrals().empty())
          value += term.weight * term.combine(I[t], &d);
        for (auto &x : d)
          x *= term.weight;
        w.push_back(d);
      }
    return w;
  }



  template <int dim>
  Vector_t
  ElasticitySimulator<dim>::Impl::goal_adjoint(const Objective<dim> &J,
                                               Vector_t             &dJ_du,
                                               double               &value)
  {
    // The Jacobian at u (a fresh factorization: the space may be new) and
    // the adjoint lambda = -z of K^T lambda = -dJ/du. Contact and IPC, whose
    // adjoint Jacobians differ from Newton's, exclude adaptivity.
    u_states.assign(1, u);
    assemble_or_throw(u, true);
    const auto w = goal_weights(J, value);
    dJ_du.reinit(owned, comm);
    accumulate(J, &w, nullptr, &dJ_du);
    Vector_t rhs(dJ_du), lambda(owned, comm);
    rhs *= -1.;
    solve_jacobian(lambda, rhs);
    constraints_zero.distribute(lambda);
    return lambda;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::assemble_or_throw(const Vector_t &state,
                                                    const bool      with_matrix)
  {
    AssertThrow(assemble(state, with_matrix, nullptr),
                ExcMessage("Finite element/Error indicator = goal: the "
                           "state one degree higher inverts an element, so "
                           "the goal estimate is not available on this mesh; "
                           "refine the starting mesh or use the Kelly "
                           "indicator."));
  }



  template <int dim>
  std::pair<double, double>
  ElasticitySimulator<dim>::Impl::estimate_goal_error()
  {
    const Objective<dim> &J = *goal;
    AssertThrow(!simplex, ExcInternalError());
    const Vector_t              u_saved      = u;
    const std::vector<Vector_t> states_saved = u_states;

    // The discrete adjoint z_h = -lambda_h; u_h and lambda_h cell by cell.
    // (Copy-assigned: a moved-in vector would drop the ghost layout.)
    Vector_t       dJ_du;
    double         value    = 0;
    const Vector_t lambda_h = goal_adjoint(J, dJ_du, value);
    Vector_t       lambda_ghost(owned, relevant, comm);
    lambda_ghost                  = lambda_h;
    u_ghost                       = u;
    const auto         u_low      = cell_values(dof_handler, u_ghost);
    const auto         lambda_low = cell_values(dof_handler, lambda_ghost);
    const unsigned int n_cells    = tria->n_active_cells();
    std::vector<unsigned int> index(n_cells, 0);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        index[cell->active_cell_index()] = cell->active_fe_index();
    const auto set_degrees = [&](const unsigned int raise) {
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          cell->set_active_fe_index(index[cell->active_cell_index()] + raise);
    };

    // Back to the solved state on the solver's own degrees, also when the
    // higher space fails; the direct factorization or AMG hierarchy kept
    // for reuse belongs to the higher space, so the solver starts afresh.
    const auto restore = [&]() {
      set_degrees(0);
      linear_solver = LinearSolver(p.linear_solver);
      setup_system();
      apply_design(design);
      u        = u_saved;
      u_ghost  = u;
      u_states = states_saved;
    };
    double estimate = 0;
    try
      {
        // One degree higher, where the discrete solutions embed exactly (the
        // spaces are nested).
        set_degrees(1);
        setup_system();
        apply_design(design); // its shape and materials, not the mesh's
        const NestedSpaces<dim> spaces(fe, index);
        const auto              embed = [&](const auto &low) {
          return spaces.embed(dof_handler, owned, comm, low);
        };

        // At u_h: the primal residual h = -rho, J and dJ/du (the adjoint
        // residual rho*(z_h)(v) = dJ/du v - a'(v, z_h) is the vector
        // dJ/du + K^T lambda_h).
        const Vector_t u_h = embed(u_low);
        u                  = u_h;
        u_states.assign(1, u);
        assemble_or_throw(u, true);
        const Vector_t h = residual;
        const auto     w = goal_weights(J, value);
        dJ_du.reinit(owned, comm);
        accumulate(J, &w, nullptr, &dJ_du);
        const Vector_t lambda_embedded = embed(lambda_low);
        Vector_t       dual(owned, comm);
        jacobian.Tvmult(dual, lambda_embedded);
        dual += dJ_du;

        // The primal one degree higher, u+: the Dirichlet data interpolated in
        // the higher space, then one Newton step (exact for linear elasticity).
        Vector_t u_high(u);
        constraints_bc.distribute(u_high);
        assemble_or_throw(u_high, false);
        Vector_t du(owned, comm), minus_h(residual);
        minus_h *= -1.;
        solve_jacobian(du, minus_h);
        constraints_zero.distribute(du);
        u_high += du;

        // The adjoint one degree higher, of J linearized at u+ rather than u_h:
        // the difference is what carries a nonlinear goal's quadratic error.
        u = u_high;
        double         value_high;
        Vector_t       dJ_du_high;
        const Vector_t lambda_high = goal_adjoint(J, dJ_du_high, value_high);

        // The estimate with weights z+ - z_h and u+ - u_h: any conforming
        // discrete function may stand for I_h z (Galerkin orthogonality), and
        // the discrete solutions are conforming across hanging nodes and degree
        // changes. The indicators with the cell's own interpolant, which
        // vanishes at the cell's lower-degree nodes and so keeps each product
        // on the cells it comes from (they mark better).
        Vector_t weight_z(lambda_high), weight_u(u_high);
        weight_z -= lambda_embedded;
        weight_u -= u_h;
        estimate = share_products(h, weight_z, dual, weight_u, nullptr);
        estimated_error.reinit(n_cells);
        share_products(h, lambda_high, dual, u_high, [&](const auto &cell) {
          return &spaces.difference.at(index[cell->active_cell_index()]);
        });
      }
    catch (...)
      {
        restore();
        throw;
      }
    restore();
    return {value, estimate};
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::share_products(
    const Vector_t           &h,
    const Vector_t           &z,
    const Vector_t           &dual,
    const Vector_t           &v,
    const LocalInterpolation &interpolation)
  {
    // eta_K = 1/2 sum_j [h_j w(z)_j + dual_j w(v)_j] / (cells at j) over the
    // DoFs j of K that are not constrained (the condensed vectors hold
    // hanging DoFs' shares at their masters); w is z itself, or z - I_h z
    // on the cell with `interpolation`. With lambda = -z and rho = -h, the
    // first product is rho(z - I_h z).
    Vector_t count;
    count.reinit(owned, relevant, comm, true); // writable ghosts
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (const auto j : dofs)
            count(j) += 1.;
        }
    count.compress(VectorOperation::add);
    const auto ghosted = [&](const Vector_t &x) {
      Vector_t g(owned, relevant, comm);
      g = x;
      return g;
    };
    const Vector_t n = ghosted(count), hg = ghosted(h), zg = ghosted(z),
                   dg = ghosted(dual), vg = ghosted(v);

    double estimate = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int     m = cell->get_fe().n_dofs_per_cell();
          dealii::Vector<double> wz(m), wv(m);
          cell->get_dof_values(zg, wz);
          cell->get_dof_values(vg, wv);
          if (interpolation)
            {
              const FullMatrix<double> &D = *interpolation(cell);
              dealii::Vector<double>    a(wz), b(wv);
              D.vmult(wz, a);
              D.vmult(wv, b);
            }
          dofs.resize(m);
          cell->get_dof_indices(dofs);
          double eta = 0;
          for (unsigned int k = 0; k < m; ++k)
            if (!constraints_zero.is_constrained(dofs[k]))
              eta +=
                0.5 * (hg(dofs[k]) * wz(k) + dg(dofs[k]) * wv(k)) / n(dofs[k]);
          if (interpolation)
            estimated_error(cell->active_cell_index()) =
              static_cast<float>(std::abs(eta));
          estimate += eta;
        }
    return Utilities::MPI::sum(estimate, comm);
  }



  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
