// Assembly of the elasticity simulator: the forms' point terms contracted
// with the shape functions once per cell, then the global (contact) terms.

#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/work_stream.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/filtered_iterator.h>
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
  Material<dim>
  ElasticitySimulator<dim>::Impl::cell_material(
    const typename DoFHandler<dim>::active_cell_iterator &cell) const
  {
    return elastic_form->material({cell->active_cell_index(),
                                   cell->material_id(),
                                   numbers::invalid_boundary_id});
  }



  template <int dim>
  unsigned int
  ElasticitySimulator<dim>::Impl::form_needs() const
  {
    unsigned int needs = 0;
    for (const auto &f : forms)
      if (form_active(*f))
        needs |= f->needs();
    return needs;
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::form_active(const Form<dim> &f) const
  {
    return transient || !f.transient_only();
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::loaded(const types::boundary_id id) const
  {
    for (const auto &f : forms)
      if (form_active(*f) && f->acts_on_boundary(id))
        return true;
    return false;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::fill_states(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    const FEValuesBase<dim>                              &fv,
    const unsigned int                                    face,
    Scratch<dim>                                         &s,
    const bool                                            for_forms) const
  {
    const FEValuesExtractors::Vector disp(0);
    const unsigned int               nq    = fv.n_quadrature_points;
    const unsigned int               needs = for_forms ? form_needs() : 0u;
    PointStates<dim>                &ps    = s.states;
    ps.cell           = {cell->active_cell_index(), cell->material_id(), 0};
    ps.time           = time;
    ps.dt             = transient ? rate_dt : 0.;
    ps.inertia_factor = transient ? inertia_factor : 0.;
    ps.grad_u.resize(nq);
    fv[disp].get_function_gradients(u_ghost, ps.grad_u);
    ps.u.assign(nq, Tensor<1, dim>());
    if (needs & Form<dim>::values)
      fv[disp].get_function_values(u_ghost, ps.u);
    ps.w.assign(nq, Tensor<1, dim>());
    if (transient && (needs & Form<dim>::history))
      fv[disp].get_function_values(w_ghost, ps.w);
    ps.grad_u_old.assign(nq, Tensor<2, dim>());
    if (transient && (needs & Form<dim>::old_gradients))
      fv[disp].get_function_gradients(u_old_ghost, ps.grad_u_old);
    ps.JxW.resize(nq);
    for (unsigned int q = 0; q < nq; ++q)
      ps.JxW[q] = fv.JxW(q);
    ps.normal.clear();
    if (face == numbers::invalid_unsigned_int)
      {
        s.reference_values.reinit(cell);
        ps.X =
          s.reference_values.get_present_fe_values().get_quadrature_points();
        return;
      }
    ps.cell.boundary_id = cell->face(face)->boundary_id();
    s.reference_face_values.reinit(cell, face);
    ps.X =
      s.reference_face_values.get_present_fe_values().get_quadrature_points();
    for (unsigned int q = 0; q < nq; ++q)
      ps.normal.push_back(fv.normal_vector(q));
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::reset_terms(PointTerms<dim>   &t,
                                              const unsigned int n,
                                              const bool         tangent,
                                              const bool         old_tangent,
                                              const bool         energy)
  {
    t.with_tangent     = tangent;
    t.with_old_tangent = old_tangent;
    t.with_energy      = energy;
    t.flux.assign(n, Tensor<2, dim>());
    t.source.assign(n, Tensor<1, dim>());
    t.flux_tangent.assign(tangent ? n : 0, Tensor<4, dim>());
    t.source_tangent.assign(tangent ? n : 0, 0.);
    t.flux_tangent_old.assign(old_tangent ? n : 0, Tensor<4, dim>());
    t.energy     = 0;
    t.admissible = true;
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::potential_merit() const
  {
    // Transient: the incremental potential of IPC runs, whose damping
    // term is the dissipation potential (Damping::dissipation_potential(),
    // exact up to O(dF^2)); without contact the residual norm decides, as
    // it always has.
    return !transient || ipc_contact != nullptr;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::assemble_cell(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    Scratch<dim>                                         &s,
    CopyData                                             &c,
    const bool                                            with_matrix,
    const bool                                            energy) const
  {
    s.fe_values.reinit(cell);
    const FEValues<dim> &fv = s.fe_values.get_present_fe_values();
    const unsigned int   n  = fv.get_fe().n_dofs_per_cell();
    c.dofs.resize(n);
    cell->get_dof_indices(c.dofs);
    c.residual.reinit(n);
    if (with_matrix && !matrix_free)
      c.matrix.reinit(n, n);
    c.admissible = true;
    c.energy     = 0;

    fill_states(cell, fv, numbers::invalid_unsigned_int, s);
    PointTerms<dim> &t = s.terms;
    reset_terms(t, fv.n_quadrature_points, with_matrix, false, energy);
    for (const auto &f : forms)
      if (form_active(*f) && f->has_cell_terms())
        {
          f->cell_terms(s.states, t);
          if (!t.admissible)
            {
              c.admissible = false;
              return;
            }
        }
    c.energy = t.energy;
    if (with_matrix && matrix_free)
      matrix_free->set_cell_tangent(cell->active_cell_index(),
                                    t.flux_tangent,
                                    t.source_tangent,
                                    transpose_matrix);
    contract_cell_terms(fv, s, c, with_matrix && !matrix_free);
    if (cell->at_boundary())
      assemble_faces(cell, s, c, with_matrix, energy);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::contract_cell_terms(const FEValues<dim> &fv,
                                                      Scratch<dim>        &s,
                                                      CopyData            &c,
                                                      const bool with_matrix)
  {
    // h_i = sum_q (flux_q : grad phi_i + source_q . phi_i) JxW_q; the
    // Jacobian through B_i = A : grad phi_i, once per shape function.
    const PointTerms<dim> &t   = s.terms;
    const auto            &cfe = fv.get_fe();
    const unsigned int     n   = cfe.n_dofs_per_cell();
    s.B.resize(n);
    for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
      {
        const double JxW = fv.JxW(q);
        for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int    ci = cfe.system_to_component_index(i).first;
            const Tensor<1, dim> &gi = fv.shape_grad(i, q);
            const double          vi = fv.shape_value(i, q);
            c.residual(i) += (t.flux[q][ci] * gi + t.source[q][ci] * vi) * JxW;
            if (with_matrix)
              for (unsigned int k = 0; k < dim; ++k)
                for (unsigned int l = 0; l < dim; ++l)
                  {
                    double b = 0;
                    for (unsigned int J = 0; J < dim; ++J)
                      b += t.flux_tangent[q][ci][J][k][l] * gi[J];
                    s.B[i][k][l] = b;
                  }
          }
        if (with_matrix)
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int ci = cfe.system_to_component_index(i).first;
              const double       vi = fv.shape_value(i, q);
              for (unsigned int j = 0; j < n; ++j)
                {
                  const unsigned int cj =
                    cfe.system_to_component_index(j).first;
                  double kij = s.B[i][cj] * fv.shape_grad(j, q);
                  if (ci == cj)
                    kij += t.source_tangent[q] * vi * fv.shape_value(j, q);
                  c.matrix(i, j) += kij * JxW;
                }
            }
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::assemble_faces(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    Scratch<dim>                                         &s,
    CopyData                                             &c,
    const bool                                            with_matrix,
    const bool                                            energy) const
  {
    PointTerms<dim> &t   = s.terms;
    const auto      &cfe = cell->get_fe();
    const unsigned   n   = cfe.n_dofs_per_cell();
    for (const auto face : cell->face_indices())
      {
        if (!cell->face(face)->at_boundary() ||
            !loaded(cell->face(face)->boundary_id()))
          continue;
        s.face_values.reinit(cell, face);
        const FEFaceValues<dim> &ff = s.face_values.get_present_fe_values();
        fill_states(cell, ff, face, s);
        reset_terms(t, ff.n_quadrature_points, with_matrix, false, energy);
        for (const auto &f : forms)
          if (form_active(*f) && f->acts_on_boundary(s.states.cell.boundary_id))
            f->face_terms(s.states, t);
        c.energy += t.energy;
        for (unsigned int q = 0; q < ff.n_quadrature_points; ++q)
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int ci = cfe.system_to_component_index(i).first;
              const double       vi = ff.shape_value(i, q);
              c.residual(i) += t.source[q][ci] * vi * ff.JxW(q);
              if (with_matrix && matrix_free && t.source_tangent[q] != 0)
                face_tangent_missed = true;
              else if (with_matrix && t.source_tangent[q] != 0)
                for (unsigned int j = 0; j < n; ++j)
                  if (cfe.system_to_component_index(j).first == ci)
                    c.matrix(i, j) += t.source_tangent[q] * vi *
                                      ff.shape_value(j, q) * ff.JxW(q);
            }
      }
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::assemble(const Vector_t &u_owned,
                                           const bool      with_matrix,
                                           Vector_t       *raw)
  {
    Timer timer;
    u_ghost = u_owned;
    if (with_matrix) // the last Jacobian's verdict holds until the next
      face_tangent_missed = false;
    if (with_matrix && !matrix_free)
      jacobian = 0;
    residual = 0;
    if (raw)
      *raw = 0;
    const bool energy = potential_merit();
    for (const auto &f : forms)
      f->set_time(time);

    auto worker =
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          Scratch<dim>                                         &s,
          CopyData &c) { assemble_cell(cell, s, c, with_matrix, energy); };

    bool   admissible = true;
    double energy_sum = 0;
    auto   copier     = [&](const CopyData &c) {
      if (!c.admissible)
        {
          admissible = false;
          return;
        }
      energy_sum += c.energy;
      if (with_matrix && !matrix_free && transpose_matrix)
        {
          FullMatrix<double> t(c.matrix.n(), c.matrix.m());
          t.copy_transposed(c.matrix);
          constraints_zero.distribute_local_to_global(
            t, c.residual, c.dofs, jacobian, residual);
        }
      else if (with_matrix && !matrix_free)
        constraints_zero.distribute_local_to_global(
          c.matrix, c.residual, c.dofs, jacobian, residual);
      else
        constraints_zero.distribute_local_to_global(c.residual,
                                                    c.dofs,
                                                    residual);
      if (raw)
        for (unsigned int i = 0; i < c.dofs.size(); ++i)
          (*raw)(c.dofs[i]) += c.residual(i);
    };

    using Iterator = typename DoFHandler<dim>::active_cell_iterator;
    WorkStream::run(
      FilteredIterator<Iterator>(IteratorFilters::LocallyOwnedCell(),
                                 dof_handler.begin_active()),
      FilteredIterator<Iterator>(IteratorFilters::LocallyOwnedCell(),
                                 dof_handler.end()),
      worker,
      copier,
      Scratch<dim>(mapping, reference_mapping, fe, quadrature, face_quadrature),
      CopyData());

    // Global terms (contact), collective, into the same containers.
    for (const auto &f : forms)
      {
        typename Form<dim>::GlobalAssembly a{u_owned,
                                             u_ghost,
                                             constraints_zero,
                                             with_matrix && !matrix_free ?
                                               &jacobian :
                                               nullptr,
                                             residual,
                                             raw,
                                             transpose_matrix,
                                             exact_contact_hessian,
                                             admissible};
        f->assemble_global(a);
        energy_sum += a.energy;
        admissible &= a.admissible;
      }

    // Compress even when a cell was inadmissible, so the containers stay
    // usable for the next (shorter-step) assembly.
    if (with_matrix && !matrix_free)
      jacobian.compress(VectorOperation::add);
    residual.compress(VectorOperation::add);
    if (raw)
      raw->compress(VectorOperation::add);
    admissible       = Utilities::MPI::min(admissible ? 1 : 0, comm) == 1;
    potential_energy = Utilities::MPI::sum(energy_sum, comm);
    assembly_seconds += timer.wall_time();
    return admissible;
  }


  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
