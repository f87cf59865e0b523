// Goal-oriented error estimation (dual-weighted residual, Becker and
// Rannacher 2001, eq. 3.13 there): for a goal J,
//   J(u) - J(u_h) ~ 1/2 rho(u_h)(z - I_h z) + 1/2 rho*(z_h)(u - I_h u),
// rho(u_h)(v) = F(v) - a(u_h, v) the primal residual, rho*(z_h)(v) =
// J'(u_h) v - a'(u_h)(v, z_h) the adjoint residual, z the adjoint of J. The
// adjoint half makes the estimate exact to third order for nonlinear goals
// (a stress norm, whose error is mostly the quadratic term a linear
// estimate misses). z - I_h z and u - I_h u vanish in the discrete space
// (Galerkin orthogonality), so z and u are approximated one degree higher
// on the same mesh, with the simulator's own forms, objective partials and
// solvers. In that space the residuals are vectors and the products are sums
// over DoFs; each cell takes the DoF's share among the cells at the DoF.

#include <deal.II/fe/fe_tools.h>
#include <deal.II/lac/full_matrix.h>

#include "simulator_impl.h"

#include <map>
#include <set>

namespace forma
{
  template <int dim>
  std::vector<std::vector<double>>
  ElasticitySimulator<dim>::Impl::goal_weights(const Objective<dim> &J)
  {
    const auto                       I = objective_integrals(J, 0);
    std::vector<std::vector<double>> w;
    for (unsigned int t = 0; t < J.terms().size(); ++t)
      {
        std::vector<double> d(J.terms()[t]->integrals().size(), 0.);
        J.terms()[t]->combine(I[t], &d);
        for (auto &x : d)
          x *= J.terms()[t]->weight;
        w.push_back(d);
      }
    return w;
  }



  template <int dim>
  Vector_t
  ElasticitySimulator<dim>::Impl::goal_adjoint(const Objective<dim> &J,
                                               Vector_t             &dJ_du)
  {
    // The Jacobian at u (setting up its pattern first) and the adjoint
    // lambda = -z of K^T lambda = -dJ/du.
    u_states.assign(1, u);
    assemble(u, true, nullptr);
    const auto w = goal_weights(J);
    dJ_du.reinit(owned, comm);
    accumulate(J, &w, nullptr, &dJ_du);
    Vector_t rhs(dJ_du), lambda(owned, comm);
    rhs *= -1.;
    solve_jacobian(lambda, rhs);
    constraints_zero.distribute(lambda);
    return lambda;
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
    const Vector_t lambda_h = goal_adjoint(J, dJ_du);
    Vector_t       lambda_ghost(owned, relevant, comm);
    lambda_ghost                                = lambda_h;
    u_ghost                                     = u;
    const unsigned int                  n_cells = tria->n_active_cells();
    std::vector<dealii::Vector<double>> u_low(n_cells), lambda_low(n_cells);
    std::vector<unsigned int>           index(n_cells, 0);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int i = cell->active_cell_index();
          index[i]             = cell->active_fe_index();
          u_low[i].reinit(cell->get_fe().n_dofs_per_cell());
          lambda_low[i].reinit(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_values(u_ghost, u_low[i]);
          cell->get_dof_values(lambda_ghost, lambda_low[i]);
        }
    const auto set_degrees = [&](const unsigned int raise) {
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          cell->set_active_fe_index(index[cell->active_cell_index()] + raise);
    };

    // One degree higher: embedding (exact, the spaces are nested) and
    // z - I_h z of every element in use.
    set_degrees(1);
    setup_system();
    std::map<unsigned int, FullMatrix<double>> embedding, difference;
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
    std::vector<types::global_dof_index> dofs;
    const auto embed = [&](const std::vector<dealii::Vector<double>> &low) {
      Vector_t high(owned, comm);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const unsigned int     i = cell->active_cell_index();
            dealii::Vector<double> local(cell->get_fe().n_dofs_per_cell());
            embedding[index[i]].vmult(local, low[i]);
            dofs.resize(local.size());
            cell->get_dof_indices(dofs);
            for (unsigned int k = 0; k < dofs.size(); ++k)
              if (owned.is_element(dofs[k]))
                high(dofs[k]) = local(k);
          }
      high.compress(VectorOperation::insert);
      return high;
    };

