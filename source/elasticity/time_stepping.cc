// Static load stepping and BDF time stepping of the elasticity simulator.

#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
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
#include <forma/solvers/linear_solver.h>

#include "simulator_impl.h"

#include <cmath>
#include <deque>
#include <fstream>
#include <iomanip>
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
    transient = true;
    const unsigned int n =
      std::max(1, static_cast<int>(std::round(p.end_time / p.time_step)));
    dt = p.end_time / n;
    const std::vector<bool> all(dim, true);

    // Initial state.
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
    make_constraints(0.);
    constraints_zero.distribute(u); // hanging nodes only matter here
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
        print_progress("[step 0/" + std::to_string(n) + "] t = 0");
      }

    u_history.clear();
    v_history.clear();
    u_history.push_front(u);
    v_history.push_front(v);
    const Vector_t u0 = u;
    step_timer.restart();
    for (unsigned int i = 1; i <= n; ++i)
      {
        const double t   = i * dt;
        const auto   bdf = bdf_coefficients_at_step(p.bdf_order, i);
        const double bdt = bdf.beta * dt;
        Vector_t     w(owned, comm);
        for (unsigned int j = 0; j < bdf.alpha.size(); ++j)
          {
            w.add(bdf.alpha[j], u_history[j]);
            w.add(bdf.alpha[j] * bdt, v_history[j]);
          }
        w_ghost        = w;
        u_old_ghost    = u_history[0];
        inertia_factor = 1. / (bdt * bdt);

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

        u_history.push_front(u);
        v_history.push_front(v);
        if (u_history.size() > p.bdf_order)
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
          continue;
        const std::string contacts = ipc_progress();
        record_step(i, t, its.first, its.second);
        if (i % p.output_every == 0 || i == n)
          write_output(i, t);
        print_progress("[step " + std::to_string(i) + "/" + std::to_string(n) +
                       "] t = " + fmt(t) + ", Newton iterations: " +
                       std::to_string(its.first) + contacts);
      }
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
