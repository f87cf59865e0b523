// Remeshing of the elasticity simulator's design shape: mesh quality,
// extraction of the current region boundaries, a Gmsh mesh of them, and
// the transfer of material coordinates to the new vertices.

#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi_remote_point_evaluation.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/vector_tools_evaluate.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/records.h>
#include <forma/base/replace_file.h>
#include <forma/base/run_context.h>
#include <forma/mesh/boundary_resampling.h>
#include <forma/mesh/remesh.h>
#include <forma/mesh/separate_interfaces.h>

#include "simulator_impl.h"

#include <algorithm>
#include <fstream>

namespace forma
{
  namespace
  {
    // det J / prod_k |J e_k|: 1 for an undistorted cell, <= 0 if inverted.
    template <int dim>
    double
    scaled_jacobian(const DerivativeForm<1, dim, dim> &J)
    {
      double lengths = 1;
      for (unsigned int k = 0; k < dim; ++k)
        {
          double c = 0;
          for (unsigned int i = 0; i < dim; ++i)
            c += J[i][k] * J[i][k];
          lengths *= std::sqrt(c);
        }
      return J.determinant() / lengths;
    }

    // The smallest scaled Jacobian over the quadrature points of a cell.
    template <int dim, typename Cell>
    double
    cell_scaled_jacobian(hp::FEValues<dim> &fv, const Cell &cell)
    {
      fv.reinit(cell);
      const auto &v     = fv.get_present_fe_values();
      double      worst = 1;
      for (unsigned int q = 0; q < v.n_quadrature_points; ++q)
        worst = std::min(worst, scaled_jacobian<dim>(v.jacobian(q)));
      return worst;
    }
  } // namespace



  template <int dim>
  hp::QCollection<dim>
  ElasticitySimulator<dim>::Impl::quality_points() const
  {
    if (!guard_corners || simplex)
      return quadrature;
    // A bilinear cell's Jacobian is smallest at a corner; quadrature
    // points alone can miss a fold there that a refinement would meet.
    // (A trilinear cell's need not be: in 3D the corners are a better
    // check, not a proof.)
    const QGaussLobatto<dim> corners(2);
    hp::QCollection<dim>     points;
    for (unsigned int k = 0; k < quadrature.size(); ++k)
      {
        auto x = quadrature[k].get_points();
        x.insert(x.end(),
                 corners.get_points().begin(),
                 corners.get_points().end());
        points.push_back(Quadrature<dim>(x, std::vector<double>(x.size(), 1.)));
      }
    return points;
  }



