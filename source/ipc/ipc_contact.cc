#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/base/records.h>
#include <forma/ipc/barrier.h>
#include <forma/ipc/broad_phase.h>
#include <forma/ipc/ipc_contact.h>
#include <forma/ipc/obstacle_mesh.h>

#include "formulas.h"
#include <Sacado.hpp>

#include <algorithm>
#include <cmath>
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

      /// Remove the negative part of a symmetric matrix (IPC's projected
      /// Newton): H - sum_{lambda_i < 0} lambda_i v_i v_i^T.
      void
      project_to_psd(FullMatrix<double> &H)
      {
        const unsigned int n = H.m();
        // Symmetrize; Gershgorin's bound: nothing to do if no eigenvalue can
        // be negative, else it bounds the search interval of LAPACK.
        double lowest = std::numeric_limits<double>::max(), scale = 0;
        for (unsigned int i = 0; i < n; ++i)
          {
            double radius = 0;
            for (unsigned int j = 0; j < n; ++j)
              {
                H(i, j) = H(j, i) = 0.5 * (H(i, j) + H(j, i));
                AssertThrow(std::isfinite(H(i, j)),
                            ExcMessage("IPC: a contact Hessian is not "
                                       "finite (degenerate pair geometry)."));
                if (j != i)
                  radius += std::abs(H(i, j));
              }
            lowest = std::min(lowest, H(i, i) - radius);
            scale  = std::max(scale, std::abs(H(i, i)) + radius);
          }
        if (lowest >= 0)
          return;
        LAPACKFullMatrix<double> A(n, n);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            A(i, j) = H(i, j);
        Vector<double>     lambda;
        FullMatrix<double> V;
        // The interval's margin covers LAPACK's error, which scales with |H|.
        A.compute_eigenvalues_symmetric(
          lowest - 1e-8 * scale - 1e-300, 0., 0., lambda, V);
        for (unsigned int k = 0; k < lambda.size(); ++k)
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              H(i, j) -= lambda[k] * V(i, k) * V(j, k);
      }

      /// An orthonormal basis of the plane orthogonal to the unit vector n
      /// (in 2D the line, within the xy-plane).
      template <int dim>
      std::array<Vec, dim - 1>
      tangent_basis(const Vec &n)
      {
        std::array<Vec, dim - 1> t;
        if (dim == 2)
          {
            t[0][0] = -n[1];
            t[0][1] = n[0];
          }
        else
          {
            // The coordinate axis least aligned with n.
            unsigned int a = 0;
            for (unsigned int d = 1; d < 3; ++d)
              if (std::abs(n[d]) < std::abs(n[a]))
                a = d;
            Vec e;
            e[a]   = 1;
            Vec t0 = cross_product_3d(n, e);
            t0 /= t0.norm();
            t[0]       = t0;
            t[dim - 2] = cross_product_3d(n, t0);
          }
        return t;
      }

      bool
      segments_cross_2d(const Vec &a, const Vec &b, const Vec &c, const Vec &d)
      {
        const auto orient = [](const Vec &p, const Vec &q, const Vec &r) {
          return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        };
        const double o1 = orient(a, b, c), o2 = orient(a, b, d);
        const double o3 = orient(c, d, a), o4 = orient(c, d, b);
        return o1 * o2 < 0 && o3 * o4 < 0;
      }

      bool
      segment_crosses_triangle(const Vec &p,
                               const Vec &q,
                               const Vec &a,
                               const Vec &b,
                               const Vec &c)
      {
        const auto vol =
          [](const Vec &w, const Vec &x, const Vec &y, const Vec &z) {
            return cross_product_3d(x - w, y - w) * (z - w);
          };
        const double sp = vol(a, b, c, p), sq = vol(a, b, c, q);
        if (sp * sq >= 0)
          return false;
        const double s1 = vol(p, q, a, b), s2 = vol(p, q, b, c),
                     s3 = vol(p, q, c, a);
        return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
      }
    } // namespace



    template <int dim>
    IpcContact<dim>::IpcContact(const IpcParameters &parameters)
      : parameters(parameters)
    {}

    template <int dim>
    IpcContact<dim>::~IpcContact() = default;

    template <int dim>
    const CollisionMesh<dim> &
    IpcContact<dim>::mesh() const
    {
      return *collision_mesh;
    }

    template <int dim>
    const IndexSet &
    IpcContact<dim>::collision_dofs() const
    {
      return collision_mesh->collision_dofs;
    }



    template <int dim>
    std::vector<Vec>
    IpcContact<dim>::displacements(const Vector_t &u)
    {
      values             = u;
      const auto      &m = *collision_mesh;
      std::vector<Vec> x(m.n_vertices());
      for (unsigned int v = 0; v < x.size(); ++v)
        if (!m.fixed(v))
          for (unsigned int d = 0; d < dim; ++d)
            x[v][d] = values(m.dofs[v][d]);
      return x;
    }



    template <int dim>
    std::vector<Vec>
    IpcContact<dim>::positions(const Vector_t &u)
    {
      std::vector<Vec> x = displacements(u);
      for (unsigned int v = 0; v < x.size(); ++v)
        x[v] += collision_mesh->rest[v];
      return x;
    }



    template <int dim>
    std::array<Vec, 4>
    IpcContact<dim>::pair_positions(const Candidate        &c,
                                    const std::vector<Vec> &x) const
    {
      std::array<Vec, 4> X;
      if (c.kind == PairKind::point_plane)
        {
          X[0] = x[c.vertex[0]];
          X[1] = parameters.planes[c.plane].origin;
          X[2] = parameters.planes[c.plane].normal;
          return X;
        }
      for (unsigned int i = 0; i < n_vertices(c.kind); ++i)
        X[i] = x[c.vertex[i]];
      return X;
    }



    template <int dim>
    void
    IpcContact<dim>::local_dofs(
      const unsigned int                   *vertex,
      const unsigned int                    n,
      std::vector<types::global_dof_index> &dofs) const
    {
      dofs.clear();
      for (unsigned int i = 0; i < n; ++i)
        if (!collision_mesh->fixed(vertex[i]))
          for (unsigned int d = 0; d < dim; ++d)
            dofs.push_back(collision_mesh->dofs[vertex[i]][d]);
    }



    template <int dim>
    double
    IpcContact<dim>::friction_coefficient(const unsigned int a,
                                          const unsigned int b) const
    {
      const auto &m = *collision_mesh;
      for (const unsigned int v : {a, b})
        if (m.fixed(v) && parameters.meshes[m.obstacle[v]].friction >= 0)
          return parameters.meshes[m.obstacle[v]].friction;
      const auto ia = m.body[a], ib = m.body[b];
      const auto it =
        parameters.pair_friction.find({std::min(ia, ib), std::max(ia, ib)});
      return it != parameters.pair_friction.end() ? it->second :
                                                    parameters.friction;
    }



    template <int dim>
    void
    IpcContact<dim>::setup(const DoFHandler<dim>            &dof_handler,
                           const hp::MappingCollection<dim> &mapping,
                           const IndexSet                   &owned,
                           const MPI_Comm                    mpi_comm)
    {
      comm    = mpi_comm;
      rank    = Utilities::MPI::this_mpi_process(comm);
      n_ranks = Utilities::MPI::n_mpi_processes(comm);
      AssertThrow(dim == 2 ||
                    !dof_handler.get_triangulation().has_hanging_nodes(),
                  ExcMessage("IPC contact in 3D needs a mesh without hanging "
                             "nodes (no adaptive refinement)."));
      collision_mesh = std::make_unique<CollisionMesh<dim>>(
        dof_handler, mapping, parameters.boundaries, comm);
      AssertThrow(collision_mesh->n_vertices() > 0,
                  ExcMessage("IPC: the collision mesh is empty: no boundary "
                             "faces with the ids of IPC/Boundaries."));
      for (unsigned int k = 0; k < parameters.meshes.size(); ++k)
        collision_mesh->add_obstacle(
          read_obstacle_mesh(parameters.meshes[k].file, dim), k);
      const auto &m   = *collision_mesh;
      dhat            = parameters.dhat > 0 ? parameters.dhat :
                                              parameters.relative_dhat * m.diagonal();
      automatic_kappa = parameters.kappa == 0;
      kappa           = parameters.kappa;
      IndexSet ghost  = m.collision_dofs;
      ghost.add_indices(owned);
      values.reinit(owned, ghost, comm);
      couplings.clear();
      friction.clear();
      previous_min_distance = std::numeric_limits<double>::max();

      Vector_t zero(owned, comm);
      update_candidates(zero, nullptr);
      check_state(zero, "the mesh as read", true);
    }



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
      if (problem.empty())
        {
          // Crossing primitives have no touching pair: test them directly.
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
                    {
                      problem = "boundary segments cross near " +
                                format_point(x[a[0]], dim);
                      break;
                    }
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
                    {
                      problem = "a boundary edge crosses a boundary "
                                "triangle near " +
                                format_point(x[e[0]], dim);
                      break;
                    }
                }
            }
        }
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



    template <int dim>
    void
    IpcContact<dim>::set_stiffness_scale(const double mean_diagonal)
    {
      if (!automatic_kappa)
        return;
      // The mean vertex area of the bodies (obstacles may be coarse).
      const auto  &m    = *collision_mesh;
      double       area = 0;
      unsigned int n    = 0;
      for (unsigned int v = 0; v < m.n_vertices(); ++v)
        if (!m.fixed(v))
          {
            area += m.vertex_area[v];
            ++n;
          }
      area /= n;
      kappa_min =
        mean_diagonal / (area * barrier_second_derivative(dhat / 2, dhat));
      kappa_max = 1e4 * kappa_min;
      kappa     = kappa_min;
    }



    template <int dim>
    void
    IpcContact<dim>::collect_candidates(const Vector_t &u, const Vector_t *du)
    {
      Timer                  timer;
      const auto            &m  = *collision_mesh;
      const std::vector<Vec> x0 = positions(u);
      std::vector<Vec>       x1 = x0;
      if (du)
        {
          const std::vector<Vec> dx = displacements(*du);
          for (unsigned int v = 0; v < x1.size(); ++v)
            x1[v] += dx[v];
        }
      const auto box = [&](const unsigned int *v, const unsigned int n) {
        Box b;
        for (unsigned int i = 0; i < n; ++i)
          {
            b.add(x0[v[i]]);
            b.add(x1[v[i]]);
          }
        b.inflate(dhat / 2);
        return b;
      };
      std::vector<Box> vb(m.n_vertices()), eb(m.edges.size());
      for (unsigned int v = 0; v < vb.size(); ++v)
        vb[v] = box(&v, 1);
      for (unsigned int e = 0; e < eb.size(); ++e)
        eb[e] = box(m.edges[e].data(), 2);

      candidates.clear();
      const auto contains = [](const auto &prim, const unsigned int v) {
        return std::find(prim.begin(), prim.end(), v) != prim.end();
      };
      // Pairs within the static obstacles never change.
      const auto still = [&](const auto &prim) {
        for (const unsigned int v : prim)
          if (!m.fixed(v))
            return false;
        return true;
      };
      if (dim == 2)
        for (const auto &p : overlapping_pairs(vb, eb))
          {
            const auto &e = m.edges[p.second];
            if (!contains(e, p.first) && !(m.fixed(p.first) && still(e)))
              candidates.push_back(
                {PairKind::point_edge, {{p.first, e[0], e[1], 0}}, 0});
          }
      else
        {
          std::vector<Box> fb(m.faces.size());
          for (unsigned int f = 0; f < fb.size(); ++f)
            fb[f] = box(m.faces[f].data(), 3);
          for (const auto &p : overlapping_pairs(vb, fb))
            {
              const auto &f = m.faces[p.second];
              if (!contains(f, p.first) && !(m.fixed(p.first) && still(f)))
                candidates.push_back(
                  {PairKind::point_triangle, {{p.first, f[0], f[1], f[2]}}, 0});
            }
          for (const auto &p : overlapping_pairs(eb))
            {
              const auto &a = m.edges[p.first], &b = m.edges[p.second];
              if (!contains(b, a[0]) && !contains(b, a[1]) &&
                  !(still(a) && still(b)))
                candidates.push_back(
                  {PairKind::edge_edge, {{a[0], a[1], b[0], b[1]}}, 0});
            }
        }
      for (unsigned int j = 0; j < parameters.planes.size(); ++j)
        {
          const Plane &pl = parameters.planes[j];
          for (unsigned int v = 0; v < x0.size(); ++v)
            if (!m.fixed(v) && std::min((x0[v] - pl.origin) * pl.normal,
                                        (x1[v] - pl.origin) * pl.normal) < dhat)
              candidates.push_back({PairKind::point_plane, {{v, 0, 0, 0}}, j});
        }
      broad_seconds += timer.wall_time();
    }



    template <int dim>
    bool
    IpcContact<dim>::update_candidates(const Vector_t &u, const Vector_t *du)
    {
      collect_candidates(u, du);
      // Couplings this rank will write: its candidates and friction pairs.
      std::set<std::pair<unsigned int, unsigned int>> required;
      const auto                                     &mesh = *collision_mesh;
      const auto require = [&](const unsigned int *v, const unsigned int n) {
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i + 1; j < n; ++j)
            if (v[i] != v[j] && !mesh.fixed(v[i]) && !mesh.fixed(v[j]))
              required.emplace(std::min(v[i], v[j]), std::max(v[i], v[j]));
      };
      for (unsigned int k = 0; k < candidates.size(); ++k)
        if (mine(k) && candidates[k].kind != PairKind::point_plane)
          require(candidates[k].vertex.data(), n_vertices(candidates[k].kind));
      for (const auto &f : friction)
        require(f.vertex.data(), f.n);
      bool rebuild = false;
      for (const auto &c : required)
        if (couplings.count(c) == 0)
          {
            rebuild = true;
            break;
          }
      // Keep the pattern from growing without bound in long runs.
      if (couplings.size() > 2 * required.size() + 256)
        rebuild = true;
      rebuild = Utilities::MPI::max(rebuild ? 1 : 0, comm) == 1;
      if (rebuild)
        couplings = required;
      return rebuild;
    }



    template <int dim>
    void
    IpcContact<dim>::add_couplings(const AffineConstraints<double> &constraints,
                                   TrilinosWrappers::SparsityPattern &sp) const
    {
      std::vector<types::global_dof_index> dofs;
      for (const auto &c : couplings)
        {
          const unsigned int v[2] = {c.first, c.second};
          local_dofs(v, 2, dofs);
          constraints.add_entries_local_to_global(dofs, sp, false);
        }
    }



    template <int dim>
    double
    IpcContact<dim>::max_step(const Vector_t &u,
                              const Vector_t &du,
                              const double    gap)
    {
      Timer                  timer;
      const std::vector<Vec> x  = positions(u);
      const std::vector<Vec> dx = displacements(du);
      double                 t  = 1;
      for (unsigned int k = 0; k < candidates.size(); ++k)
        if (mine(k))
          {
            const Candidate   &c = candidates[k];
            std::array<Vec, 4> X = pair_positions(c, x), dX;
            if (c.kind == PairKind::point_plane)
              dX[0] = dx[c.vertex[0]];
            else
              for (unsigned int i = 0; i < n_vertices(c.kind); ++i)
                dX[i] = dx[c.vertex[i]];
            t = std::min(
              t,
              additive_ccd(c.kind, X, dX, gap > 0 ? gap : parameters.ccd_gap)
                .time);
          }
      t = Utilities::MPI::min(t, comm);
      ccd_seconds += timer.wall_time();
      return t;
    }



    template <int dim>
    typename IpcContact<dim>::PairGeometry
    IpcContact<dim>::pair_geometry(const Candidate          &c,
                                   const std::array<Vec, 4> &X) const
    {
      const auto  &m = *collision_mesh;
      PairGeometry g;
      switch (c.kind)
        {
          case PairKind::point_edge:
            g.stencil = classify_point_edge(X[0], X[1], X[2]);
            break;
          case PairKind::point_triangle:
            g.stencil = classify_point_triangle(X[0], X[1], X[2], X[3]);
            break;
          case PairKind::edge_edge:
            g.stencil = classify_edge_edge(X[0], X[1], X[2], X[3]);
            break;
          case PairKind::point_plane:
            g.stencil.type             = DistanceType::point_plane;
            g.stencil.slot             = {{0, 1, 2, 0}};
            g.distance                 = (X[0] - X[1]) * X[2]; // signed
            g.stencil.distance_squared = g.distance * g.distance;
            g.weight                   = m.vertex_area[c.vertex[0]];
            return g;
        }
      g.distance = std::sqrt(g.stencil.distance_squared);
      // Areas of the bodies' side only: a coarse obstacle's vertex areas
      // say nothing of the contact's extent.
      const auto mean_area = [&](const unsigned int first,
                                 const unsigned int last) {
        double       a = 0;
        unsigned int n = 0;
        for (unsigned int i = first; i < last; ++i)
          if (!m.fixed(c.vertex[i]))
            {
              a += m.vertex_area[c.vertex[i]];
              ++n;
            }
        return n > 0 ? a / n : 0.;
      };
      if (c.kind != PairKind::edge_edge)
        {
          g.weight =
            0.5 * (m.fixed(c.vertex[0]) ? mean_area(1, n_vertices(c.kind)) :
                                          m.vertex_area[c.vertex[0]]);
          return g;
        }
      g.weight                = 0.5 * mean_area(0, 4);
      const auto rest_length2 = [&](unsigned int i, unsigned int j) {
        return (m.rest[c.vertex[i]] - m.rest[c.vertex[j]]).norm_square();
      };
      g.eps_x = 1e-3 * rest_length2(0, 1) * rest_length2(2, 3);
      std::array<internal::V3<double>, 4> y;
      for (unsigned int i = 0; i < 4; ++i)
        for (unsigned int d = 0; d < 3; ++d)
          y[i][d] = X[i][d];
      g.mollifier =
        edge_edge_mollifier(internal::edge_cross_squared(y.data()), g.eps_x);
      return g;
    }



    template <int dim>
    double
    IpcContact<dim>::assemble(const Vector_t                  &u,
                              const AffineConstraints<double> &constraints,
                              TrilinosWrappers::SparseMatrix  *matrix,
                              Vector_t                        &residual,
                              Vector_t                        *raw,
                              bool                            &admissible)
    {
      Timer                  timer;
      const auto            &m = *collision_mesh;
      const std::vector<Vec> x = positions(u);

      constexpr int N = 3 * dim + (dim == 3 ? 3 : 0); // 6 (2D), 12 (3D)
      using Inner     = Sacado::Fad::SFad<double, N>;
      using AD        = Sacado::Fad::SFad<Inner, N>;

      double             energy = 0;
      FullMatrix<double> H;
      Vector<double>     g;
      // Per-pair buffers, reused.
      std::vector<unsigned int>            used;
      std::vector<types::global_dof_index> dofs;
      // Add the local gradient g (and Hessian H) of a pair on `dofs`; the
      // force of pairs with an obstacle on the bodies adds up its reaction.
      const auto add = [&](const std::vector<types::global_dof_index> &dofs,
                           const bool against_obstacle) {
        if (against_obstacle)
          for (unsigned int i = 0; i < dofs.size(); ++i)
            obstacle_force[i % dim] -= g[i];
        if (raw)
          for (unsigned int i = 0; i < dofs.size(); ++i)
            (*raw)(dofs[i]) += g[i];
        if (matrix)
          constraints.distribute_local_to_global(H, g, dofs, *matrix, residual);
        else
          constraints.distribute_local_to_global(g, dofs, residual);
      };
      min_distance   = std::numeric_limits<double>::max();
      n_active       = 0;
      obstacle_force = 0;
      for (unsigned int k = 0; k < candidates.size(); ++k)
        {
          if (!mine(k))
            continue;
          const Candidate         &c  = candidates[k];
          const std::array<Vec, 4> X  = pair_positions(c, x);
          const PairGeometry       pg = pair_geometry(c, X);
          const DistanceStencil   &s  = pg.stencil;
          const double             d  = pg.distance;
          min_distance                = std::min(min_distance, d);
          if (d <= 0)
            {
              admissible = false;
              continue;
            }
          if (d >= dhat)
            continue;
          ++n_active;
          if (kappa == 0)
            continue; // automatic stiffness not scaled yet
          const double A       = pg.weight;
          const double eps_x   = pg.eps_x;
          const bool   mollify = pg.mollifier < 1;

          // The vertices the energy depends on, in slot order.
          used.clear();
          if (mollify)
            used = {0, 1, 2, 3};
          else if (c.kind == PairKind::point_plane)
            used = {0};
          else
            for (unsigned int a = 0; a < n_arguments(s.type); ++a)
              if (std::find(used.begin(), used.end(), s.slot[a]) == used.end())
                used.push_back(s.slot[a]);
          // Obstacle vertices do not move: constants, not variables.
          bool against_obstacle = c.kind == PairKind::point_plane;
          for (unsigned int i = 0; i < used.size();)
            if (m.fixed(c.vertex[used[i]]))
              {
                against_obstacle = true;
                used.erase(used.begin() + i);
              }
            else
              ++i;
          const unsigned int n = dim * used.size();

          std::array<internal::V3<AD>, 4> y;
          for (unsigned int i = 0; i < 4; ++i)
            for (unsigned int dd = 0; dd < 3; ++dd)
              y[i][dd] = X[i][dd];
          for (unsigned int i = 0; i < used.size(); ++i)
            for (unsigned int dd = 0; dd < dim; ++dd)
              y[used[i]][dd] =
                AD(N, dim * i + dd, Inner(N, dim * i + dd, X[used[i]][dd]));
          std::array<internal::V3<AD>, 4> args;
          for (unsigned int a = 0; a < n_arguments(s.type); ++a)
            args[a] = y[s.slot[a]];
          using std::sqrt;
          const AD dist = sqrt(internal::distance_squared(s.type, args.data()));
          AD       e    = barrier(dist, dhat);
          if (mollify)
            e *= edge_edge_mollifier(internal::edge_cross_squared(y.data()),
                                     eps_x);
          e *= kappa * A;
          energy += e.val().val();

          dofs.clear();
          for (const unsigned int i : used)
            for (unsigned int dd = 0; dd < dim; ++dd)
              dofs.push_back(m.dofs[c.vertex[i]][dd]);
          g.reinit(n);
          for (unsigned int i = 0; i < n; ++i)
            g[i] = e.dx(i).val();
          if (matrix)
            {
              H.reinit(n, n);
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  H(i, j) = e.dx(i).dx(j);
              project_to_psd(H);
            }
          add(dofs, against_obstacle);
        }

      // Lagged friction: mu N f_0(|T^T sum_i w_i (u_i - u_i^start)|).
      for (const auto &f : friction)
        {
          Vec slip;
          for (unsigned int i = 0; i < f.n; ++i)
            slip += f.weight[i] * (x[f.vertex[i]] - m.rest[f.vertex[i]] -
                                   friction_start[f.vertex[i]]);
          Tensor<1, dim - 1> tau;
          for (unsigned int j = 0; j < dim - 1; ++j)
            tau[j] = f.tangent[j] * slip;
          const double y = tau.norm();
          energy += f.mu_n * friction_f0(y, friction_eta);
          // Gradient: w_i T (mu N f_1 / y tau); Hessian w_i w_j T H_tau T^T
          // with H_tau = mu N (f_1/y I + (f_1/y)'/y tau tau^T), positive
          // semi-definite for every y.
          const double a = f.mu_n * friction_f1_over_y(y, friction_eta);
          const double b =
            y > 0 ? f.mu_n * friction_f2_term(y, friction_eta) : 0.;
          Vec force;
          for (unsigned int j = 0; j < dim - 1; ++j)
            force += a * tau[j] * f.tangent[j];
          // The moving vertices of the pair (obstacle vertices are fixed).
          used.clear();
          for (unsigned int i = 0; i < f.n; ++i)
            if (!m.fixed(f.vertex[i]))
              used.push_back(i);
          local_dofs(f.vertex.data(), f.n, dofs);
          const auto        &moving = used;
          const unsigned int n      = dofs.size();
          g.reinit(n);
          for (unsigned int k = 0; k < moving.size(); ++k)
            for (unsigned int dd = 0; dd < dim; ++dd)
              g[dim * k + dd] = f.weight[moving[k]] * force[dd];
          if (matrix)
            {
              // T H_tau T^T as a 3 x 3 block.
              Tensor<2, 3> B;
              for (unsigned int j = 0; j < dim - 1; ++j)
                for (unsigned int l = 0; l < dim - 1; ++l)
                  {
                    const double h = (j == l ? a : 0.) + b * tau[j] * tau[l];
                    B += h * outer_product(f.tangent[j], f.tangent[l]);
                  }
              H.reinit(n, n);
              for (unsigned int i = 0; i < moving.size(); ++i)
                for (unsigned int j = 0; j < moving.size(); ++j)
                  for (unsigned int p = 0; p < dim; ++p)
                    for (unsigned int q = 0; q < dim; ++q)
                      H(dim * i + p, dim * j + q) =
                        f.weight[moving[i]] * f.weight[moving[j]] * B[p][q];
            }
          add(dofs, f.obstacle);
        }
      assemble_seconds += timer.wall_time();
      return energy;
    }



    template <int dim>
    void
    IpcContact<dim>::update_friction(const Vector_t &u_lagged,
                                     const Vector_t &u_start,
                                     const double    eta)
    {
      friction.clear();
      friction_eta = eta;
      if (!parameters.has_friction())
        return;
      friction_start = displacements(u_start);
      collect_candidates(u_lagged, nullptr);
      const auto            &m = *collision_mesh;
      const std::vector<Vec> x = positions(u_lagged);
      for (unsigned int k = 0; k < candidates.size(); ++k)
        {
          if (!mine(k))
            continue;
          const Candidate         &c = candidates[k];
          const std::array<Vec, 4> X = pair_positions(c, x);
          FrictionPair             f;
          Vec                      normal;
          const PairGeometry       pg = pair_geometry(c, X);
          const double             d  = pg.distance;
          if (c.kind == PairKind::point_plane)
            {
              normal          = X[2];
              f.n             = 1;
              f.vertex        = {{c.vertex[0], 0, 0, 0}};
              f.weight        = {{1., 0., 0., 0.}};
              const double mu = parameters.planes[c.plane].friction >= 0 ?
                                  parameters.planes[c.plane].friction :
                                  parameters.friction;
              f.mu_n          = mu;
              f.obstacle      = true;
            }
          else
            {
              const DistanceStencil &s = pg.stencil;
              if (d >= dhat || d <= 0)
                continue;
              // Closest points: weights of the relative displacement and
              // the normal, by distance type.
              const auto &P = [&](unsigned int a) -> const Vec & {
                return X[s.slot[a]];
              };
              std::array<double, 4> w{{0, 0, 0, 0}};
              switch (s.type)
                {
                  case DistanceType::point_point:
                    w[0]   = 1;
                    w[1]   = -1;
                    normal = P(0) - P(1);
                    break;
                    case DistanceType::point_edge: {
                      const Vec    e = P(2) - P(1);
                      const double t = (P(0) - P(1)) * e / e.norm_square();
                      w              = {{1., -(1. - t), -t, 0.}};
                      normal         = P(0) - P(1) - t * e;
                      break;
                    }
                    case DistanceType::point_triangle: {
                      const Vec e1 = P(2) - P(1), e2 = P(3) - P(1);
                      normal           = cross_product_3d(e1, e2);
                      const Vec    r   = P(0) - P(1);
                      const double a11 = e1 * e1, a12 = e1 * e2, a22 = e2 * e2;
                      const double b1 = r * e1, b2 = r * e2;
                      const double det = a11 * a22 - a12 * a12;
                      const double l1  = (a22 * b1 - a12 * b2) / det;
                      const double l2  = (a11 * b2 - a12 * b1) / det;
                      w                = {{1., -(1. - l1 - l2), -l1, -l2}};
                      break;
                    }
                    case DistanceType::edge_edge: {
                      const Vec ea = P(1) - P(0), eb = P(3) - P(2),
                                r      = P(0) - P(2);
                      const double a11 = ea * ea, a12 = ea * eb, a22 = eb * eb;
                      const double D = ea * r, E = eb * r;
                      const double den = a11 * a22 - a12 * a12;
                      const double sa  = (a12 * E - a22 * D) / den;
                      const double tb  = (a11 * E - a12 * D) / den;
                      w                = {{1. - sa, sa, -(1. - tb), -tb}};
                      normal           = cross_product_3d(ea, eb);
                      if (normal * (P(0) + sa * ea - P(2) - tb * eb) < 0)
                        normal *= -1.;
                      break;
                    }
                  default:
                    break;
                }
              f.n = n_arguments(s.type);
              for (unsigned int a = 0; a < f.n; ++a)
                {
                  f.vertex[a] = c.vertex[s.slot[a]];
                  f.weight[a] = w[a];
                }
              f.mu_n =
                friction_coefficient(c.vertex[s.slot[0]], f.vertex[f.n - 1]);
              for (unsigned int a = 0; a < f.n; ++a)
                f.obstacle |= m.fixed(f.vertex[a]);
            }
          if (d <= 0 || d >= dhat || f.mu_n <= 0 || normal.norm() == 0)
            continue;
          normal /= normal.norm();
          f.tangent = tangent_basis<dim>(normal);
          // mu times the lagged normal force kappa A |b'(d)|.
          f.mu_n *=
            kappa * pg.weight * pg.mollifier * -barrier_derivative(d, dhat);
          friction.push_back(f);
        }
    }



    template <int dim>
    bool
    IpcContact<dim>::update_stiffness()
    {
      if (!automatic_kappa)
        return false;
      const double d = Utilities::MPI::min(min_distance, comm);
      bool         grow =
        d < 0.03 * dhat && d < previous_min_distance && kappa < kappa_max;
      previous_min_distance = d;
      if (grow)
        kappa = std::min(2 * kappa, kappa_max);
      return grow;
    }



    template <int dim>
    std::pair<double, unsigned int>
    IpcContact<dim>::last_state(const MPI_Comm c) const
    {
      return {Utilities::MPI::min(min_distance, c),
              Utilities::MPI::sum(n_active, c)};
    }



    template <int dim>
    Tensor<1, dim>
    IpcContact<dim>::obstacle_reaction(const MPI_Comm c) const
    {
      Tensor<1, dim> f;
      for (unsigned int d = 0; d < dim; ++d)
        f[d] = Utilities::MPI::sum(obstacle_force[d], c);
      return f;
    }



    template <int dim>
    nlohmann::json
    IpcContact<dim>::timings() const
    {
      return {{"broad_phase_seconds", broad_seconds},
              {"ccd_seconds", ccd_seconds},
              {"contact_assembly_seconds", assemble_seconds}};
    }

    template class IpcContact<2>;
    template class IpcContact<3>;
  } // namespace ipc
} // namespace forma
