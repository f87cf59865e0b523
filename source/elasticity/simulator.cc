#include <deal.II/base/function_parser.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/work_stream.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_series.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_fe_field.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/filtered_iterator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/hp/fe_collection.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/hp/q_collection.h>
#include <deal.II/hp/refinement.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/smoothness_estimator.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/contact/penalty_contact_form.h>
#include <forma/elasticity/simulator.h>
#include <forma/mesh/mesh.h>
#include <forma/physics/bdf.h>
#include <forma/physics/body_load_form.h>
#include <forma/physics/damping_form.h>
#include <forma/physics/inertia_form.h>
#include <forma/physics/material.h>
#include <forma/physics/surface_load_form.h>
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
  ElasticitySimulator<dim>::Impl::Impl(const ElasticityParameters &p,
                                       const MPI_Comm              comm)
    : p(p)
    , comm(comm)
    , linear_solver(p.linear_solver)
    , contact(p.contact)
  {
    AssertThrow(p.dim == dim, ExcInternalError());
    tria                          = create_distributed_mesh<dim>(p.mesh, comm);
    simplex                       = !tria->all_reference_cells_are_hyper_cube();
    const ReferenceCell cell_type = tria->get_reference_cells()[0];

    if (simplex)
      {
        AssertThrow(p.degree <= 2,
                    ExcMessage("Finite element/Degree: simplices support P1 "
                               "and P2 (got " +
                               std::to_string(p.degree) + ")."));
        AssertThrow(p.adaptivity == "none",
                    ExcMessage("Finite element/Adaptivity needs a quad/hex "
                               "mesh; simplex meshes are refined uniformly."));
        fe.push_back(FESystem<dim>(FE_SimplexP<dim>(p.degree), dim));
        quadrature.push_back(
          cell_type.template get_gauss_type_quadrature<dim>(p.degree + 1));
        face_quadrature.push_back(
          cell_type.face_reference_cell(0)
            .template get_gauss_type_quadrature<dim - 1>(p.degree + 1));
        mesh_mapping.push_back(MappingFE<dim>(FE_SimplexP<dim>(1)));
        shape_fe = std::make_unique<FESystem<dim>>(FE_SimplexP<dim>(1), dim);
      }
    else
      {
        const unsigned int top = p.adaptivity == "hp" ? p.max_degree : p.degree;
        for (unsigned int k = 1; k <= top; ++k)
          {
            fe.push_back(FESystem<dim>(FE_Q<dim>(k), dim));
            quadrature.push_back(QGauss<dim>(k + 1));
            face_quadrature.push_back(QGauss<dim - 1>(k + 1));
          }
        mesh_mapping.push_back(MappingQ<dim>(1));
        shape_fe = std::make_unique<FESystem<dim>>(FE_Q<dim>(1), dim);
      }
    reference_mapping = hp::MappingCollection<dim>(mesh_mapping);
    if (p.ipc.enabled)
      ipc_contact = std::make_unique<ipc::IpcContact<dim>>(p.ipc);
    dof_handler.reinit(*tria);
    shape_dof_handler.reinit(*tria);
    setup_shape();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        cell->set_active_fe_index(simplex ? 0 : p.degree - 1);

    build_loads();
    setup_forms();
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::setup_forms()
  {
    cell_lame    = &physical.add(std::make_unique<CellLame>());
    cell_damping = &physical.add(std::make_unique<CellDamping>());
    load_scales  = &physical.add(std::make_unique<LoadScales>());
    shape_field  = &physical.add(
      std::make_unique<ShapeField<dim>>(shape_dof_handler, shape_constraints));
    if (ipc_contact)
      friction = &physical.add(std::make_unique<FrictionCoefficients>());
    if (p.problem == "transient")
      initial = &physical.add(std::make_unique<InitialConditions>());

    std::map<types::material_id, double> density;
    bool                                 damped = p.design.has("damping");
    for (const auto &[id, m] : bodies)
      {
        density[id] = m.density;
        damped |= m.damping_shear > 0 || m.damping_bulk > 0;
      }
    // With IPC every model must stay inversion-free.
    auto elastic = std::make_unique<ElasticForm<dim>>(
      p.model, p.plane_stress, bodies, *cell_lame, ipc_contact != nullptr);
    elastic_form = elastic.get();
    forms.push_back(std::move(elastic));
    if (damped && p.problem == "transient")
      forms.push_back(std::make_unique<DampingForm<dim>>(*cell_damping));
    const unsigned int n_surface = tractions.size() + pressures.size();
    if (body_force || gravity.norm() > 0)
      forms.push_back(std::make_unique<BodyLoadForm<dim>>(
        body_force, gravity, density, *load_scales, n_surface));
    if (p.problem == "transient")
      forms.push_back(std::make_unique<InertiaForm<dim>>(density));
    if (n_surface > 0)
      {
        std::vector<typename SurfaceLoadForm<dim>::Load> t, pr;
        for (const auto &l : tractions)
          t.emplace_back(l.first, l.second);
        for (const auto &l : pressures)
          pr.emplace_back(l.first, l.second);
        forms.push_back(
          std::make_unique<SurfaceLoadForm<dim>>(t, pr, *load_scales));
      }
    add_registered_forms();
    if (!p.contact.rigid.empty() || !p.contact.deformable.empty())
      forms.push_back(
        std::make_unique<PenaltyContactForm<dim>>(contact, mapping));
    if (ipc_contact)
      {
        auto ipc =
          std::make_unique<ipc::IpcContactForm<dim>>(*ipc_contact, [this]() {
            return ipc_friction_eta();
          });
        ipc_form = ipc.get();
        forms.push_back(std::move(ipc));
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::build_loads()
  {
    constants = parse_key_values(p.constants, "Boundary conditions/Constants");

    // Materials: every material id of the mesh needs a record.
    all_ids.clear();
    for (const auto &cell : tria->active_cell_iterators())
      all_ids.insert(cell->material_id());
    {
      std::vector<types::material_id> local(all_ids.begin(), all_ids.end());
      const auto gathered = Utilities::MPI::all_gather(comm, local);
      for (const auto &g : gathered)
        all_ids.insert(g.begin(), g.end());
    }
    bodies = parse_bodies(p.bodies, "Material/Bodies");

    std::set<types::boundary_id> boundary_ids;
    for (const auto b : tria->get_boundary_ids())
      boundary_ids.insert(b);
    auto check_boundary = [&](const unsigned int id, const std::string &entry) {
      AssertThrow(id != any_id,
                  ExcMessage("'" + entry + "': give explicit boundary ids."));
      AssertThrow(boundary_ids.count(id),
                  ExcMessage("'" + entry + "': the mesh has no boundary id " +
                             std::to_string(id) + "."));
    };

    const std::string dir_entry = "Boundary conditions/Dirichlet";
    for (const auto &r : parse_records(p.dirichlet, 2, dir_entry))
      {
        check_boundary(r.id, dir_entry);
        const auto mask = parse_components(r.fields[0], dim, dir_entry);
        dirichlet.push_back(
          {static_cast<types::boundary_id>(r.id),
           mask,
           make_function<dim>(
             split_top_level(r.fields[1], ','), mask, constants, dir_entry)});
      }
    const std::vector<bool> all(dim, true);
    const std::string       tr_entry = "Boundary conditions/Traction";
    for (const auto &r : parse_records(p.traction, 1, tr_entry))
      {
        check_boundary(r.id, tr_entry);
        tractions.emplace_back(r.id,
                               make_function<dim>(split_top_level(r.fields[0],
                                                                  ','),
                                                  all,
                                                  constants,
                                                  tr_entry));
      }
    const std::string pr_entry = "Boundary conditions/Pressure";
    for (const auto &r : parse_records(p.pressure, 1, pr_entry))
      {
        check_boundary(r.id, pr_entry);
        std::vector<bool> first(dim, false);
        first[0] = true;
        pressures.emplace_back(
          r.id, make_function<dim>({r.fields[0]}, first, constants, pr_entry));
      }
    if (!p.body_force.empty())
      body_force = make_function<dim>(split_top_level(p.body_force, ','),
                                      all,
                                      constants,
                                      "Loads/Body force");
    if (!p.gravity.empty())
      {
        const auto g = parse_point<dim>(p.gravity, "Loads/Gravity");
        for (unsigned int d = 0; d < dim; ++d)
          gravity[d] = g[d];
      }
    for (const auto &text : split_top_level(p.points, ';'))
      if (!text.empty())
        points.push_back(parse_point<dim>(text, "Output/Points"));
  }



  template <int dim>
  std::map<types::material_id, MaterialProperties>
  ElasticitySimulator<dim>::Impl::parse_bodies(const std::string &text,
                                               const std::string &entry) const
  {
    std::map<unsigned int, std::map<std::string, double>> records;
    for (const auto &r : parse_records(text, 1, entry))
      records[r.id] = parse_key_values(r.fields[0], entry);
    std::map<types::material_id, MaterialProperties> result;
    for (const auto id : all_ids)
      {
        const bool specific = records.count(id) > 0;
        AssertThrow(specific || records.count(any_id),
                    ExcMessage(entry + " has no record for material id " +
                               std::to_string(id) +
                               ", which the mesh uses (a record '* : ...' "
                               "covers all ids not listed)."));
        const std::string where = entry + ", material id " + std::to_string(id);
        const auto        props = MaterialProperties::from_key_values(
          records.at(specific ? id : any_id), p.model, dim, where);
        Material<dim>(p.model, props, p.plane_stress); // checks plane stress
        result.emplace(id, props);
      }
    return result;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::reset_physical_parameters(
    const std::string &text)
  {
    const auto props =
      text.empty() ? bodies : parse_bodies(text, "Objective/Reference bodies");
    cell_lame->value.assign(tria->n_active_cells(), {{0., 0.}});
    cell_damping->value.assign(tria->n_active_cells(), {{0., 0.}});
    for (const auto &cell : tria->active_cell_iterators())
      if (!cell->is_artificial())
        {
          const auto &m = props.at(cell->material_id());
          cell_lame->value[cell->active_cell_index()]    = {{m.lambda, m.mu}};
          cell_damping->value[cell->active_cell_index()] = {
            {m.damping_shear, m.damping_bulk}};
        }
    load_scales->value.assign(tractions.size() + pressures.size() +
                                (body_force ? 1 : 0) +
                                (gravity.norm() > 0 ? 1 : 0),
                              1.);
    shape_field->offset.reinit(shape_owned, comm);
    if (initial)
      {
        initial->displacement.reinit(owned, comm);
        initial->velocity.reinit(owned, comm);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::size_physical_parameters()
  {
    shape_field->sensitivity.reinit(shape_owned, comm);
    if (!initial)
      return;
    initial->displacement_sensitivity.reinit(owned, comm);
    initial->velocity_sensitivity.reinit(owned, comm);
    initial->component = owned_components();
    // The body of a DoF: that of the first cell that has it.
    initial->body.assign(owned.n_elements(), numbers::invalid_material_id);
    std::vector<bool>                    seen(owned.n_elements(), false);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (const auto i : dofs)
            if (owned.is_element(i) && !seen[owned.index_within_set(i)])
              {
                seen[owned.index_within_set(i)]          = true;
                initial->body[owned.index_within_set(i)] = cell->material_id();
              }
        }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::setup_shape()
  {
    shape_dof_handler.distribute_dofs(*shape_fe);
    shape_owned = shape_dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(shape_dof_handler, shape_relevant);

    // Which vertices the design may move: hanging vertices follow their
    // parents, vertices on fixed boundaries stay, symmetry planes keep one
    // coordinate.
    shape_constraints.clear();
    shape_constraints.reinit(shape_relevant);
    DoFTools::make_hanging_node_constraints(shape_dof_handler,
                                            shape_constraints);
    std::set<types::boundary_id> mesh_ids;
    for (const auto b : tria->get_boundary_ids())
      mesh_ids.insert(b);
    auto constrain = [&](const unsigned int       id,
                         const std::vector<bool> &mask,
                         const std::string       &entry) {
      AssertThrow(mesh_ids.count(id),
                  ExcMessage("'" + entry + "': the mesh has no boundary id " +
                             std::to_string(id) + "."));
      VectorTools::interpolate_boundary_values(
        reference_mapping,
        shape_dof_handler,
        static_cast<types::boundary_id>(id),
        Functions::ZeroFunction<dim>(dim),
        shape_constraints,
        ComponentMask(mask));
    };
    for (const auto &id :
         Utilities::split_string_list(p.design.fixed_boundaries, ','))
      constrain(Utilities::string_to_int(id),
                std::vector<bool>(dim, true),
                "Design/Fixed boundaries");
    {
      std::set<types::material_id> fixed_bodies;
      for (const auto &id :
           Utilities::split_string_list(p.design.fixed_bodies, ','))
        fixed_bodies.insert(Utilities::string_to_int(id));
      std::set<types::material_id> mesh_materials;
      for (const auto &cell : tria->active_cell_iterators())
        if (!cell->is_artificial())
          mesh_materials.insert(cell->material_id());
      mesh_materials = Utilities::MPI::compute_set_union(mesh_materials, comm);
      for (const auto m : fixed_bodies)
        AssertThrow(mesh_materials.count(m),
                    ExcMessage("'Design/Fixed bodies': the mesh has no "
                               "material id " +
                               std::to_string(m) + "."));
      for (const auto &cell : shape_dof_handler.active_cell_iterators())
        if (!cell->is_artificial() && fixed_bodies.count(cell->material_id()))
          for (const auto v : cell->vertex_indices())
            for (unsigned int d = 0; d < dim; ++d)
              {
                const auto i = cell->vertex_dof_index(v, d);
                if (!shape_constraints.is_constrained(i))
                  shape_constraints.add_line(i);
              }
    }
    for (const auto &r :
         parse_records(p.design.symmetry_planes, 1, "Design/Symmetry planes"))
      constrain(r.id,
                parse_components(r.fields[0], dim, "Design/Symmetry planes"),
                "Design/Symmetry planes");
    if (!p.mesh.separate_interfaces.empty())
      tie_separated_vertices();
    shape_constraints.make_consistent_in_parallel(shape_owned,
                                                  shape_relevant,
                                                  comm);
    shape_constraints.close();

    Vector_t X(shape_owned, comm);
    VectorTools::get_position_vector(mesh_mapping[0], shape_dof_handler, X);
    // get_position_vector also writes entries of other ranks, buffered until
    // a compress: flush them before X is overwritten below.
    X.compress(VectorOperation::insert);
    shape_reference.reinit(shape_owned, shape_relevant, comm);
    shape_reference = X;
    shape_ghost.reinit(shape_owned, shape_relevant, comm);
    shape_ghost = X;

    // Material coordinates: the mesh itself, or after a remesh the values
    // carried over to its vertices.
    if (!material_of_vertex.empty())
      {
        const auto before = [](const Point<dim> &a, const Point<dim> &b) {
          return std::lexicographical_compare(a.begin_raw(),
                                              a.end_raw(),
                                              b.begin_raw(),
                                              b.end_raw());
        };
        for (const auto &cell : shape_dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const auto v : cell->vertex_indices())
              {
                const auto it =
                  std::lower_bound(material_of_vertex.begin(),
                                   material_of_vertex.end(),
                                   cell->vertex(v),
                                   [&](const auto &entry, const Point<dim> &x) {
                                     return before(entry.first, x);
                                   });
                AssertThrow(it != material_of_vertex.end() &&
                              it->first == cell->vertex(v),
                            ExcInternalError());
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    const auto i = cell->vertex_dof_index(v, d);
                    if (shape_owned.is_element(i))
                      X(i) = it->second[d];
                  }
              }
        X.compress(VectorOperation::insert);
      }
    material_positions.reinit(shape_owned, shape_relevant, comm);
    material_positions = X;
    // The mappings refer to the DoF handler's element: rebuild them with it.
    mapping = hp::MappingCollection<dim>(
      MappingFEField<dim, dim, Vector_t>(shape_dof_handler, shape_ghost));
    if (!material_of_vertex.empty())
      reference_mapping = hp::MappingCollection<dim>(
        MappingFEField<dim, dim, Vector_t>(shape_dof_handler,
                                           material_positions));
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::tie_separated_vertices()
  {
    // The copies of a vertex made by Mesh/Separate interfaces coincide: the
    // design moves them together, so the parts
    // stay in contact along the interface whatever the shape.
    using Entry =
      std::pair<Point<dim>, std::array<types::global_dof_index, dim>>;
    std::vector<Entry> entries;
    for (const auto &cell : shape_dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (const auto v : cell->face(f)->vertex_indices())
              {
                Entry e{cell->face(f)->vertex(v), {}};
                for (unsigned int d = 0; d < dim; ++d)
                  e.second[d] = cell->face(f)->vertex_dof_index(v, d);
                entries.push_back(e);
              }
    const auto before = [](const Entry &a, const Entry &b) {
      if (a.first != b.first)
        return std::lexicographical_compare(a.first.begin_raw(),
                                            a.first.end_raw(),
                                            b.first.begin_raw(),
                                            b.first.end_raw());
      return a.second < b.second;
    };
    std::sort(entries.begin(), entries.end(), before);
    entries.erase(std::unique(entries.begin(),
                              entries.end(),
                              [](const Entry &a, const Entry &b) {
                                return a.second == b.second;
                              }),
                  entries.end());
    for (std::size_t a = 0; a < entries.size();)
      {
        std::size_t b = a + 1;
        while (b < entries.size() && entries[b].first == entries[a].first)
          ++b;
        for (unsigned int d = 0; d < dim; ++d)
          {
            // Lead: a copy already constrained (fixed, hanging), so the
            // others follow it through a chain; else the first.
            std::size_t lead = a;
            for (std::size_t k = a; k < b; ++k)
              if (shape_constraints.is_constrained(entries[k].second[d]))
                {
                  lead = k;
                  break;
                }
            for (std::size_t k = a; k < b; ++k)
              {
                const auto i = entries[k].second[d];
                if (k == lead || shape_constraints.is_constrained(i) ||
                    !shape_relevant.is_element(i))
                  continue;
                shape_constraints.add_line(i);
                shape_constraints.add_entry(i, entries[lead].second[d], 1.);
              }
          }
        a = b;
      }
  }



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
  void
  ElasticitySimulator<dim>::Impl::add_registered_forms()
  {
    const std::string entry    = "Loads/Additional forms";
    const auto       &registry = FormRegistry<dim>::instance();
    for (const auto &text : split_top_level(p.additional_forms, ';'))
      {
        if (Utilities::trim(text).empty())
          continue;
        const auto      colon = text.find(':');
        FormRecord<dim> r;
        r.name  = Utilities::trim(text.substr(0, colon));
        r.where = entry + ", form '" + r.name + "'";
        r.keys  = parse_key_values(
          colon == std::string::npos ? "" : text.substr(colon + 1), entry);
        r.physical  = &physical;
        r.bodies    = &bodies;
        r.transient = p.problem == "transient";
        forms.push_back(registry.get(r.name, entry).create(r));
      }
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
    Scratch<dim>                                         &s) const
  {
    const FEValuesExtractors::Vector disp(0);
    const unsigned int               nq    = fv.n_quadrature_points;
    const unsigned int               needs = form_needs();
    PointStates<dim>                &ps    = s.states;
    ps.cell           = {cell->active_cell_index(), cell->material_id(), 0};
    ps.time           = time;
    ps.dt             = transient ? dt : 0.;
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
  void
  ElasticitySimulator<dim>::Impl::setup_system()
  {
    setup_shape();
    dof_handler.distribute_dofs(fe);
    owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    size_physical_parameters();
    reset_physical_parameters("");

    constraint_lines = relevant;
    if (ipc_contact)
      {
        ipc_contact->setup(
          dof_handler, mapping, owned, comm, &shape_dof_handler);
        constraint_lines.add_indices(ipc_contact->collision_dofs());
      }
    make_constraints(time);
    contact.setup(dof_handler, mapping, face_quadrature);
    check_parts_are_held(*tria);
    build_jacobian_pattern();

    u.reinit(owned, comm);
    residual.reinit(owned, comm);
    u_ghost.reinit(owned, relevant, comm);
    w_ghost.reinit(owned, relevant, comm);
    u_old_ghost.reinit(owned, relevant, comm);
    v.reinit(owned, comm);
    if (p.linear_solver.type != "direct")
      compute_null_space();
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::check_parts_are_held(
    const Triangulation<dim> &mesh) const
  {
    // Inertia and IPC barriers hold parts by other means.
    if (p.problem != "static" || ipc_contact)
      return;
    // Every rank needs all cells to see whole parts: serial meshes and the
    // shared triangulations of penalty contact have them.
    if (mesh.n_active_cells() != mesh.n_global_active_cells())
      return;
    // What each boundary id does: bit d a Dirichlet condition on component
    // d, bit dim rigid contact (which may hold in any direction), bit
    // dim + 1 deformable contact (which joins parts).
    const unsigned int rigid = 1u << dim, deformable = 2u << dim;
    std::map<types::boundary_id, unsigned int> holds;
    for (const auto &d : dirichlet)
      for (unsigned int c = 0; c < dim; ++c)
        if (d.mask[c])
          holds[d.id] |= 1u << c;
    for (const auto &[id, law] : contact.parameters.rigid)
      holds[id] |= rigid;
    for (const auto &[id, law] : contact.parameters.deformable)
      holds[id] |= deformable;

    // Parts are the vertex-connected components of the mesh (separated
    // interfaces have their own vertices on each side). Parts in
    // deformable contact (coincident faces) may hold each other: they are
    // joined, and the group needs a support.
    std::vector<unsigned int> root(mesh.n_vertices());
    std::iota(root.begin(), root.end(), 0u);
    const auto find = [&root](unsigned int v) {
      while (root[v] != v)
        v = root[v] = root[root[v]];
      return v;
    };
    const auto unite = [&](const unsigned int v, const unsigned int w) {
      root[find(v)] = find(w);
    };
    const BoundingBox<dim> all(mesh.get_vertices());
    double                 tol = 0;
    for (unsigned int d = 0; d < dim; ++d)
      tol = std::max(tol, 1e-8 * all.side_length(d));
    std::map<std::array<long long, dim>, unsigned int> contact_faces;
    for (const auto &cell : mesh.active_cell_iterators())
      {
        for (const unsigned int v : cell->vertex_indices())
          unite(cell->vertex_index(v), cell->vertex_index(0));
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && holds.count(face->boundary_id()) > 0 &&
              (holds.at(face->boundary_id()) & deformable) != 0)
            {
              std::array<long long, dim> key;
              for (unsigned int d = 0; d < dim; ++d)
                key[d] = std::llround(face->center()[d] / tol);
              const auto [other, first] =
                contact_faces.emplace(key, face->vertex_index(0));
              if (!first)
                unite(other->second, face->vertex_index(0));
            }
      }
    std::vector<unsigned int> part_holds(mesh.n_vertices(), 0);
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          if (const auto h = holds.find(face->boundary_id()); h != holds.end())
            part_holds[find(face->vertex_index(0))] |= h->second;
    const unsigned int all_components = (1u << dim) - 1;
    const auto         held           = [&](const unsigned int part) {
      return (part_holds[part] & rigid) != 0 ||
             (part_holds[part] & all_components) == all_components;
    };

    // The first part (or group) not held, in cell order (deterministic).
    std::optional<unsigned int>  part;
    std::set<types::material_id> materials;
    unsigned int                 n_cells = 0;
    BoundingBox<dim>             box;
    for (const auto &cell : mesh.active_cell_iterators())
      {
        const unsigned int r = find(cell->vertex_index(0));
        if (held(r) || (part && *part != r))
          continue;
        part = r;
        materials.insert(cell->material_id());
        if (n_cells++ == 0)
          box = cell->bounding_box();
        else
          box.merge_with(cell->bounding_box());
      }
    if (!part)
      return;
    const unsigned int what = part_holds[*part];
    std::string        ids, free;
    for (const auto m : materials)
      ids += (ids.empty() ? "" : ", ") + std::to_string(m);
    for (unsigned int c = 0; c < dim; ++c)
      if ((what & (1u << c)) == 0)
        free += (free.empty() ? "" : ", ") + std::string(1, "xyz"[c]);
    const auto point = [](const Point<dim> &x) {
      std::string s = "(";
      for (unsigned int d = 0; d < dim; ++d)
        s += (d > 0 ? ", " : "") + fmt(x[d], 4);
      return s + ")";
    };
    const bool        group = (what & deformable) != 0;
    const std::string has = group ? "have" : "has", it = group ? "them" : "it";
    AssertThrow(
      false,
      ExcMessage(
        "Boundary conditions: the part" +
        std::string(group ? "s in deformable contact with each other" : "") +
        " of material " + (materials.size() > 1 ? "ids " : "id ") + ids +
        " between " + point(box.get_boundary_points().first) + " and " +
        point(box.get_boundary_points().second) + " (" +
        std::to_string(n_cells) + " cells) " + has +
        ((what & all_components) == 0 ?
           " no Dirichlet boundary (Boundary conditions/Dirichlet) and no "
           "rigid contact (Contact/Rigid-deformable): nothing holds " +
             it :
           " no rigid contact and no Dirichlet condition on " + free +
             ": nothing holds " + it + " in " + free) +
        ", so the static problem is singular."));
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::build_jacobian_pattern()
  {
    // Rows of constraint_lines are writable: contact adds to rows of DoFs
    // owned elsewhere.
    TrilinosWrappers::SparsityPattern sp(owned, owned, constraint_lines, comm);
    DoFTools::make_sparsity_pattern(dof_handler,
                                    sp,
                                    constraints_zero,
                                    false,
                                    Utilities::MPI::this_mpi_process(comm));
    for (const auto &f : forms)
      f->add_couplings(constraints_zero, sp);
    sp.compress();
    jacobian.reinit(sp);
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
  ElasticitySimulator<dim>::Impl::make_constraints(const double t)
  {
    for (auto *c : {&constraints_zero, &constraints_bc})
      {
        c->clear();
        c->reinit(constraint_lines);
        DoFTools::make_hanging_node_constraints(dof_handler, *c);
      }
    for (const auto &d : dirichlet)
      {
        d.function->set_time(t);
        VectorTools::interpolate_boundary_values(reference_mapping,
                                                 dof_handler,
                                                 d.id,
                                                 *d.function,
                                                 constraints_bc,
                                                 ComponentMask(d.mask));
        VectorTools::interpolate_boundary_values(reference_mapping,
                                                 dof_handler,
                                                 d.id,
                                                 Functions::ZeroFunction<dim>(
                                                   dim),
                                                 constraints_zero,
                                                 ComponentMask(d.mask));
      }
    for (auto *c : {&constraints_zero, &constraints_bc})
      {
        c->make_consistent_in_parallel(owned, constraint_lines, comm);
        c->close();
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::compute_null_space()
  {
    std::map<types::global_dof_index, Point<dim>> support;
    DoFTools::map_dofs_to_support_points(mapping, dof_handler, support);
    const std::vector<unsigned int>  component = owned_components();
    const unsigned int               n_rot     = dim == 2 ? 1 : 3;
    std::vector<std::vector<double>> modes(
      dim + n_rot, std::vector<double>(owned.n_elements()));
    for (const auto i : owned)
      {
        const unsigned int k = owned.index_within_set(i);
        const unsigned int c = component[k];
        const Point<dim>   x = support.at(i);
        modes[c][k]          = 1.;
        if (dim == 2)
          modes[2][k] = (c == 0 ? -x[1] : x[0]);
        else
          {
            // rotations about z, x, y
            const double r_z[3] = {-x[1], x[0], 0};
            const double r_x[3] = {0, -x[dim - 1], x[1]};
            const double r_y[3] = {x[dim - 1], 0, -x[0]};
            modes[dim][k]       = r_z[c];
            modes[dim + 1][k]   = r_x[c];
            modes[dim + 2][k]   = r_y[c];
          }
      }
    linear_solver.set_null_space(modes);
  }



  template <int dim>
  bool
  ElasticitySimulator<dim>::Impl::assemble(const Vector_t &u_owned,
                                           const bool      with_matrix,
                                           Vector_t       *raw)
  {
    Timer timer;
    u_ghost = u_owned;
    if (with_matrix)
      jacobian = 0;
    residual = 0;
    if (raw)
      *raw = 0;
    const bool energy = potential_merit();
    for (const auto &f : forms)
      f->set_time(time);

    // The point terms of the forms, contracted with the shape functions:
    //   h_i = sum_q (flux_q : grad phi_i + source_q . phi_i) JxW_q.
    auto worker =
      [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
          Scratch<dim>                                         &s,
          CopyData                                             &c) {
        s.fe_values.reinit(cell);
        const FEValues<dim> &fv  = s.fe_values.get_present_fe_values();
        const auto          &cfe = fv.get_fe();
        const unsigned int   n   = cfe.n_dofs_per_cell();
        const unsigned int   nq  = fv.n_quadrature_points;
        c.dofs.resize(n);
        cell->get_dof_indices(c.dofs);
        c.residual.reinit(n);
        if (with_matrix)
          c.matrix.reinit(n, n);
        c.admissible = true;
        c.energy     = 0;

        fill_states(cell, fv, numbers::invalid_unsigned_int, s);
        PointTerms<dim> &t = s.terms;
        reset_terms(t, nq, with_matrix, false, energy);
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

        s.B.resize(n);
        for (unsigned int q = 0; q < nq; ++q)
          {
            const double JxW = fv.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              {
                const unsigned int ci = cfe.system_to_component_index(i).first;
                const Tensor<1, dim> &gi = fv.shape_grad(i, q);
                const double          vi = fv.shape_value(i, q);
                c.residual(i) +=
                  (t.flux[q][ci] * gi + t.source[q][ci] * vi) * JxW;
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
                  const unsigned int ci =
                    cfe.system_to_component_index(i).first;
                  const double vi = fv.shape_value(i, q);
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

        if (cell->at_boundary())
          for (const auto face : cell->face_indices())
            if (cell->face(face)->at_boundary() &&
                loaded(cell->face(face)->boundary_id()))
              {
                s.face_values.reinit(cell, face);
                const FEFaceValues<dim> &ff =
                  s.face_values.get_present_fe_values();
                fill_states(cell, ff, face, s);
                reset_terms(
                  t, ff.n_quadrature_points, with_matrix, false, energy);
                for (const auto &f : forms)
                  if (form_active(*f) &&
                      f->acts_on_boundary(s.states.cell.boundary_id))
                    f->face_terms(s.states, t);
                c.energy += t.energy;
                for (unsigned int q = 0; q < ff.n_quadrature_points; ++q)
                  for (unsigned int i = 0; i < n; ++i)
                    {
                      const unsigned int ci =
                        cfe.system_to_component_index(i).first;
                      const double vi = ff.shape_value(i, q);
                      c.residual(i) += t.source[q][ci] * vi * ff.JxW(q);
                      if (with_matrix && t.source_tangent[q] != 0)
                        for (unsigned int j = 0; j < n; ++j)
                          if (cfe.system_to_component_index(j).first == ci)
                            c.matrix(i, j) += t.source_tangent[q] * vi *
                                              ff.shape_value(j, q) * ff.JxW(q);
                    }
              }
      };

    bool   admissible = true;
    double energy_sum = 0;
    auto   copier     = [&](const CopyData &c) {
      if (!c.admissible)
        {
          admissible = false;
          return;
        }
      energy_sum += c.energy;
      if (with_matrix && transpose_matrix)
        {
          FullMatrix<double> t(c.matrix.n(), c.matrix.m());
          t.copy_transposed(c.matrix);
          constraints_zero.distribute_local_to_global(
            t, c.residual, c.dofs, jacobian, residual);
        }
      else if (with_matrix)
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
                                             with_matrix ? &jacobian : nullptr,
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
    if (with_matrix)
      jacobian.compress(VectorOperation::add);
    residual.compress(VectorOperation::add);
    if (raw)
      raw->compress(VectorOperation::add);
    admissible       = Utilities::MPI::min(admissible ? 1 : 0, comm) == 1;
    potential_energy = Utilities::MPI::sum(energy_sum, comm);
    assembly_seconds += timer.wall_time();
    return admissible;
  }



  template <int dim>
  std::pair<unsigned int, unsigned int>
  ElasticitySimulator<dim>::Impl::newton(const double       t,
                                         const std::string &where)
  {
    time = t;
    make_constraints(t);
    const Vector_t before = ipc_contact ? u : Vector_t();
    constraints_bc.distribute(u);
    if (ipc_contact)
      {
        // Prescribed boundary motion is not filtered by the barrier: it
        // must not carry a boundary into (or through) another.
        Vector_t jump = u;
        jump -= before;
        if (jump.linfty_norm() > 0)
          {
            if (ipc_contact->update_candidates(before, &jump))
              build_jacobian_pattern();
            const double s = ipc_contact->max_step(before, jump, 1e-3);
            AssertThrow(s >= 1.,
                        ExcMessage(
                          where + " (t = " + fmt(t) +
                          "): the prescribed displacements (Dirichlet) of "
                          "this step carry a boundary into contact (CCD stops "
                          "them at " +
                          fmt(s, 3) +
                          " of the step); use more load steps or a smaller "
                          "time step, or let contact move those parts."));
          }
        if (ipc_contact->update_candidates(u, nullptr))
          build_jacobian_pattern();
      }

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
    Vector_t     du(owned, comm), trial(owned, comm);
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
        linear_its +=
          linear_solver.solve(jacobian, du, rhs, fe.max_degree() > 1);
        solver_seconds += timer.wall_time();
        constraints_zero.distribute(du);

        // IPC: no step may bring a pair into contact (CCD along the step).
        double max_step = 1.;
        if (ipc_contact)
          {
            if (du.linfty_norm() <= step_tolerance)
              {
                if (context)
                  context->log("    Newton step below the step tolerance, "
                               "residual " +
                               fmt(norm, 3));
                return {it, linear_its};
              }
            if (ipc_contact->update_candidates(u, &du))
              build_jacobian_pattern();
            max_step = ipc_contact->max_step(u, du);
            if (max_step < 1.)
              ++ccd_limited_steps;
          }

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

        double step     = max_step;
        bool   accepted = false;
        for (unsigned int h = 0; h <= p.max_line_search_halvings;
             ++h, step *= 0.5)
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
                (energy_merit ?
                   potential_energy <= energy0 + 1e-4 * step * slope ||
                     residual_fallback :
                   trial_norm < (1. - 1e-4 * step) * norm))
              {
                u        = trial;
                norm     = trial_norm;
                accepted = true;
                break;
              }
          }
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
                       fmt(norm, 3) + ", step " + fmt(step, 3));
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
  void
  ElasticitySimulator<dim>::Impl::compute_reactions()
  {
    Vector_t raw(owned, comm);
    assemble(u, false, &raw);
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
    out.build_patches(mapping, simplex ? 1 : fe.max_degree());
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



  template <int dim>
  std::vector<unsigned int>
  ElasticitySimulator<dim>::Impl::owned_components() const
  {
    std::vector<unsigned int> component(owned.n_elements());
    for (unsigned int c = 0; c < dim; ++c)
      {
        std::vector<bool> m(dim, false);
        m[c] = true;
        for (const auto i :
             DoFTools::extract_dofs(dof_handler, ComponentMask(m)))
          if (owned.is_element(i))
            component[owned.index_within_set(i)] = c;
      }
    return component;
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



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::refine_mesh()
  {
    auto *ptria =
      dynamic_cast<parallel::distributed::Triangulation<dim> *>(tria.get());
    AssertThrow(ptria != nullptr,
                ExcMessage("adaptivity needs a quad/hex mesh."));
    u_ghost = u;
    estimated_error.reinit(tria->n_active_cells());
    KellyErrorEstimator<dim>::estimate(
      mapping[0],
      dof_handler,
      face_quadrature,
      std::map<types::boundary_id, const Function<dim> *>(),
      u_ghost,
      estimated_error);
    parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
      *ptria, estimated_error, p.refine_fraction, p.coarsen_fraction);
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
        hp::Refinement::choose_p_over_h(dof_handler);
      }
    tria->execute_coarsening_and_refinement();
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::run(RunContext *ctx)
  {
    context = ctx;
    const unsigned int n_cycles =
      p.adaptivity == "none" ? 1 : p.adaptive_cycles + 1;
    for (unsigned int cycle = 0; cycle < n_cycles; ++cycle)
      {
        if (cycle > 0)
          refine_mesh();
        setup_system();
        if (context)
          context->print(
            (n_cycles > 1 ? "[cycle " + std::to_string(cycle) + "/" +
                              std::to_string(n_cycles - 1) + "] " :
                            std::string()) +
            std::to_string(dim) + "D " + p.problem + ", " +
            (p.model == ConstitutiveModel::linear_elastic ? "linear elastic" :
                                                            "neo-hookean") +
            ", " + std::to_string(tria->n_global_active_cells()) + " cells, " +
            std::to_string(dof_handler.n_dofs()) + " DoFs");
        steps.clear();
        max_von_mises = max_frobenius = 0;
        if (p.problem == "static")
          {
            solve_static();
            write_output(cycle, p.end_time);
          }
        else
          solve_transient();
        typename ElasticitySimulator<dim>::CycleRecord c;
        c.cycle   = cycle;
        c.n_cells = tria->n_global_active_cells();
        c.n_dofs  = dof_handler.n_dofs();
        cycles.push_back(c);
        if (cycle_callback)
          cycle_callback(cycle);
      }
    compute_reactions();
    if (contact.active())
      contact_statistics = contact.statistics(mapping, u_ghost, comm);
    if (context)
      {
        for (const auto &r : reactions)
          context->print("reaction on boundary " + std::to_string(r.first) +
                         ": " + fmt(r.second));
        for (const auto &c : contact_statistics)
          {
            Tensor<1, dim> f;
            for (unsigned int d = 0; d < dim; ++d)
              f[d] = c["force"][d];
            context->print(
              "contact on boundary " + std::to_string(int(c["boundary"])) +
              " (" + std::string(c["type"]) + "): force " + fmt(f) +
              ", active area " + fmt(double(c["active_area"])) +
              ", max penetration " + fmt(double(c["max_penetration"]), 3) +
              ", max slip " + fmt(double(c["max_slip"]), 3));
          }
        if (ipc_contact)
          context->print(
            "IPC: smallest distance " +
            (run_min_distance < std::numeric_limits<double>::max() ?
               fmt(run_min_distance, 3) :
               std::string("above dhat")) +
            " (dhat " + fmt(ipc_contact->barrier_distance(), 3) +
            "), inverted elements " + std::to_string(inverted_elements));
        context->print("max von Mises stress: " + fmt(max_von_mises) +
                       ", max Frobenius stress: " + fmt(max_frobenius));
        context->log("assembly wall time " + fmt(assembly_seconds, 4) +
                     " s, linear solver wall time " + fmt(solver_seconds, 4) +
                     " s");
      }
  }



  // ---------------------------------------------------------------- facade

  template <int dim>
  ElasticitySimulator<dim>::ElasticitySimulator(const ElasticityParameters &p,
                                                const MPI_Comm comm)
    : impl(std::make_unique<Impl>(p, comm))
  {}

  template <int dim>
  ElasticitySimulator<dim>::~ElasticitySimulator() = default;

  template <int dim>
  void
  ElasticitySimulator<dim>::run(RunContext *context)
  {
    impl->run(context);
    if (context)
      {
        auto s = summary();
        for (auto it = s.begin(); it != s.end(); ++it)
          context->summary[it.key()] = it.value();
      }
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::set_cycle_callback(
    const std::function<void(unsigned int)> &callback)
  {
    impl->cycle_callback = callback;
  }

  template <int dim>
  Tensor<1, dim>
  ElasticitySimulator<dim>::point_displacement(const Point<dim> &x) const
  {
    impl->u_ghost = impl->u;
    return impl->point_value(x);
  }

  template <int dim>
  std::vector<std::vector<std::pair<Point<dim>, Tensor<1, dim>>>>
  ElasticitySimulator<dim>::cell_vertex_displacements() const
  {
    auto &m   = *impl;
    m.u_ghost = m.u;
    // Per cell 2^dim slots of (x, u) (simplices use fewer), summed over the
    // ranks; the vertex count is sent along.
    constexpr unsigned int slots = GeometryInfo<dim>::vertices_per_cell;
    constexpr unsigned int width = 1 + slots * 2 * dim;
    std::vector<double>    flat(width * m.tria->n_global_active_cells(), 0.);
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int n = cell->n_vertices();
          // Around the cell in 2D: quads are numbered lexicographically.
          std::vector<unsigned int> order(n);
          for (unsigned int v = 0; v < n; ++v)
            order[v] = v;
          if (dim == 2 && n == 4)
            order = {0, 1, 3, 2};
          double *row = flat.data() + width * cell->global_active_cell_index();
          row[0]      = n;
          for (unsigned int k = 0; k < n; ++k)
            {
              const unsigned int v = order[k];
              const Point<dim>   x = cell->vertex(v);
              for (unsigned int d = 0; d < dim; ++d)
                {
                  row[1 + 2 * dim * k + d] = x[d];
                  row[1 + 2 * dim * k + dim + d] =
                    m.u_ghost[cell->vertex_dof_index(
                      v, d, cell->active_fe_index())];
                }
            }
        }
    Utilities::MPI::sum(flat, m.comm, flat);
    std::vector<std::vector<std::pair<Point<dim>, Tensor<1, dim>>>> cells(
      m.tria->n_global_active_cells());
    for (unsigned int c = 0; c < cells.size(); ++c)
      {
        const double *row = flat.data() + width * c;
        for (unsigned int k = 0; k < static_cast<unsigned int>(row[0]); ++k)
          {
            Point<dim>     x;
            Tensor<1, dim> u;
            for (unsigned int d = 0; d < dim; ++d)
              {
                x[d] = row[1 + 2 * dim * k + d];
                u[d] = row[1 + 2 * dim * k + dim + d];
              }
            cells[c].emplace_back(x, u);
          }
      }
    return cells;
  }

  template <int dim>
  Tensor<1, dim>
  ElasticitySimulator<dim>::reaction(const unsigned int id) const
  {
    AssertThrow(impl->reactions.count(id),
                ExcMessage("no boundary id " + std::to_string(id)));
    return impl->reactions.at(id);
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::error_norm(const Function<dim> &exact,
                                       const bool           h1) const
  {
    impl->u_ghost = impl->u;
    Vector<float>        cell_errors(impl->tria->n_active_cells());
    hp::QCollection<dim> q;
    for (unsigned int k = 0; k < impl->quadrature.size(); ++k)
      q.push_back(impl->simplex ?
                    impl->tria->get_reference_cells()[0]
                      .template get_gauss_type_quadrature<dim>(
                        std::min(impl->fe[k].degree + 2, 4u)) :
                    Quadrature<dim>(QGauss<dim>(impl->fe[k].degree + 3)));
    const auto norm = h1 ? VectorTools::H1_seminorm : VectorTools::L2_norm;
    VectorTools::integrate_difference(impl->mapping,
                                      impl->dof_handler,
                                      impl->u_ghost,
                                      exact,
                                      cell_errors,
                                      q,
                                      norm);
    return VectorTools::compute_global_error(*impl->tria, cell_errors, norm);
  }

  template <int dim>
  unsigned long long
  ElasticitySimulator<dim>::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }

  template <int dim>
  const std::vector<typename ElasticitySimulator<dim>::StepRecord> &
  ElasticitySimulator<dim>::steps() const
  {
    return impl->steps;
  }

  template <int dim>
  const std::vector<typename ElasticitySimulator<dim>::CycleRecord> &
  ElasticitySimulator<dim>::cycles() const
  {
    return impl->cycles;
  }

  template <int dim>
  nlohmann::json
  ElasticitySimulator<dim>::summary() const
  {
    nlohmann::json s;
    s["dimension"]            = dim;
    s["n_dofs"]               = impl->dof_handler.n_dofs();
    s["n_cells"]              = impl->tria->n_global_active_cells();
    s["n_mpi_processes"]      = Utilities::MPI::n_mpi_processes(impl->comm);
    s["max_von_mises_stress"] = impl->max_von_mises;
    s["max_frobenius_stress"] = impl->max_frobenius;
    nlohmann::json steps      = nlohmann::json::array();
    for (const auto &r : impl->steps)
      {
        nlohmann::json j;
        j["step"]              = r.step;
        j["time"]              = r.time;
        j["newton_iterations"] = r.newton_iterations;
        j["linear_iterations"] = r.linear_iterations;
        j["residual"]          = r.residual;
        j["kinetic_energy"]    = r.kinetic_energy;
        j["elastic_energy"]    = r.elastic_energy;
        j["gravity_potential"] = r.gravity_potential;
        j["mean_displacement"] = to_json(r.mean_displacement);
        nlohmann::json pts     = nlohmann::json::array();
        for (const auto &d : r.point_displacements)
          pts.push_back(to_json(d));
        j["point_displacements"] = pts;
        if (!r.contact.is_null())
          j["contact"] = r.contact;
        steps.push_back(j);
      }
    s["steps"]            = steps;
    nlohmann::json cycles = nlohmann::json::array();
    for (const auto &c : impl->cycles)
      cycles.push_back(
        {{"cycle", c.cycle}, {"n_cells", c.n_cells}, {"n_dofs", c.n_dofs}});
    s["cycles"] = cycles;
    nlohmann::json reactions;
    for (const auto &r : impl->reactions)
      reactions[std::to_string(r.first)] = to_json(r.second);
    s["reactions"] = reactions;
    if (impl->contact.active())
      s["contact"] = impl->contact_statistics;
    if (impl->ipc_contact)
      {
        const auto    &m = impl->ipc_contact->mesh();
        nlohmann::json c;
        c["barrier_distance"]     = impl->ipc_contact->barrier_distance();
        c["barrier_stiffness"]    = impl->ipc_contact->barrier_stiffness();
        c["collision_vertices"]   = m.n_vertices();
        c["collision_primitives"] = dim == 2 ? m.edges.size() : m.faces.size();
        c["min_distance"] =
          impl->run_min_distance < std::numeric_limits<double>::max() ?
            nlohmann::json(impl->run_min_distance) :
            nlohmann::json();
        c["inverted_elements"] = impl->inverted_elements;
        c["timings"]           = impl->ipc_contact->timings();
        s["ipc"]               = c;
      }
    nlohmann::json pts = nlohmann::json::array();
    for (const auto &x : impl->points)
      pts.push_back(to_json(Tensor<1, dim>(x)));
    s["points"] = pts;
    return s;
  }

  template class ElasticitySimulator<2>;
  template class ElasticitySimulator<3>;
} // namespace forma
