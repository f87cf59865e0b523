// Static load stepping and BDF time stepping of the elasticity simulator.

#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/hp/fe_collection.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/hp/q_collection.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/simulator.h>
#include <forma/physics/bdf.h>
#include <forma/physics/material.h>
#include <forma/physics/time_grid.h>
#include <forma/solvers/linear_solver.h>

#include "simulator_impl.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <fstream>
#include <iomanip>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>

namespace forma
{
  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_static()
  {
    // Contact (and friction) may hold a body without supports; if it does
    // not, Newton's method says so.
    AssertThrow(!dirichlet.empty() || contact.active() || ipc_contact,
                ExcMessage(
                  "a static problem needs Dirichlet conditions "
                  "(Boundary conditions/Dirichlet) or contact to remove "
                  "rigid-body motions."));
    transient                  = false;
    u                          = 0;
    const bool lagged_friction = ipc_friction();
    step_timer.restart();
    for (unsigned int k = 1; k <= p.load_steps; ++k)
      {
        const double      t = p.end_time * k / p.load_steps;
        const std::string where =
          "load step " + std::to_string(k) + "/" + std::to_string(p.load_steps);
        prepare_ipc_stiffness();
        // IPC friction: normal forces and tangents lagged from the last
        // solve, slip measured from the previous load step.
        const Vector_t                        start = u;
        std::pair<unsigned int, unsigned int> its{0, 0};
        for (unsigned int l = 0;
             l < (lagged_friction ? p.ipc.friction_iterations : 1);
             ++l)
          {
            if (lagged_friction)
              ipc_contact->update_friction(u, start, ipc_friction_eta());
            const auto i = newton(t, where);
            its.first += i.first;
            its.second += i.second;
          }
        if (quiet)
          continue;
        const std::string contacts = ipc_progress();
        record_step(k, t, its.first, its.second);
        print_progress("[" + where + "] t = " + fmt(t) +
                       ", Newton iterations: " + std::to_string(its.first) +
                       contacts);
      }
    if (store_states)
      u_states.assign(1, u);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_transient()
  {
    transient            = true;
    const bool keep_grid = time_grid_frozen && !time_grid.empty() &&
                           time_grid.time(time_grid.n_steps()) == p.end_time;
    const bool adaptive = p.time_integrator == "adaptive" && !keep_grid;
    if (!adaptive && !keep_grid)
      time_grid = TimeGrid::uniform(
        p.end_time,
        std::max(1, static_cast<int>(std::round(p.end_time / p.time_step))));
    transient_adaptivity = p.adaptivity == "h";
    if (transient_adaptivity)
      start_mesh_adaptation();
    set_initial_state(adaptive ? "" : std::to_string(time_grid.n_steps()));

    rejected_steps = 0;
    if (adaptive)
      solve_adaptive();
    else
      for (unsigned int i = 1; i <= time_grid.n_steps(); ++i)
        {
          accept_step(i, take_step(i));
          if (adapts_after(i))
            adapt_mesh_in_time(i);
        }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::interpolate_initial_state()
  {
    const std::vector<bool> all(dim, true);
    u = 0;
    v = 0;
    if (!p.initial_displacement.empty())
      VectorTools::interpolate(
        reference_mapping,
        dof_handler,
        *make_function<dim>(split_top_level(p.initial_displacement, ','),
                            all,
                            constants,
                            "Initial conditions/Displacement"),
        u);
    if (!p.initial_velocity.empty())
      VectorTools::interpolate(
        reference_mapping,
        dof_handler,
        *make_function<dim>(split_top_level(p.initial_velocity, ','),
                            all,
                            constants,
                            "Initial conditions/Velocity"),
        v);
    // Design offsets (initial-condition parameterizations).
    u += initial->displacement;
    v += initial->velocity;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::set_initial_state(const std::string &n)
  {
    interpolate_initial_state();
    make_constraints(0.);
    constraints_zero.distribute(u); // hanging nodes only matter here
    if (transient_adaptivity) // Adaptive cycles may have left hanging nodes
      constrain_hanging_nodes({&v});
    time = 0;
    if (ipc_contact && u.linfty_norm() > 0)
      ipc_contact->check_state(u, "Initial conditions/Displacement", false);
    if (store_states)
      {
        u_states.assign(1, u);
        v_states.assign(1, v);
      }
    if (!quiet)
      {
        record_step(0, 0., 0, 0);
        write_output(0, 0.);
        print_progress("[step 0" + (n.empty() ? "" : "/" + n) + "] t = 0");
      }
    u_history.clear();
    v_history.clear();
    u_history.push_front(u);
    v_history.push_front(v);
    step_timer.restart();
  }



  template <int dim>
  std::pair<unsigned int, unsigned int>
  ElasticitySimulator<dim>::Impl::take_step(const unsigned int i)
  {
    const double t   = time_grid.time(i);
    dt               = time_grid.step(i);
    const auto   bdf = time_grid.bdf(i, p.bdf_order);
    const double bdt = bdf.beta * dt;
    Vector_t     w(owned, comm);
    for (unsigned int j = 0; j < bdf.alpha.size(); ++j)
      {
        w.add(bdf.alpha[j], u_history[j]);
        w.add(bdf.alpha[j] * bdt, v_history[j]);
      }
    w_ghost          = w;
    inertia_factor   = 1. / (bdt * bdt);
    const auto level = [&](const unsigned int j) -> const Vector_t & {
      return u_history[j - 1]; // u^{i-j}
    };
    rate_dt     = damping_rate_history(i, level, w);
    u_old_ghost = w;

    // Predictor: the previous displacement advanced by its velocity;
    // with IPC the previous state (the predictor may cross a contact;
    // Newton's CCD-filtered steps then move from a contact-free state).
    u = u_history[0];
    if (ipc_contact)
      {
        prepare_ipc_stiffness();
        if (ipc_friction())
          ipc_contact->update_friction(u_history[0],
                                       u_history[0],
                                       ipc_friction_eta());
      }
    else
      u.add(dt, v_history[0]);
    const std::string where = "time step " + std::to_string(i);
    std::pair<unsigned int, unsigned int> its;
    try
      {
        its = newton(t, where);
      }
    catch (...)
      {
        // The predictor may invert elements; restart from u^{i-1}
        // (IPC steps start there already).
        if (ipc_contact)
          throw;
        u   = u_history[0];
        its = newton(t, where);
      }

    // v^i = (u^i + sum_j alpha_j u^{i-j}) / (beta dt)
    v = u;
    for (unsigned int j = 0; j < bdf.alpha.size(); ++j)
      v.add(bdf.alpha[j], u_history[j]);
    v *= 1. / bdt;
    return its;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::accept_step(
    const unsigned int                           i,
    const std::pair<unsigned int, unsigned int> &its)
  {
    u_history.push_front(u);
    v_history.push_front(v);
    // Adaptive steps keep two more levels for the error estimates (the
    // next order's needs q + 2).
    const unsigned int keep =
      p.bdf_order + (p.time_integrator == "adaptive" ? 2 : 0);
    while (u_history.size() > keep)
      {
        u_history.pop_back();
        v_history.pop_back();
      }
    if (store_states)
      {
        u_states.push_back(u);
        v_states.push_back(v);
      }
    if (quiet)
      return;
    const double      t        = time_grid.time(i);
    const std::string contacts = ipc_progress();
    record_step(i, t, its.first, its.second);
    if (i % p.output_every == 0 || last_step(i))
      write_output(i, t);
    const std::string count =
      time_grid.is_uniform() ? "/" + std::to_string(time_grid.n_steps()) : "";
    print_progress(
      "[step " + std::to_string(i) + count + "] t = " + fmt(t) +
      (time_grid.is_uniform() ? "" : ", dt = " + fmt(dt)) +
      (p.variable_order ?
         ", BDF" + std::to_string(time_grid.order(i, p.bdf_order)) :
         "") +
      ", Newton iterations: " + std::to_string(its.first) + contacts);
  }


  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::last_step(const unsigned int i) const
  {
    // Adaptive grids end where they land on End time; uniform ones with
    // their last step (whose time may round below End time).
    return i == time_grid.n_steps() &&
           (time_grid.is_uniform() || time_grid.time(i) == p.end_time);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_adaptive()
  {
    // Error-controlled variable-step BDF (thesis eq. 3.12 with the
    // variable-step coefficients of TimeGrid): a step is accepted when its
    // estimated local error is within the tolerance; the next step size
    // follows from the error as h (0.9 / err)^(1/(q+1)), limited to
    // [h/5, 2h] after an acceptance and [h/10, h/2] after a rejection.
    // Variable order (as IDA): after q + 1 steps at order q, the next
    // order is the one among q - 1, q, q + 1 allowing the longest step;
    // two rejections in a row lower it.
    const double end = p.end_time;
    const double h_min =
      p.minimum_time_step > 0 ? p.minimum_time_step : 1e-10 * end;
    const double h_max =
      std::max(h_min, p.maximum_time_step > 0 ? p.maximum_time_step : end);
    double h           = std::clamp(p.time_step, h_min, h_max);
    time_grid          = TimeGrid::variable();
    u_scale            = u.linfty_norm();
    absolute_tolerance = p.absolute_time_tolerance;
    if (absolute_tolerance == 0)
      {
        // Tolerance times 1% of the body's size: a run from rest has no
        // displacement to be relative to.
        // The vertices of every rank's triangulation (the coarse mesh
        // included) span the body; the max keeps ranks bit-identical.
        const auto box      = GridTools::compute_bounding_box(*tria);
        double     diagonal = 0;
        for (unsigned int d = 0; d < dim; ++d)
          diagonal += std::pow(Utilities::MPI::max(box.upper_bound(d), comm) -
                                 Utilities::MPI::min(box.lower_bound(d), comm),
                               2);
        absolute_tolerance = 1e-2 * p.time_tolerance * std::sqrt(diagonal);
      }
    unsigned int order      = p.variable_order ? 1 : p.bdf_order;
    unsigned int same_order = 0, failures = 0;
    for (unsigned int i = 1; time_grid.time(i - 1) < end; ++i)
      {
        const double t0 = time_grid.time(i - 1);
        while (true)
          {
            h = cap_step_by_contact(h, h_min);
            // Land on the end time instead of leaving a sliver.
            const double step =
              t0 + 1.1 * h >= end && end - t0 <= h_max ? end - t0 : h;
            time_grid.push(step == end - t0 ? end : t0 + step, order);
            // A rejected attempt's residual must not loosen later Newton
            // tolerances (force_scale is the largest one seen).
            const double                          scale = force_scale;
            std::pair<unsigned int, unsigned int> its;
            double                                err = 0;
            try
              {
                its = take_step(i);
                err = local_error(i, time_grid.order(i, order), true);
              }
            catch (const std::exception &)
              {
                if (step <= h_min)
                  {
                    time_grid.pop();
                    throw;
                  }
                err = std::numeric_limits<double>::infinity();
              }
            const unsigned int q      = time_grid.order(i, order);
            double             factor = 0.9 * std::pow(err, -1. / (q + 1));
            if (err <= 1 || step <= h_min)
              {
                u_scale  = std::max(u_scale, u.linfty_norm());
                failures = 0;
                if (p.variable_order && ++same_order > q)
                  {
                    const auto next = next_order(i, q, err);
                    if (next.first != q)
                      same_order = 0;
                    order  = next.first;
                    factor = next.second;
                  }
                accept_step(i, its);
                // Variable-step BDF3-5 are zero-stable only for bounded step
                // ratios (BDF2: below 1 + sqrt 2): the higher the order the
                // slower the growth.
                constexpr std::array<double, 6> growth{
                  {2., 2., 2., 1.5, 1.25, 1.15}};
                h =
                  std::clamp(step * std::clamp(factor,
                                               0.2,
                                               growth[std::min(i + 1, order)]),
                             h_min,
                             h_max);
                break;
              }
            time_grid.pop();
            force_scale = scale;
            ++rejected_steps;
            if (p.variable_order && ++failures >= 2 && q > 1)
              {
                order      = q - 1;
                same_order = 0;
              }
            h = std::max(h_min, step * std::clamp(factor, 0.1, 0.5));
          }
        if (adapts_after(i))
          adapt_mesh_in_time(i);
      }
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::local_error(const unsigned int i,
                                              const unsigned int q,
                                              const bool own_order) const
  {
    // Milne's device: BDF-q's local error is E = beta h_i pi_q K, with
    // pi_q = prod_{j=1..q} (t_i - t_{i-j}) and K = u^(q+1) / (q+1)!, and the
    // degree-q extrapolation P of the earlier levels misses by u - P =
    // span pi_q K. When u^i was computed with order q it carries E itself,
    // so u^i - P = (beta h_i + span) pi_q K; another order's error is read
    // off the same difference without it (u^i's error is of higher order
    // for q - 1; for q + 1 the estimate is pessimistic, as in DASSL).
    const auto P = time_grid.extrapolation(i, q);
    Vector_t   e(u);
    for (unsigned int j = 1; j <= P.u.size(); ++j)
      e.add(-P.u[j - 1], u_history[j - 1]);
    if (P.v0 != 0)
      e.add(-P.v0, v_history[i - 1]); // Hermite: the exact v^0
    const double bh = time_grid.coefficients(i, q).beta * time_grid.step(i);
    const double c  = bh / ((own_order ? bh : 0.) + P.span);
    // Relative to the largest displacement so far, not the present one:
    // an oscillation's zero crossings would otherwise ask for tiny steps.
    const double scale = absolute_tolerance +
                         p.time_tolerance * std::max(u_scale, u.linfty_norm());
    // Prescribed values are exact: kinks in a prescribed motion must not
    // drive the step down.
    constraints_zero.set_zero(e);
    return c * e.linfty_norm() / scale;
  }



  template <int dim>
  std::pair<unsigned int, double>
  ElasticitySimulator<dim>::Impl::next_order(const unsigned int i,
                                             const unsigned int q,
                                             const double       err) const
  {
    // The order whose estimated error allows the longest next step, among
    // q - 1, q, q + 1 (the step ratio is (1 / err)^(1/(order+1))).
    unsigned int best       = q;
    double       best_ratio = std::pow(err, -1. / (q + 1));
    const auto   consider   = [&](const unsigned int r) {
      const double ratio = std::pow(local_error(i, r, false), -1. / (r + 1));
      if (ratio > best_ratio)
        {
          best       = r;
          best_ratio = ratio;
        }
    };
    if (q > 1)
      consider(q - 1);
    if (q < p.bdf_order && q + 1 <= i)
      consider(q + 1);
    return {best, 0.9 * best_ratio};
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::cap_step_by_contact(const double h,
                                                      const double h_min)
  {
    // IPC: no longer than the free flight from the last state takes to the
    // first contact (the CCD bound), so that a step cannot jump through an
    // impact its error estimate would not see.
    if (!ipc_contact)
      return h;
    Vector_t du(v_history[0]);
    du *= h;
    // The candidate pairs along the whole flight, not just the last step's.
    if (ipc_contact->update_candidates(u_history[0], &du))
      build_jacobian_pattern();
    const double f = ipc_contact->max_step(u_history[0], du);
    return f < 1 ? std::max(h_min, f * h) : h;
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
