// IPC's check of a state before any step: no boundary point on or behind
// an obstacle plane, no boundary primitives touching or crossing, and dhat
// below the distances within a body at rest.

#include <deal.II/base/exceptions.h>

#include <forma/base/records.h>
#include <forma/ipc/broad_phase.h>
#include <forma/ipc/exact_predicates.h>
#include <forma/ipc/ipc_contact.h>

#include "formulas.h"

#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    namespace
    {
      std::string
      format_point(const Vec &x, const unsigned int dim)
      {
        std::ostringstream s;
        s << std::setprecision(6) << "(";
        for (unsigned int d = 0; d < dim; ++d)
          s << (d ? ", " : "") << x[d];
        return s.str() + ")";
      }



      /// The first pair of boundary primitives that cross (2D segments, 3D
      /// an edge through a triangle, neither touching the other), decided
      /// exactly; empty if none does.
      template <int dim>
      std::string
      first_crossing(const CollisionMesh<dim> &m, const std::vector<Vec> &x)
      {
        std::vector<Box> eb(m.edges.size());
        for (unsigned int e = 0; e < m.edges.size(); ++e)
          for (const unsigned int v : m.edges[e])
            eb[e].add(x[v]);
        if (dim == 2)
          {
            for (const auto &p : overlapping_pairs(eb))
              {
                const auto &a = m.edges[p.first], &b = m.edges[p.second];
                if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] ||
                    a[1] == b[1] || (m.fixed(a[0]) && m.fixed(b[0])))
                  continue;
                if (segments_cross_2d(x[a[0]], x[a[1]], x[b[0]], x[b[1]]))
                  return "boundary segments cross near " +
                         format_point(x[a[0]], dim);
              }
          }
        else
          {
            std::vector<Box> fb(m.faces.size());
            for (unsigned int f = 0; f < m.faces.size(); ++f)
              for (const unsigned int v : m.faces[f])
                fb[f].add(x[v]);
            for (const auto &p : overlapping_pairs(eb, fb))
              {
                const auto &e = m.edges[p.first];
                const auto &f = m.faces[p.second];
                if (std::count(f.begin(), f.end(), e[0]) ||
                    std::count(f.begin(), f.end(), e[1]) ||
                    (m.fixed(e[0]) && m.fixed(f[0])))
                  continue;
                if (segment_crosses_triangle(
                      x[e[0]], x[e[1]], x[f[0]], x[f[1]], x[f[2]]))
                  return "a boundary edge crosses a boundary "
                         "triangle near " +
                         format_point(x[e[0]], dim);
              }
          }
        return "";
      }
    } // namespace



    template <int dim>
    void
    IpcContact<dim>::check_state(const Vector_t    &u,
                                 const std::string &where,
                                 const bool         rest)
    {
      collect_candidates(u, nullptr);
      const std::vector<Vec> x = positions(u);
      const auto            &m = *collision_mesh;
      std::string            problem;
      double                 closest = std::numeric_limits<double>::max();
      for (unsigned int k = 0; k < candidates.size() && problem.empty(); ++k)
        {
          const double d =
            pair_distance(candidates[k].kind, pair_positions(candidates[k], x));
          // Pairs of one body (material id) within dhat at rest would push
          // the body apart before any load: dhat is too large for the mesh.
          const auto &v   = candidates[k].vertex;
          bool        one = candidates[k].kind != PairKind::point_plane;
          for (unsigned int i = 1; one && i < n_vertices(candidates[k].kind);
               ++i)
            one = m.body[v[i]] == m.body[v[0]];
          if (one)
            closest = std::min(closest, d);
          if (d <= 0)
            problem = (candidates[k].kind == PairKind::point_plane ?
                         "the boundary point " +
                           format_point(x[candidates[k].vertex[0]], dim) +
                           " lies on or behind obstacle plane " +
                           std::to_string(candidates[k].plane + 1) :
                         "boundary primitives touch at " +
                           format_point(x[candidates[k].vertex[0]], dim));
        }
      for (unsigned int v = 0; v < x.size() && problem.empty(); ++v)
        for (unsigned int j = 0; j < parameters.planes.size() && !m.fixed(v);
             ++j)
          if ((x[v] - parameters.planes[j].origin) *
                parameters.planes[j].normal <=
              0)
            {
              problem = "the boundary point " + format_point(x[v], dim) +
                        " lies on or behind obstacle plane " +
                        std::to_string(j + 1);
              break;
            }
      // Crossing primitives have no touching pair: test them directly.
      if (problem.empty())
        problem = first_crossing(m, x);
      AssertThrow(problem.empty(),
                  ExcMessage("IPC: the geometry of " + where +
                             " already intersects: " + problem +
                             ". Bodies must start apart (and on the open "
                             "side of every obstacle)."));
      AssertThrow(!rest || closest > dhat,
                  ExcMessage("IPC/Barrier distance (" + sig(dhat) +
                             ") must be below the distance between boundary "
                             "primitives of one body at rest (" +
                             sig(closest) +
                             "): lower it or coarsen the mesh (bodies that "
                             "start within dhat of each other need "
                             "different material ids)."));
    }



    template void
    IpcContact<2>::check_state(const IpcContact<2>::Vector_t &,
                               const std::string &,
                               const bool);
    template void
    IpcContact<3>::check_state(const IpcContact<3>::Vector_t &,
                               const std::string &,
                               const bool);
  } // namespace ipc
} // namespace forma
