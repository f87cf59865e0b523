// One pass over the cells of the elasticity simulator's current step state
// for an objective: its integrals, its partials dJ/du and dJ/dm, and the
// forms' adjoint products p^T dh/dm (thesis eqs. 3.24, 3.31-3.35).

#include <deal.II/fe/fe_values.h>
#include <deal.II/hp/fe_values.h>

#include <forma/physics/contractions.h>

#include "simulator_impl.h"

#include <optional>

namespace forma
{
  template <int dim>
  class ElasticitySimulator<dim>::Impl::ObjectivePass
  {
  public:
    using cell_iterator = typename DoFHandler<dim>::active_cell_iterator;

    ObjectivePass(Impl                                   &sim,
                  const Objective<dim>                   &J,
                  const std::vector<std::vector<double>> *weights,
                  const Vector_t                         *adjoint,
                  Vector_t                               *dJ_du);

    void
    cell(const cell_iterator &cell);

    /// Compress the outputs.
    void
    finish();

  private:
    /// FE values, states and local vectors of a cell.
    void
    reinit(const cell_iterator &cell);
    /// The objective's volume integrands at the cell's points.
    void
    volume_points(const cell_iterator &cell);
    /// The forms' point-term products at the cell.
    void
    form_products();
    void
    face(const cell_iterator &cell, const unsigned int face);
    /// Which integrals of J act on this face.
    bool
    face_mask(const cell_iterator &cell, const unsigned int face);
    /// The objective's integrand contributions at point q of `fv` (`sv`:
    /// the shape field's values there, null without a shape design).
    void
    point(const FEValuesBase<dim>         &fv,
          const FEValuesBase<dim>         *sv,
          const unsigned int               q,
          const std::vector<unsigned int> &term_integrals,
          const bool                       boundary,
          const unsigned int               cell_index);
    /// The adjoint at the points of `fv`.
    void
    adjoint_at(const FEValuesBase<dim> &fv);
    /// The reference run's deformed positions (targets) at `fv`'s points.
    void
    targets_at(const FEValuesBase<dim> &fv);

    Impl                                   &sim;
    const Objective<dim>                   &J;
    const std::vector<std::vector<double>> *weights;
    const Vector_t                         *adjoint;
    Vector_t                               *dJ_du;
    const FEValuesExtractors::Vector        disp{0};
    const bool                              values_only;
    const bool                              want_shape;
    CellLame                               *lame_wanted;
    Vector_t                                adjoint_ghost, reference_ghost;
    const bool                              has_reference;

    Scratch<dim>                         s;
    hp::FECollection<dim>                shape_collection;
    hp::FEValues<dim>                    shape_values;
    hp::FEFaceValues<dim>                shape_face_values;
    const unsigned int                   ns;
    dealii::Vector<double>               local_shape, local_u;
    std::vector<types::global_dof_index> shape_dofs, dofs;
    std::vector<Tensor<1, dim>>          ref_u;
    PointAdjoint<dim>                    adj;
    std::vector<Tensor<2, dim>>          face_kernel;
    cell_iterator                        shape_cell;
    const FEValues<dim>                 *sv = nullptr;
    std::optional<Material<dim>>         mat;
    IntegrandContext<dim>                ctx;
    IntegrandValue<dim>                  r;

    // Which integrals live on the volume, which on a boundary id.
    std::vector<unsigned int>                 volume_mask, any_boundary;
    std::vector<unsigned int>                 n_integrals, cell_mask, mask;
    std::vector<std::set<types::material_id>> integral_materials;
    bool any_restriction = false, has_boundary_terms = false;
  };



