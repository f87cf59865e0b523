#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_q.h>
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
#include <forma/contact/penalty_contact_form.h>
#include <forma/elasticity/simulator.h>
#include <forma/mesh/mesh.h>
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
        // The goal estimate raises every cell one degree for the adjoint.
        const unsigned int top =
          (p.adaptivity == "hp" ? p.max_degree : p.degree) +
          (p.goal_estimate ? 1 : 0);
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
    if (p.adaptivity != "none" && p.goal_estimate)
      {
        goal = std::make_shared<const Objective<dim>>(p.objective);
        AssertThrow(!goal->needs_reference_run(),
                    ExcMessage(
                      "Finite element/Error indicator = goal (or "
                      "Goal estimate): objectives that track a reference run "
                      "(target terms) are not available; choose "
                      "another Objective/Terms."));
      }
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
    for (const auto &[id, m] : bodies)
      density[id] = m.density;
    // With IPC every model must stay inversion-free.
    auto elastic = std::make_unique<ElasticForm<dim>>(
      p.model, p.plane_stress, bodies, *cell_lame, ipc_contact != nullptr);
    elastic_form = elastic.get();
    forms.push_back(std::move(elastic));
    // Damping in every transient problem: a design or a reference run may
    // give damping to bodies that have none (undamped cells cost nothing
    // but their previous-step gradients).
    if (p.problem == "transient")
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
    if (p.linear_solver.type == "cg-mg")
      {
        for (const auto &f : forms)
          AssertThrow(!f->has_global_terms(),
                      ExcMessage("Solver/Linear solver = cg-mg cannot apply "
                                 "the global terms of the form '" +
                                 f->name() +
                                 "'; use cg-amg, gmres-amg or direct."));
        matrix_free =
          std::make_unique<MatrixFreeElasticity<dim>>(p.linear_solver);
      }
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
    physical.reset(); // parameters of added forms
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
  void
  ElasticitySimulator<dim>::Impl::run(RunContext *ctx)
  {
    context = ctx;
    cycles.clear();
    cycle_contact.clear();
    // Transient problems adapt during the run (Adaptive cycles refine the
    // initial state there).
    const unsigned int n_cycles =
      p.adaptivity == "none" || p.problem != "static" ? 1 :
                                                        p.adaptive_cycles + 1;
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
        typename ElasticitySimulator<dim>::CycleRecord c;
        if (p.problem == "static")
          {
            solve_static();
            if (goal)
              {
                std::tie(c.objective, c.estimate) = estimate_goal_error();
                if (context)
                  context->print(
                    "goal: J(u_h) = " + fmt(c.objective, 8) +
                    ", estimated J(u) - J(u_h) = " + fmt(c.estimate, 3));
              }
            write_output(cycle, p.end_time);
          }
        else
          solve_transient();
        if (contact.active() && n_cycles > 1)
          {
            u_ghost = u;
            cycle_contact.push_back(contact.statistics(mapping, u_ghost, comm));
          }
        c.cycle   = cycle;
        c.n_cells = tria->n_global_active_cells();
        c.n_dofs  = dof_handler.n_dofs();
        cycles.push_back(c);
        if (cycle_callback)
          cycle_callback(cycle);
      }
    compute_reactions();
    if (!cycle_contact.empty()) // the last cycle's, already computed
      contact_statistics = cycle_contact.back();
    else if (contact.active())
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
              ", max slip " + fmt(double(c["max_slip"]), 3) +
              ", max pressure " + fmt(double(c["max_pressure"]), 4));
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
        if (matrix_free)
          context->log("cg-mg: last preconditioner setup " +
                       fmt(matrix_free->last_times().first, 4) +
                       " s, last Krylov solve " +
                       fmt(matrix_free->last_times().second, 4) + " s");
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
    s["steps"] = steps;
    if (impl->p.time_integrator == "adaptive")
      {
        // Accepted steps per order, index 0: BDF1.
        const auto per_order =
          impl->time_grid.steps_per_order(impl->p.bdf_order);
        s["time_integration"] = {{"integrator", "adaptive"},
                                 {"accepted_steps", impl->time_grid.n_steps()},
                                 {"rejected_steps", impl->rejected_steps},
                                 {"steps_per_order", per_order}};
      }
    if (impl->transient_adaptivity && !impl->steps.empty())
      {
        // The cost of a run on moving meshes: DoFs summed over the steps.
        unsigned long long dof_steps = 0, fewest = impl->steps[0].n_dofs,
                           most = fewest;
        for (std::size_t k = 1; k < impl->steps.size(); ++k)
          {
            dof_steps += impl->steps[k].n_dofs;
            fewest = std::min(fewest, impl->steps[k].n_dofs);
            most   = std::max(most, impl->steps[k].n_dofs);
          }
        s["mesh_adaptation"] = {{"adapt_every", impl->p.adapt_every},
                                {"adaptations", impl->mesh_adaptations},
                                {"dof_steps", dof_steps},
                                {"min_dofs", fewest},
                                {"max_dofs", most}};
        for (std::size_t k = 0; k < impl->steps.size(); ++k)
          s["steps"][k]["n_dofs"] = impl->steps[k].n_dofs;
      }
    nlohmann::json cycles = nlohmann::json::array();
    for (const auto &c : impl->cycles)
      {
        nlohmann::json j = {{"cycle", c.cycle},
                            {"n_cells", c.n_cells},
                            {"n_dofs", c.n_dofs}};
        if (impl->goal)
          {
            j["objective"] = c.objective;
            j["estimate"]  = c.estimate;
          }
        if (c.cycle < impl->cycle_contact.size())
          j["contact"] = impl->cycle_contact[c.cycle];
        cycles.push_back(j);
      }
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
