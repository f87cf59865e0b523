#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/base/records.h>
#include <forma/ipc/barrier.h>
#include <forma/ipc/broad_phase.h>
#include <forma/ipc/ipc_contact.h>
#include <forma/ipc/obstacle_mesh.h>
#include <forma/solvers/psd_projection.h>

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

      /**
       * Pair positions X as nested forward-AD values: the coordinates of the
       * moving vertices `used` are variables dim * i + d of both levels (the
       * outer level may have more variables), the rest constants.
       */
      template <int dim, typename Outer, typename Inner>
      std::array<internal::V3<Outer>, 4>
      seeded_positions(const std::array<Vec, 4>        &X,
                       const std::vector<unsigned int> &used,
                       const int                        n_outer,
                       const int                        n_inner)
      {
        std::array<internal::V3<Outer>, 4> y;
        for (unsigned int i = 0; i < 4; ++i)
          for (unsigned int d = 0; d < 3; ++d)
            y[i][d] = X[i][d];
        for (unsigned int i = 0; i < used.size(); ++i)
          for (unsigned int d = 0; d < dim; ++d)
            y[used[i]][d] = Outer(n_outer,
                                  dim * i + d,
                                  Inner(n_inner, dim * i + d, X[used[i]][d]));
        return y;
      }

      /**
       * The barrier of a classified pair at its vertex positions y (slots
       * of the candidate), times the edge-edge mollifier where it acts:
       * b(d) m(c, eps_x), generic in the number types for AD.
       */
      template <typename T, typename Eps>
      T
      barrier_term(const DistanceStencil                &s,
                   const std::array<internal::V3<T>, 4> &y,
                   const bool                            mollify,
                   const Eps                            &eps_x,
                   const double                          dhat)
      {
        using std::sqrt;
        std::array<internal::V3<T>, 4> args;
        for (unsigned int a = 0; a < n_arguments(s.type); ++a)
          args[a] = y[s.slot[a]];
        const T d = sqrt(internal::distance_squared(s.type, args.data()));
        T       e = barrier(d, dhat);
        if (mollify)
          e *=
            edge_edge_mollifier(internal::edge_cross_squared(y.data()), eps_x);
        return e;
      }
    } // namespace



    template <int dim>
    IpcContact<dim>::IpcContact(const IpcParameters &parameters)
      : parameters(parameters)
    {
      source_names.push_back("IPC/Friction coefficient");
      source_values.push_back(parameters.friction);
      for (const auto &[ids, mu] : parameters.pair_friction)
        {
          pair_source[ids] = source_values.size();
          source_names.push_back("Friction pairs " + std::to_string(ids.first) +
                                 "-" + std::to_string(ids.second));
          source_values.push_back(mu);
        }
      const auto own = [&](const double mu, const std::string &name) {
        if (mu < 0)
          return -1;
        source_names.push_back(name);
        source_values.push_back(mu);
        return int(source_values.size()) - 1;
      };
      for (unsigned int k = 0; k < parameters.planes.size(); ++k)
        plane_source.push_back(own(parameters.planes[k].friction,
                                   "obstacle plane " + std::to_string(k + 1)));
      for (unsigned int k = 0; k < parameters.meshes.size(); ++k)
        mesh_source.push_back(own(parameters.meshes[k].friction,
                                  "obstacle mesh " + std::to_string(k + 1)));
    }



    template <int dim>
    void
    IpcContact<dim>::freeze()
    {
      frozen = true;
    }



    template <int dim>
    void
    IpcContact<dim>::set_friction_values(const std::vector<double> &values)
    {
      AssertThrow(values.size() == source_values.size(), ExcInternalError());
      for (unsigned int k = 0; k < values.size(); ++k)
        AssertThrow(values[k] >= 0,
                    ExcMessage("Design (friction): " + source_names[k] +
                               " must be >= 0 (got " + sig(values[k]) + ")."));
      source_values      = values;
      keep_zero_friction = true;
    }



    template <int dim>
    bool
    IpcContact<dim>::has_friction() const
    {
      return keep_zero_friction ||
             std::any_of(source_values.begin(),
                         source_values.end(),
                         [](const double mu) { return mu > 0; });
    }

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
    unsigned int
    IpcContact<dim>::friction_source(const Candidate       &c,
                                     const DistanceStencil &s) const
    {
      if (c.kind == PairKind::point_plane)
        return std::max(plane_source[c.plane], 0);
      // The two sides: the first and the last argument of the formula.
      const auto        &m = *collision_mesh;
      const unsigned int a = c.vertex[s.slot[0]];
      const unsigned int b = c.vertex[s.slot[n_arguments(s.type) - 1]];
      for (const unsigned int v : {a, b})
        if (m.fixed(v) && mesh_source[m.obstacle[v]] >= 0)
          return mesh_source[m.obstacle[v]];
      const auto ia = m.body[a], ib = m.body[b];
      const auto it = pair_source.find({std::min(ia, ib), std::max(ia, ib)});
      return it != pair_source.end() ? it->second : 0;
    }



    template <int dim>
    bool
    IpcContact<dim>::barrier_variables(const Candidate           &c,
                                       const PairGeometry        &pg,
                                       std::vector<unsigned int> &used) const
    {
      const DistanceStencil &s = pg.stencil;
      used.clear();
      if (pg.mollifier < 1)
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
        if (collision_mesh->fixed(c.vertex[used[i]]))
          {
            against_obstacle = true;
            used.erase(used.begin() + i);
          }
        else
          ++i;
      return against_obstacle;
    }



    template <int dim>
    void
    IpcContact<dim>::setup(const DoFHandler<dim>            &dof_handler,
                           const hp::MappingCollection<dim> &mapping,
                           const IndexSet                   &owned,
                           const MPI_Comm                    mpi_comm,
                           const DoFHandler<dim>            *shape_dof_handler,
                           const std::string                &where)
    {
      comm    = mpi_comm;
      rank    = Utilities::MPI::this_mpi_process(comm);
      n_ranks = Utilities::MPI::n_mpi_processes(comm);
      AssertThrow(dim == 2 ||
                    !dof_handler.get_triangulation().has_hanging_nodes(),
                  ExcMessage("IPC contact in 3D needs a mesh without hanging "
                             "nodes (no adaptive refinement)."));
      collision_mesh = std::make_unique<CollisionMesh<dim>>(
        dof_handler, mapping, parameters.boundaries, comm, shape_dof_handler);
      AssertThrow(collision_mesh->n_vertices() > 0,
                  ExcMessage("IPC: the collision mesh is empty: no boundary "
                             "faces with the ids of IPC/Boundaries."));
      for (unsigned int k = 0; k < parameters.meshes.size(); ++k)
        collision_mesh->add_obstacle(
          read_obstacle_mesh(parameters.meshes[k].file, dim), k);
      const auto &m = *collision_mesh;
      // Frozen: dhat and kappa stay as they are once set.
      if (!frozen || dhat == 0)
        dhat = parameters.dhat > 0 ? parameters.dhat :
                                     parameters.relative_dhat * m.diagonal();
      automatic_kappa = parameters.kappa == 0;
      if (!frozen || kappa == 0)
        kappa = parameters.kappa;
      IndexSet ghost = m.collision_dofs;
      ghost.add_indices(owned);
      values.reinit(owned, ghost, comm);
      couplings.clear();
      friction.clear();
      previous_min_distance = std::numeric_limits<double>::max();

      Vector_t zero(owned, comm);
      update_candidates(zero, nullptr);
      check_state(zero, where, true);
    }



    template <int dim>
    void
    IpcContact<dim>::set_stiffness_scale(const double mean_diagonal)
    {
      if (!automatic_kappa || (frozen && kappa > 0))
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
        // With (v, v): this rank may write the rows of vertices whose
        // cells other ranks own (a point against a plane or an obstacle).
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i; j < n; ++j)
            if (!mesh.fixed(v[i]) && !mesh.fixed(v[j]))
              required.emplace(std::min(v[i], v[j]), std::max(v[i], v[j]));
      };
      for (unsigned int k = 0; k < candidates.size(); ++k)
        if (mine(k))
          require(candidates[k].vertex.data(),
                  candidates[k].kind == PairKind::point_plane ?
                    1 :
                    n_vertices(candidates[k].kind));
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
            g.weight_terms             = {{c.vertex[0], 1.}};
            return g;
        }
      g.distance = std::sqrt(g.stencil.distance_squared);
      // Areas of the bodies' side only: a coarse obstacle's vertex areas
      // say nothing of the contact's extent.
      // Half the mean vertex area of the moving vertices in [first, last).
      const auto half_mean_area = [&](const unsigned int first,
                                      const unsigned int last) {
        unsigned int n = 0;
        for (unsigned int i = first; i < last; ++i)
          n += !m.fixed(c.vertex[i]);
        g.weight = 0;
        for (unsigned int i = first; i < last; ++i)
          if (!m.fixed(c.vertex[i]))
            {
              g.weight_terms.emplace_back(c.vertex[i], 0.5 / n);
              g.weight += 0.5 / n * m.vertex_area[c.vertex[i]];
            }
      };
      if (c.kind != PairKind::edge_edge)
        {
          if (m.fixed(c.vertex[0]))
            half_mean_area(1, n_vertices(c.kind));
          else
            half_mean_area(0, 1);
          return g;
        }
      half_mean_area(0, 4);
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
                              bool                            &admissible,
                              const bool                       project)
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
          const bool         against_obstacle = barrier_variables(c, pg, used);
          const unsigned int n                = dim * used.size();

          const auto y = seeded_positions<dim, AD, Inner>(X, used, N, N);
          AD e = barrier_term(pg.stencil, y, pg.mollifier < 1, pg.eps_x, dhat);
          e *= kappa * pg.weight;
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
              if (project)
                project_to_psd(H, "IPC contact (degenerate pair geometry)");
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
      if (!has_friction())
        return;
      friction_start = displacements(u_start);
      collect_candidates(u_lagged, nullptr);
      friction_lagged = positions(u_lagged);
      const auto &m   = *collision_mesh;
      for (unsigned int k = 0; k < candidates.size(); ++k)
        {
          if (!mine(k))
            continue;
          const Candidate         &c  = candidates[k];
          const std::array<Vec, 4> X  = pair_positions(c, friction_lagged);
          const PairGeometry       pg = pair_geometry(c, X);
          const DistanceStencil   &s  = pg.stencil;
          const double             d  = pg.distance;
          if (d <= 0 || d >= dhat)
            continue;
          FrictionPair f;
          f.candidate = c;
          f.source    = friction_source(c, s);
          f.n         = n_arguments(s.type);
          // Closest points (weights of the arguments) and the normal.
          std::array<internal::V3<double>, 4> args;
          for (unsigned int a = 0; a < f.n; ++a)
            for (unsigned int dd = 0; dd < 3; ++dd)
              args[a][dd] = X[s.slot[a]][dd];
          std::array<double, 4> w;
          internal::V3<double>  nv;
          internal::closest_point_frame(s.type, args.data(), w, nv);
          Vec normal;
          for (unsigned int dd = 0; dd < 3; ++dd)
            normal[dd] = nv[dd];
          if (c.kind == PairKind::point_plane)
            f.n = 1; // the plane's origin and normal carry no slip
          for (unsigned int a = 0; a < f.n; ++a)
            {
              f.vertex[a] = c.vertex[s.slot[a]];
              f.weight[a] = w[a];
              f.obstacle |= m.fixed(f.vertex[a]);
            }
          f.obstacle |= c.kind == PairKind::point_plane;
          const double mu = source_values[f.source];
          if ((mu <= 0 && !keep_zero_friction) || normal.norm() == 0)
            continue;
          normal /= normal.norm();
          f.tangent = tangent_basis<dim>(normal);
          // mu times the lagged normal force kappa A m |b'(d)|.
          f.mu_n = mu * kappa * pg.weight * pg.mollifier *
                   -barrier_derivative(d, dhat);
          friction.push_back(f);
        }
    }



    template <int dim>
    void
    IpcContact<dim>::add_threshold_gradient(const Candidate  &c,
                                            const double      s,
                                            std::vector<Vec> &rest) const
    {
      // eps_x = 1e-3 |e_a|^2 |e_b|^2 at rest.
      const auto              &m  = *collision_mesh;
      const Vec                ea = m.rest[c.vertex[1]] - m.rest[c.vertex[0]];
      const Vec                eb = m.rest[c.vertex[3]] - m.rest[c.vertex[2]];
      const Vec                ga = 2e-3 * s * eb.norm_square() * ea;
      const Vec                gb = 2e-3 * s * ea.norm_square() * eb;
      const std::array<Vec, 4> g{{-ga, ga, -gb, gb}};
      for (unsigned int i = 0; i < 4; ++i)
        if (!m.fixed(c.vertex[i]))
          rest[c.vertex[i]] += g[i];
    }



    namespace
    {
      // Nested forward AD over the moving coordinates of a pair (and the
      // mollifier threshold, variable N of the outer level).
      template <int dim>
      constexpr int n_pair_variables = 3 * dim + (dim == 3 ? 3 : 0);
      template <int dim>
      using PairInner = Sacado::Fad::SFad<double, n_pair_variables<dim>>;
      template <int dim>
      using PairOuter =
        Sacado::Fad::SFad<PairInner<dim>, n_pair_variables<dim> + 1>;
    } // namespace



    template <int dim>
    template <typename F>
    void
    IpcContact<dim>::for_each_barrier_pair(const std::vector<Vec> &x,
                                           const F                &f) const
    {
      constexpr int N = n_pair_variables<dim>;
      using Inner     = PairInner<dim>;
      using Outer     = PairOuter<dim>;
      std::vector<unsigned int> used;
      for (unsigned int k = 0; k < candidates.size(); ++k)
        {
          if (!mine(k))
            continue;
          const Candidate         &c  = candidates[k];
          const std::array<Vec, 4> X  = pair_positions(c, x);
          const PairGeometry       pg = pair_geometry(c, X);
          if (pg.distance <= 0 || pg.distance >= dhat)
            continue;
          barrier_variables(c, pg, used);
          const bool mollify = pg.mollifier < 1;
          const auto y = seeded_positions<dim, Outer, Inner>(X, used, N + 1, N);
          Outer      eps = pg.eps_x;
          if (mollify)
            eps = Outer(N + 1, N, Inner(pg.eps_x));
          // kappa A_k b(d) m: e.val().dx(i) is the gradient, e.dx(j).dx(i)
          // the Hessian, e.dx(N).dx(i) the mixed threshold derivative.
          Outer e = barrier_term(pg.stencil, y, mollify, eps, dhat);
          e *= kappa * pg.weight;
          f(c, pg, used, e);
        }
    }



    template <int dim>
    void
    IpcContact<dim>::barrier_products(
      const std::vector<Vec>          &x,
      const std::vector<Vec>          &pv,
      std::vector<Vec>                &rest,
      std::vector<double>             &area,
      const AffineConstraints<double> *constraints,
      Vector_t                        *hessian_p) const
    {
      // p^T grad E; its derivative along the positions x = rest + u is the
      // Hessian times p, plus the explicit rest terms (area weight,
      // mollifier threshold).
      Assert(!hessian_p || constraints, ExcInternalError());
      constexpr int                        N = n_pair_variables<dim>;
      const auto                          &m = *collision_mesh;
      std::vector<double>                  pl, Hp;
      std::vector<types::global_dof_index> dofs;
      for_each_barrier_pair(
        x,
        [&](const Candidate                 &c,
            const PairGeometry              &pg,
            const std::vector<unsigned int> &used,
            const PairOuter<dim>            &e) {
          const unsigned int n = dim * used.size();
          pl.resize(n);
          Hp.resize(n);
          for (unsigned int i = 0; i < n; ++i)
            pl[i] = pv[c.vertex[used[i / dim]]][i % dim];
          double pF = 0;
          for (unsigned int i = 0; i < n; ++i)
            pF += e.val().dx(i) * pl[i];
          for (unsigned int j = 0; j < n; ++j)
            {
              Hp[j] = 0;
              for (unsigned int i = 0; i < n; ++i)
                Hp[j] += e.dx(j).dx(i) * pl[i];
              rest[c.vertex[used[j / dim]]][j % dim] += Hp[j];
            }
          if (hessian_p)
            {
              dofs.clear();
              for (const unsigned int i : used)
                for (unsigned int d = 0; d < dim; ++d)
                  dofs.push_back(m.dofs[c.vertex[i]][d]);
              const Vector<double> local(Hp.begin(), Hp.end());
              constraints->distribute_local_to_global(local, dofs, *hessian_p);
            }
          if (pg.mollifier < 1)
            {
              double s = 0;
              for (unsigned int i = 0; i < n; ++i)
                s += e.dx(N).dx(i) * pl[i];
              add_threshold_gradient(c, s, rest);
            }
          for (const auto &[v, coefficient] : pg.weight_terms)
            area[v] += coefficient * pF / pg.weight;
        });
    }



    template <int dim>
    Tensor<1, dim>
    IpcContact<dim>::barrier_resultant(
      const Vector_t                     &u,
      const std::set<types::material_id> &bodies)
    {
      const auto            &m = *collision_mesh;
      const std::vector<Vec> x = positions(u);
      Tensor<1, dim>         R;
      for_each_barrier_pair(x,
                            [&](const Candidate &c,
                                const PairGeometry &,
                                const std::vector<unsigned int> &used,
                                const PairOuter<dim>            &e) {
                              for (unsigned int i = 0; i < dim * used.size();
                                   ++i)
                                {
                                  const unsigned int v =
                                    c.vertex[used[i / dim]];
                                  if (bodies.empty() || bodies.count(m.body[v]))
                                    R[i % dim] -= e.val().dx(i);
                                }
                            });
      return Utilities::MPI::sum(R, comm);
    }



    template <int dim>
    void
    IpcContact<dim>::barrier_resultant_products(
      const Vector_t                     &u,
      const Tensor<1, dim>               &dJ_dR,
      const std::set<types::material_id> &bodies,
      const AffineConstraints<double>    &constraints,
      Vector_t                           &dJ_du,
      std::vector<Vec>                   &rest)
    {
      // R = -sum over the bodies' vertices of grad E = -s^T grad E with s
      // the indicator of their DoFs, so J(R) has the products of p = -s
      // dJ/dR: dJ/du = H p, dJ/d rest = d(p^T grad E)/d rest.
      const auto            &m = *collision_mesh;
      const std::vector<Vec> x = positions(u);
      std::vector<Vec>       pv(m.n_vertices());
      for (unsigned int v = 0; v < m.n_vertices(); ++v)
        if (!m.fixed(v) && (bodies.empty() || bodies.count(m.body[v])))
          for (unsigned int d = 0; d < dim; ++d)
            pv[v][d] = -dJ_dR[d];
      rest.resize(m.n_vertices());
      std::vector<double> area(m.n_vertices(), 0.);
      barrier_products(x, pv, rest, area, &constraints, &dJ_du);
      m.add_area_gradient(area, rest);
      dJ_du.compress(VectorOperation::add);
    }



    template <int dim>
    void
    IpcContact<dim>::adjoint_products(
      const Vector_t                  &u,
      const Vector_t                  &p,
      const AffineConstraints<double> &constraints,
      Vector_t                        *lagged,
      AdjointProducts                 &out)
    {
      Timer                  timer;
      const auto            &m  = *collision_mesh;
      const std::vector<Vec> x  = positions(u);
      const std::vector<Vec> pv = displacements(p);
      out.rest.resize(m.n_vertices());
      out.friction.resize(source_values.size(), 0.);
      std::vector<double>                  area(m.n_vertices(), 0.);
      std::vector<double>                  values;
      std::vector<types::global_dof_index> dofs;

      barrier_products(x, pv, out.rest, area, nullptr, nullptr);

      // Lagged friction (eqs. 3.26-3.29): p^T h^f = M fy (p~ . P s) with
      // M = kappa A m |b'(d)| mu, the slip s = sum_a w_a (u_a - u_a^start),
      // P the tangent projector, fy = f_1(|P s|) / |P s| and p~ = sum_a w_a
      // p_a; M, w and P depend on the lagged positions (forward AD), s on
      // the start through the slip (closed form).
      if (!friction.empty())
        {
          // u at the vertices from x (no communication: only some ranks
          // have friction pairs).
          std::vector<Vec> now = x;
          for (unsigned int v = 0; v < now.size(); ++v)
            now[v] -= m.rest[v];
          using F = Sacado::Fad::SFad<double, 13>;
          for (const auto &f : friction)
            {
              const Candidate         &c  = f.candidate;
              const std::array<Vec, 4> XL = pair_positions(c, friction_lagged);
              const PairGeometry       pg = pair_geometry(c, XL);
              const DistanceStencil   &st = pg.stencil;
              const bool               mollify = pg.mollifier < 1;
              const bool               plane = c.kind == PairKind::point_plane;
              const unsigned int       nv    = plane ? 1 : n_vertices(c.kind);
              std::array<internal::V3<F>, 4> y;
              for (unsigned int i = 0; i < 4; ++i)
                for (unsigned int dd = 0; dd < 3; ++dd)
                  y[i][dd] = XL[i][dd];
              for (unsigned int i = 0; i < nv; ++i)
                if (!m.fixed(c.vertex[i]))
                  for (unsigned int dd = 0; dd < dim; ++dd)
                    y[i][dd] = F(13, 3 * i + dd, XL[i][dd]);
              F eps = pg.eps_x;
              if (mollify)
                eps = F(13, 12, pg.eps_x);
              std::array<internal::V3<F>, 4> args;
              for (unsigned int a = 0; a < n_arguments(st.type); ++a)
                args[a] = y[st.slot[a]];
              using std::sqrt;
              const F d =
                plane ?
                  internal::dot(internal::sub(args[0], args[1]), args[2]) :
                  sqrt(internal::distance_squared(st.type, args.data()));
              F M = -kappa * pg.weight * barrier_derivative(d, dhat);
              if (mollify)
                M *= edge_edge_mollifier(internal::edge_cross_squared(y.data()),
                                         eps);
              std::array<F, 4> w;
              internal::V3<F>  normal;
              internal::closest_point_frame(st.type, args.data(), w, normal);
              const F nn = sqrt(internal::dot(normal, normal));
              for (auto &v : normal)
                v /= nn;
              internal::V3<F> slip{{F(0.), F(0.), F(0.)}}, pt = slip;
              for (unsigned int a = 0; a < f.n; ++a)
                if (!m.fixed(f.vertex[a]))
                  for (unsigned int dd = 0; dd < dim; ++dd)
                    {
                      slip[dd] += w[a] * (now[f.vertex[a]][dd] -
                                          friction_start[f.vertex[a]][dd]);
                      pt[dd] += w[a] * pv[f.vertex[a]][dd];
                    }
              const F         sn = internal::dot(normal, slip);
              internal::V3<F> Ps;
              for (unsigned int dd = 0; dd < 3; ++dd)
                Ps[dd] = slip[dd] - sn * normal[dd];
              const F y2 = internal::dot(Ps, Ps);
              // At zero slip P s = 0: f_1(y)/y acts as its limit 2 / eta.
              const F      fy  = y2.val() > 0 ?
                                   friction_f1_over_y(F(sqrt(y2)), friction_eta) :
                                   F(2. / friction_eta);
              const F      pF1 = M * fy * internal::dot(pt, Ps); // mu = 1
              const double mu  = source_values[f.source];
              out.friction[f.source] += pF1.val();
              for (const auto &[v, coefficient] : pg.weight_terms)
                area[v] += coefficient * mu * pF1.val() / pg.weight;
              if (mollify)
                add_threshold_gradient(c, mu * pF1.dx(12), out.rest);

              // Lagged positions x = rest + u_lagged: both gradients.
              dofs.clear();
              values.clear();
              for (unsigned int i = 0; i < nv; ++i)
                if (!m.fixed(c.vertex[i]))
                  for (unsigned int dd = 0; dd < dim; ++dd)
                    {
                      const double g = mu * pF1.dx(3 * i + dd);
                      out.rest[c.vertex[i]][dd] += g;
                      if (lagged)
                        {
                          dofs.push_back(m.dofs[c.vertex[i]][dd]);
                          values.push_back(g);
                        }
                    }
              // The start of the slip: -M w_b H_s p~, H_s = fy P + fy' / y
              // (P s)(P s)^T.
              if (lagged)
                {
                  const double y = std::sqrt(y2.val());
                  const double f2 =
                    y > 0 ? friction_f2_term(y, friction_eta) : 0.;
                  double Ppt[3], ps_pt = 0, n_pt = 0;
                  for (unsigned int dd = 0; dd < 3; ++dd)
                    {
                      ps_pt += Ps[dd].val() * pt[dd].val();
                      n_pt += normal[dd].val() * pt[dd].val();
                    }
                  for (unsigned int dd = 0; dd < 3; ++dd)
                    Ppt[dd] = pt[dd].val() - n_pt * normal[dd].val();
                  for (unsigned int a = 0; a < f.n; ++a)
                    if (!m.fixed(f.vertex[a]))
                      for (unsigned int dd = 0; dd < dim; ++dd)
                        {
                          dofs.push_back(m.dofs[f.vertex[a]][dd]);
                          values.push_back(
                            -mu * M.val() * w[a].val() *
                            (fy.val() * Ppt[dd] + f2 * ps_pt * Ps[dd].val()));
                        }
                  const Vector<double> local(values.begin(), values.end());
                  constraints.distribute_local_to_global(local, dofs, *lagged);
                }
            }
        }
      m.add_area_gradient(area, out.rest);
      if (lagged)
        lagged->compress(VectorOperation::add);
      assemble_seconds += timer.wall_time();
    }



    template <int dim>
    bool
    IpcContact<dim>::update_stiffness()
    {
      if (!automatic_kappa || frozen)
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
