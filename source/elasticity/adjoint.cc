// The adjoint layer of the elasticity simulator (thesis ch. 3.3-3.8):
// objectives over the stored states, the static and BDF transient adjoints,
// and the products p^T dh/dm of the forms into the physical parameters'
// sensitivities (adjoint/form.h, adjoint/physical_parameters.h).

#include <deal.II/base/numbers.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/run_context.h>
#include <forma/physics/bdf.h>
#include <forma/physics/contractions.h>

#include "simulator_impl.h"

#include <cmath>
#include <cstdint>

namespace forma
{
  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_forward(const bool quiet_run)
  {
    Timer timer;
    quiet        = quiet_run;
    store_states = true;
    force_scale  = 0;
    steps.clear();
    if (p.problem == "static")
      solve_static();
    else
      solve_transient();
    quiet = false;
    forward_seconds += timer.wall_time();
    ++forward_solves;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::set_step_state(const unsigned int i)
  {
    if (p.problem == "static")
      {
        transient = false;
        time      = p.end_time;
        u         = u_states[0];
        u_ghost   = u;
        return;
      }
    transient  = true;
    step_index = i;
    time       = time_grid.time(i);
    dt         = time_grid.step(i);
    u          = u_states[i];
    u_ghost    = u;
    if (i == 0)
      {
        inertia_factor = 0;
        rate_dt        = time_grid.step(1); // any: u_old = u, no rate
        w_ghost        = 0;
        u_old_ghost    = u;
        return;
      }
    const auto   bdf = time_grid.bdf(i, p.bdf_order);
    const double bdt = bdf.beta * dt;
    Vector_t     w(owned, comm);
    for (unsigned int j = 0; j < bdf.alpha.size(); ++j)
      {
        w.add(bdf.alpha[j], u_states[i - 1 - j]);
        w.add(bdf.alpha[j] * bdt, v_states[i - 1 - j]);
      }
    w_ghost          = w;
    inertia_factor   = 1. / (bdt * bdt);
    const auto level = [&](const unsigned int j) -> const Vector_t & {
      return u_states[i - j];
    };
    rate_dt     = damping_rate_history(i, level, w);
    u_old_ghost = w;
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::damping_rate_history(
    const unsigned int                                   k,
    const std::function<const Vector_t &(unsigned int)> &level,
    Vector_t                                            &u_old) const
  {
    const auto bdf = time_grid.bdf(k, p.bdf_order);
    if (!p.bdf_damping_rate)
      {
        u_old = level(1);
        return time_grid.step(k);
      }
    u_old = 0;
    for (unsigned int j = 1; j <= bdf.alpha.size(); ++j)
      u_old.add(-bdf.alpha[j - 1], level(j));
    return bdf.beta * time_grid.step(k);
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::damping_rate_weight(
    const unsigned int k,
    const unsigned int j) const
  {
    if (!p.bdf_damping_rate)
      return j == 1 ? 1. : 0.;
    const auto bdf = time_grid.bdf(k, p.bdf_order);
    return j <= bdf.alpha.size() ? -bdf.alpha[j - 1] : 0.;
  }



  template <int dim>
  std::vector<std::vector<double>>
  ElasticitySimulator<dim>::Impl::objective_integrals(const Objective<dim> &J,
                                                      const unsigned int    i)
  {
    set_step_state(i);
    // accumulate() with no outputs leaves the integrals in `objective_cache`.
    accumulate(J, nullptr, nullptr, nullptr);
    auto I = objective_cache;
    for (auto &v : I)
      Utilities::MPI::sum(v, comm, v);
    return I;
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::objective_value(const Objective<dim> &J)
  {
    const unsigned int n         = u_states.size() - 1;
    double             value     = 0;
    const bool         is_static = p.problem == "static";
    term_values.assign(J.terms().size(), 0.);
    for (unsigned int i = 0; i <= n; ++i)
      {
        const double sw = is_static ? 1. : J.step_weight(i, time_grid);
        if (sw == 0)
          continue;
        const auto I = objective_integrals(J, i);
        const auto c = contact_force_terms(J, i, sw, nullptr);
        for (unsigned int t = 0; t < J.terms().size(); ++t)
          {
            const double v =
              sw * J.terms()[t]->weight * J.terms()[t]->combine(I[t], nullptr) +
              c[t];
            term_values[t] += v;
            value += v;
          }
      }
    const auto r = regularization(J, false);
    for (unsigned int t = 0; t < r.size(); ++t)
      {
        term_values[t] += r[t];
        value += r[t];
      }
    return value;
  }



  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::Impl::regularization(const Objective<dim> &J,
                                                 const bool with_gradient)
  {
    CellLame *lame = with_gradient ? physical.wanted<CellLame>() : nullptr;
    ShapeField<dim> *g =
      with_gradient && shape_field->wanted ? shape_field : nullptr;
    using R = typename ObjectiveTerm<dim>::Regularization;
    std::vector<double> values(J.terms().size(), 0.);
    for (unsigned int t = 0; t < J.terms().size(); ++t)
      {
        const auto &term = *J.terms()[t];
        double      v    = 0;
        if (term.regularization == R::material_smoothing)
          {
            // eq. 3.44 over ordered pairs (cell, face neighbor), from the
            // owned cell's side; neighbors may be ghosts or finer cells.
            auto pair = [&](const auto &a, const auto &b) {
              const auto &la = cell_lame->value[a->active_cell_index()];
              const auto &lb = cell_lame->value[b->active_cell_index()];
              for (unsigned int k = 0; k < 2; ++k)
                {
                  const double r = 1. - lb[k] / la[k];
                  v += term.weight * r * r;
                  if (lame)
                    {
                      lame->sensitivity[a->active_cell_index()][k] +=
                        term.weight * 2. * r * lb[k] / (la[k] * la[k]);
                      lame->sensitivity[b->active_cell_index()][k] -=
                        term.weight * 2. * r / la[k];
                    }
                }
            };
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned())
                for (const auto f : cell->face_indices())
                  {
                    if (cell->at_boundary(f))
                      continue;
                    if (cell->face(f)->has_children())
                      for (unsigned int c = 0;
                           c < cell->face(f)->n_active_descendants();
                           ++c)
                        pair(cell, cell->neighbor_child_on_subface(f, c));
                    else
                      pair(cell, cell->neighbor(f));
                  }
          }
        else if (term.regularization == R::boundary_smoothing)
          {
            AssertThrow(shape_field->wanted,
                        ExcMessage("Objective/Terms: 'boundary smoothing' "
                                   "needs the shape block in "
                                   "Design/Parameters."));
            // eq. 3.43: boundary vertices and their neighbours along
            // boundary edges, from owned and ghost cells; each vertex is
            // counted by the rank that owns its first coordinate.
            std::map<unsigned int, std::set<unsigned int>> neighbours;
            std::map<unsigned int, std::array<types::global_dof_index, dim>>
              dofs;
            for (const auto &cell : shape_dof_handler.active_cell_iterators())
              if (!cell->is_artificial() && cell->at_boundary())
                for (const auto f : cell->face_indices())
                  {
                    if (!cell->at_boundary(f))
                      continue;
                    const auto face = cell->face(f);
                    for (unsigned int v = 0; v < face->n_vertices(); ++v)
                      for (unsigned int d = 0; d < dim; ++d)
                        dofs[face->vertex_index(v)][d] =
                          face->vertex_dof_index(v, d);
                    if (dim == 2)
                      {
                        neighbours[face->vertex_index(0)].insert(
                          face->vertex_index(1));
                        neighbours[face->vertex_index(1)].insert(
                          face->vertex_index(0));
                      }
                    else
                      for (unsigned int l = 0; l < face->n_lines(); ++l)
                        {
                          const auto line = face->line(l);
                          neighbours[line->vertex_index(0)].insert(
                            line->vertex_index(1));
                          neighbours[line->vertex_index(1)].insert(
                            line->vertex_index(0));
                        }
                  }
            auto position = [&](const unsigned int vertex) {
              Tensor<1, dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x[d] = shape_ghost(dofs.at(vertex)[d]);
              return x;
            };
            const double p_exp = term.exponent;
            for (const auto &[i, ns] : neighbours)
              {
                if (!shape_owned.is_element(dofs.at(i)[0]))
                  continue;
                const Tensor<1, dim> xi = position(i);
                Tensor<1, dim>       A, sum_e;
                double               L = 0;
                for (const auto j : ns)
                  {
                    const Tensor<1, dim> e = xi - position(j);
                    A += e;
                    L += e.norm();
                    sum_e += e / e.norm();
                  }
                const Tensor<1, dim> s_i = A / L;
                const double         s2  = s_i.norm_square();
                v += term.weight * std::pow(s2, 0.5 * p_exp);
                if (!g || s2 == 0)
                  continue;
                // dJ/ds, then ds = dA / L - A dL / L^2.
                const Tensor<1, dim> gs =
                  term.weight * p_exp * std::pow(s2, 0.5 * p_exp - 1) * s_i;
                const double   gA = gs * A / (L * L);
                Tensor<1, dim> gi = double(ns.size()) * gs / L - gA * sum_e;
                std::vector<types::global_dof_index> indices;
                Vector<double> local(dim * (ns.size() + 1));
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    indices.push_back(dofs.at(i)[d]);
                    local(d) = gi[d];
                  }
                for (const auto j : ns)
                  {
                    const Tensor<1, dim> e  = xi - position(j);
                    const Tensor<1, dim> gj = -gs / L + gA * e / e.norm();
                    for (unsigned int d = 0; d < dim; ++d)
                      {
                        local(indices.size()) = gj[d];
                        indices.push_back(dofs.at(j)[d]);
                      }
                  }
                g->add(local, indices);
              }
            if (g)
              g->sensitivity.compress(VectorOperation::add);
          }
        values[t] = Utilities::MPI::sum(v, comm);
      }
    return values;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::add_transport_products(
    const FEValuesBase<dim> &fv,
    const FEValuesBase<dim> &sv,
    const PointAdjoint<dim> &adj,
    Scratch<dim>            &s,
    dealii::Vector<double>  &local_shape) const
  {
    // p^T dh/dx theta of the point terms transported with the domain
    // (eq. 3.24): the forms' integrands are functions of grad u, grad u^{i-1}
    // and u at material points, so only grad u, grad u^{i-1} and JxW move.
    PointTerms<dim> &t = s.terms;
    reset_terms(t, fv.n_quadrature_points, true, true, false);
    for (const auto &f : forms)
      if (form_active(*f) && f->has_cell_terms())
        f->cell_terms(s.states, t);
    AssertThrow(t.admissible,
                ExcMessage("adjoint: a stored state lies outside a form's "
                           "domain (an inverted element)."));
    for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
      {
        const Tensor<2, dim> &G     = adj.G[q];
        const Tensor<2, dim>  H     = contract_left(G, t.flux_tangent[q]);
        const Tensor<2, dim>  H_old = transient ?
                                        contract_left(G, t.flux_tangent_old[q]) :
                                        Tensor<2, dim>();
        Tensor<2, dim>        V     = transport_kernel(H, s.states.grad_u[q]) +
                           transport_kernel(H_old, s.states.grad_u_old[q]) -
                           transpose(G) * t.flux[q];
        const double div_term =
          scalar_product(t.flux[q], G) + t.source[q] * adj.p[q];
        for (unsigned int d = 0; d < dim; ++d)
          V[d][d] += div_term;
        for (unsigned int a = 0; a < local_shape.size(); ++a)
          local_shape(a) +=
            row_dot(V,
                    shape_fe->system_to_component_index(a).first,
                    sv.shape_grad(a, q)) *
            fv.JxW(q);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::global_products(const Vector_t &lambda,
                                                  Vector_t       *lagged)
  {
    Vector_t lambda_ghost(owned, relevant, comm);
    lambda_ghost = lambda;
    u_ghost      = u;
    const typename Form<dim>::GlobalAdjoint a{
      u, u_ghost, lambda, lambda_ghost, constraints_zero, lagged};
    for (const auto &f : forms)
      f->global_products(a, physical);
    if (shape_field->wanted)
      shape_field->sensitivity.compress(VectorOperation::add);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::history_products(
    const Vector_t                  &z,
    const std::vector<Vector_t>     *lambda,
    const unsigned int               i,
    const AffineConstraints<double> &constraints,
    Vector_t                        &result)
  {
    result = 0;
    Vector_t z_ghost(owned, relevant, comm);
    z_ghost = z;
    // The later steps whose damping rate reads u^i: their adjoint, state,
    // rate history and rate step, and the weight of u^i in the rate.
    struct Coupling
    {
      Vector_t lambda, u, u_old;
      double   dt, weight;
    };
    std::vector<Coupling> couplings;
    const unsigned int    n = u_states.size() - 1;
    if (lambda && (form_needs() & Form<dim>::old_gradients))
      for (unsigned int k = i + 1; k <= std::min(n, i + p.bdf_order); ++k)
        {
          const double weight = damping_rate_weight(k, k - i);
          if (weight == 0)
            continue;
          const auto level = [&](const unsigned int j) -> const Vector_t & {
            return u_states[k - j];
          };
          Vector_t u_old(owned, comm);
          Coupling c;
          c.dt     = damping_rate_history(k, level, u_old);
          c.weight = weight;
          for (auto *v : {&c.lambda, &c.u, &c.u_old})
            v->reinit(owned, relevant, comm);
          c.lambda = (*lambda)[k];
          c.u      = u_states[k];
          c.u_old  = u_old;
          couplings.push_back(std::move(c));
        }
    const FEValuesExtractors::Vector     disp(0);
    hp::FEValues<dim>                    hp_fv(mapping,
                            fe,
                            quadrature,
                            update_values | update_gradients |
                              update_JxW_values);
    HistoryStates<dim>                   hs;
    PointTerms<dim>                      t;
    std::vector<types::global_dof_index> dofs;
    Vector<double>                       local;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_fv.reinit(cell);
          const auto        &fv  = hp_fv.get_present_fe_values();
          const auto        &cfe = fv.get_fe();
          const unsigned int n   = cfe.n_dofs_per_cell(),
                             nq  = fv.n_quadrature_points;
          dofs.resize(n);
          cell->get_dof_indices(dofs);
          local.reinit(n);
          hs.cell = {cell->active_cell_index(), cell->material_id(), 0};
          hs.z.resize(nq);
          fv[disp].get_function_values(z_ghost, hs.z);
          hs.JxW.resize(nq);
          for (unsigned int q = 0; q < nq; ++q)
            hs.JxW[q] = fv.JxW(q);
          hs.G_next.clear();
          reset_terms(t, nq, false, false, false);
          for (const auto &f : forms)
            f->history_terms(hs, t); // M z
          // One pass per coupled step, z zero: the forms' terms are linear
          // in G_next, which carries the weight.
          for (const auto &c : couplings)
            {
              std::fill(hs.z.begin(), hs.z.end(), Tensor<1, dim>());
              hs.dt = c.dt;
              hs.grad_u_next.resize(nq);
              hs.grad_u_prev.resize(nq);
              hs.G_next.resize(nq);
              fv[disp].get_function_gradients(c.u, hs.grad_u_next);
              fv[disp].get_function_gradients(c.u_old, hs.grad_u_prev);
              fv[disp].get_function_gradients(c.lambda, hs.G_next);
              for (auto &G : hs.G_next)
                G *= c.weight;
              for (const auto &f : forms)
                f->history_terms(hs, t);
            }
          for (unsigned int q = 0; q < nq; ++q)
            for (unsigned int i = 0; i < n; ++i)
              {
                const unsigned int c = cfe.system_to_component_index(i).first;
                local(i) += (t.source[q][c] * fv.shape_value(i, q) +
                             row_dot(t.flux[q], c, fv.shape_grad(i, q))) *
                            fv.JxW(q);
              }
          constraints.distribute_local_to_global(local, dofs, result);
        }
    result.compress(VectorOperation::add);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::assemble_adjoint_jacobian(
    const unsigned int i,
    const bool         transpose)
  {
    // Forms whose Newton Jacobian is convexified or lagged state depends on
    // the step set up the stored state's; then the exact Jacobian.
    const Vector_t *lagged =
      p.problem == "transient" && i > 0 ? &u_states[i - 1] : nullptr;
    bool rebuild = false;
    for (const auto &f : forms)
      rebuild |= f->prepare_adjoint_step(u, lagged);
    if (rebuild)
      build_jacobian_pattern();
    transpose_matrix      = transpose;
    exact_contact_hessian = true;
    assemble(u, true, nullptr);
    transpose_matrix      = false;
    exact_contact_hessian = false;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_static_adjoint(const Vector_t &rhs,
                                                       Vector_t       &lambda)
  {
    // The Jacobian of the converged Newton step is still assembled; static
    // tangents are symmetric, so it is its own transpose, unless a form's
    // is unsymmetric (friction) or not exact (a convexified contact
    // Hessian).
    bool symmetric = true, exact = true;
    for (const auto &f : forms)
      {
        symmetric &= f->is_symmetric();
        exact &= f->newton_jacobian_is_exact();
      }
    if (symmetric && exact)
      {
        solve_jacobian(lambda, rhs, true);
        return;
      }
    assemble_adjoint_jacobian(0, !symmetric);
    solve_jacobian(lambda, rhs);
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::compute_gradient(const Objective<dim> &J,
                                                   std::vector<double>  &dJ)
  {
    Timer      timer;
    const bool is_static = p.problem == "static";
    physical.clear_sensitivities();

    // dJ/dI of every integral at step i, scaled by the step weight.
    double value           = 0;
    auto   weights_at_step = [&](const unsigned int i) {
      const double sw = is_static ? 1. : J.step_weight(i, time_grid);
      std::vector<std::vector<double>> w;
      const auto                       I = sw != 0 ? objective_integrals(J, i) :
                                                       std::vector<std::vector<double>>();
      for (unsigned int t = 0; t < J.terms().size(); ++t)
        {
          std::vector<double> d(J.terms()[t]->integrals().size(), 0.);
          if (sw != 0)
            {
              value +=
                sw * J.terms()[t]->weight * J.terms()[t]->combine(I[t], &d);
              for (auto &x : d)
                x *= sw * J.terms()[t]->weight;
            }
          w.push_back(d);
        }
      return w;
    };

    Vector_t dJ_du(owned, comm), rhs(owned, comm);
    // The contact force terms' partials at step i.
    auto contact_partials = [&](const unsigned int i) {
      const double sw = is_static ? 1. : J.step_weight(i, time_grid);
      for (const double v : contact_force_terms(J, i, sw, &dJ_du))
        value += v;
    };
    if (is_static)
      {
        const auto w = weights_at_step(0);
        accumulate(J, &w, nullptr, &dJ_du); // objective partials
        contact_partials(0);
        rhs = dJ_du;
        rhs *= -1.;
        Timer    solve_timer;
        Vector_t lambda(owned, comm);
        solve_static_adjoint(rhs, lambda);
        constraints_zero.distribute(lambda);
        adjoint_solve_seconds += solve_timer.wall_time();
        accumulate(J, nullptr, &lambda, nullptr); // p^T d_q h
        global_products(lambda, nullptr);
      }
    else
      transient_adjoint(J, weights_at_step, contact_partials, dJ_du);

    for (const double r : regularization(J, true))
      value += r;
    chain_to_design(dJ);
    adjoint_seconds += timer.wall_time();
    ++gradients;
    return value;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::transient_adjoint(
    const Objective<dim> &J,
    const std::function<std::vector<std::vector<double>>(unsigned int)>
                                            &weights_at_step,
    const std::function<void(unsigned int)> &contact_partials,
    Vector_t                                &dJ_du)
  {
    // Backward BDF sweep (thesis eqs. 3.16-3.22 for u^i alone: the
    // velocities are eliminated through v^i = (u^i + sum_j a_j u^{i-j}) /
    // (beta dt)). lambda_i is the adjoint of the step residual R_i, y_i =
    // mu_i / M the adjoint of the velocity update.
    const unsigned int    n = u_states.size() - 1;
    const unsigned int    m = p.bdf_order;
    std::vector<Vector_t> lambda(n + 2), y(n + 2);
    auto                  beta_dt = [&](const unsigned int k) {
      return time_grid.bdf(k, m).beta * time_grid.step(k);
    };
    auto alpha = [&](const unsigned int k, const unsigned int j) {
      const auto c = time_grid.bdf(k, m);
      return j <= c.alpha.size() ? c.alpha[j - 1] : 0.;
    };
    Vector_t z(owned, comm), products(owned, comm), rhs(owned, comm);
    // (d h_{i+1} / d u^i)^T lambda_{i+1} of lagged forms (IPC friction).
    Vector_t lagged(owned, comm);
    for (unsigned int i = n; i >= 1; --i)
      {
        const double bi = beta_dt(i);
        z               = 0;
        for (unsigned int k = i + 1; k <= std::min(n, i + m); ++k)
          {
            const double a = alpha(k, k - i);
            if (a == 0)
              continue;
            z.add(a / (beta_dt(k) * bi), lambda[k]);
            z.add(a, y[k]);
          }
        const auto w = weights_at_step(i);
        dJ_du        = 0;
        accumulate(J, &w, nullptr, &dJ_du);
        contact_partials(i);
        history_products(z, &lambda, i, constraints_zero, products);
        rhs = dJ_du;
        rhs += products;
        if (i < n)
          rhs += lagged;
        rhs *= -1.;

        // (M / (beta dt)^2 + K_i)^T lambda_i = rhs, at the stored state.
        set_step_state(i);
        make_constraints(time);
        Timer solve_timer;
        assemble_adjoint_jacobian(i, true);
        lambda[i].reinit(owned, comm);
        solve_jacobian(lambda[i], rhs);
        constraints_zero.distribute(lambda[i]);
        adjoint_solve_seconds += solve_timer.wall_time();

        y[i].reinit(owned, comm);
        y[i].add(1. / (bi * bi), lambda[i]);
        for (unsigned int k = i + 1; k <= std::min(n, i + m); ++k)
          {
            const double a = alpha(k, k - i);
            if (a != 0)
              y[i].add(a / (beta_dt(k) * bi), lambda[k]);
          }
        set_step_state(i);
        accumulate(J, nullptr, &lambda[i], nullptr);
        lagged = 0;
        global_products(lambda[i], &lagged);
      }

    // Step 0: the initial conditions (eq. 3.21).
    const auto w = weights_at_step(0);
    dJ_du        = 0;
    accumulate(J, &w, nullptr, &dJ_du);
    contact_partials(0);
    z = 0;
    Vector_t zv(owned, comm);
    for (unsigned int k = 1; k <= std::min(n, m); ++k)
      {
        z.add(alpha(k, k), y[k]);
        zv.add(alpha(k, k) / beta_dt(k), lambda[k]);
      }
    history_products(z, &lambda, 0, constraints_zero, products);
    dJ_du += products;
    if (n > 0)
      dJ_du += lagged;
    // dJ/dv^0 = M zv on every DoF (v^0 is not constrained).
    AffineConstraints<double> none;
    none.close();
    Vector_t dJ_dv(owned, comm);
    history_products(zv, nullptr, 0, none, dJ_dv);
    initial->displacement_sensitivity = dJ_du;
    initial->velocity_sensitivity     = dJ_dv;
    // Forward states (u, v per step) and adjoint states (lambda, y).
    memory_of_states = 0;
    for (unsigned int i = 0; i <= n; ++i)
      memory_of_states +=
        u_states[i].memory_consumption() + v_states[i].memory_consumption() +
        (i > 0 ? lambda[i].memory_consumption() + y[i].memory_consumption() :
                 0);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::update_ipc_geometry(const std::string &where)
  {
    if (!ipc_contact)
      return;
    ipc_contact->setup(
      dof_handler, mapping, owned, comm, &shape_dof_handler, where);
    build_jacobian_pattern(); // the couplings at rest of the new shape
  }



  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::Impl::contact_force_terms(const Objective<dim> &J,
                                                      const unsigned int    i,
                                                      const double          sw,
                                                      Vector_t *dJ_du)
  {
    std::vector<double> values(J.terms().size(), 0.);
    bool                any = false;
    for (const auto &t : J.terms())
      any |= t->contact_force;
    if (!any || sw == 0)
      return values;
    set_step_state(i);
    if (ipc_contact->update_candidates(u, nullptr))
      build_jacobian_pattern();
    for (unsigned int k = 0; k < J.terms().size(); ++k)
      {
        const auto &term = *J.terms()[k];
        if (!term.contact_force)
          continue;
        const Tensor<1, dim> R =
          ipc_contact->barrier_resultant(u, term.contact_bodies);
        const double p = term.exponent, r2 = R.norm_square();
        const double c = sw * term.weight;
        values[k]      = c * std::pow(r2, 0.5 * p);
        if (!dJ_du || r2 == 0)
          continue;
        std::vector<ipc::Vec> rest;
        ipc_contact->barrier_resultant_products(u,
                                                c * p *
                                                  std::pow(r2, 0.5 * p - 1) * R,
                                                term.contact_bodies,
                                                constraints_zero,
                                                *dJ_du,
                                                rest);
        if (shape_field->wanted)
          ipc_form->add_rest_gradient(rest, *shape_field);
      }
    return values;
  }



  // ---------------------------------------------------------------- facade

  template <int dim>
  void
  ElasticitySimulator<dim>::prepare(RunContext *context)
  {
    if (!impl->prepared && impl->ipc_contact)
      {
        const auto &p = impl->p;
        // Static friction is lagged over load steps and friction
        // iterations; the adjoint covers the one lagged at rest.
        AssertThrow(p.problem == "transient" ||
                      !(p.ipc.has_friction() || p.design.has("friction")) ||
                      (p.load_steps == 1 && p.ipc.friction_iterations == 1),
                    ExcMessage(
                      "IPC: static gradients with friction need Time/Load "
                      "steps = 1 and IPC/Friction iterations = 1 (friction "
                      "lagged at rest); use a transient problem for "
                      "friction that follows the motion."));
        AssertThrow(p.adaptivity == "none",
                    ExcMessage("IPC: gradients need Finite element/"
                               "Adaptivity = none."));
        impl->ipc_contact->freeze();
      }
    AssertThrow(impl->p.adaptivity == "none" || impl->p.problem == "static",
                ExcMessage("Finite element/Adaptivity: gradients of a "
                           "transient run whose mesh adapts (an adjoint over "
                           "a sequence of meshes) are not available yet; set "
                           "Adaptivity = none for optimize and verify "
                           "gradient."));
    if (!impl->prepared)
      {
        impl->prepared = true;
        if (impl->p.adaptivity != "none")
          impl->run(context); // adapt the mesh to the starting design
        else
          impl->setup_system();
        impl->build_design_layout();
        impl->apply_design(impl->design);
      }
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::set_objective(
    const std::shared_ptr<const Objective<dim>> &J)
  {
    for (const auto &t : J->terms())
      if (t->contact_force)
        {
          AssertThrow(impl->ipc_contact,
                      ExcMessage("Objective/Terms: 'contact force' measures "
                                 "IPC barrier forces: it needs "
                                 "forma-transient-ipc with IPC/Enabled = "
                                 "true."));
          std::vector<types::material_id> ids;
          for (const auto &cell : impl->tria->active_cell_iterators())
            if (cell->is_locally_owned())
              ids.push_back(cell->material_id());
          ids = Utilities::MPI::compute_set_union(ids, impl->comm);
          for (const auto id : t->contact_bodies)
            AssertThrow(std::find(ids.begin(), ids.end(), id) != ids.end(),
                        ExcMessage("Objective/Terms, term 'contact force': "
                                   "no body has material id " +
                                   std::to_string(id) + "."));
        }
    impl->objective = J;
    impl->reference_states.clear();
    impl->time_grid_frozen = false; // a new objective chooses its levels
    if (!J->needs_reference_run())
      return;
    // The reference run: the mesh as read, with the reference materials.
    const auto saved = impl->design;
    impl->reset_physical_parameters(J->parameters.reference_bodies);
    impl->shape_ghost = impl->material_positions;
    if (impl->shape_field->wanted)
      impl->update_ipc_geometry("the mesh as read");
    if (impl->friction && impl->friction->wanted)
      impl->ipc_contact->set_friction_values(impl->problem_friction);
    impl->solve_forward(true);
    impl->reference_states = impl->u_states;
    // Adaptive steps: the design runs step on the target's levels.
    impl->time_grid_frozen = true;
    if (J->parameters.target_noise > 0)
      {
        // Noise by (step, support point, component): the same for every
        // partition and DoF numbering. A splitmix64 hash gives two
        // uniforms, Box-Muller a normal value.
        const double sigma = J->parameters.target_noise;
        std::map<types::global_dof_index, Point<dim>> support;
        DoFTools::map_dofs_to_support_points(impl->reference_mapping,
                                             impl->dof_handler,
                                             support);
        const auto component = impl->owned_components();
        const auto mix       = [](std::uint64_t z) {
          z += 0x9E3779B97F4A7C15ull;
          z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
          z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
          return z ^ (z >> 31);
        };
        for (unsigned int i = 0; i < impl->reference_states.size(); ++i)
          {
            auto &x = impl->reference_states[i];
            for (const auto k : impl->owned)
              {
                std::uint64_t h = mix(i);
                for (unsigned int d = 0; d < dim; ++d)
                  h = mix(h ^ static_cast<std::uint64_t>(
                                std::llround(support.at(k)[d] * 1e9)));
                h = mix(h ^ component[impl->owned.index_within_set(k)]);
                const double a = 1. - (h >> 11) * 0x1.0p-53; // (0, 1]
                const double b = (mix(h) >> 11) * 0x1.0p-53;
                x(k) += sigma * std::sqrt(-2. * std::log(a)) *
                        std::cos(2. * numbers::PI * b);
              }
            x.compress(VectorOperation::insert);
          }
      }
    impl->apply_design(saved);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::solve_design()
  {
    impl->solve_forward(true);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::freeze_time_steps(const bool freeze)
  {
    // A target trajectory's levels stay frozen.
    impl->time_grid_frozen = freeze || !impl->reference_states.empty();
  }

  template <int dim>
  bool
  ElasticitySimulator<dim>::adaptive_time_steps() const
  {
    return impl->p.problem == "transient" &&
           impl->p.time_integrator == "adaptive";
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::objective() const
  {
    AssertThrow(impl->objective, ExcMessage("no objective set"));
    return impl->objective_value(*impl->objective);
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::gradient(std::vector<double> &dJ) const
  {
    AssertThrow(impl->objective, ExcMessage("no objective set"));
    return impl->compute_gradient(*impl->objective, dJ);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::write_state(const unsigned int index,
                                        RunContext        &context)
  {
    impl->context = &context;
    impl->set_step_state(impl->u_states.size() - 1);
    if (impl->transient)
      impl->v = impl->v_states.back();
    impl->write_output(index, index);
  }

  template <int dim>
  std::vector<std::pair<std::string, double>>
  ElasticitySimulator<dim>::objective_terms() const
  {
    std::vector<std::pair<std::string, double>> r;
    for (unsigned int t = 0; t < impl->term_values.size(); ++t)
      r.emplace_back(impl->objective->terms()[t]->name, impl->term_values[t]);
    return r;
  }

  template void
  ElasticitySimulator<2>::solve_design();
  template void
  ElasticitySimulator<3>::solve_design();
  template void
  ElasticitySimulator<2>::prepare(RunContext *);
  template void
  ElasticitySimulator<3>::prepare(RunContext *);
  template void
  ElasticitySimulator<2>::set_objective(
    const std::shared_ptr<const Objective<2>> &);
  template void
  ElasticitySimulator<3>::set_objective(
    const std::shared_ptr<const Objective<3>> &);
  template void
  ElasticitySimulator<2>::freeze_time_steps(const bool);
  template void
  ElasticitySimulator<3>::freeze_time_steps(const bool);
  template bool
  ElasticitySimulator<2>::adaptive_time_steps() const;
  template bool
  ElasticitySimulator<3>::adaptive_time_steps() const;
  template double
  ElasticitySimulator<2>::objective() const;
  template double
  ElasticitySimulator<3>::objective() const;
  template double
  ElasticitySimulator<2>::gradient(std::vector<double> &) const;
  template double
  ElasticitySimulator<3>::gradient(std::vector<double> &) const;
  template void
  ElasticitySimulator<2>::write_state(const unsigned int, RunContext &);
  template void
  ElasticitySimulator<3>::write_state(const unsigned int, RunContext &);
  template std::vector<std::pair<std::string, double>>
  ElasticitySimulator<2>::objective_terms() const;
  template std::vector<std::pair<std::string, double>>
  ElasticitySimulator<3>::objective_terms() const;
  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
