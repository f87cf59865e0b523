// The Newton solver of a load or time step: line search on the potential
// energy or the residual, CCD-filtered steps with IPC contact, the barrier
// stiffness.

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

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/simulator.h>
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
  ElasticitySimulator<dim>::Impl::update_form_states(const Vector_t &state,
                                                     const Vector_t *step)
  {
    bool rebuild = false;
    for (const auto &f : forms)
      rebuild |= f->update_state(state, step);
    if (rebuild)
      build_jacobian_pattern();
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::forms_max_step(const Vector_t &state,
                                                 const Vector_t &step,
                                                 const double    gap)
  {
    double s = 1.;
    for (const auto &f : forms)
      s = std::min(s, f->max_step(state, step, gap));
    return s;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::apply_prescribed_motion(
    const double       t,
    const std::string &where)
  {
    const Vector_t before = u;
    constraints_bc.distribute(u);
    // Prescribed boundary motion is not filtered by a form's step bound
    // (the IPC barrier): it must not carry a boundary into (or through)
    // another.
    Vector_t jump = u;
    jump -= before;
    if (jump.linfty_norm() > 0)
      {
        update_form_states(before, &jump);
        const double s = forms_max_step(before, jump, 1e-3);
        AssertThrow(s >= 1.,
                    ExcMessage(where + " (t = " + fmt(t) +
                               "): the prescribed displacements (Dirichlet) of "
                               "this step carry a boundary into contact (CCD "
                               "stops them at " +
                               fmt(s, 3) +
                               " of the step); use more load steps or a "
                               "smaller time step, or let contact move those "
                               "parts."));
      }
    update_form_states(u, nullptr);
  }



  template <int dim>
  std::optional<double>
  ElasticitySimulator<dim>::Impl::line_search(const Vector_t &du,
                                              const double    max_step,
                                              const double    tolerance,
                                              double         &norm)
  {
    // Static problems are minimizations of the potential energy: its
    // Armijo condition accepts the long Newton steps that a residual
    // norm merit would cut (large rotations). Where the energy change
    // is at round-off level, or with inertia/damping, the residual
    // norm decides.
    const double energy0 = potential_energy;
    const double slope   = residual * du;
    // Friction is not a potential force: there only the residual
    // decides.
    const bool energy_merit =
      potential_merit() &&
      std::all_of(forms.begin(),
                  forms.end(),
                  [](const auto &f) { return f->is_potential(); }) &&
      slope < -1e-10 * (std::abs(energy0) + 1e-300);

    Vector_t trial(owned, comm);
    double   step = max_step;
    for (unsigned int h = 0; h <= p.max_line_search_halvings; ++h, step *= 0.5)
      {
        if (h > 0 && norm <= 1e-8 * force_scale)
          break; // round-off level: shorter steps will not help
        trial = u;
        trial.add(step, du);
        if (!assemble(trial, true, nullptr))
          continue; // inverted: shorter step
        const double trial_norm = residual.l2_norm();
        // IPC: the merit's damping term matches the damping force only
        // up to O(dF^2), and near convergence energy changes sink into
        // round-off: there a residual decrease with the energy level
        // kept also accepts a step (CCD has made it contact-free).
        const bool residual_fallback =
          ipc_contact && trial_norm < (1. - 1e-4 * step) * norm &&
          potential_energy <= energy0 + 1e-8 * std::abs(energy0);
        if (trial_norm <= tolerance ||
            (energy_merit ? potential_energy <= energy0 + 1e-4 * step * slope ||
                              residual_fallback :
                            trial_norm < (1. - 1e-4 * step) * norm))
          {
            u    = trial;
            norm = trial_norm;
            return step;
          }
      }
    return {};
  }



  template <int dim>
  unsigned int
  ElasticitySimulator<dim>::Impl::solve_jacobian(Vector_t       &x,
                                                 const Vector_t &b,
                                                 const bool      reuse)
  {
    if (!matrix_free)
      return reuse ? linear_solver.solve_reusing(jacobian, x, b) :
                     linear_solver.solve(jacobian, x, b, solve_degree() > 1);
    AssertThrow(!Utilities::MPI::logical_or(face_tangent_missed.load(), comm),
                ExcMessage("Solver/Linear solver = cg-mg: a boundary load "
                           "depends on the displacement (its tangent lives on "
                           "faces, which the matrix-free operator does not "
                           "apply); use cg-amg or direct."));
    return matrix_free->solve(x, b);
  }



  template <int dim>
  std::pair<unsigned int, unsigned int>
  ElasticitySimulator<dim>::Impl::newton(const double       t,
                                         const std::string &where)
  {
    time = t;
    make_constraints(t);
    apply_prescribed_motion(t, where);
    if (matrix_free) // the mesh, its mapping or the constraints may be new
      matrix_free->reinit(mapping[0], dof_handler, constraints_zero, p.degree);

    AssertThrow(assemble(u, true, nullptr),
                ExcMessage(where + " (t = " + fmt(t) +
                           "): the initial guess "
                           "inverts an element (det F <= 0)" +
                           (ipc_contact ? std::string(" or touches a contact") :
                                          std::string()) +
                           "; use more load "
                           "steps or a smaller time step."));
    double norm = residual.l2_norm();
    force_scale = std::max(force_scale, norm);
    const double tolerance =
      std::max(p.newton_absolute_tolerance,
               p.newton_relative_tolerance * force_scale);

    // Without an equilibrium Newton fails one of two ways; with contact
    // the likely cause is the model, not the step.
    const std::string contact_hint =
      contact.active() ? " With contact: check that the contacts and supports "
                         "can hold the load (friction mu above the "
                         "tangential-to-normal load ratio, no part held by "
                         "contact alone pulled away)." :
                         "";
    unsigned int linear_its = 0;
    Vector_t     du(owned, comm);
    // IPC: a full Newton step shorter than this is convergence (the
    // Newton decrement of Li et al. 2020, in the max norm).
    // Design runs (gradients) need the residual criterion alone.
    const double step_tolerance = ipc_contact && !prepared ?
                                    p.ipc.newton_step_tolerance *
                                      ipc_contact->mesh().diagonal() *
                                      (transient ? dt : 1.) :
                                    0.;
    for (unsigned int it = 0; it < p.max_newton_iterations; ++it)
      {
        if (norm <= tolerance)
          return {it, linear_its};
        Vector_t rhs = residual;
        rhs *= -1.;
        du = 0;
        Timer timer;
        linear_its += solve_jacobian(du, rhs);
        solver_seconds += timer.wall_time();
        constraints_zero.distribute(du);

        if (ipc_contact && du.linfty_norm() <= step_tolerance)
          {
            if (context)
              context->log("    Newton step below the step tolerance, "
                           "residual " +
                           fmt(norm, 3));
            return {it, linear_its};
          }
        // No step may bring a pair into contact (IPC: CCD along the step).
        update_form_states(u, &du);
        const double max_step = forms_max_step(u, du, 0.);
        if (max_step < 1.)
          ++ccd_limited_steps;

        const std::optional<double> step =
          line_search(du, max_step, tolerance, norm);
        const bool accepted = step.has_value();
        // Below 1e-8 of the force scale the residual is at the round-off
        // level of tight tolerances (gradient checks): stagnation there is
        // convergence, the state left as the last accepted one.
        if (!accepted && norm <= 1e-8 * force_scale)
          {
            assemble(u, true, nullptr);
            if (context)
              context->log(
                "    Newton stagnated at round-off level, residual " +
                fmt(norm, 3));
            return {it + 1, linear_its};
          }
        AssertThrow(accepted,
                    ExcMessage(where + " (t = " + fmt(t) +
                               "): the Newton line "
                               "search found no step that reduces the residual "
                               "(norm " +
                               fmt(norm, 3) +
                               ") without inverting an "
                               "element; use more load steps or a smaller time "
                               "step." +
                               contact_hint));
        if (ipc_contact && ipc_contact->update_stiffness())
          {
            // A stiffer barrier: the state's residual and merit change.
            assemble(u, true, nullptr);
            norm = residual.l2_norm();
            if (context)
              context->log("    barrier stiffness raised to " +
                           fmt(ipc_contact->barrier_stiffness(), 4));
          }
        if (context)
          context->log("    Newton " + std::to_string(it + 1) + ": residual " +
                       fmt(norm, 3) + ", step " + fmt(*step, 3));
      }
    // A tolerance below round-off (gradient checks ask for 1e-12) is met
    // as well as the arithmetic allows.
    if (norm > tolerance && norm <= 1e-8 * force_scale)
      {
        if (context)
          context->log("    Newton stopped at round-off level, residual " +
                       fmt(norm, 3));
        return {p.max_newton_iterations, linear_its};
      }
    AssertThrow(norm <= tolerance,
                ExcMessage(
                  where + " (t = " + fmt(t) +
                  "): Newton's method did "
                  "not converge in " +
                  std::to_string(p.max_newton_iterations) +
                  " iterations: residual norm " + fmt(norm, 3) +
                  ", tolerance " + fmt(tolerance, 3) +
                  ". Use more load steps, a smaller time step or raise "
                  "'Max Newton iterations'." +
                  contact_hint));
    return {p.max_newton_iterations, linear_its};
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::prepare_ipc_stiffness()
  {
    if (!ipc_contact || ipc_contact->barrier_stiffness() > 0)
      return;
    // The automatic barrier stiffness follows the stiffness of the rest of
    // the system: the mean diagonal of its Jacobian at the current state.
    if (ipc_contact->update_candidates(u, nullptr))
      build_jacobian_pattern();
    assemble(u, true, nullptr);
    double sum = 0;
    for (const auto i : owned)
      sum += std::abs(jacobian.diag_element(i));
    ipc_contact->set_stiffness_scale(Utilities::MPI::sum(sum, comm) /
                                     dof_handler.n_dofs());
    if (context)
      context->log(
        "IPC: barrier distance " + fmt(ipc_contact->barrier_distance(), 4) +
        ", barrier stiffness " + fmt(ipc_contact->barrier_stiffness(), 4));
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::ipc_friction_eta() const
  {
    return p.ipc.friction_velocity *
           (p.problem == "static" ? p.end_time / p.load_steps : dt);
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::ipc_friction() const
  {
    return ipc_contact && ipc_contact->has_friction();
  }



  template <int dim>
  std::string
  ElasticitySimulator<dim>::Impl::ipc_progress()
  {
    if (!ipc_contact)
      return "";
    const auto st    = ipc_contact->last_state(comm);
    run_min_distance = std::min(run_min_distance, st.first);
    last_ipc_step    = {{"active_pairs", st.second},
                        {"barrier_stiffness", ipc_contact->barrier_stiffness()},
                        {"ccd_limited_steps", ccd_limited_steps}};
    last_ipc_step["obstacle_force"] =
      to_json(ipc_contact->obstacle_reaction(comm));
    last_ipc_step["min_distance"] =
      st.first < std::numeric_limits<double>::max() ? nlohmann::json(st.first) :
                                                      nlohmann::json();
    ccd_limited_steps = 0;
    // Wall time of the step and its parts (this rank; machine dependent,
    // so in summary.json only).
    const nlohmann::json now = ipc_contact->timings();
    nlohmann::json       seconds;
    seconds["step"] = step_timer.wall_time();
    for (const auto &k :
         {"broad_phase_seconds", "ccd_seconds", "contact_assembly_seconds"})
      seconds[std::string(k).substr(0, std::string(k).size() - 8)] =
        double(now[k]) -
        (last_timings.is_null() ? 0. : double(last_timings[k]));
    seconds["assembly"]      = assembly_seconds - last_assembly_seconds;
    seconds["linear_solver"] = solver_seconds - last_solver_seconds;
    last_ipc_step["seconds"] = seconds;
    last_ipc_step["ccd_share"] =
      double(seconds["step"]) > 0 ?
        double(seconds["ccd"]) / double(seconds["step"]) :
        0.;
    last_timings          = now;
    last_assembly_seconds = assembly_seconds;
    last_solver_seconds   = solver_seconds;
    step_timer.restart();
    return ", contacts " + std::to_string(st.second) +
           (st.second > 0 ? ", min distance " + fmt(st.first, 3) : "");
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