    // At u_h one degree higher: the primal residual h = -rho, J, dJ/du and
    // one Newton step to the higher-degree primal u+ (exact for linear
    // elasticity).
    u = embed(u_low);
    u_states.assign(1, u);
    assemble(u, true, nullptr);
    const Vector_t h     = residual;
    const double   value = objective_value(J);
    {
      const auto w = goal_weights(J);
      dJ_du.reinit(owned, comm);
      accumulate(J, &w, nullptr, &dJ_du);
    }
    Vector_t du(owned, comm), minus_h(h);
    minus_h *= -1.;
    solve_jacobian(du, minus_h);
    constraints_zero.distribute(du);
    Vector_t u_high(u);
    u_high += du;

    // The adjoint residual rho*(z_h)(v) = dJ/du v - a'(v, z_h): with
    // lambda_h = -z_h, the vector dJ/du + K^T lambda_h.
    Vector_t dual(owned, comm);
    jacobian.Tvmult(dual, embed(lambda_low));
    dual += dJ_du;

    // The adjoint one degree higher, of J linearized at u+ rather than u_h:
    // the difference is what carries a nonlinear goal's quadratic error.
    u                          = u_high;
    const Vector_t lambda_high = goal_adjoint(J, dJ_du);

    estimated_error.reinit(n_cells);
    const double estimate =
      share_products(h, lambda_high, dual, u_high, difference, index);

    // Back to the solved state on the solver's own degrees; the direct
    // factorization or AMG hierarchy kept for reuse belongs to the higher
    // space, so the solver starts afresh.
    set_degrees(0);
    linear_solver = LinearSolver(p.linear_solver);
    setup_system();
    u        = u_saved;
    u_ghost  = u;
    u_states = states_saved;
    return {value, estimate};
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::share_products(
    const Vector_t                                   &h,
    const Vector_t                                   &lambda,
    const Vector_t                                   &dual,
    const Vector_t                                   &u_high,
    const std::map<unsigned int, FullMatrix<double>> &difference,
    const std::vector<unsigned int>                  &index)
  {
    // eta_K = 1/2 sum_j [h_j (lambda - I_h lambda)_j + dual_j (u - I_h u)_j]
    // / (cells at j) over the DoFs j of K that are not constrained (the
    // condensed vectors hold hanging DoFs' shares at their masters); with
    // lambda = -z and rho = -h, the first product is rho(z - I_h z).
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
    const auto ghosted = [&](const Vector_t &v) {
      Vector_t g(owned, relevant, comm);
      g = v;
      return g;
    };
    const Vector_t n = ghosted(count), hg = ghosted(h), lg = ghosted(lambda),
                   dg = ghosted(dual), ug = ghosted(u_high);

    double estimate = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int     i = cell->active_cell_index();
          const unsigned int     m = cell->get_fe().n_dofs_per_cell();
          dealii::Vector<double> z(m), wz(m), v(m), wu(m);
          cell->get_dof_values(lg, z);
          cell->get_dof_values(ug, v);
          difference.at(index[i]).vmult(wz, z);
          difference.at(index[i]).vmult(wu, v);
          dofs.resize(m);
          cell->get_dof_indices(dofs);
          double eta = 0;
          for (unsigned int k = 0; k < m; ++k)
            if (!constraints_zero.is_constrained(dofs[k]))
              eta +=
                0.5 * (hg(dofs[k]) * wz(k) + dg(dofs[k]) * wu(k)) / n(dofs[k]);
          estimated_error(i) = static_cast<float>(std::abs(eta));
          estimate += eta;
        }
    return Utilities::MPI::sum(estimate, comm);
  }



  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
