#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/mesh.h>
#include <forma/mesh/polygon_domain.h>
#include <forma/mesh/remesh.h>

#include "gmsh_session.h"
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // Physical tags must be positive: ids are shifted by one in the file.
    int
    physical_tag(const unsigned int id)
    {
      return static_cast<int>(id) + 1;
    }

    // The material ids on either side of the facets.
    template <int dim>
    std::set<unsigned int>
    regions_of(const RegionBoundaries<dim> &b)
    {
      std::set<unsigned int> regions;
      for (const auto &f : b.facets)
        {
          regions.insert(f.inside);
          if (f.outside != numbers::invalid_material_id)
            regions.insert(f.outside);
        }
      return regions;
    }

    // Domain-boundary entities (those with a `key` and a Gmsh `tag`) by
    // boundary id, regions by material id.
    template <typename Entities>
    void
    add_physical_groups(const int       dim,
                        const Entities &entities,
                        const std::map<unsigned int, std::vector<int>> &cells)
    {
      std::map<unsigned int, std::vector<int>> faces;
      for (const auto &e : entities)
        if (e.key[1] == numbers::invalid_material_id)
          faces[e.key[2]].push_back(e.tag);
      for (const auto &[id, tags] : faces)
        gmsh::model::addPhysicalGroup(dim - 1, tags, physical_tag(id));
      for (const auto &[id, tags] : cells)
        gmsh::model::addPhysicalGroup(dim, tags, physical_tag(id));
    }

    std::string
    gmsh_error(const std::string &what)
    {
      return internal::gmsh_error("remeshing", what);
    }

    using Key = std::array<unsigned int, 3>; // inside, outside, boundary id

    template <int dim>
    Key
    key_of(const typename RegionBoundaries<dim>::Facet &f)
    {
      return {{f.inside, f.outside, f.boundary_id}};
    }

    // ------------------------------------------------------------- 2D

    bool
    inside_polygon(const Point<2> &x, const std::vector<Point<2>> &polygon)
    {
      bool in = false;
      for (unsigned int i = 0, j = polygon.size() - 1; i < polygon.size();
           j = i++)
        {
          const auto &a = polygon[i], &b = polygon[j];
          if ((a[1] > x[1]) != (b[1] > x[1]) &&
              x[0] < (b[0] - a[0]) * (x[1] - a[1]) / (b[1] - a[1]) + a[0])
            in = !in;
        }
      return in;
    }

    /// A Gmsh line of the 2D remesh: one facet, or two paired ones.
    struct Line
    {
      unsigned int a, b;
      int          middle; ///< the vertex between paired facets, or -1
      Key          key;
      int          tag = 0;
    };



    /**
     * One line per facet (meshed with no new node: the boundary keeps its
     * vertices), shared by the regions on both sides so that the mesh
     * stays conforming; with `paired`, one per two facets of a chain.
     * Lines are made along chains of facets with one key, which checks that
     * the boundaries are manifold.
     */
    std::vector<Line>
    boundary_lines(const RegionBoundaries<2> &b, const bool paired)
    {
      std::map<Key, std::map<unsigned int, unsigned int>> next; // a -> b
      for (const auto &f : b.facets)
        {
          auto &n = next[key_of<2>(f)];
          AssertThrow(
            n.emplace(f.vertices[0], f.vertices[1]).second,
            ExcMessage(
              "remeshing: the boundary of material " +
              std::to_string(f.inside) + " touches itself at vertex (" +
              Utilities::to_string(b.vertices[f.vertices[0]][0]) + ", " +
              Utilities::to_string(b.vertices[f.vertices[0]][1]) +
              "): cannot remesh a pinched region."));
        }
      std::vector<Line> lines;
      for (auto &[key, n] : next)
        {
          std::set<unsigned int> heads;
          for (const auto &e : n)
            heads.insert(e.first);
          for (const auto &e : n)
            heads.erase(e.second);
          // Open paths first, then closed cycles.
          while (!n.empty())
            {
              unsigned int start =
                heads.empty() ? n.begin()->first : *heads.begin();
              heads.erase(start);
              std::vector<unsigned int> chain{start};
              for (auto it = n.find(start); it != n.end(); it = n.find(start))
                {
                  start = it->second;
                  n.erase(it);
                  chain.push_back(start);
                }
              for (unsigned int i = 0; i + 1 < chain.size();)
                if (paired && i + 2 < chain.size())
                  {
                    lines.push_back({chain[i],
                                     chain[i + 2],
                                     static_cast<int>(chain[i + 1]),
                                     key});
                    i += 2;
                  }
                else
                  {
                    lines.push_back({chain[i], chain[i + 1], -1, key});
                    i += 1;
                  }
            }
        }
      return lines;
    }



    /// The lines' points (sized by the lengths of the lines through them)
    /// and lines in Gmsh; sets each line's tag.
    void
    add_lines(const RegionBoundaries<2> &b, std::vector<Line> &lines)
    {
      std::map<unsigned int, std::pair<double, unsigned int>> size;
      for (const auto &l : lines)
        for (const auto v : {l.a, l.b})
          {
            auto &s = size[v];
            s.first += b.vertices[l.a].distance(b.vertices[l.b]);
            s.second += 1;
          }
      std::map<unsigned int, int> point_tag;
      for (const auto &[v, s] : size)
        point_tag[v] = gmsh::model::geo::addPoint(b.vertices[v][0],
                                                  b.vertices[v][1],
                                                  0,
                                                  s.first / s.second);
      for (auto &l : lines)
        {
          l.tag = gmsh::model::geo::addLine(point_tag[l.a], point_tag[l.b]);
          gmsh::model::geo::mesh::setTransfiniteCurve(l.tag, 2);
        }
    }



    /// The plane surfaces of material m: its loops of lines,
    /// counterclockwise around it, each hole in the smallest outer loop
    /// around it.
    std::vector<int>
    add_region_surfaces(const RegionBoundaries<2> &b,
                        const std::vector<Line>   &lines,
                        const unsigned int         m)
    {
      std::map<unsigned int, std::pair<unsigned int, int>> from; // a->b
      for (const auto &l : lines)
        if (l.key[0] == m)
          from.emplace(l.a, std::make_pair(l.b, l.tag));
        else if (l.key[1] == m)
          from.emplace(l.b, std::make_pair(l.a, -l.tag));
      struct Loop
      {
        std::vector<int>      curves;
        std::vector<Point<2>> polygon;
        double                area;
      };
      std::vector<Loop> outer, holes;
      while (!from.empty())
        {
          Loop               loop;
          const unsigned int start = from.begin()->first;
          unsigned int       v     = start;
          for (auto it = from.find(v); it != from.end(); it = from.find(v))
            {
              loop.curves.push_back(it->second.second);
              loop.polygon.push_back(b.vertices[v]);
              v = it->second.first;
              from.erase(it);
            }
          AssertThrow(v == start,
                      ExcMessage(
                        "remeshing: the boundary of material " +
                        std::to_string(m) + " is not closed: it ends at (" +
                        Utilities::to_string(b.vertices[v][0]) + ", " +
                        Utilities::to_string(b.vertices[v][1]) + ")."));
          loop.area = signed_area(loop.polygon);
          (loop.area > 0 ? outer : holes).push_back(std::move(loop));
        }
      AssertThrow(!outer.empty(),
                  ExcMessage("remeshing: material " + std::to_string(m) +
                             " has no outer boundary."));
      std::vector<std::vector<int>> surface_loops(outer.size());
      for (unsigned int k = 0; k < outer.size(); ++k)
        surface_loops[k].push_back(
          gmsh::model::geo::addCurveLoop(outer[k].curves));
      for (const auto &h : holes)
        {
          int best = -1;
          for (unsigned int k = 0; k < outer.size(); ++k)
            if (inside_polygon(h.polygon[0], outer[k].polygon) &&
                (best < 0 || outer[k].area < outer[best].area))
              best = k;
          AssertThrow(best >= 0,
                      ExcMessage("remeshing: a hole of material " +
                                 std::to_string(m) +
                                 " lies outside all its boundaries."));
          surface_loops[best].push_back(
            gmsh::model::geo::addCurveLoop(h.curves));
        }
      std::vector<int> surfaces;
      for (const auto &s : surface_loops)
        surfaces.push_back(gmsh::model::geo::addPlaneSurface(s));
      return surfaces;
    }



    // `paired`: every Gmsh line spans two facets of a chain (one where a
    // chain has an odd count); the mesh is made at that size, recombined
    // and subdivided into quads, and the midpoint Gmsh puts on each line
    // is moved to the vertex between its two facets.
    std::string
    mesh_2d(const RegionBoundaries<2> &b, const bool quads, const bool paired)
    {
      std::vector<Line> lines = boundary_lines(b, paired);
      add_lines(b, lines);
      std::map<unsigned int, std::vector<int>> physical_surfaces;
      for (const auto m : regions_of(b))
        physical_surfaces[m] = add_region_surfaces(b, lines, m);
      gmsh::model::geo::synchronize();

      add_physical_groups(2, lines, physical_surfaces);

      // Frontal-Delaunay makes the best triangles, but Blossom pairs
      // Delaunay triangles into better quads when no subdivision follows
      // (measured on distorted strips: min scaled Jacobian 0.69 vs 0.67;
      // 0.73 with subdivision).
      gmsh::option::setNumber("Mesh.Algorithm", quads && !paired ? 5 : 6);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
      if (quads)
        {
          gmsh::option::setNumber("Mesh.RecombineAll", 1);
          gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1); // Blossom
          if (paired)
            gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
        }
      gmsh::model::mesh::generate(2);
      internal::gmsh_check_generated(2, "remeshing");
      if (quads && !paired)
        {
          std::vector<int>                      types;
          std::vector<std::vector<std::size_t>> tags, nodes;
          gmsh::model::mesh::getElements(types, tags, nodes, 2);
          for (unsigned int k = 0; k < types.size(); ++k)
            if (types[k] != 3 && !tags[k].empty())
              return {}; // not all quads
        }
      if (paired)
        for (const auto &l : lines)
          {
            std::vector<std::size_t> tags;
            std::vector<double>      x, u;
            gmsh::model::mesh::getNodes(tags, x, u, 1, l.tag, false, false);
            AssertThrow(tags.size() == 1,
                        ExcMessage(gmsh_error("did not split a boundary line "
                                              "once")));
            if (l.middle >= 0)
              {
                const auto &p = b.vertices[l.middle];
                gmsh::model::mesh::setNode(tags[0], {p[0], p[1], 0.}, {});
              }
          }
      return internal::gmsh_written_mesh();
    }



    // ------------------------------------------------------------- 3D

    // Connected components of `items` (index lists of vertices) through
    // shared vertices.
    std::vector<unsigned int>
    components(const std::vector<std::vector<unsigned int>> &items,
               unsigned int                                 &n_components)
    {
      std::vector<unsigned int> parent(items.size());
      std::iota(parent.begin(), parent.end(), 0u);
      std::function<unsigned int(unsigned int)> root = [&](unsigned int i) {
        return parent[i] == i ? i : parent[i] = root(parent[i]);
      };
      std::map<unsigned int, unsigned int> owner;
      for (unsigned int i = 0; i < items.size(); ++i)
        for (const auto v : items[i])
          {
            const auto it   = owner.emplace(v, i).first;
            parent[root(i)] = root(it->second);
          }
      std::map<unsigned int, unsigned int> index;
      std::vector<unsigned int>            c(items.size());
      for (unsigned int i = 0; i < items.size(); ++i)
        c[i] = index.emplace(root(i), index.size()).first->second;
      n_components = index.size();
      return c;
    }

    // A connected patch of boundary facets with one key (the regions on its
    // two sides): a discrete Gmsh surface.
    struct Surface
    {
      Key                       key;
      std::vector<unsigned int> facets;
      std::set<unsigned int>    vertices;
      int                       tag = 0;
    };



    std::vector<Surface>
    surface_patches(const RegionBoundaries<3> &b)
    {
      std::map<Key, std::vector<unsigned int>> by_key;
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        by_key[key_of<3>(b.facets[i])].push_back(i);
      std::vector<Surface> surfaces;
      for (const auto &[key, facets] : by_key)
        {
          std::vector<std::vector<unsigned int>> items;
          for (const auto i : facets)
            items.emplace_back(b.facets[i].vertices.begin(),
                               b.facets[i].vertices.end());
          unsigned int n;
          const auto   c     = components(items, n);
          const auto   first = surfaces.size();
          surfaces.resize(first + n);
          for (unsigned int k = 0; k < facets.size(); ++k)
            {
              auto &s = surfaces[first + c[k]];
              s.key   = key;
              s.facets.push_back(facets[k]);
              s.vertices.insert(items[k].begin(), items[k].end());
            }
        }
      return surfaces;
    }



    // The patches as discrete Gmsh surfaces on the boundary's vertices (their
    // tags set).
    void
    add_discrete_surfaces(const RegionBoundaries<3> &b,
                          std::vector<Surface>      &surfaces)
    {
      std::vector<std::size_t> node_tags(b.vertices.size());
      std::vector<double>      coordinates;
      for (unsigned int v = 0; v < b.vertices.size(); ++v)
        {
          node_tags[v] = v + 1;
          for (unsigned int d = 0; d < 3; ++d)
            coordinates.push_back(b.vertices[v][d]);
        }
      for (unsigned int k = 0; k < surfaces.size(); ++k)
        {
          auto &s = surfaces[k];
          s.tag   = gmsh::model::addDiscreteEntity(2);
          if (k == 0)
            gmsh::model::mesh::addNodes(2, s.tag, node_tags, coordinates);
          std::vector<std::size_t> nodes;
          for (const auto i : s.facets)
            for (const auto v : b.facets[i].vertices)
              nodes.push_back(v + 1);
          gmsh::model::mesh::addElementsByType(s.tag, 2, {}, nodes);
        }
    }



    // A closed shell of a region's surfaces: its enclosed volume (negative,
    // normals into the region: a cavity) and bounding box.
    struct Shell
    {
      std::vector<int> surfaces;
      double           volume = 0;
      Point<3>         low, high;
    };



    std::vector<Shell>
    region_shells(const RegionBoundaries<3>  &b,
                  const std::vector<Surface> &surfaces,
                  const unsigned int          m)
    {
      std::vector<unsigned int>              mine;
      std::vector<std::vector<unsigned int>> items;
      for (unsigned int k = 0; k < surfaces.size(); ++k)
        if (surfaces[k].key[0] == m || surfaces[k].key[1] == m)
          {
            mine.push_back(k);
            items.emplace_back(surfaces[k].vertices.begin(),
                               surfaces[k].vertices.end());
          }
      unsigned int       n;
      const auto         c = components(items, n);
      std::vector<Shell> shells(n);
      for (auto &s : shells)
        for (unsigned int d = 0; d < 3; ++d)
          {
            s.low[d]  = std::numeric_limits<double>::max();
            s.high[d] = -std::numeric_limits<double>::max();
          }
      for (unsigned int k = 0; k < mine.size(); ++k)
        {
          const auto &surface = surfaces[mine[k]];
          auto       &shell   = shells[c[k]];
          shell.surfaces.push_back(surface.tag);
          const double sign = surface.key[0] == m ? 1. : -1.;
          for (const auto i : surface.facets)
            {
              const auto &v  = b.facets[i].vertices;
              const auto &x0 = b.vertices[v[0]], &x1 = b.vertices[v[1]],
                         &x2 = b.vertices[v[2]];
              shell.volume += sign *
                              (x0[0] * (x1[1] * x2[2] - x1[2] * x2[1]) -
                               x0[1] * (x1[0] * x2[2] - x1[2] * x2[0]) +
                               x0[2] * (x1[0] * x2[1] - x1[1] * x2[0])) /
                              6.;
              for (const auto j : v)
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    shell.low[d]  = std::min(shell.low[d], b.vertices[j][d]);
                    shell.high[d] = std::max(shell.high[d], b.vertices[j][d]);
                  }
            }
        }
      return shells;
    }



    // Gmsh volumes of region m: one per outer shell, each with the cavities
    // its box holds (the smallest such outer shell's).
    std::vector<int>
    region_volumes(const std::vector<Shell> &shells, const unsigned int m)
    {
      std::vector<std::vector<int>> loops;
      std::vector<unsigned int>     outer;
      for (unsigned int k = 0; k < shells.size(); ++k)
        if (shells[k].volume > 0)
          {
            outer.push_back(k);
            loops.push_back(
              {gmsh::model::geo::addSurfaceLoop(shells[k].surfaces)});
          }
      AssertThrow(!outer.empty(),
                  ExcMessage("remeshing: material " + std::to_string(m) +
                             " has no closed outer boundary."));
      for (unsigned int k = 0; k < shells.size(); ++k)
        if (shells[k].volume <= 0)
          {
            int best = -1;
            for (unsigned int o = 0; o < outer.size(); ++o)
              {
                const auto &s  = shells[outer[o]];
                bool        in = true;
                for (unsigned int d = 0; d < 3; ++d)
                  in = in && s.low[d] <= shells[k].low[d] &&
                       shells[k].high[d] <= s.high[d];
                if (in && (best < 0 || s.volume < shells[outer[best]].volume))
                  best = o;
              }
            AssertThrow(best >= 0,
                        ExcMessage("remeshing: a cavity of material " +
                                   std::to_string(m) +
                                   " lies outside all its boundaries."));
            loops[best].push_back(
              gmsh::model::geo::addSurfaceLoop(shells[k].surfaces));
          }
      std::vector<int> volumes;
      for (const auto &l : loops)
        volumes.push_back(gmsh::model::geo::addVolume(l));
      return volumes;
    }



    std::string
    mesh_3d(const RegionBoundaries<3> &b)
    {
      auto surfaces = surface_patches(b);
      add_discrete_surfaces(b, surfaces);
      std::map<unsigned int, std::vector<int>> physical_volumes;
      for (const auto m : regions_of(b))
        physical_volumes[m] = region_volumes(region_shells(b, surfaces, m), m);
      gmsh::model::geo::synchronize();

      add_physical_groups(3, surfaces, physical_volumes);

      gmsh::option::setNumber("Mesh.Algorithm3D", 1); // Delaunay
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
      gmsh::option::setNumber("Mesh.Optimize", 1);
      // Optimize every tetrahedron of quality below 0.5 (default 0.3):
      // fewer slivers along a resampled surface.
      gmsh::option::setNumber("Mesh.OptimizeThreshold", 0.5);
      gmsh::model::mesh::generate(3);
      internal::gmsh_check_generated(3, "remeshing");
      return internal::gmsh_written_mesh();
    }
  } // namespace



  template <int dim>
  std::string
  mesh_regions(const RegionBoundaries<dim> &boundaries, const bool quads)
  {
    AssertThrow(dim == 2 || !quads,
                ExcMessage("remeshing: Gmsh cannot make hexahedral meshes."));
    AssertThrow(!boundaries.facets.empty(),
                ExcMessage("remeshing: the mesh has no boundary."));
    const auto in_session = [](const std::function<std::string()> &f) {
      std::string msh;
      internal::in_gmsh_session("forma-remesh", "remeshing", [&]() {
        msh = f();
      });
      return msh;
    };
    if constexpr (dim == 2)
      {
        // Quads: Blossom recombination keeping every boundary segment (a
        // region of a quad mesh has an even number) gives an all-quad mesh
        // of the same resolution in most cases; where it leaves triangles,
        // subdivide a mesh of twice the size.
        if (quads)
          {
            const std::string msh =
              in_session([&]() { return mesh_2d(boundaries, true, false); });
            if (!msh.empty())
              return msh;
          }
        return in_session([&]() { return mesh_2d(boundaries, quads, quads); });
      }
    else
      return in_session([&]() { return mesh_3d(boundaries); });
  }



  template <int dim>
  void
  read_regions_mesh(const std::string &msh, Triangulation<dim> &tria)
  {
    Triangulation<dim> shifted;
    {
      std::istringstream in(msh);
      GridIn<dim>        grid_in(shifted);
      grid_in.read_msh(in);
    }
    // Undo the shift of physical tags (mesh_regions writes id + 1).
    for (const auto &cell : shifted.active_cell_iterators())
      {
        AssertThrow(cell->material_id() > 0, ExcInternalError());
        cell->set_material_id(cell->material_id() - 1);
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              AssertThrow(cell->face(f)->boundary_id() > 0,
                          ExcMessage("remeshing: a boundary face lost its "
                                     "boundary id."));
              cell->face(f)->set_boundary_id(cell->face(f)->boundary_id() - 1);
            }
      }
    check_mesh_validity(shifted, "the remeshed design");
    tria.clear();
    tria.copy_triangulation(shifted);
  }

  template std::string
  mesh_regions<2>(const RegionBoundaries<2> &, const bool);
  template std::string
  mesh_regions<3>(const RegionBoundaries<3> &, const bool);
  template void
  read_regions_mesh<2>(const std::string &, Triangulation<2> &);
  template void
  read_regions_mesh<3>(const std::string &, Triangulation<3> &);
} // namespace forma
