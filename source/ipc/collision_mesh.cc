#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/hp/q_collection.h>

#include <forma/ipc/broad_phase.h>
#include <forma/ipc/collision_mesh.h>
#include <forma/ipc/obstacle_mesh.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    namespace
    {
      /**
       * Triangles of the lattice of a face's support points (unit face
       * coordinates `unit`): tensor grids on quads (any distinct coordinate
       * values), the equispaced lattice of degree k on triangles.
       */
      template <int dim>
      std::vector<std::array<unsigned int, 3>>
      lattice_triangles(const std::vector<Point<dim - 1>> &unit,
                        const bool                         quad)
      {
        std::vector<std::array<unsigned int, 3>> tris;
        if constexpr (dim == 3)
          {
            std::map<std::pair<int, int>, unsigned int> at;
            int                                         n = 0;
            if (quad)
              {
                std::vector<double> xs, ys;
                for (const auto &p : unit)
                  {
                    xs.push_back(p[0]);
                    ys.push_back(p[1]);
                  }
                const auto distinct = [](std::vector<double> &v) {
                  std::sort(v.begin(), v.end());
                  v.erase(std::unique(v.begin(),
                                      v.end(),
                                      [](double a, double b) {
                                        return std::abs(a - b) < 1e-8;
                                      }),
                          v.end());
                };
                distinct(xs);
                distinct(ys);
                const auto index = [](const std::vector<double> &v, double x) {
                  return int(std::lower_bound(v.begin(), v.end(), x - 1e-8) -
                             v.begin());
                };
                for (unsigned int i = 0; i < unit.size(); ++i)
                  at[{index(xs, unit[i][0]), index(ys, unit[i][1])}] = i;
                n = int(xs.size()) - 1;
                for (int i = 0; i < n; ++i)
                  for (int j = 0; j < n; ++j)
                    {
                      const unsigned int a = at.at({i, j}),
                                         b = at.at({i + 1, j}),
                                         c = at.at({i + 1, j + 1}),
                                         d = at.at({i, j + 1});
                      tris.push_back({{a, b, c}});
                      tris.push_back({{a, c, d}});
                    }
              }
            else
              {
                // P_k: k (k + 1) / 2 + ... points; k from the count.
                while ((n + 1) * (n + 2) / 2 < int(unit.size()))
                  ++n;
                for (unsigned int i = 0; i < unit.size(); ++i)
                  at[{int(std::lround(n * unit[i][0])),
                      int(std::lround(n * unit[i][1]))}] = i;
                for (int i = 0; i < n; ++i)
                  for (int j = 0; i + j < n; ++j)
                    {
                      tris.push_back({{at.at({i, j}),
                                       at.at({i + 1, j}),
                                       at.at({i, j + 1})}});
                      if (i + j < n - 1)
                        tris.push_back({{at.at({i + 1, j}),
                                         at.at({i + 1, j + 1}),
                                         at.at({i, j + 1})}});
                    }
              }
          }
        (void)unit;
        (void)quad;
        return tris;
      }



      /**
       * A rank's records of its boundary support points, to be gathered:
       * per vertex [key, dofs..., body] and [x, y, z]; per primitive its
       * vertex keys (the key of a vertex is its x DoF); with a shape DoF
       * handler, per vertex [key, n, (shape DoF, component) x n] and the n
       * weights (the shape field at the vertex).
       */
      template <int dim>
      class BoundaryRecords
      {
      public:
        BoundaryRecords(const DoFHandler<dim> *shape_dof_handler)
          : shape_dof_handler(shape_dof_handler)
        {}

        /// The support points and primitives of face f of `cell` (fv: the
        /// cell's support points, cell_dofs its DoFs).
        void
        add_face(const typename DoFHandler<dim>::active_cell_iterator &cell,
                 const unsigned int                                    f,
                 const FEValues<dim>                                  &fv,
                 const std::vector<types::global_dof_index> &cell_dofs);

        std::vector<types::global_dof_index> v_ints, prims, w_ints;
        std::vector<double>                  v_reals, w_reals;

      private:
        /// Support point i of the cell, with the DoFs `point`.
        void
        add_vertex(const typename DoFHandler<dim>::active_cell_iterator &cell,
                   const std::array<types::global_dof_index, dim>       &point,
                   const unsigned int                                    i,
                   const FEValues<dim>                                  &fv);

        void
        add_shape_weights(
          const typename DoFHandler<dim>::active_cell_iterator &cell,
          const types::global_dof_index                         key,
          const unsigned int                                    i);

        const DoFHandler<dim> *shape_dof_handler;
        /// Position of each vertex's record in v_ints.
        std::map<types::global_dof_index, unsigned int> seen;
        std::vector<types::global_dof_index>            face_dofs, shape_dofs;
      };



      template <int dim>
      void
      BoundaryRecords<dim>::add_face(
        const typename DoFHandler<dim>::active_cell_iterator &cell,
        const unsigned int                                    f,
        const FEValues<dim>                                  &fv,
        const std::vector<types::global_dof_index>           &cell_dofs)
      {
        const auto        &cfe      = cell->get_fe();
        const auto        &base     = cfe.base_element(0);
        const unsigned int n_points = base.n_dofs_per_face(f);
        const auto         face     = cell->face(f);
        face_dofs.resize(cfe.n_dofs_per_face(f));
        face->get_dof_indices(face_dofs, cell->active_fe_index());
        std::vector<std::array<types::global_dof_index, dim>> point(n_points);
        for (unsigned int i = 0; i < face_dofs.size(); ++i)
          {
            const auto ci = cfe.face_system_to_component_index(i, f);
            point[ci.second][ci.first] = face_dofs[i];
          }
        for (unsigned int b = 0; b < n_points; ++b)
          {
            const unsigned int i =
              std::find(cell_dofs.begin(), cell_dofs.end(), point[b][0]) -
              cell_dofs.begin();
            Assert(i < cell_dofs.size(), ExcInternalError());
            add_vertex(cell, point[b], i, fv);
          }

        const std::vector<Point<dim - 1>> &unit =
          base.get_unit_face_support_points(f);
        if (dim == 2)
          {
            std::vector<unsigned int> order(n_points);
            for (unsigned int b = 0; b < n_points; ++b)
              order[b] = b;
            std::sort(order.begin(),
                      order.end(),
                      [&](unsigned int a, unsigned int b) {
                        return unit[a][0] < unit[b][0];
                      });
            for (unsigned int k = 0; k + 1 < n_points; ++k)
              {
                prims.push_back(point[order[k]][0]);
                prims.push_back(point[order[k + 1]][0]);
              }
          }
        else
          for (const auto &t :
               lattice_triangles<dim>(unit, face->n_vertices() == 4))
            for (const unsigned int b : t)
              prims.push_back(point[b][0]);
      }



      template <int dim>
      void
      BoundaryRecords<dim>::add_vertex(
        const typename DoFHandler<dim>::active_cell_iterator &cell,
        const std::array<types::global_dof_index, dim>       &point,
        const unsigned int                                    i,
        const FEValues<dim>                                  &fv)
      {
        const types::global_dof_index key = point[0];
        const auto                    it  = seen.find(key);
        if (it != seen.end())
          {
            // A vertex of several bodies: the lowest material id, whatever
            // the cell order.
            auto &body = v_ints[it->second + dim + 1];
            body = std::min<types::global_dof_index>(body, cell->material_id());
            return;
          }
        seen[key] = v_ints.size();
        v_ints.push_back(key);
        for (unsigned int d = 0; d < dim; ++d)
          v_ints.push_back(point[d]);
        v_ints.push_back(cell->material_id());
        for (unsigned int d = 0; d < 3; ++d)
          v_reals.push_back(d < dim ? fv.quadrature_point(i)[d] : 0.);
        if (shape_dof_handler)
          add_shape_weights(cell, key, i);
      }



      template <int dim>
      void
      BoundaryRecords<dim>::add_shape_weights(
        const typename DoFHandler<dim>::active_cell_iterator &cell,
        const types::global_dof_index                         key,
        const unsigned int                                    i)
      {
        const typename DoFHandler<dim>::active_cell_iterator shape_cell(
          &cell->get_triangulation(),
          cell->level(),
          cell->index(),
          shape_dof_handler);
        const auto &sfe = shape_cell->get_fe();
        shape_dofs.resize(sfe.n_dofs_per_cell());
        shape_cell->get_dof_indices(shape_dofs);
        const Point<dim> &xi = cell->get_fe().get_unit_support_points()[i];
        w_ints.push_back(key);
        const std::size_t count = w_ints.size();
        w_ints.push_back(0);
        for (unsigned int a = 0; a < sfe.n_dofs_per_cell(); ++a)
          {
            const double value = sfe.shape_value(a, xi);
            if (std::abs(value) < 1e-12)
              continue;
            ++w_ints[count];
            w_ints.push_back(shape_dofs[a]);
            w_ints.push_back(sfe.system_to_component_index(a).first);
            w_reals.push_back(value);
          }
      }



      /// A vertex of the collision mesh as gathered from the ranks.
      template <int dim>
      struct GatheredVertex
      {
        std::array<types::global_dof_index, dim> dofs;
        types::material_id                       body;
        Vec                                      x;
      };



      /// Every rank's vertex records, by key (the lowest body of a vertex
      /// that several ranks hold).
      template <int dim>
      std::map<types::global_dof_index, GatheredVertex<dim>>
      gather_vertices(const BoundaryRecords<dim> &records, const MPI_Comm comm)
      {
        const auto all_ints = Utilities::MPI::all_gather(comm, records.v_ints);
        const auto all_reals =
          Utilities::MPI::all_gather(comm, records.v_reals);
        std::map<types::global_dof_index, GatheredVertex<dim>> vertices;
        for (unsigned int r = 0; r < all_ints.size(); ++r)
          for (unsigned int k = 0; k * (dim + 2) < all_ints[r].size(); ++k)
            {
              const types::global_dof_index *v  = &all_ints[r][k * (dim + 2)];
              auto                           it = vertices.find(v[0]);
              if (it != vertices.end())
                {
                  it->second.body =
                    std::min<types::material_id>(it->second.body, v[dim + 1]);
                  continue;
                }
              GatheredVertex<dim> x;
              for (unsigned int d = 0; d < dim; ++d)
                x.dofs[d] = v[1 + d];
              x.body = v[dim + 1];
              for (unsigned int d = 0; d < 3; ++d)
                x.x[d] = all_reals[r][3 * k + d];
              vertices.emplace(v[0], x);
            }
        return vertices;
      }
    } // namespace



    template <int dim>
    CollisionMesh<dim>::CollisionMesh(
      const DoFHandler<dim>              &dof_handler,
      const hp::MappingCollection<dim>   &mapping,
      const std::set<types::boundary_id> &boundaries,
      const MPI_Comm                      comm,
      const DoFHandler<dim>              *shape_dof_handler)
    {
      const auto          &fe = dof_handler.get_fe_collection();
      hp::QCollection<dim> support;
      for (unsigned int i = 0; i < fe.size(); ++i)
        {
          AssertThrow(fe[i].n_base_elements() == 1 &&
                        fe[i].base_element(0).has_support_points(),
                      ExcMessage("IPC contact needs Lagrange elements."));
          AssertThrow(dim == 2 || fe[i].degree <= 2,
                      ExcMessage("IPC contact in 3D: Finite element/Degree "
                                 "must be 1 or 2."));
          support.push_back(Quadrature<dim>(fe[i].get_unit_support_points()));
        }
      hp::FEValues<dim> fe_values(mapping,
                                  fe,
                                  support,
                                  update_quadrature_points);

      BoundaryRecords<dim>                 records(shape_dof_handler);
      std::vector<types::global_dof_index> cell_dofs;
      for (const auto &cell : dof_handler.active_cell_iterators())
        {
          if (!cell->is_locally_owned() || !cell->at_boundary())
            continue;
          bool fe_ready = false;
          for (const unsigned int f : cell->face_indices())
            {
              const auto face = cell->face(f);
              if (!face->at_boundary() ||
                  (!boundaries.empty() &&
                   boundaries.count(face->boundary_id()) == 0))
                continue;
              if (!fe_ready)
                {
                  fe_values.reinit(cell);
                  cell_dofs.resize(cell->get_fe().n_dofs_per_cell());
                  cell->get_dof_indices(cell_dofs);
                  fe_ready = true;
                }
              records.add_face(cell,
                               f,
                               fe_values.get_present_fe_values(),
                               cell_dofs);
            }
        }

      // Gather everything on every rank.
      std::map<types::global_dof_index, unsigned int> index;
      collision_dofs.set_size(dof_handler.n_dofs());
      for (const auto &[key, v] : gather_vertices(records, comm))
        {
          index[key] = rest.size();
          rest.push_back(v.x);
          dofs.push_back(v.dofs);
          body.push_back(v.body);
          for (const auto i : v.dofs)
            collision_dofs.add_index(i);
        }
      collision_dofs.compress();

      shape_weights.assign(rest.size(), {});
      if (shape_dof_handler)
        {
          const auto all_ints =
            Utilities::MPI::all_gather(comm, records.w_ints);
          const auto all_reals =
            Utilities::MPI::all_gather(comm, records.w_reals);
          for (unsigned int r = 0; r < all_ints.size(); ++r)
            for (std::size_t k = 0, l = 0; k < all_ints[r].size();)
              {
                const unsigned int v = index.at(all_ints[r][k]);
                const unsigned int n = all_ints[r][k + 1];
                k += 2;
                const bool first = shape_weights[v].empty();
                for (unsigned int j = 0; j < n; ++j, k += 2, ++l)
                  if (first)
                    shape_weights[v].push_back(
                      {all_ints[r][k],
                       static_cast<unsigned int>(all_ints[r][k + 1]),
                       all_reals[r][l]});
              }
        }

      const auto all_prims = Utilities::MPI::all_gather(comm, records.prims);
      obstacle.assign(rest.size(), -1);
      for (const auto &p : all_prims)
        for (unsigned int k = 0; dim * k < p.size(); ++k)
          {
            if (dim == 2)
              edges.push_back({{index.at(p[2 * k]), index.at(p[2 * k + 1])}});
            else
              faces.push_back({{index.at(p[3 * k]),
                                index.at(p[3 * k + 1]),
                                index.at(p[3 * k + 2])}});
          }
      finalize();
    }



    template <int dim>
    void
    CollisionMesh<dim>::add_obstacle(const ObstacleMesh &o,
                                     const unsigned int  id)
    {
      const unsigned int                       offset = rest.size();
      std::array<types::global_dof_index, dim> none;
      none.fill(numbers::invalid_dof_index);
      for (const Vec &x : o.vertices)
        {
          rest.push_back(x);
          dofs.push_back(none);
          body.push_back(numbers::invalid_material_id);
          obstacle.push_back(id);
        }
      if (dim == 2)
        for (const auto &e : o.edges)
          edges.push_back({{offset + e[0], offset + e[1]}});
      else
        for (const auto &f : o.faces)
          faces.push_back({{offset + f[0], offset + f[1], offset + f[2]}});
      finalize();
    }



    template <int dim>
    void
    CollisionMesh<dim>::finalize()
    {
      vertex_area.assign(rest.size(), 0.);
      if (dim == 2)
        {
          edge_area.clear();
          for (const auto &e : edges)
            {
              const double l = (rest[e[0]] - rest[e[1]]).norm();
              edge_area.push_back(l);
              vertex_area[e[0]] += l / 2;
              vertex_area[e[1]] += l / 2;
            }
        }
      else
        {
          // The edges of the triangles, with a third of their areas.
          std::map<std::pair<unsigned int, unsigned int>, double> edge_map;
          for (const auto &t : faces)
            {
              const double a = 0.5 * cross_product_3d(rest[t[1]] - rest[t[0]],
                                                      rest[t[2]] - rest[t[0]])
                                       .norm();
              for (unsigned int j = 0; j < 3; ++j)
                {
                  vertex_area[t[j]] += a / 3;
                  const unsigned int u = t[j], w = t[(j + 1) % 3];
                  edge_map[{std::min(u, w), std::max(u, w)}] += a / 3;
                }
            }
          edges.clear();
          edge_area.clear();
          for (const auto &e : edge_map)
            {
              edges.push_back({{e.first.first, e.first.second}});
              edge_area.push_back(e.second);
            }
        }
    }



    template <int dim>
    void
    CollisionMesh<dim>::add_area_gradient(const std::vector<double> &s,
                                          std::vector<Vec> &gradient) const
    {
      if (dim == 2)
        for (const auto &e : edges)
          {
            // l / 2 to each end.
            const double c = s[e[0]] + s[e[1]];
            if (c == 0)
              continue;
            const Vec t = rest[e[0]] - rest[e[1]];
            const Vec g = 0.5 * c / t.norm() * t;
            gradient[e[0]] += g;
            gradient[e[1]] -= g;
          }
      else
        for (const auto &t : faces)
          {
            // a / 3 to each vertex, a = |n| / 2, n = (x1 - x0) x (x2 - x0).
            const double c = (s[t[0]] + s[t[1]] + s[t[2]]) / 3.;
            if (c == 0)
              continue;
            const Vec n = cross_product_3d(rest[t[1]] - rest[t[0]],
                                           rest[t[2]] - rest[t[0]]);
            const Vec m = 0.5 * c / n.norm() * n;
            // d|n| = n/|n| . (dx1 x e2 + e1 x dx2 - dx0 x (e2 - e1)).
            for (unsigned int j = 0; j < 3; ++j)
              gradient[t[j]] +=
                cross_product_3d(rest[t[(j + 1) % 3]] - rest[t[(j + 2) % 3]],
                                 m);
          }
    }



    template <int dim>
    double
    CollisionMesh<dim>::diagonal() const
    {
      // Of the bodies (obstacles may be large).
      Box box;
      for (unsigned int v = 0; v < rest.size(); ++v)
        if (!fixed(v))
          box.add(rest[v]);
      double d2 = 0;
      for (unsigned int d = 0; d < 3; ++d)
        d2 += std::pow(std::max(box.hi[d] - box.lo[d], 0.), 2);
      return std::sqrt(d2);
    }



    template struct CollisionMesh<2>;
    template struct CollisionMesh<3>;
  } // namespace ipc
} // namespace forma