  template <int dim>
  double
  ElasticitySimulator<dim>::Impl::min_scaled_jacobian(Point<dim> *where) const
  {
    hp::FEValues<dim> fv(mapping, fe, quality_points(), update_jacobians);
    double            worst = 1;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const double sj = cell_scaled_jacobian(fv, cell);
          if (sj < worst)
            {
              worst = sj;
              if (where)
                *where = cell->center();
            }
        }
    return worst;
  }



  template <int dim>
  RegionBoundaries<dim>
  ElasticitySimulator<dim>::Impl::region_boundaries(
    const std::vector<bool> *removed,
    const types::boundary_id open_id) const
  {
    // Facets of the locally owned cells, vertices named by their first
    // shape DoF (global, the same on every rank): boundary faces, and
    // interfaces between materials seen from the finer side, or from the
    // smaller material id on a level interface.
    std::vector<types::global_dof_index> keys;
    std::vector<double>                  x;
    std::vector<unsigned int>            ids; // inside, outside, boundary
    const auto                           gone = [&](const auto &c) {
      return removed && (*removed)[c->active_cell_index()];
    };
    for (const auto &cell : shape_dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && !gone(cell))
        for (const auto f : cell->face_indices())
          {
            const auto         face    = cell->face(f);
            types::material_id outside = numbers::invalid_material_id;
            types::boundary_id id      = 0;
            if (face->at_boundary())
              id = face->boundary_id();
            else if (face->has_children())
              continue;
            else if (gone(cell->neighbor(f)))
              id = open_id; // a face the removed cells leave open
            else
              {
                const auto neighbor = cell->neighbor(f);
                if (neighbor->material_id() == cell->material_id() ||
                    (!cell->neighbor_is_coarser(f) &&
                     neighbor->material_id() < cell->material_id()))
                  continue;
                outside = neighbor->material_id();
              }
            std::array<unsigned int, dim> order;
            std::array<Point<dim>, dim>   p;
            AssertThrow(face->n_vertices() == dim, ExcInternalError());
            for (unsigned int v = 0; v < dim; ++v)
              {
                order[v] = v;
                for (unsigned int d = 0; d < dim; ++d)
                  p[v][d] = shape_ghost(face->vertex_dof_index(v, d));
              }
            // Orient the facet with its normal out of the cell, decided on
            // the mesh itself: the design keeps the orientation of every
            // cell, and distorted cells can put their center on the wrong
            // side of a facet.
            const auto &y = face;
            double      side;
            if constexpr (dim == 2)
              side = (y->vertex(1)[0] - y->vertex(0)[0]) *
                       (cell->center()[1] - y->vertex(0)[1]) -
                     (y->vertex(1)[1] - y->vertex(0)[1]) *
                       (cell->center()[0] - y->vertex(0)[0]);
            else
              side = -(cross_product_3d(y->vertex(1) - y->vertex(0),
                                        y->vertex(2) - y->vertex(0)) *
                       (cell->center() - y->vertex(0)));
            if (side < 0)
              std::swap(order[0], order[1]);
            for (const auto v : order)
              {
                keys.push_back(face->vertex_dof_index(v, 0));
                for (unsigned int d = 0; d < dim; ++d)
                  x.push_back(p[v][d]);
              }
            ids.insert(ids.end(), {cell->material_id(), outside, id});
          }

    const auto            all_keys = Utilities::MPI::gather(comm, keys);
    const auto            all_x    = Utilities::MPI::gather(comm, x);
    const auto            all_ids  = Utilities::MPI::gather(comm, ids);
    RegionBoundaries<dim> result;
    std::map<types::global_dof_index, unsigned int> vertex;
    for (unsigned int r = 0; r < all_keys.size(); ++r)
      for (unsigned int k = 0; k < all_ids[r].size() / 3; ++k)
        {
          typename RegionBoundaries<dim>::Facet facet;
          for (unsigned int v = 0; v < dim; ++v)
            {
              const auto key = all_keys[r][dim * k + v];
              const auto it  = vertex.emplace(key, vertex.size()).first;
              if (it->second == result.vertices.size())
                {
                  Point<dim> p;
                  for (unsigned int d = 0; d < dim; ++d)
                    p[d] = all_x[r][dim * (dim * k + v) + d];
                  result.vertices.push_back(p);
                }
              facet.vertices[v] = it->second;
            }
          facet.inside      = all_ids[r][3 * k];
          facet.outside     = all_ids[r][3 * k + 1];
          facet.boundary_id = all_ids[r][3 * k + 2];
          result.facets.push_back(facet);
        }
    return result; // complete on rank 0, empty elsewhere
  }



  template <int dim>
  BoundaryResampling
  ElasticitySimulator<dim>::Impl::boundary_resampling() const
  {
    BoundaryResampling o;
    o.size          = p.design.remesh_boundary_size;
    o.feature_angle = p.design.remesh_feature_angle * numbers::PI / 180;
    for (const auto &id :
         Utilities::split_string_list(p.design.fixed_boundaries, ','))
      o.kept_boundaries.insert(Utilities::string_to_int(id));
    for (const auto &id :
         Utilities::split_string_list(p.design.fixed_bodies, ','))
      o.kept_materials.insert(Utilities::string_to_int(id));
    // 3D resampling remeshes each side of a cut interface on its own: they
    // would no longer match, so both keep their facets (2D resamples the
    // two sides identically).
    if (dim == 3)
      for (const auto &cut : parse_interface_cuts(p.mesh.separate_interfaces,
                                                  "Mesh/Separate interfaces"))
        o.kept_boundaries.insert(cut.boundary);
    return o;
  }



  template <int dim>
  std::vector<Point<dim>>
  ElasticitySimulator<dim>::Impl::material_points(
    const std::vector<Point<dim>> &x) const
  {
    Utilities::MPI::RemotePointEvaluation<dim> cache(1e-8);
    const auto values = VectorTools::point_values<dim>(
      mapping[0], shape_dof_handler, material_positions, x, cache);
    std::vector<Point<dim>>   X(x.size());
    std::vector<Point<dim>>   outside;
    std::vector<unsigned int> where;
    for (unsigned int i = 0; i < x.size(); ++i)
      if (cache.point_found(i))
        X[i] = Point<dim>(values[i]);
      else
        outside.push_back(x[i]), where.push_back(i);
    // A resampled boundary vertex may lie a fraction of a sagitta outside
    // the old mesh (resample_boundaries() keeps the areas): extrapolate
    // from the nearest boundary cell.
    Utilities::MPI::RemotePointEvaluation<dim> near(0.25, true);
    const auto extrapolated = VectorTools::point_values<dim>(
      mapping[0], shape_dof_handler, material_positions, outside, near);
    AssertThrow(near.all_points_found(),
                ExcMessage("remeshing: a vertex of the new mesh lies outside "
                           "the old one."));
    for (unsigned int k = 0; k < where.size(); ++k)
      X[where[k]] = Point<dim>(extrapolated[k]);
    return X;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::replace_mesh(const Triangulation<dim> &serial,
                                               const std::vector<Point<dim>> &X)
  {
    AssertThrow(serial.n_vertices() == X.size(),
                ExcMessage("remeshing: the material coordinates do not match "
                           "the mesh (" +
                           std::to_string(X.size()) + " for " +
                           std::to_string(serial.n_vertices()) +
                           " vertices)."));
    std::vector<std::pair<Point<dim>, Point<dim>>> vertex_map;
    for (unsigned int v = 0; v < X.size(); ++v)
      vertex_map.emplace_back(serial.get_vertices()[v], X[v]);
    std::sort(vertex_map.begin(),
              vertex_map.end(),
              [](const auto &a, const auto &b) {
                return lexicographically_before(a.first, b.first);
              });
    auto new_tria =
      make_parallel_triangulation<dim>(simplex,
                                       !p.mesh.separate_interfaces.empty(),
                                       comm);
    new_tria->copy_triangulation(serial);

    // Kept before anything changes, so that a failure from here on can
    // be undone.
    previous_mesh                     = std::make_unique<PreviousMesh>();
    previous_mesh->material_of_vertex = material_of_vertex;
    previous_mesh->remeshed           = remeshed;
    previous_mesh->design             = design;
    previous_mesh->refinements        = std::move(refinements);
    refinements.clear();
    const auto old_layout = layout;
    remeshed              = true;
    ++n_remeshes;
    adopt_mesh(std::move(new_tria), std::move(vertex_map), previous_mesh->tria);

    // The design: a fresh shape block (the new vertices are the current
    // shape), the other blocks as they were.
    build_design_layout();
    carry_design(old_layout, previous_mesh->design, "remeshing", false);
    apply_design(design);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::undo_remesh()
  {
    AssertThrow(previous_mesh, ExcInternalError());
    const auto previous = std::move(previous_mesh);
    remeshed            = previous->remeshed;
    refinements         = previous->refinements;
    --n_remeshes;
    if (!previous->tria) // failed before the mesh was replaced
      return;
    std::unique_ptr<parallel::TriangulationBase<dim>> failed;
    adopt_mesh(std::move(previous->tria),
               std::move(previous->material_of_vertex),
               failed);
    build_design_layout();
    AssertThrow(previous->design.size() == design.size(), ExcInternalError());
    design = previous->design;
    apply_design(design);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::adopt_mesh(
    std::unique_ptr<parallel::TriangulationBase<dim>>  new_tria,
    std::vector<std::pair<Point<dim>, Point<dim>>>   &&vertex_map,
    std::unique_ptr<parallel::TriangulationBase<dim>> &old_tria)
  {
    // Both meshes stay alive until the DoF handlers have moved over.
    old_tria = std::move(tria);
    tria     = std::move(new_tria);
    dof_handler.reinit(*tria);
    shape_dof_handler.reinit(*tria);
    if (matrix_free) // its own DoF handlers hold the old mesh too
      matrix_free =
        std::make_unique<MatrixFreeElasticity<dim>>(p.linear_solver);
    material_of_vertex = std::move(vertex_map);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        cell->set_active_fe_index(simplex ? 0 : p.degree - 1);

    // Factorizations of the old matrices are useless now.
    linear_solver = LinearSolver(p.linear_solver);
    u_history.clear();
    v_history.clear();
    u_states.clear();
    v_states.clear();
    reference_states.clear();
    objective_cache.clear();
    setup_system();
  }



  template <int dim>
  std::string
  ElasticitySimulator<dim>::Impl::new_mesh(const std::vector<bool> *removed,
                                           const types::boundary_id open_id)
  {
    if (!removed && !pending_mesh.empty() && pending_design == design &&
        pending_size == tria->n_global_active_cells())
      return pending_mesh;
    AssertThrow(dim == 2 || simplex,
                ExcMessage("remeshing: hexahedral meshes cannot be remeshed "
                           "(Gmsh makes tetrahedra); use 'Mesh/Convert to "
                           "simplices = true' for 3D shape optimization with "
                           "remeshing."));
    const double      before = Utilities::MPI::min(min_scaled_jacobian(), comm);
    auto              boundary = region_boundaries(removed, open_id);
    const std::string msh      = on_root_or_throw(comm, [&]() {
      if (p.design.resample_boundary)
        boundary = resample_boundaries(boundary, boundary_resampling());
      return mesh_regions(boundary, !simplex);
    });

    // A remesh that does not improve the quality (the kept boundary can
    // limit it) is refused.
    Triangulation<dim> serial;
    read_regions_mesh(msh, serial);
    const unsigned int k = simplex ? 0 : p.degree - 1;
    FEValues<dim>      fv(mesh_mapping[0],
                     *shape_fe,
                     quality_points()[k],
                     update_jacobians);
    double             after = 1;
    Point<dim>         worst;
    for (const auto &cell : serial.active_cell_iterators())
      {
        fv.reinit(cell);
        for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
          {
            const double sj = scaled_jacobian<dim>(fv.jacobian(q));
            if (sj < after)
              after = sj, worst = cell->center();
          }
      }
    AssertThrow(after >= p.design.min_scaled_jacobian,
                ExcMessage("remeshing: the new mesh has a cell of scaled "
                           "Jacobian " +
                           fmt(after, 3) + " < Design/Min scaled Jacobian = " +
                           fmt(p.design.min_scaled_jacobian, 3) + " near " +
                           fmt(Tensor<1, dim>(worst)) + "."));
    if (removed)
      return msh;
    pending_mesh    = msh;
    pending_design  = design;
    pending_quality = {before, after};
    pending_size    = tria->n_global_active_cells();
    return msh;
  }



  // ---------------------------------------------------------------- facade

  template <int dim>
  double
  ElasticitySimulator<dim>::mesh_quality() const
  {
    return Utilities::MPI::min(impl->min_scaled_jacobian(), impl->comm);
  }

  template <int dim>
  std::vector<unsigned int>
  ElasticitySimulator<dim>::degenerate_shape_entries(
    const double threshold) const
  {
    const auto               *b = impl->layout.find("shape");
    std::vector<unsigned int> entries;
    if (!b)
      return entries;
    const Impl       &I = *impl;
    hp::FEValues<dim> fv(I.mapping, I.fe, I.quality_points(), update_jacobians);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : I.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          if (cell_scaled_jacobian(fv, cell) >= threshold)
            continue;
          const typename DoFHandler<dim>::active_cell_iterator shape_cell(
            &*I.tria, cell->level(), cell->index(), &I.shape_dof_handler);
          dofs.resize(shape_cell->get_fe().n_dofs_per_cell());
          shape_cell->get_dof_indices(dofs);
          for (const auto i : dofs)
            if (I.shape_constraints.is_constrained(i))
              {
                // A fixed vertex does not move; an interface copy follows
                // its partner: hold that one.
                if (const auto *c =
                      I.shape_constraints.get_constraint_entries(i))
                  for (const auto &[j, weight] : *c)
                    entries.push_back(b->offset + j);
              }
            else
              {
                // With boundary shape parameters an interior vertex follows
                // the boundary (harmonic extension): no entry to hold.
                if (!I.extension || I.extension->is_boundary(i))
                  entries.push_back(b->offset + i);
              }
        }
    std::vector<unsigned int> all;
    for (const auto &part : Utilities::MPI::all_gather(I.comm, entries))
      all.insert(all.end(), part.begin(), part.end());
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::guard_cell_corners(const bool on)
  {
    impl->guard_corners = on;
  }

  template <int dim>
  bool
  ElasticitySimulator<dim>::remesh_improves(std::string &reason)
  {
    try
      {
        impl->new_mesh();
        const auto [before, after] = impl->pending_quality;
        AssertThrow(after > before,
                    ExcMessage(
                      "remeshing: the new mesh would not be better "
                      "(min scaled Jacobian " +
                      fmt(before, 3) + " -> " + fmt(after, 3) + "); " +
                      (impl->p.design.resample_boundary ?
                         "the boundary's corners and fixed pieces, which "
                         "resampling keeps, limit the quality." :
                         "the boundary, which remeshing keeps, limits the "
                         "quality.")));
        return true;
      }
    catch (const std::exception &e)
      {
        reason = error_message(e);
        return false;
      }
  }

  template <int dim>
  std::string
  ElasticitySimulator<dim>::remesh(const std::string &file_stem)
  {
    return remesh_without(file_stem, {}, 0);
  }

  template <int dim>
  std::set<types::boundary_id>
  ElasticitySimulator<dim>::holding_boundaries() const
  {
    std::set<types::boundary_id> ids;
    for (const auto &d : impl->dirichlet)
      ids.insert(d.id);
    for (const auto *laws :
         {&impl->p.contact.rigid, &impl->p.contact.deformable})
      for (const auto &[id, law] : *laws)
        ids.insert(id);
    return ids;
  }

  template <int dim>
  const Triangulation<dim, dim> &
  ElasticitySimulator<dim>::triangulation() const
  {
    return *impl->tria;
  }

  template <int dim>
  std::string
  ElasticitySimulator<dim>::remesh_without(const std::string       &file_stem,
                                           const std::vector<bool> &removed,
                                           const types::boundary_id open_id)
  {
    auto        &s        = *impl;
    const double before   = mesh_quality();
    const auto   n_before = s.tria->n_global_active_cells();
    AssertThrow(removed.empty() || removed.size() == s.tria->n_active_cells(),
                ExcInternalError());
    const std::string msh =
      removed.empty() ? s.new_mesh() : s.new_mesh(&removed, open_id);
    s.pending_mesh.clear();
    Triangulation<dim> serial;
    read_regions_mesh(msh, serial);

    // Material coordinates of the new vertices, from the old mesh.
    const auto X = s.material_points(serial.get_vertices());

    // Files first: a resumed run restores this mesh from them; so only a
    // mesh that setup_system() will take, checked before anything changes.
    s.check_parts_are_held(serial);
    if (!file_stem.empty())
      on_root_or_throw(
        s.comm,
        [&]() {
          nlohmann::json j = nlohmann::json::array();
          for (const auto &p : X)
            j.push_back(std::vector<double>(p.begin_raw(), p.end_raw()));
          replace_file_text(file_stem + ".msh", msh);
          replace_file_text(file_stem + ".json", j.dump());
        },
        "remeshing");
    s.replace_mesh(serial, X);
    if (s.objective)
      set_objective(s.objective); // the reference run on the new mesh
    if (!removed.empty())
      return "removed " +
             std::to_string(std::count(removed.begin(), removed.end(), true)) +
             " low-stress cells and remeshed: " + std::to_string(n_before) +
             " -> " + std::to_string(s.tria->n_global_active_cells()) +
             " cells, min scaled Jacobian " + fmt(mesh_quality(), 3);
    return "remeshed (min scaled Jacobian " + fmt(before, 3) +
           "): " + std::to_string(n_before) + " -> " +
           std::to_string(s.tria->n_global_active_cells()) +
           " cells, min scaled Jacobian " + fmt(mesh_quality(), 3);
  }

  template <int dim>
  bool
  ElasticitySimulator<dim>::undo_remesh()
  {
    if (!impl->previous_mesh)
      return false;
    impl->undo_remesh();
    if (impl->objective)
      set_objective(impl->objective);
    return true;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::commit_remesh()
  {
    impl->previous_mesh.reset();
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::load_remeshed(const std::string &file_stem)
  {
    std::ifstream msh_in(file_stem + ".msh"), json_in(file_stem + ".json");
    AssertThrow(msh_in && json_in,
                ExcMessage("cannot read the remeshed design '" + file_stem +
                           ".msh/.json'."));
    std::ostringstream msh;
    msh << msh_in.rdbuf();
    std::vector<Point<dim>> X;
    try
      {
        nlohmann::json j;
        json_in >> j;
        for (const auto &c : j)
          {
            Point<dim> p;
            for (unsigned int d = 0; d < dim; ++d)
              p[d] = c.at(d).get<double>();
            X.push_back(p);
          }
      }
    catch (const std::exception &e)
      {
        AssertThrow(false,
                    ExcMessage("the remeshed design '" + file_stem +
                               ".json' is unreadable: " + e.what()));
      }
    Triangulation<dim> serial;
    read_regions_mesh(msh.str(), serial);
    impl->replace_mesh(serial, X);
    if (impl->objective)
      set_objective(impl->objective);
  }

  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::material_offsets() const
  {
    std::vector<double> offsets(impl->layout.size(), 0.);
    if (const auto *b = impl->layout.find("shape"))
      {
        for (const auto i : impl->shape_owned)
          offsets[b->offset + i] =
            impl->material_positions(i) - impl->shape_reference(i);
        Utilities::MPI::sum(offsets, impl->comm, offsets);
      }
    return offsets;
  }

  template <int dim>
  unsigned int
  ElasticitySimulator<dim>::n_remeshes() const
  {
    return impl->n_remeshes;
  }

  // Explicit instantiation of the members defined here (the class itself is
  // instantiated in simulator.cc).
#define FORMA_INSTANTIATE(dim)                                                   \
  template double ElasticitySimulator<dim>::Impl::min_scaled_jacobian(           \
    Point<dim> *) const;                                                         \
  template double ElasticitySimulator<dim>::mesh_quality() const;                \
  template void   ElasticitySimulator<dim>::guard_cell_corners(const bool);      \
  template std::vector<unsigned int>                                             \
  ElasticitySimulator<dim>::degenerate_shape_entries(const double) const;        \
  template bool        ElasticitySimulator<dim>::remesh_improves(std::string &); \
  template std::string ElasticitySimulator<dim>::remesh(const std::string &);    \
  template std::string ElasticitySimulator<dim>::remesh_without(                 \
    const std::string &, const std::vector<bool> &, types::boundary_id);         \
  template std::set<types::boundary_id>                                          \
  ElasticitySimulator<dim>::holding_boundaries() const;                          \
  template const Triangulation<dim, dim>                                         \
               &ElasticitySimulator<dim>::triangulation() const;                 \
  template void ElasticitySimulator<dim>::load_remeshed(const std::string &);    \
  template bool ElasticitySimulator<dim>::undo_remesh();                         \
  template void ElasticitySimulator<dim>::commit_remesh();                       \
  template std::vector<double> ElasticitySimulator<dim>::material_offsets()      \
    const;                                                                       \
  template unsigned int ElasticitySimulator<dim>::n_remeshes() const;
  FORMA_INSTANTIATE(2)
  FORMA_INSTANTIATE(3)
#undef FORMA_INSTANTIATE
  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
