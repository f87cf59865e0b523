// The adjoint layer of the elasticity simulator (thesis ch. 3.3-3.8): design
// vectors, objectives, static and BDF transient adjoints, and the parameter
// derivative products p^T d_q h of every force.

#include <deal.II/base/numbers.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_fe_field.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/physics/bdf.h>

#include "simulator_impl.h"

#include <cmath>
#include <cstdint>

namespace forma
{
  namespace
  {
    // Blocks in the order they appear in a design vector.
    const std::vector<std::string> block_order = {
      "shape",
      "cell material",
      "material",
      "damping",
      "friction",
      "loads",
      "initial displacement",
      "initial velocity",
      "initial displacement per body",
      "initial velocity per body",
      "initial displacement field",
      "initial velocity field"};

    // Product (A : B) of the rank-one gradient e_c (x) g with a tensor M:
    // sum_l M[c][l] g[l].
    template <int dim>
    inline double
    row_dot(const Tensor<2, dim> &M,
            const unsigned int    c,
            const Tensor<1, dim> &g)
    {
      return M[c] * g;
    }

    // H_kl = sum_ij G_ij A_ijkl.
    template <int dim>
    Tensor<2, dim>
    contract_left(const Tensor<2, dim> &G, const Tensor<4, dim> &A)
    {
      Tensor<2, dim> H;
      for (unsigned int i = 0; i < dim; ++i)
        for (unsigned int j = 0; j < dim; ++j)
          if (G[i][j] != 0)
            H += G[i][j] * A[i][j];
      return H;
    }

    // Shape-derivative kernel of an integrand of grad u transported with the
    // domain: d/d eps grad u = -grad u grad theta, so
    //   D : (-grad u grad theta) = -sum_l (sum_k D_kl gu_kc) dN_l
    // for theta = N e_c; returned as rows c of the tensor W_cl.
    template <int dim>
    Tensor<2, dim>
    transport_kernel(const Tensor<2, dim> &D, const Tensor<2, dim> &grad_u)
    {
      return -transpose(grad_u) * D;
    }
  } // namespace



