// Adaptive meshes of the elasticity simulator: the refinement between the
// static cycles, and transient runs whose mesh follows the solution, with
// every BDF history level carried to the new mesh.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_series.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/refinement.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/smoothness_estimator.h>

#include <forma/base/run_context.h>
#include <forma/elasticity/simulator.h>
#include <forma/solvers/matrix_free_elasticity.h>

#include "simulator_impl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace forma
{
  namespace
  {
    /// The distributed mesh that adaptivity refines (throws otherwise).
    template <int dim>
    parallel::distributed::Triangulation<dim> &
    adaptive_mesh(Triangulation<dim> &tria)
    {
      auto *ptria =
        dynamic_cast<parallel::distributed::Triangulation<dim> *>(&tria);
      AssertThrow(ptria != nullptr,
                  ExcMessage("adaptivity needs a quad/hex mesh."));
      return *ptria;
    }
  } // namespace



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::constrain_hanging_nodes(
    std::vector<Vector_t *> vectors) const
  {
    // Not constraints_zero: that would zero Dirichlet values.
    AffineConstraints<double> hanging(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);
    hanging.close();
    for (auto *x : vectors)
      hanging.distribute(*x);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::flag_cells(const Vector<float> &eta,
                                             const double coarsen_fraction)
  {
    auto &mesh = adaptive_mesh(*tria);
    AssertThrow(eta.size() == tria->n_active_cells(), ExcInternalError());
    if (p.marking == "error fraction")
      parallel::distributed::GridRefinement::refine_and_coarsen_fixed_fraction(
        mesh, eta, p.refine_fraction, coarsen_fraction);
    else
      parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
        mesh, eta, p.refine_fraction, coarsen_fraction);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::mark_cells(const bool level_limits)
  {
    auto &mesh = adaptive_mesh(*tria);
    flag_cells(estimated_error, p.coarsen_fraction);
    // Transient runs: within the starting mesh's levels and Max refinement
    // level more, so that a moving front cannot refine without bound.
    if (level_limits)
      for (const auto &cell : mesh.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            if (cell->level() >= static_cast<int>(top_level))
              cell->clear_refine_flag();
            if (cell->level() <= static_cast<int>(base_level))
              cell->clear_coarsen_flag();
          }
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::mesh_will_change() const
  {
    auto &mesh = adaptive_mesh(*tria);
    mesh.prepare_coarsening_and_refinement();
    bool flagged = false;
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->is_locally_owned() &&
          (cell->refine_flag_set() || cell->coarsen_flag_set()))
        flagged = true;
    return Utilities::MPI::logical_or(flagged, comm);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::kelly_indicators()
  {
    estimated_error.reinit(tria->n_active_cells());
    KellyErrorEstimator<dim>::estimate(
      mapping[0],
      dof_handler,
      face_quadrature,
      std::map<types::boundary_id, const Function<dim> *>(),
      u_ghost,
      estimated_error);
    if (contact.active() && p.contact_residual)
      add_contact_residuals(estimated_error);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::refine_mesh()
  {
    u_ghost = u;
    // Error indicator = goal: the indicators of the last solve's estimate.
    if (p.error_indicator != "goal")
      kelly_indicators();
    mark_cells(false);
    if (p.adaptivity == "hp")
      {
        Vector<float>           smoothness(tria->n_active_cells());
        FESeries::Legendre<dim> legendre =
          SmoothnessEstimator::Legendre::default_fe_series(fe);
        SmoothnessEstimator::Legendre::coefficient_decay(legendre,
                                                         dof_handler,
                                                         u_ghost,
                                                         smoothness);
        hp::Refinement::p_adaptivity_from_relative_threshold(dof_handler,
                                                             smoothness,
                                                             0.2,
                                                             0.2);
        // The goal estimate's element one degree up is not for the solve.
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned() && cell->future_fe_index_set() &&
              cell->future_fe_index() + 1 > p.max_degree)
            cell->clear_future_fe_index();
        hp::Refinement::choose_p_over_h(dof_handler);
      }
    tria->execute_coarsening_and_refinement();
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::add_contact_residuals(
    Vector<float> &eta) const
  {
    // The boundary term of the residual estimator on the contact faces,
    // scaled like Kelly's face jumps of grad u (a strain): Kelly counts
    // no boundary face, so without it a coarse cell at the edge of the
    // contact zone, where the traction jumps from 0 to the pressure, is
    // never flagged for what the contact law asks of it.
    // Gauss-Lobatto points hold the face's vertices: a vertex that
    // penetrates the obstacle is seen even where the contact's own Gauss
    // points all miss it (a coarse face on a curved contact).
    const FEValuesExtractors::Vector disp(0);
    hp::QCollection<dim - 1>         rule;
    for (const auto &f : fe)
      rule.push_back(QGaussLobatto<dim - 1>(f.degree + 2));
    hp::FEFaceValues<dim>       hp_fv(mapping,
                                fe,
                                rule,
                                update_values | update_gradients |
                                  update_normal_vectors |
                                  update_quadrature_points | update_JxW_values);
    std::vector<Tensor<1, dim>> values;
    std::vector<Tensor<2, dim>> grads;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          {
            if (!cell->face(f)->at_boundary())
              continue;
            const auto id = cell->face(f)->boundary_id();
            if (!contact.parameters.rigid.count(id))
              continue;
            hp_fv.reinit(cell, f);
            const auto        &fv  = hp_fv.get_present_fe_values();
            const unsigned int nq  = fv.n_quadrature_points;
            const auto         mat = cell_material(cell);
            const double       modulus =
              mat.properties().lambda + 2 * mat.properties().mu;
            values.resize(nq);
            grads.resize(nq);
            fv[disp].get_function_values(u_ghost, values);
            fv[disp].get_function_gradients(u_ghost, grads);
            double integral = 0;
            for (unsigned int q = 0; q < nq; ++q)
              {
                const Tensor<1, dim> &n = fv.normal_vector(q);
                const Tensor<1, dim>  r =
                  mat.cauchy_stress(grads[q]) * n +
                  contact.rigid_traction(id,
                                         fv.quadrature_point(q),
                                         values[q],
                                         n);
                integral += r.norm_square() * fv.JxW(q);
              }
            float &e = eta[cell->active_cell_index()];
            e        = std::sqrt(e * e + cell->diameter() / 24. * integral /
                                    (modulus * modulus));
          }
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::transient_indicators()
  {
    // Kelly's face jumps of grad u (stress) and of grad v (strain rate):
    // the first sees where the body is strained, the second where a wave
    // front passes before it has strained much. Each is taken relative to
    // its global norm, so that neither unit decides.
    std::vector<Vector_t> ghosted(2, Vector_t(owned, relevant, comm));
    ghosted[0] = u;
    ghosted[1] = v;
    std::vector<Vector<float>>    eta(2, Vector<float>(tria->n_active_cells()));
    std::vector<const Vector_t *> in{&ghosted[0], &ghosted[1]};
    std::vector<Vector<float> *>  out{&eta[0], &eta[1]};
    KellyErrorEstimator<dim>::estimate(
      mapping[0],
      dof_handler,
      face_quadrature,
      std::map<types::boundary_id, const Function<dim> *>(),
      in,
      out);
    estimated_error.reinit(tria->n_active_cells());
    bool any = false;
    for (const auto &e : eta)
      {
        double sum = 0; // over owned cells: others hold zeros
        for (const auto &cell : tria->active_cell_iterators())
          if (cell->is_locally_owned())
            sum += std::pow(e[cell->active_cell_index()], 2);
        const double norm = std::sqrt(Utilities::MPI::sum(sum, comm));
        if (norm == 0)
          continue;
        any = true;
        estimated_error.add(1. / norm, e);
      }
    return any;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::start_mesh_adaptation()
  {
    // Levels counted on the starting mesh: cells never coarsen below it.
    unsigned int lowest = std::numeric_limits<unsigned int>::max();
    for (const auto &cell : tria->active_cell_iterators())
      if (cell->is_locally_owned())
        lowest = std::min<unsigned int>(lowest, cell->level());
    base_level       = Utilities::MPI::min(lowest, comm);
    top_level        = tria->n_global_levels() - 1 + p.max_refinement_level;
    mesh_adaptations = 0;
    // Adaptive cycles: the initial state, refined before the first step.
    for (unsigned int c = 0; c < p.adaptive_cycles; ++c)
      {
        interpolate_initial_state();
        constrain_hanging_nodes({&u, &v});
        if (!transient_indicators())
          break;
        mark_cells(true);
        if (!mesh_will_change())
          break;
        tria->execute_coarsening_and_refinement();
        setup_mesh_dependents();
        if (context)
          context->print("[initial state] mesh refined: " +
                         std::to_string(tria->n_global_active_cells()) +
                         " cells, " + std::to_string(dof_handler.n_dofs()) +
                         " DoFs");
      }
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::adapts_after(const unsigned int i) const
  {
    return transient_adaptivity && i % p.adapt_every == 0 && !last_step(i);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::adapt_mesh_in_time(const unsigned int i)
  {
    AssertThrow(!store_states,
                ExcMessage("a transient run whose mesh adapts cannot store "
                           "its states for an adjoint (gradients over a "
                           "sequence of meshes are not available yet); set "
                           "Finite element/Adaptivity = none."));
    if (!transient_indicators())
      return;
    mark_cells(true);
    if (!mesh_will_change())
      return;

    // Every history level (u^{i-j}, v^{i-j}) moves to the new mesh; the
    // newest level is u, v themselves.
    const unsigned int    levels = u_history.size();
    std::vector<Vector_t> old(2 * levels, Vector_t(owned, relevant, comm));
    std::vector<const Vector_t *> in;
    for (unsigned int j = 0; j < levels; ++j)
      {
        old[j]          = u_history[j];
        old[levels + j] = v_history[j];
      }
    for (const auto &x : old)
      in.push_back(&x);
    parallel::distributed::SolutionTransfer<dim, Vector_t> transfer(
      dof_handler);
    transfer.prepare_for_coarsening_and_refinement(in);
    tria->execute_coarsening_and_refinement();
    setup_mesh_dependents();

    std::vector<Vector_t>   moved(2 * levels, Vector_t(owned, comm));
    std::vector<Vector_t *> out;
    for (auto &x : moved)
      out.push_back(&x);
    transfer.interpolate(out);
    // Hanging DoFs take their masters' values. A new Dirichlet DoF of
    // u^{i-j} takes g(t_{i-j}) itself, not the old mesh's interpolant of it:
    // the next velocity divides the difference by the step.
    std::vector<Vector_t *> velocities;
    for (unsigned int j = 0; j < levels; ++j)
      {
        make_constraints(time_grid.time(i - j));
        constraints_bc.distribute(moved[j]);
        velocities.push_back(&moved[levels + j]);
      }
    constrain_hanging_nodes(velocities); // one set of constraints for all
    for (unsigned int j = 0; j < levels; ++j)
      {
        u_history[j] = moved[j];
        v_history[j] = moved[levels + j];
      }
    make_constraints(time);
    u = u_history[0];
    v = v_history[0];
    ++mesh_adaptations;
    if (context && !quiet)
      context->print(
        "[step " + std::to_string(i) +
        "] mesh adapted: " + std::to_string(tria->n_global_active_cells()) +
        " cells, " + std::to_string(dof_handler.n_dofs()) + " DoFs");
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::setup_mesh_dependents()
  {
    // Factorizations and preconditioners of the old matrices are useless.
    linear_solver = LinearSolver(p.linear_solver);
    setup_system();
    if (matrix_free) // its own DoF handlers hold the old mesh too
      matrix_free =
        std::make_unique<MatrixFreeElasticity<dim>>(p.linear_solver);
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