  template <int dim>
  ElasticitySimulator<dim>::Impl::ObjectivePass::ObjectivePass(
    Impl                                   &sim,
    const Objective<dim>                   &J,
    const std::vector<std::vector<double>> *weights,
    const Vector_t                         *adjoint,
    Vector_t                               *dJ_du)
    : sim(sim)
    , J(J)
    , weights(weights)
    , adjoint(adjoint)
    , dJ_du(dJ_du)
    , values_only(!weights && !adjoint)
    , want_shape(!values_only && sim.shape_field->wanted)
    , lame_wanted(values_only ? nullptr : sim.physical.wanted<CellLame>())
    , has_reference(!sim.reference_states.empty())
    , s(sim.mapping,
        sim.reference_mapping,
        sim.fe,
        sim.quadrature,
        sim.face_quadrature)
    , shape_collection(*sim.shape_fe)
    , shape_values(sim.mapping,
                   shape_collection,
                   sim.quadrature,
                   update_values | update_gradients)
    , shape_face_values(sim.mapping,
                        shape_collection,
                        sim.face_quadrature,
                        update_values | update_gradients)
    , ns(sim.shape_fe->n_dofs_per_cell())
    , local_shape(ns)
    , shape_dofs(ns)
  {
    if (adjoint)
      {
        adjoint_ghost.reinit(sim.owned, sim.relevant, sim.comm);
        adjoint_ghost = *adjoint;
      }
    if (has_reference)
      {
        reference_ghost.reinit(sim.owned, sim.relevant, sim.comm);
        const unsigned int i = sim.p.problem == "static" ? 0 : sim.step_index;
        reference_ghost      = sim.reference_states[std::min<std::size_t>(
          i, sim.reference_states.size() - 1)];
      }
    for (const auto &t : J.terms())
      {
        for (const auto &i : t->integrals())
          {
            volume_mask.push_back(!i.boundary);
            any_boundary.push_back(i.boundary);
            integral_materials.push_back(i.material_ids);
            any_restriction |= !i.material_ids.empty();
            has_boundary_terms |= i.boundary;
          }
        n_integrals.push_back(t->integrals().size());
      }
    cell_mask        = volume_mask;
    ctx.time         = sim.time;
    ctx.model        = sim.p.model;
    ctx.plane_stress = sim.p.plane_stress;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::cell(const cell_iterator &c)
  {
    reinit(c);
    volume_points(c);
    if (adjoint)
      form_products();
    if (c->at_boundary() && (has_boundary_terms || adjoint))
      for (const auto f : c->face_indices())
        if (c->face(f)->at_boundary())
          face(c, f);
    if (dJ_du)
      sim.constraints_zero.distribute_local_to_global(local_u, dofs, *dJ_du);
    if (want_shape)
      sim.shape_field->add(local_shape, shape_dofs);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::reinit(const cell_iterator &c)
  {
    s.fe_values.reinit(c);
    const FEValues<dim> &fv = s.fe_values.get_present_fe_values();
    const unsigned int   n  = fv.get_fe().n_dofs_per_cell();
    dofs.resize(n);
    c->get_dof_indices(dofs);
    local_u.reinit(dJ_du ? n : 0);
    local_shape = 0;
    shape_cell =
      cell_iterator(&*sim.tria, c->level(), c->index(), &sim.shape_dof_handler);
    sv = nullptr;
    if (want_shape)
      {
        shape_values.reinit(shape_cell, c->active_fe_index(), 0, 0);
        sv = &shape_values.get_present_fe_values();
        shape_cell->get_dof_indices(shape_dofs);
      }
    mat.emplace(sim.cell_material(c));
    // The forms' states only where they add products.
    sim.fill_states(c, fv, numbers::invalid_unsigned_int, s, adjoint);
    fv[disp].get_function_values(sim.u_ghost, s.states.u);
    ctx.density = mat->properties().density;
    ctx.normal  = Tensor<1, dim>(); // volume points have none
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::volume_points(
    const cell_iterator &c)
  {
    const FEValues<dim> &fv = s.fe_values.get_present_fe_values();
    targets_at(fv);
    // Volume integrals restricted to some materials skip the others.
    if (any_restriction)
      for (unsigned int k = 0; k < cell_mask.size(); ++k)
        cell_mask[k] =
          volume_mask[k] && (integral_materials[k].empty() ||
                             integral_materials[k].count(c->material_id()));
    for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
      {
        ctx.X = s.states.X[q];
        if (has_reference)
          ctx.target = Tensor<1, dim>(s.states.X[q]) + ref_u[q];
        point(fv, sv, q, cell_mask, false, c->active_cell_index());
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::form_products()
  {
    // p^T d_q h of the forms' point terms: the shape by transport (eq.
    // 3.24), the other parameters by the forms.
    const FEValues<dim> &fv = s.fe_values.get_present_fe_values();
    adjoint_at(fv);
    if (want_shape)
      sim.add_transport_products(fv, *sv, adj, s, local_shape);
    for (const auto &f : sim.forms)
      if (sim.form_active(*f) && f->has_cell_terms())
        f->cell_products(s.states, adj, sim.physical);
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::ObjectivePass::face_mask(
    const cell_iterator &c,
    const unsigned int   f)
  {
    const types::boundary_id id = c->face(f)->boundary_id();
    mask.assign(any_boundary.size(), 0);
    bool         any = false;
    unsigned int idx = 0;
    for (const auto &t : J.terms())
      for (const auto &i : t->integrals())
        {
          mask[idx] =
            i.boundary &&
            (i.boundary_ids.empty() || i.boundary_ids.count(id)) &&
            (i.material_ids.empty() || i.material_ids.count(c->material_id()));
          any |= mask[idx++] != 0;
        }
    return any;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::face(const cell_iterator &c,
                                                      const unsigned int   f)
  {
    // Boundary objective integrals and the forms' face terms.
    const types::boundary_id id   = c->face(f)->boundary_id();
    const bool               any  = face_mask(c, f);
    const bool               load = adjoint && sim.loaded(id);
    if (!any && !load)
      return;
    s.face_values.reinit(c, f);
    const FEFaceValues<dim> &ff = s.face_values.get_present_fe_values();
    const FEFaceValues<dim> *sf = nullptr;
    if (want_shape)
      {
        shape_face_values.reinit(shape_cell, f, c->active_fe_index(), 0, 0);
        sf = &shape_face_values.get_present_fe_values();
      }
    sim.fill_states(c, ff, f, s, load);
    ff[disp].get_function_values(sim.u_ghost, s.states.u);
    const unsigned int nf = ff.n_quadrature_points;
    if (any)
      {
        targets_at(ff);
        for (unsigned int q = 0; q < nf; ++q)
          {
            ctx.X      = s.states.X[q];
            ctx.normal = ff.normal_vector(q);
            if (has_reference)
              ctx.target = Tensor<1, dim>(s.states.X[q]) + ref_u[q];
            point(ff, sf, q, mask, true, c->active_cell_index());
          }
      }
    if (!load)
      return;
    adjoint_at(ff);
    face_kernel.assign(nf, Tensor<2, dim>());
    for (const auto &form : sim.forms)
      if (sim.form_active(*form) && form->acts_on_boundary(id))
        form->face_products(s.states, adj, face_kernel, sim.physical);
    if (want_shape)
      for (unsigned int q = 0; q < nf; ++q)
        for (unsigned int a = 0; a < ns; ++a)
          local_shape(a) +=
            row_dot(face_kernel[q],
                    sim.shape_fe->system_to_component_index(a).first,
                    sf->shape_grad(a, q));
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::point(
    const FEValuesBase<dim>         &fv,
    const FEValuesBase<dim>         *sv,
    const unsigned int               q,
    const std::vector<unsigned int> &term_integrals,
    const bool                       boundary,
    const unsigned int               cell_index)
  {
    const double JxW = fv.JxW(q);
    const auto  &ps  = s.states;
    for (unsigned int t = 0, idx = 0; t < J.terms().size(); ++t)
      {
        const auto &term = *J.terms()[t];
        for (unsigned int k = 0; k < n_integrals[t]; ++k, ++idx)
          {
            if (!term_integrals[idx])
              continue;
            const double w = weights ? (*weights)[t][k] : 0.;
            if (!values_only && w == 0)
              continue;
            term.integrand(k,
                           ctx,
                           fv.quadrature_point(q),
                           ps.u[q],
                           ps.grad_u[q],
                           mat->properties().lambda,
                           mat->properties().mu,
                           !values_only,
                           r);
            if (values_only)
              {
                sim.objective_cache[t][k] += r.value * JxW;
                continue;
              }
            if (dJ_du)
              for (unsigned int i = 0; i < local_u.size(); ++i)
                {
                  const unsigned int c =
                    fv.get_fe().system_to_component_index(i).first;
                  local_u(i) += w *
                                (r.d_u[c] * fv.shape_value(i, q) +
                                 row_dot(r.d_grad_u, c, fv.shape_grad(i, q))) *
                                JxW;
                }
            if (sv)
              {
                // eqs. 3.31/3.34 (surface divergence on faces)
                Tensor<2, dim> W = transport_kernel(r.d_grad_u, ps.grad_u[q]);
                for (unsigned int d = 0; d < dim; ++d)
                  W[d][d] += r.value;
                for (unsigned int a = 0; a < ns; ++a)
                  {
                    const unsigned int c =
                      sim.shape_fe->system_to_component_index(a).first;
                    const Tensor<1, dim> dN = sv->shape_grad(a, q);
                    double               v =
                      row_dot(W, c, dN) + r.d_x[c] * sv->shape_value(a, q);
                    if (boundary)
                      {
                        // d(ds) = div_S theta ds and, for integrands of the
                        // normal, dn = -(I - n n^T) grad theta^T n.
                        const Tensor<1, dim> &n  = fv.normal_vector(q);
                        const double          dn = dN * n;
                        v -= r.value * n[c] * dn +
                             n[c] * (r.d_n * dN - (r.d_n * n) * dn);
                      }
                    local_shape(a) += w * v * JxW;
                  }
              }
            if (lame_wanted)
              {
                auto &l = lame_wanted->sensitivity[cell_index];
                l[0] += w * r.d_lambda * JxW;
                l[1] += w * r.d_mu * JxW;
              }
          }
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::adjoint_at(
    const FEValuesBase<dim> &fv)
  {
    const unsigned int nq = fv.n_quadrature_points;
    adj.p.resize(nq);
    adj.G.resize(nq);
    fv[disp].get_function_values(adjoint_ghost, adj.p);
    fv[disp].get_function_gradients(adjoint_ghost, adj.G);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::targets_at(
    const FEValuesBase<dim> &fv)
  {
    if (!has_reference)
      return;
    ref_u.resize(fv.n_quadrature_points);
    fv[disp].get_function_values(reference_ghost, ref_u);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ObjectivePass::finish()
  {
    if (dJ_du)
      dJ_du->compress(VectorOperation::add);
    if (want_shape)
      sim.shape_field->sensitivity.compress(VectorOperation::add);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::accumulate(
    const Objective<dim>                   &J,
    const std::vector<std::vector<double>> *weights,
    const Vector_t                         *adjoint,
    Vector_t                               *dJ_du)
  {
    objective_cache.clear();
    for (const auto &t : J.terms())
      objective_cache.emplace_back(t->integrals().size(), 0.);
    for (const auto &f : forms)
      f->set_time(time);
    ObjectivePass pass(*this, J, weights, adjoint, dJ_du);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        pass.cell(cell);
    pass.finish();
  }

  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