  template <int dim>
  struct ElasticitySimulator<dim>::Impl::PhysicalGradient
  {
    Vector_t                           shape; ///< on shape DoFs, condensed
    std::vector<std::array<double, 2>> lame, damping; ///< per active cell
    std::vector<double>                loads;
    std::vector<double>                friction; ///< per IPC friction source
    Tensor<1, dim>                     initial_u, initial_v;
    Vector_t initial_u_field, initial_v_field; ///< dJ/du^0, dJ/dv^0
  };



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::build_design_layout()
  {
    layout.blocks.clear();
    unsigned int offset       = 0;
    const bool   is_transient = p.problem == "transient";
    design_bodies.clear();
    for (const auto &id : Utilities::split_string_list(p.design.bodies, ','))
      {
        const auto m = static_cast<types::material_id>(std::stoi(id));
        AssertThrow(all_ids.count(m),
                    ExcMessage("Design/Bodies: the mesh has no material id " +
                               id + "."));
        design_bodies.push_back(m);
      }
    if (design_bodies.empty())
      design_bodies.assign(all_ids.begin(), all_ids.end());
    for (const auto &name : block_order)
      {
        if (!p.design.has(name))
          continue;
        unsigned int size = 0;
        if (name == "shape")
          size = shape_dof_handler.n_dofs();
        else if (name == "cell material")
          size = 2 * tria->n_global_active_cells();
        else if (name == "material" || name == "damping")
          size = 2 * all_ids.size();
        else if (name == "friction")
          {
            AssertThrow(ipc_contact,
                        ExcMessage("Design/Parameters: 'friction' needs IPC "
                                   "contact (IPC/Enabled = true)."));
            size = ipc_contact->friction_names().size();
          }
        else if (name == "loads")
          size = tractions.size() + pressures.size() + (body_force ? 1 : 0) +
                 (gravity.norm() > 0 ? 1 : 0);
        else if (name.find("field") != std::string::npos)
          size = dof_handler.n_dofs();
        else if (name.find("per body") != std::string::npos)
          size = dim * design_bodies.size();
        else
          size = dim;
        AssertThrow(size > 0,
                    ExcMessage("Design/Parameters: 'loads' needs tractions, "
                               "pressures, a body force or gravity."));
        AssertThrow(is_transient ||
                      (name != "damping" && name.find("initial") != 0),
                    ExcMessage("Design/Parameters: '" + name +
                               "' needs a transient problem."));
        layout.blocks.push_back({name, offset, size});
        offset += size;
      }

    // The starting design: the mesh moved by the shape perturbation, the
    // materials of Material/Bodies, unit load scales, no offsets.
    design.assign(layout.size(), 0.);
    if (const auto *b = layout.find("shape"))
      if (!p.design.shape_perturbation.empty())
        {
          Vector_t delta(shape_owned, comm);
          VectorTools::interpolate(
            reference_mapping[0],
            shape_dof_handler,
            *make_function<dim>(split_top_level(p.design.shape_perturbation,
                                                ','),
                                std::vector<bool>(dim, true),
                                constants,
                                "Design/Shape perturbation"),
            delta);
          shape_constraints.set_zero(delta);
          std::vector<double> local(b->size, 0.);
          for (const auto i : shape_owned)
            local[i] = delta(i);
          Utilities::MPI::sum(local, comm, local);
          std::copy(local.begin(), local.end(), design.begin() + b->offset);
        }
    auto pair_of = [&](const MaterialProperties &m, const bool elastic) {
      if (!elastic)
        return std::array<double, 2>{{m.damping_shear, m.damping_bulk}};
      return p.design.young_poisson ?
               std::array<double, 2>{{m.youngs_modulus, m.poisson_ratio}} :
               std::array<double, 2>{{m.lambda, m.mu}};
    };
    if (const auto *b = layout.find("cell material"))
      {
        std::vector<double> local(b->size, 0.);
        for (const auto &cell : tria->active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto v = pair_of(bodies.at(cell->material_id()), true);
              local[2 * cell->global_active_cell_index()]     = v[0];
              local[2 * cell->global_active_cell_index() + 1] = v[1];
            }
        Utilities::MPI::sum(local, comm, local);
        std::copy(local.begin(), local.end(), design.begin() + b->offset);
      }
    unsigned int k = 0;
    for (const auto id : all_ids)
      {
        for (const std::string name : {"material", "damping"})
          if (const auto *b = layout.find(name))
            {
              const auto v = pair_of(bodies.at(id), name == "material");
              design[b->offset + 2 * k]     = v[0];
              design[b->offset + 2 * k + 1] = v[1];
            }
        ++k;
      }
    if (ipc_contact && problem_friction.empty()) // not a remeshed design's
      problem_friction = ipc_contact->friction_values();
    if (const auto *b = layout.find("friction"))
      std::copy(ipc_contact->friction_values().begin(),
                ipc_contact->friction_values().end(),
                design.begin() + b->offset);
    if (const auto *b = layout.find("loads"))
      std::fill(design.begin() + b->offset,
                design.begin() + b->offset + b->size,
                1.);

    // Design/Start: other starting values (recoveries).
    for (const auto &record : split_top_level(p.design.start, ';'))
      {
        if (record.empty())
          continue;
        const auto colon = record.find(':');
        AssertThrow(colon != std::string::npos,
                    ExcMessage("Design/Start: '" + record +
                               "' is not 'block : values'."));
        const std::string  name = Utilities::trim(record.substr(0, colon));
        const DesignBlock *b    = layout.find(name);
        AssertThrow(b && name != "shape",
                    ExcMessage("Design/Start: '" + name +
                               "' is not in Design/Parameters" +
                               (name == "shape" ?
                                  std::string(" (a shape starts at Design/"
                                              "Shape perturbation).") :
                                  std::string("."))));
        const auto values = parse_numbers(record.substr(colon + 1),
                                          "Design/Start (" + name + ")",
                                          -std::numeric_limits<double>::max(),
                                          std::numeric_limits<double>::max());
        AssertThrow(values.size() == b->size,
                    ExcMessage("Design/Start: '" + name + "' has " +
                               std::to_string(b->size) + " entries, got " +
                               std::to_string(values.size()) + "."));
        std::copy(values.begin(), values.end(), design.begin() + b->offset);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::setup_extension()
  {
    extension_constraints.clear();
    extension_constraints.reinit(shape_relevant);
    DoFTools::make_hanging_node_constraints(shape_dof_handler,
                                            extension_constraints);
    for (const auto i : DoFTools::extract_boundary_dofs(shape_dof_handler))
      if (shape_relevant.is_element(i) &&
          !extension_constraints.is_constrained(i))
        extension_constraints.add_line(i);
    extension_constraints.make_consistent_in_parallel(shape_owned,
                                                      shape_relevant,
                                                      comm);
    extension_constraints.close();

    TrilinosWrappers::SparsityPattern sp(shape_owned,
                                         shape_owned,
                                         shape_relevant,
                                         comm);
    DoFTools::make_sparsity_pattern(shape_dof_handler,
                                    sp,
                                    extension_constraints,
                                    false,
                                    Utilities::MPI::this_mpi_process(comm));
    sp.compress();
    extension_matrix.reinit(sp);
    const Quadrature<dim> q =
      tria->get_reference_cells()[0].template get_gauss_type_quadrature<dim>(2);
    FEValues<dim>                        fv(mesh_mapping[0],
                     *shape_fe,
                     q,
                     update_gradients | update_JxW_values);
    const unsigned int                   n = shape_fe->n_dofs_per_cell();
    FullMatrix<double>                   K(n, n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : shape_dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          K = 0;
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              if (shape_fe->system_to_component_index(a).first ==
                  shape_fe->system_to_component_index(b).first)
                for (unsigned int k = 0; k < q.size(); ++k)
                  K(a, b) +=
                    fv.shape_grad(a, k) * fv.shape_grad(b, k) * fv.JxW(k);
          cell->get_dof_indices(dofs);
          extension_constraints.distribute_local_to_global(K,
                                                           dofs,
                                                           extension_matrix);
        }
    extension_matrix.compress(VectorOperation::add);
    extension_ready = true;
  }



  template <int dim>
  Vector_t
  ElasticitySimulator<dim>::Impl::laplacian_times(
    const Vector_t                  &x,
    const AffineConstraints<double> &constraints)
  {
    Vector_t x_ghost(shape_owned, shape_relevant, comm);
    x_ghost = x;
    Vector_t              result(shape_owned, comm);
    const Quadrature<dim> q =
      tria->get_reference_cells()[0].template get_gauss_type_quadrature<dim>(2);
    FEValues<dim>                        fv(mesh_mapping[0],
                     *shape_fe,
                     q,
                     update_gradients | update_JxW_values);
    const unsigned int                   n = shape_fe->n_dofs_per_cell();
    Vector<double>                       local(n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : shape_dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          cell->get_dof_indices(dofs);
          local = 0;
          for (unsigned int a = 0; a < n; ++a)
            for (unsigned int b = 0; b < n; ++b)
              if (shape_fe->system_to_component_index(a).first ==
                  shape_fe->system_to_component_index(b).first)
                for (unsigned int k = 0; k < q.size(); ++k)
                  local(a) += fv.shape_grad(a, k) * fv.shape_grad(b, k) *
                              fv.JxW(k) * x_ghost(dofs[b]);
          constraints.distribute_local_to_global(local, dofs, result);
        }
    result.compress(VectorOperation::add);
    return result;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::extend(Vector_t &delta)
  {
    if (!extension_ready)
      setup_extension();
    // delta_B: the boundary entries (fixed and hanging ones follow from
    // shape_constraints); interior entries solve the Laplace problem
    //   A_II delta_I = -A_IB delta_B.
    Vector_t boundary_part(delta);
    for (const auto i : shape_owned)
      if (!extension_constraints.is_constrained(i))
        boundary_part(i) = 0;
    boundary_part.compress(VectorOperation::insert);
    shape_constraints.distribute(boundary_part);
    Vector_t rhs = laplacian_times(boundary_part, extension_constraints);
    rhs *= -1.;
    Vector_t interior(shape_owned, comm);
    extension_solver.solve_reusing(extension_matrix, interior, rhs);
    extension_constraints.set_zero(interior);
    delta = boundary_part;
    delta += interior;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::extend_transpose(Vector_t &gradient)
  {
    if (!extension_ready)
      setup_extension();
    // g_B - A_BI A_II^-1 g_I (A symmetric); interior entries become zero.
    Vector_t g_interior(gradient);
    extension_constraints.set_zero(g_interior);
    Vector_t w(shape_owned, comm);
    extension_solver.solve_reusing(extension_matrix, w, g_interior);
    extension_constraints.set_zero(w);
    extension_constraints.distribute(w); // hanging interior values
    const Vector_t r = laplacian_times(w, shape_constraints);
    for (const auto i : shape_owned)
      gradient(i) =
        extension_constraints.is_constrained(i) ? gradient(i) - r(i) : 0.;
    gradient.compress(VectorOperation::insert);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::apply_design(const std::vector<double> &q)
  {
    AssertThrow(q.size() == layout.size(),
                ExcMessage("the design vector has " + std::to_string(q.size()) +
                           " entries; the design space has " +
                           std::to_string(layout.size()) + "."));
    design = q;
    reset_physical_parameters("");

    // Material pairs from the design, checked for admissibility.
    auto lame_of = [&](const double a, const double b, const std::string &w) {
      std::array<double, 2> l = {{a, b}};
      if (p.design.young_poisson)
        {
          AssertThrow(a > 0 && b > -1 && b < 0.5,
                      ExcMessage(w + ": inadmissible E = " + fmt(a) +
                                 ", nu = " + fmt(b) +
                                 " (need E > 0, -1 < nu < 0.5)."));
          l = lame_from_young_poisson(a, b);
        }
      AssertThrow(l[1] > 0 && l[0] + 2. * l[1] / dim > 0,
                  ExcMessage(w + ": inadmissible lambda = " + fmt(l[0]) +
                             ", mu = " + fmt(l[1]) + "."));
      return l;
    };
    std::map<types::material_id, unsigned int> body_index;
    for (const auto id : all_ids)
      body_index.emplace(id, body_index.size());

    for (const auto &b : layout.blocks)
      {
        const double *v = q.data() + b.offset;
        if (b.name == "shape")
          {
            Vector_t x(shape_owned, comm);
            for (const auto i : shape_owned)
              x(i) = v[i];
            x.compress(VectorOperation::insert);
            if (p.design.boundary_shape)
              extend(x); // interior vertices follow the boundary
            shape_constraints.set_zero(x); // fixed vertices do not move
            shape_constraints.distribute(x);
            Vector_t X(shape_owned, comm);
            X = shape_reference;
            x += X;
            shape_ghost = x;
          }
        else if (b.name == "friction")
          ipc_contact->set_friction_values(std::vector<double>(v, v + b.size));
        else if (b.name == "cell material")
          {
            for (const auto &cell : tria->active_cell_iterators())
              if (!cell->is_artificial())
                {
                  const auto g = cell->global_active_cell_index();
                  cell_lame[cell->active_cell_index()] =
                    lame_of(v[2 * g],
                            v[2 * g + 1],
                            "Design (cell material), cell " +
                              std::to_string(g));
                }
          }
        else if (b.name == "material" || b.name == "damping")
          {
            std::map<types::material_id, std::array<double, 2>> per_body;
            for (const auto &[id, k] : body_index)
              {
                const std::string w =
                  "Design (" + b.name + "), material id " + std::to_string(id);
                if (b.name == "material")
                  per_body[id] = lame_of(v[2 * k], v[2 * k + 1], w);
                else
                  {
                    AssertThrow(v[2 * k] >= 0 && v[2 * k + 1] >= 0,
                                ExcMessage(w + ": damping must be >= 0."));
                    per_body[id] = {{v[2 * k], v[2 * k + 1]}};
                  }
              }
            for (const auto &cell : tria->active_cell_iterators())
              if (!cell->is_artificial())
                (b.name == "material" ?
                   cell_lame :
                   cell_damping_coefficients)[cell->active_cell_index()] =
                  per_body.at(cell->material_id());
          }
        else if (b.name == "loads")
          {
            unsigned int k = 0;
            for (; k < surface_load_scale.size(); ++k)
              surface_load_scale[k] = v[k];
            if (body_force)
              body_force_scale = v[k++];
            if (gravity.norm() > 0)
              gravity_scale = v[k++];
          }
        else if (b.name.find("per body") != std::string::npos)
          {
            auto &offsets = b.name == "initial displacement per body" ?
                              body_initial_u :
                              body_initial_v;
            offsets.assign(design_bodies.size(), Tensor<1, dim>());
            for (unsigned int k = 0; k < design_bodies.size(); ++k)
              for (unsigned int d = 0; d < dim; ++d)
                offsets[k][d] = v[dim * k + d];
          }
        else if (b.name.find("field") != std::string::npos)
          {
            Vector_t &f = b.name == "initial displacement field" ?
                            initial_displacement_field :
                            initial_velocity_field;
            f.reinit(owned, comm);
            for (const auto i : owned)
              f(i) = v[i];
            f.compress(VectorOperation::insert);
          }
        else
          for (unsigned int d = 0; d < dim; ++d)
            (b.name == "initial displacement" ? initial_displacement_offset :
                                                initial_velocity_offset)[d] =
              v[d];
      }

    // A shape that inverts or flattens a cell has no meaning: say so
    // instead of solving.
    if (layout.find("shape"))
      {
        Point<dim>   where;
        const double worst  = min_scaled_jacobian(&where);
        const double global = Utilities::MPI::min(worst, comm);
        AssertThrow(global >= p.design.min_scaled_jacobian,
                    ExcMessage(
                      "the design " +
                      std::string(global <= 0 ? "inverts" : "degenerates") +
                      " a cell (scaled Jacobian " + fmt(global, 3) +
                      " < Design/Min scaled Jacobian = " +
                      fmt(p.design.min_scaled_jacobian, 3) + ")" +
                      (worst == global ? " near " + fmt(Tensor<1, dim>(where)) +
                                           " of the mesh as read" :
                                         std::string()) +
                      "."));
        update_ipc_geometry("the design");
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::solve_forward(const bool quiet_run)
  {
    Timer timer;
    quiet        = quiet_run;
    store_states = true;
    force_scale  = 0;
    steps.clear();
    if (p.problem == "static")
      solve_static();
    else
      solve_transient();
    quiet = false;
    forward_seconds += timer.wall_time();
    ++forward_solves;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::set_step_state(const unsigned int i)
  {
    if (p.problem == "static")
      {
        transient = false;
        time      = p.end_time;
        u         = u_states[0];
        u_ghost   = u;
        return;
      }
    transient            = true;
    const unsigned int n = u_states.size() - 1;
    dt                   = p.end_time / n;
    time                 = i * dt;
    u                    = u_states[i];
    u_ghost              = u;
    if (i == 0)
      {
        inertia_factor = 0;
        w_ghost        = 0;
        u_old_ghost    = u;
        return;
      }
    const auto   bdf = bdf_coefficients_at_step(p.bdf_order, i);
    const double bdt = bdf.beta * dt;
    Vector_t     w(owned, comm);
    for (unsigned int j = 0; j < bdf.alpha.size(); ++j)
      {
        w.add(bdf.alpha[j], u_states[i - 1 - j]);
        w.add(bdf.alpha[j] * bdt, v_states[i - 1 - j]);
      }
    w_ghost        = w;
    u_old_ghost    = u_states[i - 1];
    inertia_factor = 1. / (bdt * bdt);
  }



  template <int dim>
  std::vector<std::vector<double>>
  ElasticitySimulator<dim>::Impl::objective_integrals(const Objective<dim> &J,
                                                      const unsigned int    i)
  {
    set_step_state(i);
    // accumulate() with no outputs leaves the integrals in `objective_cache`.
    accumulate(J, nullptr, nullptr, nullptr, nullptr);
    auto I = objective_cache;
    for (auto &v : I)
      Utilities::MPI::sum(v, comm, v);
    return I;
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::objective_value(const Objective<dim> &J)
  {
    const unsigned int n         = u_states.size() - 1;
    double             value     = 0;
    const bool         is_static = p.problem == "static";
    term_values.assign(J.terms().size(), 0.);
    for (unsigned int i = 0; i <= n; ++i)
      {
        const double sw = is_static ? 1. : J.step_weight(i, n, p.end_time / n);
        if (sw == 0)
          continue;
        const auto I = objective_integrals(J, i);
        const auto c = contact_force_terms(J, i, sw, nullptr, nullptr);
        for (unsigned int t = 0; t < J.terms().size(); ++t)
          {
            const double v =
              sw * J.terms()[t]->weight * J.terms()[t]->combine(I[t], nullptr) +
              c[t];
            term_values[t] += v;
            value += v;
          }
      }
    const auto r = regularization(J, nullptr);
    for (unsigned int t = 0; t < r.size(); ++t)
      {
        term_values[t] += r[t];
        value += r[t];
      }
    return value;
  }



  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::Impl::regularization(const Objective<dim> &J,
                                                 PhysicalGradient     *g)
  {
    using R = typename ObjectiveTerm<dim>::Regularization;
    std::vector<double> values(J.terms().size(), 0.);
    for (unsigned int t = 0; t < J.terms().size(); ++t)
      {
        const auto &term = *J.terms()[t];
        double      v    = 0;
        if (term.regularization == R::material_smoothing)
          {
            // eq. 3.44 over ordered pairs (cell, face neighbor), from the
            // owned cell's side; neighbors may be ghosts or finer cells.
            auto pair = [&](const auto &a, const auto &b) {
              const auto &la = cell_lame[a->active_cell_index()];
              const auto &lb = cell_lame[b->active_cell_index()];
              for (unsigned int k = 0; k < 2; ++k)
                {
                  const double r = 1. - lb[k] / la[k];
                  v += term.weight * r * r;
                  if (g)
                    {
                      g->lame[a->active_cell_index()][k] +=
                        term.weight * 2. * r * lb[k] / (la[k] * la[k]);
                      g->lame[b->active_cell_index()][k] -=
                        term.weight * 2. * r / la[k];
                    }
                }
            };
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned())
                for (const auto f : cell->face_indices())
                  {
                    if (cell->at_boundary(f))
                      continue;
                    if (cell->face(f)->has_children())
                      for (unsigned int c = 0;
                           c < cell->face(f)->n_active_descendants();
                           ++c)
                        pair(cell, cell->neighbor_child_on_subface(f, c));
                    else
                      pair(cell, cell->neighbor(f));
                  }
          }
        else if (term.regularization == R::boundary_smoothing)
          {
            AssertThrow(layout.find("shape"),
                        ExcMessage("Objective/Terms: 'boundary smoothing' "
                                   "needs the shape block in "
                                   "Design/Parameters."));
            // eq. 3.43: boundary vertices and their neighbours along
            // boundary edges, from owned and ghost cells; each vertex is
            // counted by the rank that owns its first coordinate.
            std::map<unsigned int, std::set<unsigned int>> neighbours;
            std::map<unsigned int, std::array<types::global_dof_index, dim>>
              dofs;
            for (const auto &cell : shape_dof_handler.active_cell_iterators())
              if (!cell->is_artificial() && cell->at_boundary())
                for (const auto f : cell->face_indices())
                  {
                    if (!cell->at_boundary(f))
                      continue;
                    const auto face = cell->face(f);
                    for (unsigned int v = 0; v < face->n_vertices(); ++v)
                      for (unsigned int d = 0; d < dim; ++d)
                        dofs[face->vertex_index(v)][d] =
                          face->vertex_dof_index(v, d);
                    if (dim == 2)
                      {
                        neighbours[face->vertex_index(0)].insert(
                          face->vertex_index(1));
                        neighbours[face->vertex_index(1)].insert(
                          face->vertex_index(0));
                      }
                    else
                      for (unsigned int l = 0; l < face->n_lines(); ++l)
                        {
                          const auto line = face->line(l);
                          neighbours[line->vertex_index(0)].insert(
                            line->vertex_index(1));
                          neighbours[line->vertex_index(1)].insert(
                            line->vertex_index(0));
                        }
                  }
            auto position = [&](const unsigned int vertex) {
              Tensor<1, dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x[d] = shape_ghost(dofs.at(vertex)[d]);
              return x;
            };
            const double p_exp = term.exponent;
            for (const auto &[i, ns] : neighbours)
              {
                if (!shape_owned.is_element(dofs.at(i)[0]))
                  continue;
                const Tensor<1, dim> xi = position(i);
                Tensor<1, dim>       A, sum_e;
                double               L = 0;
                for (const auto j : ns)
                  {
                    const Tensor<1, dim> e = xi - position(j);
                    A += e;
                    L += e.norm();
                    sum_e += e / e.norm();
                  }
                const Tensor<1, dim> s_i = A / L;
                const double         s2  = s_i.norm_square();
                v += term.weight * std::pow(s2, 0.5 * p_exp);
                if (!g || s2 == 0)
                  continue;
                // dJ/ds, then ds = dA / L - A dL / L^2.
                const Tensor<1, dim> gs =
                  term.weight * p_exp * std::pow(s2, 0.5 * p_exp - 1) * s_i;
                const double   gA = gs * A / (L * L);
                Tensor<1, dim> gi = double(ns.size()) * gs / L - gA * sum_e;
                std::vector<types::global_dof_index> indices;
                Vector<double> local(dim * (ns.size() + 1));
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    indices.push_back(dofs.at(i)[d]);
                    local(d) = gi[d];
                  }
                for (const auto j : ns)
                  {
                    const Tensor<1, dim> e  = xi - position(j);
                    const Tensor<1, dim> gj = -gs / L + gA * e / e.norm();
                    for (unsigned int d = 0; d < dim; ++d)
                      {
                        local(indices.size()) = gj[d];
                        indices.push_back(dofs.at(j)[d]);
                      }
                  }
                shape_constraints.distribute_local_to_global(local,
                                                             indices,
                                                             g->shape);
              }
            if (g)
              g->shape.compress(VectorOperation::add);
          }
        values[t] = Utilities::MPI::sum(v, comm);
      }
    return values;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::accumulate(
    const Objective<dim>                   &J,
    const std::vector<std::vector<double>> *weights,
    const Vector_t                         *adjoint,
    Vector_t                               *dJ_du,
    PhysicalGradient                       *g)
  {
    const FEValuesExtractors::Vector disp(0);
    const bool                       values_only = !weights && !adjoint;
    objective_cache.clear();
    for (const auto &t : J.terms())
      objective_cache.emplace_back(t->integrals().size(), 0.);

    Vector_t adjoint_ghost, reference_ghost;
    if (adjoint)
      {
        adjoint_ghost.reinit(owned, relevant, comm);
        adjoint_ghost = *adjoint;
      }
    const bool has_reference = !reference_states.empty();
    if (has_reference)
      {
        reference_ghost.reinit(owned, relevant, comm);
        const unsigned int i =
          p.problem == "static" ?
            0 :
            static_cast<unsigned int>(std::round(time / std::max(dt, 1e-300)));
        reference_ghost =
          reference_states[std::min<std::size_t>(i,
                                                 reference_states.size() - 1)];
      }

    Scratch<dim> s(mapping, reference_mapping, fe, quadrature, face_quadrature);
    hp::FECollection<dim> shape_collection(*shape_fe);
    const UpdateFlags     shape_flags = update_values | update_gradients;
    hp::FEValues<dim>     shape_values(mapping,
                                   shape_collection,
                                   quadrature,
                                   shape_flags);
    hp::FEFaceValues<dim> shape_face_values(mapping,
                                            shape_collection,
                                            face_quadrature,
                                            shape_flags);
    const bool            want_shape = g && layout.find("shape");
    const unsigned int    ns         = shape_fe->n_dofs_per_cell();
    Vector<double>        local_shape(ns), local_u;
    std::vector<types::global_dof_index> shape_dofs(ns), dofs;
    std::vector<Tensor<1, dim>>          ref_u, adj_u, u_vals;
    std::vector<Tensor<2, dim>>          adj_grad, grads, grads_old;

    // Which integrals live on the volume, which on a boundary id.
    std::vector<unsigned int> volume_mask, any_boundary, n_integrals;
    std::vector<std::set<types::material_id>> integral_materials;
    for (const auto &t : J.terms())
      for (const auto &i : t->integrals())
        {
          volume_mask.push_back(!i.boundary);
          any_boundary.push_back(i.boundary);
          integral_materials.push_back(i.material_ids);
        }
    const bool any_restriction =
      std::any_of(integral_materials.begin(),
                  integral_materials.end(),
                  [](const auto &m) { return !m.empty(); });
    std::vector<unsigned int> cell_mask = volume_mask;
    for (const auto &t : J.terms())
      n_integrals.push_back(t->integrals().size());
    const bool has_boundary_terms =
      std::find(any_boundary.begin(), any_boundary.end(), 1u) !=
      any_boundary.end();

    // Objective integrand contributions at one point (volume or face).
    IntegrandValue<dim> r;
    auto                objective_point =
      [&](const FEValuesBase<dim>                              &fv,
          const FEValuesBase<dim>                              *sv,
          const unsigned int                                    q,
          const IntegrandContext<dim>                          &ctx,
          const Material<dim>                                  &mat,
          const std::vector<unsigned int>                      &term_integrals,
          const bool                                            boundary,
          const typename DoFHandler<dim>::active_cell_iterator &cell) {
        const double JxW = fv.JxW(q);
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
                               u_vals[q],
                               grads[q],
                               mat.properties().lambda,
                               mat.properties().mu,
                               !values_only,
                               r);
                if (values_only)
                  {
                    objective_cache[t][k] += r.value * JxW;
                    continue;
                  }
                if (dJ_du)
                  for (unsigned int i = 0; i < local_u.size(); ++i)
                    {
                      const unsigned int c =
                        fv.get_fe().system_to_component_index(i).first;
                      local_u(i) +=
                        w *
                        (r.d_u[c] * fv.shape_value(i, q) +
                         row_dot(r.d_grad_u, c, fv.shape_grad(i, q))) *
                        JxW;
                    }
                if (!g)
                  continue;
                if (sv)
                  {
                    // eqs. 3.31/3.34 (surface divergence on faces)
                    Tensor<2, dim> W = transport_kernel(r.d_grad_u, grads[q]);
                    for (unsigned int d = 0; d < dim; ++d)
                      W[d][d] += r.value;
                    for (unsigned int a = 0; a < ns; ++a)
                      {
                        const unsigned int c =
                          shape_fe->system_to_component_index(a).first;
                        const Tensor<1, dim> dN = sv->shape_grad(a, q);
                        double               v =
                          row_dot(W, c, dN) + r.d_x[c] * sv->shape_value(a, q);
                        if (boundary)
                          {
                            // d(ds) = div_S theta ds and, for integrands of
                            // the normal, dn = -(I - n n^T) grad theta^T n.
                            const Tensor<1, dim> &n  = fv.normal_vector(q);
                            const double          dn = dN * n;
                            v -= r.value * n[c] * dn +
                                 n[c] * (r.d_n * dN - (r.d_n * n) * dn);
                          }
                        local_shape(a) += w * v * JxW;
                      }
                  }
                auto &l = g->lame[cell->active_cell_index()];
                l[0] += w * r.d_lambda * JxW;
                l[1] += w * r.d_mu * JxW;
              }
          }
      };


    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        s.fe_values.reinit(cell);
        const FEValues<dim> &fv  = s.fe_values.get_present_fe_values();
        const auto          &cfe = fv.get_fe();
        const unsigned int   n   = cfe.n_dofs_per_cell();
        const unsigned int   nq  = fv.n_quadrature_points;
        dofs.resize(n);
        cell->get_dof_indices(dofs);
        local_u.reinit(dJ_du ? n : 0);
        local_shape = 0;
        const typename DoFHandler<dim>::active_cell_iterator shape_cell(
          &*tria, cell->level(), cell->index(), &shape_dof_handler);
        const FEValues<dim> *sv = nullptr;
        if (want_shape)
          {
            shape_values.reinit(shape_cell, cell->active_fe_index(), 0, 0);
            sv = &shape_values.get_present_fe_values();
            shape_cell->get_dof_indices(shape_dofs);
          }

        const Material<dim> mat  = cell_material(cell);
        const Damping<dim>  damp = cell_damping(cell);
        const double        rho  = mat.properties().density;
        grads.resize(nq);
        u_vals.resize(nq);
        fv[disp].get_function_gradients(u_ghost, grads);
        fv[disp].get_function_values(u_ghost, u_vals);
        reference_points(cell, s);

        IntegrandContext<dim> ctx;
        ctx.density      = rho;
        ctx.time         = time;
        ctx.model        = p.model;
        ctx.plane_stress = p.plane_stress;
        if (has_reference)
          {
            ref_u.resize(nq);
            fv[disp].get_function_values(reference_ghost, ref_u);
          }
        // Volume integrals restricted to some materials skip the others.
        if (any_restriction)
          for (unsigned int k = 0; k < cell_mask.size(); ++k)
            cell_mask[k] = volume_mask[k] &&
                           (integral_materials[k].empty() ||
                            integral_materials[k].count(cell->material_id()));
        for (unsigned int q = 0; q < nq; ++q)
          {
            ctx.X = s.X[q];
            if (has_reference)
              ctx.target = Tensor<1, dim>(s.X[q]) + ref_u[q];
            objective_point(fv, sv, q, ctx, mat, cell_mask, false, cell);
          }

        // p^T d_q h of the volume forces (eq. 3.24 and the material forms).
        if (adjoint)
          {
            adj_grad.resize(nq);
            adj_u.resize(nq);
            fv[disp].get_function_gradients(adjoint_ghost, adj_grad);
            fv[disp].get_function_values(adjoint_ghost, adj_u);
            s.u.assign(nq, Tensor<1, dim>());
            s.w.assign(nq, Tensor<1, dim>());
            grads_old.assign(nq, Tensor<2, dim>());
            if (transient)
              {
                fv[disp].get_function_values(w_ghost, s.w);
                s.u = u_vals;
                fv[disp].get_function_gradients(u_old_ghost, grads_old);
              }
            const Damping<dim> unit_shear(1., 0.), unit_bulk(0., 1.);
            for (unsigned int q = 0; q < nq; ++q)
              {
                const double          JxW = fv.JxW(q);
                const Tensor<2, dim> &G   = adj_grad[q];
                Tensor<2, dim>        P   = mat.stress(grads[q]);
                Tensor<4, dim>        A   = mat.tangent(grads[q]);
                Tensor<2, dim>        H_old;
                if (transient)
                  {
                    P += damp.stress(grads[q], grads_old[q], dt);
                    A += damp.tangent(grads[q], grads_old[q], dt);
                    H_old = contract_left(
                      G, damp.tangent_old(grads[q], grads_old[q], dt));
                  }
                const Tensor<1, dim> f =
                  volume_force(rho, s.X[q], s.u[q], s.w[q]);
                if (want_shape)
                  {
                    const Tensor<2, dim> H = contract_left(G, A);
                    Tensor<2, dim>       V = transport_kernel(H, grads[q]) +
                                       transport_kernel(H_old, grads_old[q]) -
                                       transpose(G) * P;
                    const double div_term = scalar_product(P, G) + f * adj_u[q];
                    for (unsigned int d = 0; d < dim; ++d)
                      V[d][d] += div_term;
                    for (unsigned int a = 0; a < ns; ++a)
                      local_shape(a) +=
                        row_dot(V,
                                shape_fe->system_to_component_index(a).first,
                                sv->shape_grad(a, q)) *
                        JxW;
                  }
                const auto dP = mat.stress_lame_derivatives(grads[q]);
                auto      &l  = g->lame[cell->active_cell_index()];
                l[0] += scalar_product(dP[0], G) * JxW;
                l[1] += scalar_product(dP[1], G) * JxW;
                if (transient)
                  {
                    auto &dd = g->damping[cell->active_cell_index()];
                    dd[0] +=
                      scalar_product(
                        unit_shear.stress(grads[q], grads_old[q], dt), G) *
                      JxW;
                    dd[1] +=
                      scalar_product(
                        unit_bulk.stress(grads[q], grads_old[q], dt), G) *
                      JxW;
                  }
                // Load scales: d/ds of -int s b . p.
                unsigned int k = surface_load_scale.size();
                if (body_force)
                  {
                    static thread_local Vector<double> b(dim);
                    body_force->vector_value(s.X[q], b);
                    double bp = 0;
                    for (unsigned int d = 0; d < dim; ++d)
                      bp += b[d] * adj_u[q][d];
                    g->loads[k++] -= bp * JxW;
                  }
                if (gravity.norm() > 0)
                  g->loads[k++] -= rho * (gravity * adj_u[q]) * JxW;
              }
          }

        // Faces: boundary objective integrals and surface loads.
        if (cell->at_boundary() && (has_boundary_terms || adjoint))
          for (const auto face : cell->face_indices())
            {
              if (!cell->face(face)->at_boundary())
                continue;
              const types::boundary_id  id = cell->face(face)->boundary_id();
              std::vector<unsigned int> mask(any_boundary.size(), 0);
              bool                      any = false;
              unsigned int              idx = 0;
              for (const auto &t : J.terms())
                for (const auto &i : t->integrals())
                  {
                    mask[idx] =
                      i.boundary &&
                      (i.boundary_ids.empty() || i.boundary_ids.count(id)) &&
                      (i.material_ids.empty() ||
                       i.material_ids.count(cell->material_id()));
                    any |= mask[idx++] != 0;
                  }
              const bool load = adjoint && loaded(id);
              if (!any && !load)
                continue;
              s.face_values.reinit(cell, face);
              const FEFaceValues<dim> &ff =
                s.face_values.get_present_fe_values();
              const FEFaceValues<dim> *sf = nullptr;
              if (want_shape)
                {
                  shape_face_values.reinit(
                    shape_cell, face, cell->active_fe_index(), 0, 0);
                  sf = &shape_face_values.get_present_fe_values();
                }
              reference_face_points(cell, face, s);
              const unsigned int nf = ff.n_quadrature_points;
              grads.resize(nf);
              u_vals.resize(nf);
              ff[disp].get_function_gradients(u_ghost, grads);
              ff[disp].get_function_values(u_ghost, u_vals);
              if (any)
                {
                  if (has_reference)
                    {
                      ref_u.resize(nf);
                      ff[disp].get_function_values(reference_ghost, ref_u);
                    }
                  for (unsigned int q = 0; q < nf; ++q)
                    {
                      ctx.X      = s.X[q];
                      ctx.normal = ff.normal_vector(q);
                      if (has_reference)
                        ctx.target = Tensor<1, dim>(s.X[q]) + ref_u[q];
                      objective_point(ff, sf, q, ctx, mat, mask, true, cell);
                    }
                }
              if (!load)
                continue;
              adj_u.resize(nf);
              ff[disp].get_function_values(adjoint_ghost, adj_u);
              static thread_local Vector<double> val(dim);
              for (unsigned int q = 0; q < nf; ++q)
                {
                  const double          JxW = ff.JxW(q);
                  const Tensor<1, dim> &n   = ff.normal_vector(q);
                  Tensor<1, dim>        traction;
                  double                pressure = 0;
                  for (unsigned int k = 0; k < tractions.size(); ++k)
                    if (tractions[k].first == id)
                      {
                        tractions[k].second->vector_value(s.X[q], val);
                        double tp = 0;
                        for (unsigned int d = 0; d < dim; ++d)
                          {
                            traction[d] += surface_load_scale[k] * val[d];
                            tp += val[d] * adj_u[q][d];
                          }
                        g->loads[k] -= tp * JxW;
                      }
                  for (unsigned int k = 0; k < pressures.size(); ++k)
                    if (pressures[k].first == id)
                      {
                        const double pk = pressures[k].second->value(s.X[q]);
                        const unsigned int m = tractions.size() + k;
                        pressure += surface_load_scale[m] * pk;
                        g->loads[m] += pk * (n * adj_u[q]) * JxW;
                      }
                  if (!want_shape)
                    continue;
                  // -int t.p ds and int P n.p ds on the moving surface:
                  // d(ds) = div_S theta ds, d(n ds) = (div theta n -
                  // grad theta^T n) ds.
                  const double tp = traction * adj_u[q];
                  const double np = n * adj_u[q];
                  for (unsigned int a = 0; a < ns; ++a)
                    {
                      const unsigned int c =
                        shape_fe->system_to_component_index(a).first;
                      const Tensor<1, dim> dN    = sf->shape_grad(a, q);
                      const double         div   = dN[c];
                      const double         div_s = div - n[c] * (dN * n);
                      local_shape(a) +=
                        (-tp * div_s +
                         pressure * (np * div - n[c] * (adj_u[q] * dN))) *
                        JxW;
                    }
                }
            }

        if (dJ_du)
          constraints_zero.distribute_local_to_global(local_u, dofs, *dJ_du);
        if (want_shape)
          shape_constraints.distribute_local_to_global(local_shape,
                                                       shape_dofs,
                                                       g->shape);
      }
    if (adjoint && want_shape)
      contact.add_shape_products(mapping,
                                 u_ghost,
                                 adjoint_ghost,
                                 shape_dof_handler,
                                 shape_constraints,
                                 g->shape);
    if (dJ_du)
      dJ_du->compress(VectorOperation::add);
    if (want_shape)
      g->shape.compress(VectorOperation::add);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::mass_and_damping_products(
    const Vector_t    &z,
    const Vector_t    *adjoint_next,
    const unsigned int next,
    Vector_t          &result)
  {
    // C^T [M z + (d f(u^next, u^{next-1}) / d u^{next-1})^T p_next]
    result = 0;
    Vector_t z_ghost(owned, relevant, comm), a_ghost, u_next, u_prev;
    z_ghost = z;
    if (adjoint_next)
      {
        a_ghost.reinit(owned, relevant, comm);
        a_ghost = *adjoint_next;
        u_next.reinit(owned, relevant, comm);
        u_next = u_states[next];
        u_prev.reinit(owned, relevant, comm);
        u_prev = u_states[next - 1];
      }
    const FEValuesExtractors::Vector     disp(0);
    hp::FEValues<dim>                    hp_fv(mapping,
                            fe,
                            quadrature,
                            update_values | update_gradients |
                              update_JxW_values);
    std::vector<Tensor<1, dim>>          zq;
    std::vector<Tensor<2, dim>>          gn, gp, ga;
    std::vector<types::global_dof_index> dofs;
    Vector<double>                       local;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_fv.reinit(cell);
          const auto        &fv  = hp_fv.get_present_fe_values();
          const auto        &cfe = fv.get_fe();
          const unsigned int n   = cfe.n_dofs_per_cell(),
                             nq  = fv.n_quadrature_points;
          dofs.resize(n);
          cell->get_dof_indices(dofs);
          local.reinit(n);
          const double       rho    = bodies.at(cell->material_id()).density;
          const Damping<dim> damp   = cell_damping(cell);
          const bool         damped = adjoint_next && damp.active();
          zq.resize(nq);
          fv[disp].get_function_values(z_ghost, zq);
          if (damped)
            {
              gn.resize(nq);
              gp.resize(nq);
              ga.resize(nq);
              fv[disp].get_function_gradients(u_next, gn);
              fv[disp].get_function_gradients(u_prev, gp);
              fv[disp].get_function_gradients(a_ghost, ga);
            }
          for (unsigned int q = 0; q < nq; ++q)
            {
              Tensor<2, dim> H;
              if (damped)
                H = contract_left(ga[q], damp.tangent_old(gn[q], gp[q], dt));
              for (unsigned int i = 0; i < n; ++i)
                {
                  const unsigned int c = cfe.system_to_component_index(i).first;
                  local(i) += (rho * zq[q][c] * fv.shape_value(i, q) +
                               row_dot(H, c, fv.shape_grad(i, q))) *
                              fv.JxW(q);
                }
            }
          constraints_zero.distribute_local_to_global(local, dofs, result);
        }
    result.compress(VectorOperation::add);
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::compute_gradient(const Objective<dim> &J,
                                                   std::vector<double>  &dJ)
  {
    Timer              timer;
    const unsigned int n         = u_states.size() - 1;
    const bool         is_static = p.problem == "static";
    const double       step      = is_static ? 0. : p.end_time / n;

    PhysicalGradient g;
    g.shape.reinit(shape_owned, comm);
    g.lame.assign(tria->n_active_cells(), {{0., 0.}});
    g.damping.assign(tria->n_active_cells(), {{0., 0.}});
    g.loads.assign(tractions.size() + pressures.size() + 2, 0.);
    g.friction.assign(ipc_contact ? ipc_contact->friction_names().size() : 0,
                      0.);

    // dJ/dI of every integral at step i, scaled by the step weight.
    double value           = 0;
    auto   weights_at_step = [&](const unsigned int i) {
      const double sw = is_static ? 1. : J.step_weight(i, n, step);
      std::vector<std::vector<double>> w;
      const auto                       I = sw != 0 ? objective_integrals(J, i) :
                                                       std::vector<std::vector<double>>();
      for (unsigned int t = 0; t < J.terms().size(); ++t)
        {
          std::vector<double> d(J.terms()[t]->integrals().size(), 0.);
          if (sw != 0)
            {
              value +=
                sw * J.terms()[t]->weight * J.terms()[t]->combine(I[t], &d);
              for (auto &x : d)
                x *= sw * J.terms()[t]->weight;
            }
          w.push_back(d);
        }
      return w;
    };

    Vector_t dJ_du(owned, comm), rhs(owned, comm);
    // The contact force terms' partials at step i.
    auto contact_partials = [&](const unsigned int i) {
      const double sw = is_static ? 1. : J.step_weight(i, n, step);
      for (const double v : contact_force_terms(J, i, sw, &dJ_du, &g))
        value += v;
    };
    if (is_static)
      {
        const auto w = weights_at_step(0);
        accumulate(J, &w, nullptr, &dJ_du, &g); // objective partials
        contact_partials(0);
        rhs = dJ_du;
        rhs *= -1.;
        Timer solve_timer;
        // The Jacobian of the converged Newton step is still assembled;
        // static tangents are symmetric, so it is its own transpose, unless
        // friction makes it unsymmetric.
        Vector_t lambda(owned, comm);
        if (ipc_contact)
          {
            // The exact contact Hessian (symmetric: frictionless, or
            // friction lagged at rest).
            ipc_adjoint_state(0);
            exact_contact_hessian = true;
            assemble(u, true, nullptr);
            exact_contact_hessian = false;
            linear_solver.solve(jacobian, lambda, rhs, fe.max_degree() > 1);
          }
        else if (contact.has_friction())
          {
            transpose_matrix = true;
            assemble(u, true, nullptr);
            transpose_matrix = false;
            linear_solver.solve(jacobian, lambda, rhs, fe.max_degree() > 1);
          }
        else
          linear_solver.solve_reusing(jacobian, lambda, rhs);
        constraints_zero.distribute(lambda);
        adjoint_solve_seconds += solve_timer.wall_time();
        accumulate(J, nullptr, &lambda, nullptr, &g); // p^T d_q h
        if (ipc_contact)
          ipc_adjoint_products(lambda, g, nullptr);
      }
    else
      {
        // Backward BDF sweep (thesis eqs. 3.16-3.22 for u^i alone: the
        // velocities are eliminated through v^i = (u^i + sum_j a_j u^{i-j}) /
        // (beta dt)). lambda_i is the adjoint of the step residual R_i,
        // y_i = mu_i / M the adjoint of the velocity update.
        const unsigned int    m = p.bdf_order;
        std::vector<Vector_t> lambda(n + 2), y(n + 2);
        auto                  beta_dt = [&](const unsigned int k) {
          return bdf_coefficients_at_step(m, k).beta * step;
        };
        auto alpha = [&](const unsigned int k, const unsigned int j) {
          const auto c = bdf_coefficients_at_step(m, k);
          return j <= c.alpha.size() ? c.alpha[j - 1] : 0.;
        };
        Vector_t z(owned, comm), products(owned, comm);
        // (d h_{i+1} / d u^i)^T lambda_{i+1} of lagged IPC friction.
        Vector_t ipc_lagged(owned, comm);
        for (unsigned int i = n; i >= 1; --i)
          {
            const double bi = beta_dt(i);
            z               = 0;
            for (unsigned int k = i + 1; k <= std::min(n, i + m); ++k)
              {
                const double a = alpha(k, k - i);
                if (a == 0)
                  continue;
                z.add(a / (beta_dt(k) * bi), lambda[k]);
                z.add(a, y[k]);
              }
            const auto w = weights_at_step(i);
            dJ_du        = 0;
            accumulate(J, &w, nullptr, &dJ_du, &g);
            contact_partials(i);
            mass_and_damping_products(z,
                                      i < n ? &lambda[i + 1] : nullptr,
                                      i + 1,
                                      products);
            rhs = dJ_du;
            rhs += products;
            if (ipc_contact && i < n)
              rhs += ipc_lagged;
            rhs *= -1.;

            // (M / (beta dt)^2 + K_i)^T lambda_i = rhs, at the stored state.
            set_step_state(i);
            make_constraints(time);
            if (ipc_contact)
              ipc_adjoint_state(i);
            Timer solve_timer;
            transpose_matrix      = true;
            exact_contact_hessian = true;
            assemble(u, true, nullptr);
            transpose_matrix      = false;
            exact_contact_hessian = false;
            lambda[i].reinit(owned, comm);
            linear_solver.solve(jacobian, lambda[i], rhs, fe.max_degree() > 1);
            constraints_zero.distribute(lambda[i]);
            adjoint_solve_seconds += solve_timer.wall_time();

            y[i].reinit(owned, comm);
            y[i].add(1. / (bi * bi), lambda[i]);
            for (unsigned int k = i + 1; k <= std::min(n, i + m); ++k)
              {
                const double a = alpha(k, k - i);
                if (a != 0)
                  y[i].add(a / (beta_dt(k) * bi), lambda[k]);
              }
            set_step_state(i);
            accumulate(J, nullptr, &lambda[i], nullptr, &g);
            if (ipc_contact)
              {
                ipc_lagged = 0;
                ipc_adjoint_products(lambda[i], g, &ipc_lagged);
              }
          }

        // Step 0: the initial conditions (eq. 3.21).
        const auto w = weights_at_step(0);
        dJ_du        = 0;
        accumulate(J, &w, nullptr, &dJ_du, &g);
        contact_partials(0);
        z = 0;
        Vector_t zv(owned, comm);
        for (unsigned int k = 1; k <= std::min(n, m); ++k)
          {
            z.add(alpha(k, k), y[k]);
            zv.add(alpha(k, k) / beta_dt(k), lambda[k]);
          }
        mass_and_damping_products(z, &lambda[1], 1, products);
        dJ_du += products;
        if (ipc_contact && n > 0)
          dJ_du += ipc_lagged;
        // dJ/dv^0 = M zv on every DoF (v^0 is not constrained).
        Vector_t dJ_dv(owned, comm);
        {
          AffineConstraints<double> none;
          none.close();
          std::swap(none, constraints_zero);
          mass_and_damping_products(zv, nullptr, 0, dJ_dv);
          std::swap(none, constraints_zero);
        }
        g.initial_u = component_sums(dJ_du); // adjoint of add_uniform()
        g.initial_v = component_sums(dJ_dv);
        g.initial_u_field.reinit(dJ_du);
        g.initial_u_field = dJ_du;
        g.initial_v_field.reinit(dJ_dv);
        g.initial_v_field = dJ_dv;
        // Forward states (u, v per step) and adjoint states (lambda, y).
        memory_of_states = 0;
        for (unsigned int i = 0; i <= n; ++i)
          memory_of_states += u_states[i].memory_consumption() +
                              v_states[i].memory_consumption() +
                              (i > 0 ? lambda[i].memory_consumption() +
                                         y[i].memory_consumption() :
                                       0);
      }

    for (const double r : regularization(J, &g))
      value += r;

    // Pull the physical gradient back to the design blocks.
    dJ.assign(layout.size(), 0.);
    std::map<types::material_id, unsigned int> body_index;
    for (const auto id : all_ids)
      body_index.emplace(id, body_index.size());
    for (const auto &b : layout.blocks)
      {
        double *d = dJ.data() + b.offset;
        if (b.name == "shape")
          {
            if (p.design.boundary_shape)
              extend_transpose(g.shape);
            for (const auto i : shape_owned)
              d[i] = g.shape(i);
          }
        else if (b.name == "cell material" || b.name == "material" ||
                 b.name == "damping")
          {
            // Ghost cells carry the regularization's share of their owner.
            for (const auto &cell : tria->active_cell_iterators())
              {
                if (cell->is_artificial())
                  continue;
                const unsigned int    c = cell->active_cell_index();
                std::array<double, 2> v =
                  b.name == "damping" ? g.damping[c] : g.lame[c];
                const unsigned int slot = b.name == "cell material" ?
                                            cell->global_active_cell_index() :
                                            body_index.at(cell->material_id());
                if (b.name != "damping" && p.design.young_poisson)
                  {
                    const double E  = design[b.offset + 2 * slot];
                    const double nu = design[b.offset + 2 * slot + 1];
                    double       jac[2][2];
                    lame_from_young_poisson(E, nu, jac);
                    v = {{v[0] * jac[0][0] + v[1] * jac[1][0],
                          v[0] * jac[0][1] + v[1] * jac[1][1]}};
                  }
                d[2 * slot] += v[0];
                d[2 * slot + 1] += v[1];
              }
          }
        else if (b.name == "friction")
          std::copy(g.friction.begin(), g.friction.end(), d);
        else if (b.name == "loads")
          {
            unsigned int k = 0, j = surface_load_scale.size();
            for (; k < surface_load_scale.size(); ++k)
              d[k] = g.loads[k];
            if (body_force)
              d[k++] = g.loads[j++];
            if (gravity.norm() > 0)
              d[k++] = g.loads[j++];
          }
        else if (b.name.find("per body") != std::string::npos)
          {
            const auto sums = body_component_sums(
              b.name == "initial displacement per body" ? g.initial_u_field :
                                                          g.initial_v_field);
            for (unsigned int k = 0; k < sums.size(); ++k)
              for (unsigned int c = 0; c < dim; ++c)
                d[dim * k + c] = sums[k][c];
          }
        else if (b.name.find("field") != std::string::npos)
          {
            const Vector_t &f = b.name == "initial displacement field" ?
                                  g.initial_u_field :
                                  g.initial_v_field;
            for (const auto i : owned)
              d[i] = f(i);
          }
        else
          for (unsigned int c = 0; c < dim; ++c)
            d[c] =
              (b.name == "initial displacement" ? g.initial_u : g.initial_v)[c];
      }
    Utilities::MPI::sum(dJ, comm, dJ);
    adjoint_seconds += timer.wall_time();
    ++gradients;
    return value;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::update_ipc_geometry(const std::string &where)
  {
    if (!ipc_contact)
      return;
    ipc_contact->setup(
      dof_handler, mapping, owned, comm, &shape_dof_handler, where);
    build_jacobian_pattern(); // the couplings at rest of the new shape
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ipc_adjoint_state(const unsigned int i)
  {
    if (ipc_friction())
      {
        Vector_t lagged(owned, comm);
        if (p.problem == "transient")
          lagged = u_states[i - 1];
        ipc_contact->update_friction(lagged, lagged, ipc_friction_eta());
      }
    if (ipc_contact->update_candidates(u, nullptr))
      build_jacobian_pattern();
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::ipc_adjoint_products(const Vector_t   &lambda,
                                                       PhysicalGradient &g,
                                                       Vector_t         *lagged)
  {
    typename ipc::IpcContact<dim>::AdjointProducts out;
    ipc_contact->adjoint_products(u, lambda, constraints_zero, lagged, out);
    for (unsigned int k = 0; k < out.friction.size(); ++k)
      g.friction[k] += out.friction[k];
    add_rest_gradient(out.rest, g);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::add_rest_gradient(
    const std::vector<ipc::Vec> &rest,
    PhysicalGradient            &g)
  {
    if (!layout.find("shape"))
      return;
    const auto                          &m = ipc_contact->mesh();
    std::vector<types::global_dof_index> dofs;
    std::vector<double>                  values;
    for (unsigned int v = 0; v < m.n_vertices(); ++v)
      if (!m.fixed(v) && rest[v].norm_square() > 0)
        for (const auto &w : m.shape_weights[v])
          {
            dofs.push_back(w.dof);
            values.push_back(w.weight * rest[v][w.component]);
          }
    Vector<double> local(values.begin(), values.end());
    shape_constraints.distribute_local_to_global(local, dofs, g.shape);
    g.shape.compress(VectorOperation::add);
  }



  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::Impl::contact_force_terms(const Objective<dim> &J,
                                                      const unsigned int    i,
                                                      const double          sw,
                                                      Vector_t         *dJ_du,
                                                      PhysicalGradient *g)
  {
    std::vector<double> values(J.terms().size(), 0.);
    bool                any = false;
    for (const auto &t : J.terms())
      any |= t->contact_force;
    if (!any || sw == 0)
      return values;
    set_step_state(i);
    if (ipc_contact->update_candidates(u, nullptr))
      build_jacobian_pattern();
    for (unsigned int k = 0; k < J.terms().size(); ++k)
      {
        const auto &term = *J.terms()[k];
        if (!term.contact_force)
          continue;
        const Tensor<1, dim> R =
          ipc_contact->barrier_resultant(u, term.contact_bodies);
        const double p = term.exponent, r2 = R.norm_square();
        const double c = sw * term.weight;
        values[k]      = c * std::pow(r2, 0.5 * p);
        if (!g || r2 == 0)
          continue;
        std::vector<ipc::Vec> rest;
        ipc_contact->barrier_resultant_products(u,
                                                c * p *
                                                  std::pow(r2, 0.5 * p - 1) * R,
                                                term.contact_bodies,
                                                constraints_zero,
                                                *dJ_du,
                                                rest);
        add_rest_gradient(rest, *g);
      }
    return values;
  }



  // ---------------------------------------------------------------- facade

  template <int dim>
  void
  ElasticitySimulator<dim>::prepare(RunContext *context)
  {
    if (!impl->prepared && impl->ipc_contact)
      {
        const auto &p = impl->p;
        // Static friction is lagged over load steps and friction
        // iterations; the adjoint covers the one lagged at rest.
        AssertThrow(p.problem == "transient" ||
                      !(p.ipc.has_friction() || p.design.has("friction")) ||
                      (p.load_steps == 1 && p.ipc.friction_iterations == 1),
                    ExcMessage(
                      "IPC: static gradients with friction need Time/Load "
                      "steps = 1 and IPC/Friction iterations = 1 (friction "
                      "lagged at rest); use a transient problem for "
                      "friction that follows the motion."));
        AssertThrow(p.adaptivity == "none",
                    ExcMessage("IPC: gradients need Finite element/"
                               "Adaptivity = none."));
        impl->ipc_contact->freeze();
      }
    if (!impl->prepared)
      {
        impl->prepared = true;
        if (impl->p.adaptivity != "none")
          impl->run(context); // adapt the mesh to the starting design
        else
          impl->setup_system();
        impl->build_design_layout();
        impl->apply_design(impl->design);
      }
  }

  template <int dim>
  const DesignLayout &
  ElasticitySimulator<dim>::design_layout() const
  {
    return impl->layout;
  }

  template <int dim>
  const std::vector<double> &
  ElasticitySimulator<dim>::design() const
  {
    return impl->design;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::set_design(const std::vector<double> &q)
  {
    impl->apply_design(q);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::set_objective(
    const std::shared_ptr<const Objective<dim>> &J)
  {
    for (const auto &t : J->terms())
      if (t->contact_force)
        {
          AssertThrow(impl->ipc_contact,
                      ExcMessage("Objective/Terms: 'contact force' measures "
                                 "IPC barrier forces: it needs "
                                 "forma-transient-ipc with IPC/Enabled = "
                                 "true."));
          std::vector<types::material_id> ids;
          for (const auto &cell : impl->tria->active_cell_iterators())
            if (cell->is_locally_owned())
              ids.push_back(cell->material_id());
          ids = Utilities::MPI::compute_set_union(ids, impl->comm);
          for (const auto id : t->contact_bodies)
            AssertThrow(std::find(ids.begin(), ids.end(), id) != ids.end(),
                        ExcMessage("Objective/Terms, term 'contact force': "
                                   "no body has material id " +
                                   std::to_string(id) + "."));
        }
    impl->objective = J;
    impl->reference_states.clear();
    if (!J->needs_reference_run())
      return;
    // The reference run: the mesh as read, with the reference materials.
    const auto saved = impl->design;
    impl->reset_physical_parameters(J->parameters.reference_bodies);
    impl->shape_ghost = impl->material_positions;
    if (impl->layout.find("shape"))
      impl->update_ipc_geometry("the mesh as read");
    if (impl->layout.find("friction"))
      impl->ipc_contact->set_friction_values(impl->problem_friction);
    impl->solve_forward(true);
    impl->reference_states = impl->u_states;
    if (J->parameters.target_noise > 0)
      {
        // Noise by (step, support point, component): the same for every
        // partition and DoF numbering. A splitmix64 hash gives two
        // uniforms, Box-Muller a normal value.
        const double sigma = J->parameters.target_noise;
        std::map<types::global_dof_index, Point<dim>> support;
        DoFTools::map_dofs_to_support_points(impl->reference_mapping,
                                             impl->dof_handler,
                                             support);
        const auto component = impl->owned_components();
        const auto mix       = [](std::uint64_t z) {
          z += 0x9E3779B97F4A7C15ull;
          z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
          z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
          return z ^ (z >> 31);
        };
        for (unsigned int i = 0; i < impl->reference_states.size(); ++i)
          {
            auto &x = impl->reference_states[i];
            for (const auto k : impl->owned)
              {
                std::uint64_t h = mix(i);
                for (unsigned int d = 0; d < dim; ++d)
                  h = mix(h ^ static_cast<std::uint64_t>(
                                std::llround(support.at(k)[d] * 1e9)));
                h = mix(h ^ component[impl->owned.index_within_set(k)]);
                const double a = 1. - (h >> 11) * 0x1.0p-53; // (0, 1]
                const double b = (mix(h) >> 11) * 0x1.0p-53;
                x(k) += sigma * std::sqrt(-2. * std::log(a)) *
                        std::cos(2. * numbers::PI * b);
              }
            x.compress(VectorOperation::insert);
          }
      }
    impl->apply_design(saved);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::solve_design()
  {
    impl->solve_forward(true);
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::objective() const
  {
    AssertThrow(impl->objective, ExcMessage("no objective set"));
    return impl->objective_value(*impl->objective);
  }

  template <int dim>
  double
  ElasticitySimulator<dim>::gradient(std::vector<double> &dJ) const
  {
    AssertThrow(impl->objective, ExcMessage("no objective set"));
    return impl->compute_gradient(*impl->objective, dJ);
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::write_state(const unsigned int index,
                                        RunContext        &context)
  {
    impl->context = &context;
    impl->set_step_state(impl->u_states.size() - 1);
    if (impl->transient)
      impl->v = impl->v_states.back();
    impl->write_output(index, index);
  }

  template <int dim>
  std::vector<std::pair<std::string, double>>
  ElasticitySimulator<dim>::objective_terms() const
  {
    std::vector<std::pair<std::string, double>> r;
    for (unsigned int t = 0; t < impl->term_values.size(); ++t)
      r.emplace_back(impl->objective->terms()[t]->name, impl->term_values[t]);
    return r;
  }

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
    const auto &m = *impl;
    return {{"n_dofs", m.dof_handler.n_dofs()},
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
            {"seconds_per_gradient",
             m.adjoint_seconds / std::max(1u, m.gradients)},
            {"stored_state_bytes", m.memory_of_states}};
  }

  template void
  ElasticitySimulator<2>::prepare(RunContext *);
  template void
  ElasticitySimulator<3>::prepare(RunContext *);
  template const DesignLayout &
  ElasticitySimulator<2>::design_layout() const;
  template const DesignLayout &
  ElasticitySimulator<3>::design_layout() const;
  template const std::vector<double> &
  ElasticitySimulator<2>::design() const;
  template const std::vector<double> &
  ElasticitySimulator<3>::design() const;
  template void
  ElasticitySimulator<2>::set_design(const std::vector<double> &);
  template void
  ElasticitySimulator<3>::set_design(const std::vector<double> &);
  template void
  ElasticitySimulator<2>::set_objective(
    const std::shared_ptr<const Objective<2>> &);
  template void
  ElasticitySimulator<3>::set_objective(
    const std::shared_ptr<const Objective<3>> &);
  template void
  ElasticitySimulator<2>::solve_design();
  template void
  ElasticitySimulator<3>::solve_design();
  template double
  ElasticitySimulator<2>::objective() const;
  template double
  ElasticitySimulator<3>::objective() const;
  template double
  ElasticitySimulator<2>::gradient(std::vector<double> &) const;
  template double
  ElasticitySimulator<3>::gradient(std::vector<double> &) const;
  template void
  ElasticitySimulator<2>::write_state(const unsigned int, RunContext &);
  template void
  ElasticitySimulator<3>::write_state(const unsigned int, RunContext &);
  template std::vector<std::pair<std::string, double>>
  ElasticitySimulator<2>::objective_terms() const;
  template std::vector<std::pair<std::string, double>>
  ElasticitySimulator<3>::objective_terms() const;
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
} // namespace forma
