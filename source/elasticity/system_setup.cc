// The elasticity simulator's discrete system: the shape field and its
// constraints, the DoFs, boundary constraints, the Jacobian's pattern, the
// null space.

#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_series.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe_field.h>
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
#include <deal.II/numerics/error_estimator.h>
#include <deal.II/numerics/smoothness_estimator.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/simulator.h>
#include <forma/mesh/mesh.h>
#include <forma/physics/material.h>
#include <forma/solvers/linear_solver.h>
#include <forma/solvers/rigid_body_modes.h>

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
        for (const auto &cell : shape_dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const auto v : cell->vertex_indices())
              {
                const auto it = std::lower_bound(
                  material_of_vertex.begin(),
                  material_of_vertex.end(),
                  cell->vertex(v),
                  [&](const auto &entry, const Point<dim> &x) {
                    return lexicographically_before(entry.first, x);
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
        return lexicographically_before(a.first, b.first);
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
    if (p.linear_solver.type == "cg-amg" || p.linear_solver.type == "gmres-amg")
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
    if (matrix_free)
      return; // no matrix: the memory cg-mg saves
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
    RigidBodyModes r = rigid_body_modes(mapping, dof_handler);
    linear_solver.set_null_space(std::move(r.modes), r.pde_equations);
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



  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
