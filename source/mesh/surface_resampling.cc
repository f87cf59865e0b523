// Resampling of the boundary surfaces of a 3D mesh before it is remeshed:
// the 3D counterpart of boundary_resampling.cc. Shape optimization
// stretches and shears the surface triangles, and a remesh that keeps them
// cannot mend the tetrahedra behind them (thesis Algorithm 1 remeshes the
// boundary too). CGAL's isotropic remeshing regenerates each surface patch
// on its current shape; the feature curves between patches stay.

#include <deal.II/base/exceptions.h>

#include <forma/mesh/boundary_resampling.h>

#include "resampling_check.h"
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace forma
{
  using namespace dealii;

  namespace
  {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Mesh   = CGAL::Surface_mesh<Kernel::Point_3>;
    using Key    = std::array<unsigned int, 3>; // inside, outside, boundary
    using Edge   = std::pair<unsigned int, unsigned int>; // sorted
    using Facet  = RegionBoundaries<3>::Facet;

    constexpr unsigned int no_vertex = numbers::invalid_unsigned_int;

    Key
    key_of(const Facet &f)
    {
      return {{f.inside, f.outside, f.boundary_id}};
    }

    Edge
    edge(const unsigned int a, const unsigned int b)
    {
      return a < b ? Edge{a, b} : Edge{b, a};
    }

    std::string
    name(const Key &key)
    {
      return key[1] == numbers::invalid_material_id ?
               "boundary " + std::to_string(key[2]) + " of material " +
                 std::to_string(key[0]) :
               "interface of materials " + std::to_string(key[0]) + " and " +
                 std::to_string(key[1]);
    }

    // det(x0, x1, x2) / 6: the facet's share of the volume it encloses.
    double
    signed_volume(const Point<3> &x0, const Point<3> &x1, const Point<3> &x2)
    {
      return x0 * cross_product_3d(x1, x2) / 6;
    }

    Tensor<1, 3>
    normal(const RegionBoundaries<3> &b, const Facet &f)
    {
      const auto &x = b.vertices;
      return cross_product_3d(x[f.vertices[1]] - x[f.vertices[0]],
                              x[f.vertices[2]] - x[f.vertices[0]]);
    }

    // The facets around every edge.
    std::map<Edge, std::vector<unsigned int>>
    edge_facets(const RegionBoundaries<3> &b)
    {
      std::map<Edge, std::vector<unsigned int>> facets;
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        for (unsigned int k = 0; k < 3; ++k)
          facets[edge(b.facets[i].vertices[k],
                      b.facets[i].vertices[(k + 1) % 3])]
            .push_back(i);
      return facets;
    }

    // Patches: facets of one key connected through their edges (a surface
    // CGAL can hold). Returns the patch of every facet.
    std::vector<unsigned int>
    find_patches(const RegionBoundaries<3> &b, unsigned int &n_patches)
    {
      std::vector<unsigned int> parent(b.facets.size());
      std::iota(parent.begin(), parent.end(), 0u);
      const auto root = [&](unsigned int i) {
        while (parent[i] != i)
          i = parent[i] = parent[parent[i]]; // path halving
        return i;
      };
      for (const auto &[e, facets] : edge_facets(b))
        for (const auto i : facets)
          if (key_of(b.facets[i]) == key_of(b.facets[facets[0]]))
            parent[root(i)] = root(facets[0]);
      std::map<unsigned int, unsigned int> index;
      std::vector<unsigned int>            patch(b.facets.size());
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        patch[i] = index.emplace(root(i), index.size()).first->second;
      n_patches = index.size();
      return patch;
    }

    // The surface as patches, with the feature edges that stay: patch
    // borders, and edges where the surface bends by more than the feature
    // angle.
    struct Patches
    {
      std::vector<unsigned int> of_facet;
      std::vector<Key>          key;
      std::vector<bool>         kept;
      std::set<Edge>            features;
    };

    Patches
    find_features(const RegionBoundaries<3> &b, const BoundaryResampling &o)
    {
      Patches      p;
      unsigned int n;
      p.of_facet = find_patches(b, n);
      p.key.resize(n);
      p.kept.resize(n);
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        {
          const auto &f         = b.facets[i];
          p.key[p.of_facet[i]]  = key_of(f);
          p.kept[p.of_facet[i]] = o.keeps(f.inside, f.outside, f.boundary_id);
        }
      for (const auto &[e, facets] : edge_facets(b))
        {
          bool feature = facets.size() != 2;
          if (!feature)
            {
              const auto n0 = normal(b, b.facets[facets[0]]),
                         n1 = normal(b, b.facets[facets[1]]);
              feature =
                p.of_facet[facets[0]] != p.of_facet[facets[1]] ||
                n0 * n1 < std::cos(o.feature_angle) * n0.norm() * n1.norm();
            }
          if (feature)
            p.features.insert(e);
        }
      return p;
    }

    // The copies of a vertex on the two sides of a cut interface lie at one
    // point: a patch all of whose vertices have such a twin is one side of
    // a cut interface. Both sides stay, so that they keep matching.
    void
    keep_cut_interfaces(const RegionBoundaries<3> &b, Patches &p)
    {
      Point<3> low = b.vertices[0], high = b.vertices[0];
      for (const auto &x : b.vertices)
        for (unsigned int d = 0; d < 3; ++d)
          low[d] = std::min(low[d], x[d]), high[d] = std::max(high[d], x[d]);
      const double tolerance = 1e-10 * (high - low).norm();
      std::map<std::array<long long, 3>, unsigned int> copies;
      std::vector<std::array<long long, 3>>            where(b.vertices.size());
      for (unsigned int v = 0; v < b.vertices.size(); ++v)
        {
          for (unsigned int d = 0; d < 3; ++d)
            where[v][d] = std::llround(b.vertices[v][d] / tolerance);
          ++copies[where[v]];
        }
      std::vector<bool> all_doubled(p.key.size(), true);
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        for (const auto v : b.facets[i].vertices)
          if (copies[where[v]] < 2)
            all_doubled[p.of_facet[i]] = false;
      for (unsigned int k = 0; k < p.key.size(); ++k)
        if (all_doubled[k])
          p.kept[k] = true;
    }

    // Splits every feature edge beside a free patch that is longer than
    // `high` at its midpoint (the facets on all sides with it), until none
    // is: CGAL keeps the feature edges and needs them no longer than 4/3
    // of its target. The geometry does not change.
    void
    split_long_features(RegionBoundaries<3> &b, Patches &p, const double high)
    {
      auto facets_of = edge_facets(b);
      for (bool again = true; again;)
        {
          again = false;
          const std::vector<Edge> features(p.features.begin(),
                                           p.features.end());
          for (const auto &e : features)
            {
              const auto &xa = b.vertices[e.first], &xb = b.vertices[e.second];
              const auto &around = facets_of[e];
              // Only CGAL's (free) patches need short features: kept ones,
              // the two sides of a cut among them, stay as they are.
              if ((xb - xa).norm() <= high ||
                  std::all_of(around.begin(),
                              around.end(),
                              [&](const unsigned int f) {
                                return p.kept[p.of_facet[f]];
                              }))
                continue;
              again                = true;
              const unsigned int m = b.vertices.size();
              b.vertices.push_back((xa + xb) / 2);
              p.features.erase(e);
              p.features.insert(edge(e.first, m));
              p.features.insert(edge(m, e.second));
              for (const auto f : facets_of[e])
                {
                  // (.., a, b, c ..) -> (a, m, c) in f, (m, b, c) in g.
                  auto        &v = b.facets[f].vertices;
                  unsigned int k = 0;
                  while (edge(v[k], v[(k + 1) % 3]) != e)
                    ++k;
                  const unsigned int a = v[k], c = v[(k + 2) % 3],
                                     bb = v[(k + 1) % 3];
                  const unsigned int g  = b.facets.size();
                  b.facets.push_back(b.facets[f]);
                  p.of_facet.push_back(p.of_facet[f]);
                  b.facets[f].vertices[(k + 1) % 3] = m;
                  b.facets[g].vertices[k]           = m;
                  auto &bc                          = facets_of[edge(bb, c)];
                  std::replace(bc.begin(), bc.end(), f, g);
                  facets_of[edge(a, m)].push_back(f);
                  facets_of[edge(m, bb)].push_back(g);
                  facets_of[edge(m, c)].insert(facets_of[edge(m, c)].end(),
                                               {f, g});
                }
              facets_of.erase(e);
            }
        }
    }

    // Collapses the vertices inside one free patch that lie on a feature
    // (sharp) edge curve, between two feature edges one of which is
    // shorter than `low`, into the nearer neighbour on that curve: CGAL
    // cannot shorten protected edges, and a short one keeps a needle
    // triangle beside it. A collapse that would flip or crush a facet, or
    // join two vertices with other common neighbours, is skipped. Patch
    // borders do not change.
    void
    collapse_short_features(RegionBoundaries<3> &b,
                            Patches             &p,
                            const double         low)
    {
      std::vector<std::vector<unsigned int>> around(b.vertices.size());
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        for (const auto v : b.facets[i].vertices)
          around[v].push_back(i);
      std::vector<std::vector<unsigned int>> curve(b.vertices.size());
      for (const auto &e : p.features)
        curve[e.first].push_back(e.second), curve[e.second].push_back(e.first);
      std::vector<bool> dead(b.facets.size()), touched(b.vertices.size());
      for (unsigned int v = 0; v < b.vertices.size(); ++v)
        {
          if (curve[v].size() != 2 || around[v].empty() || touched[v])
            continue;
          const unsigned int patch = p.of_facet[around[v][0]];
          bool               one   = !p.kept[patch];
          for (const auto i : around[v])
            one = one && p.of_facet[i] == patch;
          const auto length = [&](const unsigned int u) {
            return (b.vertices[u] - b.vertices[v]).norm();
          };
          const unsigned int u = length(curve[v][0]) < length(curve[v][1]) ?
                                   curve[v][0] :
                                   curve[v][1];
          const unsigned int w = u == curve[v][0] ? curve[v][1] : curve[v][0];
          if (!one || length(u) >= low || touched[u] || touched[w])
            continue;
          // The facets on edge (v, u) go; the others of v move to u.
          std::set<unsigned int>    opposite, others, near_u;
          std::vector<unsigned int> gone, moved;
          for (const auto i : around[v])
            {
              const auto &x = b.facets[i].vertices;
              if (std::count(x.begin(), x.end(), u))
                {
                  gone.push_back(i);
                  for (const auto y : x)
                    if (y != u && y != v)
                      opposite.insert(y);
                }
              else
                {
                  moved.push_back(i);
                  others.insert(x.begin(), x.end());
                }
            }
          for (const auto i : around[u])
            near_u.insert(b.facets[i].vertices.begin(),
                          b.facets[i].vertices.end());
          bool valid = gone.size() == 2 && opposite.size() == 2;
          for (const auto y : others)
            valid = valid && (y == v || !near_u.count(y) || opposite.count(y));
          for (const auto i : moved)
            {
              auto f = b.facets[i];
              std::replace(f.vertices.begin(), f.vertices.end(), v, u);
              const auto n0 = normal(b, b.facets[i]), n1 = normal(b, f);
              valid = valid && n0 * n1 > 0.1 * n0.norm() * n1.norm();
            }
          if (!valid)
            continue;
          for (const auto i : gone)
            dead[i] = true;
          for (const auto i : moved)
            {
              auto &x = b.facets[i].vertices;
              std::replace(x.begin(), x.end(), v, u);
            }
          p.features.erase(edge(v, u));
          p.features.erase(edge(v, w));
          p.features.insert(edge(u, w));
          for (const auto y : others)
            touched[y] = true;
          touched[u] = touched[w] = touched[v] = true;
        }
      unsigned int kept = 0;
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        if (!dead[i])
          {
            b.facets[kept]     = b.facets[i];
            p.of_facet[kept++] = p.of_facet[i];
          }
      b.facets.resize(kept);
      p.of_facet.resize(kept);
    }

    // The target edge length: the mean edge length of the free patches.
    double
    mean_free_edge(const RegionBoundaries<3> &b, const Patches &p)
    {
      double       sum = 0;
      unsigned int n   = 0;
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        if (!p.kept[p.of_facet[i]])
          for (unsigned int k = 0; k < 3; ++k)
            sum += (b.vertices[b.facets[i].vertices[(k + 1) % 3]] -
                    b.vertices[b.facets[i].vertices[k]])
                     .norm(),
              ++n;
      return n ? sum / n : 0;
    }

    Point<3>
    point(const Kernel::Point_3 &x)
    {
      return {x.x(), x.y(), x.z()};
    }

    double
    enclosed(const Mesh &mesh)
    {
      double s = 0;
      for (const auto f : mesh.faces())
        {
          std::array<Point<3>, 3> x;
          unsigned int            k = 0;
          for (const auto v :
               CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            x[k++] = point(mesh.point(v));
          s += signed_volume(x[0], x[1], x[2]);
        }
      return s;
    }

    // Moves the free vertices of `mesh` along the gradient of the volume
    // it encloses until that is `target` again: a patch keeps the volume
    // between it and its old shape at zero (its border stays), so every
    // region keeps its volume. Returns the largest move of a vertex.
    template <typename Fixed>
    double
    restore_volume(Mesh &mesh, const Fixed &fixed, const double target)
    {
      std::map<Mesh::Vertex_index, Tensor<1, 3>> moved;
      for (unsigned int step = 0; step < 3; ++step)
        {
          std::map<Mesh::Vertex_index, Tensor<1, 3>> gradient;
          for (const auto f : mesh.faces())
            for (const auto g :
                 CGAL::halfedges_around_face(mesh.halfedge(f), mesh))
              {
                const auto v = mesh.target(g);
                if (fixed(v))
                  continue;
                const auto a = point(mesh.point(mesh.target(mesh.next(g))));
                const auto c =
                  point(mesh.point(mesh.target(mesh.next(mesh.next(g)))));
                gradient[v] += cross_product_3d(a, c) / 6;
              }
          double norm2 = 0;
          for (const auto &[v, g] : gradient)
            norm2 += g * g;
          if (norm2 == 0)
            break;
          const double t = (target - enclosed(mesh)) / norm2;
          for (const auto &[v, g] : gradient)
            {
              mesh.point(v) =
                mesh.point(v) + Kernel::Vector_3(t * g[0], t * g[1], t * g[2]);
              moved[v] += t * g;
            }
        }
      double largest = 0;
      for (const auto &[v, d] : moved)
        largest = std::max(largest, d.norm());
      return largest;
    }

    // Remeshes the facets of one patch (the border and the feature edges
    // stay), gives it back the volume it enclosed before any change, and
    // appends the result to `out`; `index` maps the vertices of `b` that
    // stay to those of `out`.
    void
    remesh_patch(const RegionBoundaries<3>       &b,
                 const std::vector<unsigned int> &facets,
                 const Patches                   &p,
                 const std::vector<bool>         &shared,
                 const double                     size,
                 const double                     enclosed_before,
                 const std::function<unsigned int(unsigned int)> &index,
                 RegionBoundaries<3>                             &out)
    {
      Mesh mesh;
      auto global =
        mesh
          .add_property_map<Mesh::Vertex_index, unsigned int>("v:global",
                                                              no_vertex)
          .first;
      std::map<unsigned int, Mesh::Vertex_index> local;
      const auto key = key_of(b.facets[facets[0]]);
      for (const auto i : facets)
        {
          std::array<Mesh::Vertex_index, 3> v;
          for (unsigned int k = 0; k < 3; ++k)
            {
              const unsigned int g  = b.facets[i].vertices[k];
              const auto        &x  = b.vertices[g];
              const auto         it = local.find(g);
              v[k]                  = it != local.end() ?
                                        it->second :
                                        local[g] = mesh.add_vertex({x[0], x[1], x[2]});
              global[v[k]]          = g;
            }
          AssertThrow(
            mesh.add_face(v[0], v[1], v[2]) != Mesh::null_face(),
            ExcMessage(
              "boundary resampling: the " + name(key) +
              " is not a manifold surface near (" +
              internal::fmt3(b.vertices[b.facets[i].vertices[0]][0]) + ", " +
              internal::fmt3(b.vertices[b.facets[i].vertices[0]][1]) + ", " +
              internal::fmt3(b.vertices[b.facets[i].vertices[0]][2]) + ")."));
        }
      auto feature =
        mesh.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
      for (const auto e : mesh.edges())
        feature[e] = p.features.count(
          edge(global[mesh.vertex(e, 0)], global[mesh.vertex(e, 1)]));
      auto pinned =
        mesh.add_property_map<Mesh::Vertex_index, bool>("v:pinned", false)
          .first;
      for (const auto v : mesh.vertices())
        pinned[v] = shared[global[v]];

      namespace PMP = CGAL::Polygon_mesh_processing;
      PMP::isotropic_remeshing(mesh.faces(),
                               size,
                               mesh,
                               CGAL::parameters::number_of_iterations(3)
                                 .protect_constraints(true)
                                 .edge_is_constrained_map(feature)
                                 .vertex_is_constrained_map(pinned));
      mesh.collect_garbage();
      // What stays: vertices on the border, on feature edges, or shared.
      std::vector<bool> fixed(mesh.number_of_vertices(), false);
      for (const auto h : mesh.halfedges())
        if (mesh.is_border(mesh.edge(h)) || feature[mesh.edge(h)])
          fixed[mesh.target(h)] = fixed[mesh.source(h)] = true;
      for (const auto v : mesh.vertices())
        fixed[v] = fixed[v] || pinned[v];
      const double moved = restore_volume(
        mesh, [&](const auto v) { return fixed[v]; }, enclosed_before);
      // A large correction would fold the surface: the patch lost or gained
      // too much volume where it could not move (too few free vertices).
      AssertThrow(moved <= size / 4,
                  ExcMessage("boundary resampling: keeping the volume of the " +
                             name(key) + " would move its vertices by " +
                             internal::fmt3(moved) +
                             " (more than a quarter of the size " +
                             internal::fmt3(size) +
                             "); lower the feature angle so that more edges "
                             "stay."));

      std::vector<unsigned int> to_out(mesh.number_of_vertices());
      for (const auto v : mesh.vertices())
        if (fixed[v])
          {
            // Protected edges are never split: what stays is original.
            AssertThrow(global[v] != no_vertex, ExcInternalError());
            to_out[v] = index(global[v]);
          }
        else
          {
            to_out[v] = out.vertices.size();
            out.vertices.push_back(point(mesh.point(v)));
          }
      for (const auto f : mesh.faces())
        {
          Facet        facet = b.facets[facets[0]];
          unsigned int k     = 0;
          for (const auto v :
               CGAL::vertices_around_face(mesh.halfedge(f), mesh))
            facet.vertices[k++] = to_out[v];
          out.facets.push_back(facet);
        }
    }
  } // namespace



  bool
  BoundaryResampling::keeps(const types::material_id inside,
                            const types::material_id outside,
                            const types::boundary_id boundary) const
  {
    return kept_materials.count(inside) ||
           (outside != numbers::invalid_material_id &&
            kept_materials.count(outside)) ||
           (outside == numbers::invalid_material_id &&
            kept_boundaries.count(boundary));
  }



  std::map<types::material_id, double>
  region_volumes(const RegionBoundaries<3> &b)
  {
    std::map<types::material_id, double> volume;
    for (const auto &f : b.facets)
      {
        const auto  &x = f.vertices;
        const double v =
          signed_volume(b.vertices[x[0]], b.vertices[x[1]], b.vertices[x[2]]);
        volume[f.inside] += v;
        if (f.outside != numbers::invalid_material_id)
          volume[f.outside] -= v;
      }
    return volume;
  }



  RegionBoundaries<3>
  resample_boundaries(const RegionBoundaries<3> &boundaries,
                      const BoundaryResampling  &o)
  {
    AssertThrow(!boundaries.facets.empty(),
                ExcMessage("boundary resampling: the mesh has no boundary."));
    RegionBoundaries<3> b = boundaries;
    Patches             p = find_features(b, o);
    keep_cut_interfaces(b, p);
    const double size = o.size > 0 ? o.size : mean_free_edge(b, p);
    if (size == 0) // everything is kept
      return boundaries;
    // What each patch encloses now (the collapses below change it).
    std::vector<double> enclosed_before(p.key.size(), 0.);
    for (unsigned int i = 0; i < b.facets.size(); ++i)
      {
        const auto &x = b.facets[i].vertices;
        enclosed_before[p.of_facet[i]] +=
          signed_volume(b.vertices[x[0]], b.vertices[x[1]], b.vertices[x[2]]);
      }
    collapse_short_features(b, p, 4. / 5. * size);
    split_long_features(b, p, 4. / 3. * size);

    // A vertex of several patches stays where it is.
    std::vector<std::set<unsigned int>> patches_of(b.vertices.size());
    for (unsigned int i = 0; i < b.facets.size(); ++i)
      for (const auto v : b.facets[i].vertices)
        patches_of[v].insert(p.of_facet[i]);
    std::vector<bool> shared(b.vertices.size());
    for (unsigned int v = 0; v < b.vertices.size(); ++v)
      shared[v] = patches_of[v].size() > 1;

    RegionBoundaries<3>       result;
    std::vector<unsigned int> index(b.vertices.size(), no_vertex);
    const auto                kept_index = [&](const unsigned int v) {
      if (index[v] == no_vertex)
        {
          index[v] = result.vertices.size();
          result.vertices.push_back(b.vertices[v]);
        }
      return index[v];
    };
    std::vector<std::vector<unsigned int>> facets(p.key.size());
    for (unsigned int i = 0; i < b.facets.size(); ++i)
      facets[p.of_facet[i]].push_back(i);
    for (unsigned int k = 0; k < facets.size(); ++k)
      if (p.kept[k])
        for (const auto i : facets[k])
          {
            auto facet = b.facets[i];
            for (auto &v : facet.vertices)
              v = kept_index(v);
            result.facets.push_back(facet);
          }
      else
        try
          {
            remesh_patch(b,
                         facets[k],
                         p,
                         shared,
                         size,
                         enclosed_before[k],
                         kept_index,
                         result);
          }
        catch (const CGAL::Failure_exception &e)
          {
            AssertThrow(false,
                        ExcMessage("boundary resampling: CGAL failed on the " +
                                   name(p.key[k]) + " (" + e.message() + ")."));
          }

    internal::check_region_change(region_volumes(boundaries),
                                  region_volumes(result),
                                  o.max_area_change,
                                  "volume",
                                  "lower the feature angle so that more "
                                  "edges stay.");
    return result;
  }
} // namespace forma
