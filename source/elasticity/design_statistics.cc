// Statistics of the elasticity simulator's last solved state and design:
// stresses, volume, offsets, cell centers, adjoint timings.

#include <deal.II/base/timer.h>
#include <deal.II/grid/grid_tools.h>

#include "simulator_impl.h"

namespace forma
{
  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::for_each_stress(
    const std::function<
      void(const typename DoFHandler<dim>::active_cell_iterator &,
           const Tensor<2, dim> &,
           double)> &f)
  {
    set_step_state(u_states.size() - 1);
    hp::FEValues<dim>           hp_fv(mapping,
                            fe,
                            quadrature,
                            update_gradients | update_JxW_values);
    std::vector<Tensor<2, dim>> grads;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_fv.reinit(cell);
          const auto &fv = hp_fv.get_present_fe_values();
          grads.resize(fv.n_quadrature_points);
          fv[FEValuesExtractors::Vector(0)].get_function_gradients(u_ghost,
                                                                   grads);
          const Material<dim> mat = cell_material(cell);
          for (unsigned int q = 0; q < grads.size(); ++q)
            f(cell, mat.cauchy_stress(grads[q]), fv.JxW(q));
        }
  }

  template <int dim>
  nlohmann::json
  ElasticitySimulator<dim>::state_statistics() const
  {
    auto                                &m  = *impl;
    double                               vm = 0, frobenius = 0, volume = 0;
    std::map<types::material_id, double> by_material, volume_by_material;
    for (const auto id : m.all_ids)
      by_material[id] = volume_by_material[id] = 0;
    m.for_each_stress([&](const auto &cell, const auto &s, const double JxW) {
      vm        = std::max(vm, von_mises(s));
      frobenius = std::max(frobenius, s.norm());
      by_material[cell->material_id()] =
        std::max(by_material[cell->material_id()], s.norm());
      volume += JxW;
      volume_by_material[cell->material_id()] += JxW;
    });
    nlohmann::json j;
    j["max_von_mises_stress"] = Utilities::MPI::max(vm, m.comm);
    j["max_stress"]           = Utilities::MPI::max(frobenius, m.comm);
    j["volume"]               = Utilities::MPI::sum(volume, m.comm);
    if (by_material.size() > 1)
      for (const auto &[id, value] : by_material)
        j["max_stress_by_material"][std::to_string(id)] =
          Utilities::MPI::max(value, m.comm);
    if (volume_by_material.size() > 1)
      for (const auto &[id, value] : volume_by_material)
        j["volume_by_material"][std::to_string(id)] =
          Utilities::MPI::sum(value, m.comm);
    if (m.contact.active())
      j["contact"] = m.contact.statistics(m.mapping, m.u_ghost, m.comm);
    return j;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::cap_volume_bounds()
  {
    auto &m = *impl;
    if (!m.objective)
      return;
    const auto I = m.objective_integrals(*m.objective, m.u_states.size() - 1);
    for (unsigned int t = 0; t < I.size(); ++t)
      if (!I[t].empty())
        m.objective->terms()[t]->cap_volume_bound(I[t][0]);
  }

  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::cell_mean_stress() const
  {
    auto &m = *impl;
    AssertThrow(
      Utilities::MPI::n_mpi_processes(m.comm) == 1 ||
        !dynamic_cast<const parallel::distributed::Triangulation<dim> *>(
          m.tria.get()),
      ExcMessage("Optimization/Element removal needs every cell on every "
                 "rank: run it on one MPI rank or with separated interfaces "
                 "(a shared mesh)."));
    std::vector<double> stress(m.tria->n_active_cells(), 0.);
    std::vector<double> volume(m.tria->n_active_cells(), 0.);
    m.for_each_stress([&](const auto &cell, const auto &s, const double JxW) {
      stress[cell->active_cell_index()] += s.norm() * JxW;
      volume[cell->active_cell_index()] += JxW;
    });
    for (unsigned int c = 0; c < stress.size(); ++c)
      if (volume[c] > 0)
        stress[c] /= volume[c];
    Utilities::MPI::sum(stress, m.comm, stress);
    return stress;
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::max_shape_offset() const
  {
    double m = 0;
    for (const auto i : impl->shape_owned)
      m =
        std::max(m,
                 std::abs(impl->shape_ghost(i) - impl->material_positions(i)));
    return Utilities::MPI::max(m, impl->comm);
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::cell_size() const
  {
    return GridTools::minimal_cell_diameter(*impl->tria);
  }

  template <int dim>
  std::vector<Point<dim>>
  ElasticitySimulator<dim>::cell_centers() const
  {
    const auto         &tria = *impl->tria;
    std::vector<double> flat(dim * tria.n_global_active_cells(), 0.);
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (unsigned int d = 0; d < dim; ++d)
          flat[dim * cell->global_active_cell_index() + d] = cell->center()[d];
    Utilities::MPI::sum(flat, impl->comm, flat);
    std::vector<Point<dim>> centers(tria.n_global_active_cells());
    for (unsigned int c = 0; c < centers.size(); ++c)
      for (unsigned int d = 0; d < dim; ++d)
        centers[c][d] = flat[dim * c + d];
    return centers;
  }

  template <int dim>
  nlohmann::json
  ElasticitySimulator<dim>::adjoint_statistics() const
  {
    const auto    &m = *impl;
    nlohmann::json s = {
      {"n_dofs", m.dof_handler.n_dofs()},
      {"forward_solves", m.forward_solves},
      {"gradients", m.gradients},
      {"forward_seconds", m.forward_seconds},
      {"adjoint_seconds", m.adjoint_seconds},
      // The gradient's time split: the adjoint linear solves (with the
      // transposed assembly where needed), and the rest: objective
      // partials and the shape/parameter derivative products.
      {"adjoint_solve_seconds", m.adjoint_solve_seconds},
      {"derivative_products_seconds",
       m.adjoint_seconds - m.adjoint_solve_seconds},
      {"seconds_per_forward_solve",
       m.forward_seconds / std::max(1u, m.forward_solves)},
      {"seconds_per_gradient", m.adjoint_seconds / std::max(1u, m.gradients)},
      {"stored_state_bytes", m.memory_of_states}};
    if (m.p.problem == "transient" && !m.time_grid.empty())
      {
        // The levels the gradients are the discrete ones of.
        double smallest = m.p.end_time, largest = 0;
        for (unsigned int i = 1; i <= m.time_grid.n_steps(); ++i)
          {
            smallest = std::min(smallest, m.time_grid.step(i));
            largest  = std::max(largest, m.time_grid.step(i));
          }
        s["time_steps"]         = m.time_grid.n_steps();
        s["smallest_time_step"] = smallest;
        s["largest_time_step"]  = largest;
        s["steps_per_order"]    = m.time_grid.steps_per_order(m.p.bdf_order);
      }
    return s;
  }

  template nlohmann::json
  ElasticitySimulator<2>::state_statistics() const;
  template nlohmann::json
  ElasticitySimulator<3>::state_statistics() const;
  template std::vector<double>
  ElasticitySimulator<2>::cell_mean_stress() const;
  template void
  ElasticitySimulator<2>::cap_volume_bounds();
  template void
  ElasticitySimulator<3>::cap_volume_bounds();
  template std::vector<double>
  ElasticitySimulator<3>::cell_mean_stress() const;
  template double
  ElasticitySimulator<2>::max_shape_offset() const;
  template double
  ElasticitySimulator<3>::max_shape_offset() const;
  template double
  ElasticitySimulator<2>::cell_size() const;
  template std::vector<Point<2>>
  ElasticitySimulator<2>::cell_centers() const;
  template std::vector<Point<3>>
  ElasticitySimulator<3>::cell_centers() const;
  template double
  ElasticitySimulator<3>::cell_size() const;
  template nlohmann::json
  ElasticitySimulator<2>::adjoint_statistics() const;
  template nlohmann::json
  ElasticitySimulator<3>::adjoint_statistics() const;
  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
