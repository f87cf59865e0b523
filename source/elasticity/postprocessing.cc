// Postprocessing of the elasticity simulator: step records, point values,
// reactions, VTU output, progress lines.

#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
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
#include <deal.II/numerics/data_out.h>

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
  ElasticitySimulator<dim>::Impl::record_step(const unsigned int step,
                                              const double       t,
                                              const unsigned int newton_its,
                                              const unsigned int linear_its)
  {
    u_ghost = u;
    Vector_t v_ghost(owned, relevant, comm);
    if (transient)
      v_ghost = v;

    const FEValuesExtractors::Vector disp(0);
    hp::FEValues<dim>                hp_fv(mapping,
                            fe,
                            quadrature,
                            update_values | update_gradients |
                              update_JxW_values);
    double         kinetic = 0, elastic = 0, potential = 0, mass = 0;
    unsigned int   inverted = 0;
    Tensor<1, dim> first_moment;
    std::vector<Tensor<2, dim>> grads;
    std::vector<Tensor<1, dim>> vals, vels;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_fv.reinit(cell);
          const auto        &fv  = hp_fv.get_present_fe_values();
          const auto         mat = cell_material(cell);
          const double       rho = mat.properties().density;
          const unsigned int nq  = fv.n_quadrature_points;
          grads.resize(nq);
          vals.resize(nq);
          vels.resize(nq);
          fv[disp].get_function_gradients(u_ghost, grads);
          fv[disp].get_function_values(u_ghost, vals);
          if (transient)
            fv[disp].get_function_values(v_ghost, vels);
          bool cell_inverted = false;
          for (unsigned int q = 0; q < nq; ++q)
            {
              cell_inverted |=
                determinant(unit_symmetric_tensor<dim>() + grads[q]) <= 0;
              const double JxW = fv.JxW(q);
              elastic += mat.energy_density(grads[q]) * JxW;
              if (transient)
                kinetic += 0.5 * rho * vels[q].norm_square() * JxW;
              potential -= rho * (gravity * vals[q]) * JxW;
              mass += rho * JxW;
              first_moment += rho * vals[q] * JxW;
              const Tensor<2, dim> sigma = mat.cauchy_stress(grads[q]);
              max_von_mises = std::max(max_von_mises, von_mises(sigma));
              max_frobenius = std::max(max_frobenius, sigma.norm());
            }
          inverted += cell_inverted ? 1 : 0;
        }
    typename ElasticitySimulator<dim>::StepRecord r;
    r.step              = step;
    r.time              = t;
    r.newton_iterations = newton_its;
    r.linear_iterations = linear_its;
    r.residual          = residual.l2_norm();
    r.n_dofs            = dof_handler.n_dofs();
    r.kinetic_energy    = Utilities::MPI::sum(kinetic, comm);
    r.elastic_energy    = Utilities::MPI::sum(elastic, comm);
    r.gravity_potential = Utilities::MPI::sum(potential, comm);
    r.mean_displacement =
      Utilities::MPI::sum(first_moment, comm) / Utilities::MPI::sum(mass, comm);
    max_von_mises = Utilities::MPI::max(max_von_mises, comm);
    max_frobenius = Utilities::MPI::max(max_frobenius, comm);
    for (const auto &x : points)
      r.point_displacements.push_back(point_value(x));
    if (ipc_contact)
      {
        // Step 0 (initial state): no solve yet.
        r.contact =
          last_ipc_step.is_null() ?
            nlohmann::json{{"active_pairs", 0}, {"min_distance", nullptr}} :
            last_ipc_step;
        r.contact["inverted_elements"] = Utilities::MPI::sum(inverted, comm);
        inverted_elements =
          std::max<unsigned int>(inverted_elements,
                                 r.contact["inverted_elements"]);
      }
    steps.push_back(r);
  }



  template <int dim>
  Tensor<1, dim>
  ElasticitySimulator<dim>::Impl::point_value(const Point<dim> &x) const
  {
    // The owner with the lowest rank evaluates; everyone gets its value.
    const unsigned int rank  = Utilities::MPI::this_mpi_process(comm);
    unsigned int       owner = numbers::invalid_unsigned_int;
    Tensor<1, dim>     value;
    try
      {
        const auto found =
          GridTools::find_active_cell_around_point(reference_mapping,
                                                   dof_handler,
                                                   x);
        if (found.first.state() == IteratorState::valid &&
            found.first->is_locally_owned())
          {
            owner                 = rank;
            const auto      &cell = found.first;
            const Point<dim> ref  = found.second;
            FEValues<dim>    fv(reference_mapping[0],
                             fe[cell->active_fe_index()],
                             Quadrature<dim>(ref),
                             update_values);
            fv.reinit(cell);
            std::vector<Tensor<1, dim>> vals(1);
            fv[FEValuesExtractors::Vector(0)].get_function_values(u_ghost,
                                                                  vals);
            value = vals[0];
          }
      }
    catch (...)
      {}
    const unsigned int first = Utilities::MPI::min(owner, comm);
    AssertThrow(first != numbers::invalid_unsigned_int,
                ExcMessage("Output/Points: the point (" +
                           fmt(Tensor<1, dim>(x)) + ") is outside the mesh."));
    return Utilities::MPI::sum(rank == first ? value : Tensor<1, dim>(), comm);
  }



  template <int dim>
  Vector_t
  ElasticitySimulator<dim>::Impl::conforming_residual(const Vector_t &raw) const
  {
    // A support's force is the residual tested with the conforming basis
    // functions at its DoFs: a hanging DoF's residual belongs to its
    // masters (psi_j = phi_j + sum_h c_hj phi_h).
    AffineConstraints<double> hanging;
    hanging.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);
    hanging.close();
    Vector_t moved;
    moved.reinit(owned, relevant, comm, true); // writable ghosts
    for (const auto &line : hanging.get_lines())
      if (owned.is_element(line.index))
        for (const auto &[j, c] : line.entries)
          moved(j) += c * raw(line.index);
    moved.compress(VectorOperation::add);
    Vector_t result(owned, comm);
    for (const auto i : owned)
      result(i) = hanging.is_constrained(i) ? 0. : raw(i) + moved(i);
    result.compress(VectorOperation::insert);
    return result;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::compute_reactions()
  {
    Vector_t raw(owned, comm);
    assemble(u, false, &raw);
    raw = conforming_residual(raw);
    reactions.clear();
    std::vector<IndexSet> component_dofs;
    for (unsigned int c = 0; c < dim; ++c)
      {
        std::vector<bool> m(dim, false);
        m[c] = true;
        component_dofs.push_back(
          DoFTools::extract_dofs(dof_handler, ComponentMask(m)));
      }
    // Supports are the Dirichlet boundaries; a DoF on two of them (a corner)
    // counts in both.
    std::set<types::boundary_id> supports;
    for (const auto &d : dirichlet)
      supports.insert(d.id);
    for (const auto id : supports)
      {
        const IndexSet on_boundary =
          DoFTools::extract_boundary_dofs(dof_handler, ComponentMask(), {id});
        Tensor<1, dim> f;
        for (const auto i : on_boundary)
          if (owned.is_element(i))
            for (unsigned int c = 0; c < dim; ++c)
              if (component_dofs[c].is_element(i))
                f[c] += raw(i);
        reactions[id] = Utilities::MPI::sum(f, comm);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::write_output(const unsigned int step,
                                               const double       t)
  {
    if (!context || !p.write_vtu)
      return;
    u_ghost = u;
    Vector<float> vm(tria->n_active_cells()), fro(tria->n_active_cells()),
      material(tria->n_active_cells()), partition(tria->n_active_cells()),
      degree(tria->n_active_cells());
    const FEValuesExtractors::Vector disp(0);
    hp::FEValues<dim>                hp_fv(mapping,
                            fe,
                            quadrature,
                            update_gradients | update_JxW_values);
    std::vector<Tensor<2, dim>>      grads;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_fv.reinit(cell);
          const auto &fv  = hp_fv.get_present_fe_values();
          const auto  mat = cell_material(cell);
          grads.resize(fv.n_quadrature_points);
          fv[disp].get_function_gradients(u_ghost, grads);
          double a = 0, b = 0, vol = 0;
          for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
            {
              const Tensor<2, dim> s = mat.cauchy_stress(grads[q]);
              a += von_mises(s) * fv.JxW(q);
              b += s.norm() * fv.JxW(q);
              vol += fv.JxW(q);
            }
          const unsigned int k = cell->active_cell_index();
          vm[k]                = a / vol;
          fro[k]               = b / vol;
          material[k]          = cell->material_id();
          partition[k]         = cell->subdomain_id();
          degree[k]            = cell->get_fe().degree;
        }

    DataOut<dim> out;
    out.attach_dof_handler(dof_handler);
    std::vector<DataComponentInterpretation::DataComponentInterpretation> vec(
      dim, DataComponentInterpretation::component_is_part_of_vector);
    out.add_data_vector(u_ghost,
                        std::vector<std::string>(dim, "displacement"),
                        DataOut<dim>::type_dof_data,
                        vec);
    Vector_t v_ghost(owned, relevant, comm); // must outlive build_patches()
    if (transient)
      {
        v_ghost = v;
        out.add_data_vector(v_ghost,
                            std::vector<std::string>(dim, "velocity"),
                            DataOut<dim>::type_dof_data,
                            vec);
      }
    out.add_data_vector(vm, "von_mises");
    out.add_data_vector(fro, "stress_frobenius");
    out.add_data_vector(material, "material_id");
    out.add_data_vector(partition, "partition");
    out.add_data_vector(degree, "fe_degree");
    out.build_patches(mapping, simplex ? 1 : solve_degree());
    const std::string name = out.write_vtu_with_pvtu_record(
      context->directory() + "/", "solution", step, comm, 4);
    pvd_records.emplace_back(t, name);
    if (context->is_root())
      {
        std::ofstream pvd(context->path("solution.pvd"));
        DataOutBase::write_pvd_record(pvd, pvd_records);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::print_progress(const std::string &head) const
  {
    if (!context)
      return;
    const auto &r    = steps.back();
    std::string line = head;
    if (transient)
      line += ", kinetic energy: " + fmt(r.kinetic_energy);
    line += ", elastic energy: " + fmt(r.elastic_energy);
    for (unsigned int k = 0; k < points.size(); ++k)
      line += ", u" + fmt(Tensor<1, dim>(points[k])) + " = " +
              fmt(r.point_displacements[k]);
    context->print(line);
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
