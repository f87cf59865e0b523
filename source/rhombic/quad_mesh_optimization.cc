#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <forma/base/records.h>
#include <forma/rhombic/quad_mesh_optimization.h>
#include <forma/solvers/psd_projection.h>

#include <Sacado.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    void
    QuadMeshOptimizationParameters::declare(ParameterHandler &prm)
    {
      prm.declare_entry("Minimum angle",
                        "45",
                        Patterns::Double(1, 90),
                        "theta_m of thesis eq. 4.13 (degrees): target rhombi "
                        "are not sharper than this; the smallest angle the "
                        "material-to-geometry map covers.");
      prm.declare_entry(
        "Angle floor",
        "0",
        Patterns::Double(0, 89),
        "The smallest rhombus angle alpha (degrees) the optimized quads may "
        "have (0: none). Quads sharper than this after the continuation in "
        "s are pushed up by a penalty on their fitted parallelogram's "
        "angle, ten times stronger each round (at most 12 rounds) until "
        "every quad meets the floor; where the mesh's vertex valences leave "
        "no room it is not met and the run says which quad stays below. "
        "Unlike a larger Minimum angle, this leaves the quads above the "
        "floor free to stay rhombic.");
      prm.declare_entry(
        "Exponents",
        "1, 4, 16",
        Patterns::List(Patterns::Double(0)),
        "The continuation in s of the exponential distortion energy "
        "(eq. 4.14): the larger s, the more the largest distortion counts.");
      prm.declare_entry("Boundary weight",
                        "1e4",
                        Patterns::Double(0),
                        "lambda of eq. 4.16: how strongly boundary vertices "
                        "stay on the input boundary (they may slide along it; "
                        "vertices at its corners stay).");
      prm.declare_entry("Max iterations",
                        "100",
                        Patterns::Integer(1),
                        "Local/global iterations per exponent at most.");
      prm.declare_entry("Tolerance",
                        "1e-3",
                        Patterns::Double(0),
                        "An exponent ends when no vertex moves by more than "
                        "this times the mean edge length.");
    }



    void
    QuadMeshOptimizationParameters::parse(ParameterHandler &prm)
    {
      min_angle   = prm.get_double("Minimum angle") * M_PI / 180;
      angle_floor = prm.get_double("Angle floor") * M_PI / 180;
      exponents.clear();
      for (const std::string &s :
           Utilities::split_string_list(prm.get("Exponents")))
        exponents.push_back(Utilities::string_to_double(s));
      AssertThrow(!exponents.empty(),
                  ExcMessage("Quad mesh/Exponents: give at least one."));
      boundary_weight = prm.get_double("Boundary weight");
      max_iterations  = prm.get_integer("Max iterations");
      tolerance       = prm.get_double("Tolerance");
    }



    namespace
    {
      using Quad = std::array<Point<2>, 4>;

      // Corners of the reference square centered at the origin, in
      // deal.II's vertex order.
      constexpr double q_corner[4][2] = {{-0.5, -0.5},
                                         {0.5, -0.5},
                                         {-0.5, 0.5},
                                         {0.5, 0.5}};
      // The vertices in cyclic order around the quad.
      constexpr unsigned int cyclic[4] = {0, 1, 3, 2};

      /// The least-squares parallelogram T Q (eq. 4.12): T's columns t1, t2
      /// (N: double, or a Sacado type for the angle floor's derivatives).
      template <typename N, typename Vertex>
      Tensor<2, 2, N>
      parallelogram_fit(const std::array<Vertex, 4> &f)
      {
        Tensor<1, 2, N> c;
        for (const Vertex &p : f)
          for (unsigned int a = 0; a < 2; ++a)
            c[a] += 0.25 * p[a];
        // sum_i q_i q_i^T = I for the corners +-1/2.
        Tensor<2, 2, N> T;
        for (unsigned int i = 0; i < 4; ++i)
          for (unsigned int a = 0; a < 2; ++a)
            for (unsigned int b = 0; b < 2; ++b)
              T[a][b] += (f[i][a] - c[a]) * q_corner[i][b];
        return T;
      }

      /// The edge matrix W = l [e1, e2] of the rhombus with angle `angle`
      /// at vertex 0 and area `area` (orientation of `sign`).
      Tensor<2, 2>
      rhombus_edges(const double angle, const double area, const double sign)
      {
        const double l = std::sqrt(area / std::sin(angle));
        Tensor<2, 2> W;
        W[0][0] = l;
        W[0][1] = l * std::cos(angle);
        W[1][1] = sign * l * std::sin(angle);
        return W;
      }

      double
      corner_sine(const Quad &f, const unsigned int k)
      {
        const Point<2>    &p = f[cyclic[k]];
        const Tensor<1, 2> a = f[cyclic[(k + 1) % 4]] - p;
        const Tensor<1, 2> b = f[cyclic[(k + 3) % 4]] - p;
        return (a[0] * b[1] - a[1] * b[0]) / (a.norm() * b.norm());
      }

      double
      corner_angle(const Quad &f, const unsigned int k)
      {
        const Point<2>    &p = f[cyclic[k]];
        const Tensor<1, 2> a = f[cyclic[(k + 1) % 4]] - p;
        const Tensor<1, 2> b = f[cyclic[(k + 3) % 4]] - p;
        return std::atan2(a[0] * b[1] - a[1] * b[0], a * b);
      }

      // Gauss points of the 2 x 2 rule on [0, 1]^2.
      constexpr double g_lo = 0.5 - 0.5 / 1.7320508075688772;
      constexpr double g_hi = 0.5 + 0.5 / 1.7320508075688772;

      /// (A_Q / A) avg_g exp(s (D - 4)) of one quad (x: its 4 vertices),
      /// infinite when a Gauss point or a corner folds.
      template <typename N>
      N
      quad_energy(const std::array<Tensor<1, 2, N>, 4> &x,
                  const Tensor<2, 2>                   &W_inverse,
                  const double                          weight,
                  const double                          s)
      {
        N e = 0;
        for (const double xi : {g_lo, g_hi})
          for (const double eta : {g_lo, g_hi})
            {
              const double    dN[4][2] = {{-(1 - eta), -(1 - xi)},
                                          {1 - eta, -xi},
                                          {-eta, 1 - xi},
                                          {eta, xi}};
              Tensor<2, 2, N> G;
              for (unsigned int k = 0; k < 4; ++k)
                for (unsigned int a = 0; a < 2; ++a)
                  for (unsigned int b = 0; b < 2; ++b)
                    G[a][b] += x[k][a] * dN[k][b];
              Tensor<2, 2, N> J;
              for (unsigned int a = 0; a < 2; ++a)
                for (unsigned int b = 0; b < 2; ++b)
                  for (unsigned int c = 0; c < 2; ++c)
                    J[a][b] += G[a][c] * W_inverse[c][b];
              const N det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
              if (!(Sacado::ScalarValue<N>::eval(det) > 0))
                return N(std::numeric_limits<double>::infinity());
              // |J^-1|^2 = |J|^2 / det^2 in 2D.
              const N f2 = J[0][0] * J[0][0] + J[0][1] * J[0][1] +
                           J[1][0] * J[1][0] + J[1][1] * J[1][1];
              const N D = f2 * (1. + 1. / (det * det));
              e += 0.25 * std::exp(s * (D - 4.));
            }
        return weight * e;
      }

      /// mu (A_Q / A) max(0, |cos phi| - cos(floor))^2, phi the angle of
      /// the quad's least-squares parallelogram (eq. 4.12): zero while
      /// its smaller angle alpha is at least `floor`.
      template <typename N>
      N
      floor_energy(const std::array<Tensor<1, 2, N>, 4> &x,
                   const double                          cos_floor,
                   const double                          weight)
      {
        const Tensor<2, 2, N> T   = parallelogram_fit<N>(x);
        const N               t12 = T[0][0] * T[0][1] + T[1][0] * T[1][1];
        const N               t11 = T[0][0] * T[0][0] + T[1][0] * T[1][0];
        const N               t22 = T[0][1] * T[0][1] + T[1][1] * T[1][1];
        const N               c   = t12 / std::sqrt(t11 * t22);
        const N               excess =
          (Sacado::ScalarValue<N>::eval(c) < 0 ? -c : c) - cos_floor;
        if (!(Sacado::ScalarValue<N>::eval(excess) > 0))
          return N(0.);
        return weight * excess * excess;
      }

      struct Segment
      {
        Point<2> a, b;
      };

      /// The closest point to p on the segments `which` of `segs`.
      Point<2>
      closest_on_segments(const Point<2>                  &p,
                          const std::vector<Segment>      &segs,
                          const std::vector<unsigned int> &which,
                          unsigned int                    *segment = nullptr)
      {
        Point<2> best;
        double   best_d = std::numeric_limits<double>::max();
        for (const unsigned int k : which)
          {
            const Segment     &s  = segs[k];
            const Tensor<1, 2> d  = s.b - s.a;
            const double       t  = std::clamp((p - s.a) * d / (d * d), 0., 1.);
            const Point<2>     c  = s.a + t * d;
            const double       dc = (p - c).norm_square();
            if (dc < best_d)
              {
                best_d = dc;
                best   = c;
                if (segment)
                  *segment = k;
              }
          }
        return best;
      }
    } // namespace



    RhombicFit
    fit_rhombus(const Quad &f)
    {
      const Tensor<2, 2> T = parallelogram_fit<double>(f);
      const Tensor<1, 2> t1({T[0][0], T[1][0]}), t2({T[0][1], T[1][1]});
      RhombicFit         r;
      const double       cross = t1[0] * t2[1] - t1[1] * t2[0];
      r.area                   = std::abs(cross);
      r.angle =
        std::acos(std::clamp(t1 * t2 / (t1.norm() * t2.norm()), -1., 1.));
      r.alpha = std::min(r.angle, M_PI - r.angle);
      if (!(r.area > 0))
        {
          r.error = std::numeric_limits<double>::infinity();
          return r;
        }
      // Closest rhombus of this angle: orthogonal Procrustes with scale.
      const Tensor<2, 2> W = rhombus_edges(r.angle, 1, cross > 0 ? 1 : -1);
      Point<2>           c;
      for (const Point<2> &p : f)
        c += 0.25 * p;
      std::array<Tensor<1, 2>, 4> rv, fv;
      Tensor<2, 2>                M;
      double                      rr = 0;
      for (unsigned int i = 0; i < 4; ++i)
        {
          rv[i] = W * Tensor<1, 2>({q_corner[i][0], q_corner[i][1]});
          fv[i] = f[i] - c;
          M += outer_product(fv[i], rv[i]);
          rr += rv[i] * rv[i];
        }
      const double phi = std::atan2(M[1][0] - M[0][1], M[0][0] + M[1][1]);
      Tensor<2, 2> R;
      R[0][0] = R[1][1] = std::cos(phi);
      R[1][0]           = std::sin(phi);
      R[0][1]           = -R[1][0];
      double fr         = 0;
      for (unsigned int i = 0; i < 4; ++i)
        fr += fv[i] * (R * rv[i]);
      const double scale = fr / rr;
      for (unsigned int i = 0; i < 4; ++i)
        r.error += (fv[i] - scale * (R * rv[i])).norm();
      return r;
    }



    QuadMeshShape
    quad_mesh_shape(const Triangulation<2, 2> &tria)
    {
      QuadMeshShape s;
      const auto    n = tria.n_active_cells();
      s.alpha.reserve(n);
      s.rhombic_error.reserve(n);
      s.smallest_angle.reserve(n);
      s.min_alpha = s.min_interior_angle = s.min_scaled_jacobian =
        std::numeric_limits<double>::max();
      double area = 0;
      for (const auto &cell : tria.active_cell_iterators())
        {
          AssertThrow(cell->n_vertices() == 4,
                      ExcMessage("quad mesh: cell " + cell->id().to_string() +
                                 " is not a quadrilateral."));
          Quad f;
          for (unsigned int v = 0; v < 4; ++v)
            f[v] = cell->vertex(v);
          const RhombicFit r        = fit_rhombus(f);
          double           smallest = M_PI;
          for (unsigned int k = 0; k < 4; ++k)
            {
              smallest = std::min(smallest, corner_angle(f, k));
              s.min_scaled_jacobian =
                std::min(s.min_scaled_jacobian, corner_sine(f, k));
            }
          s.alpha.push_back(r.alpha);
          s.rhombic_error.push_back(r.error);
          s.smallest_angle.push_back(smallest);
          s.min_alpha = std::min(s.min_alpha, r.alpha);
          s.mean_alpha += r.alpha / n;
          s.min_interior_angle = std::min(s.min_interior_angle, smallest);
          area += r.area / n;
        }
      const double unit = std::sqrt(area);
      for (double &e : s.rhombic_error)
        {
          e /= unit;
          s.mean_error += e / n;
          s.max_error = std::max(s.max_error, e);
        }
      return s;
    }



    namespace
    {
      /// One optimize_rhombic_mesh() run: the mesh as vertex positions and
      /// quads, its input boundary, and the local and global steps.
      class RhombicMeshOptimizer
      {
      public:
        RhombicMeshOptimizer(const Triangulation<2, 2>            &tria,
                             const QuadMeshOptimizationParameters &prm,
                             const std::vector<bool>              &fixed);

        /// Local/global iterations at the exponent s until no vertex moves
        /// by more than the tolerance (or the iteration cap).
        void
        run_exponent(const double                           s,
                     std::vector<QuadMeshOptimizationStep> &history);

        /// After the continuation: rounds at the last exponent with the
        /// angle floor's penalty, ten times stronger each round, until every
        /// quad's alpha reaches the floor (at most angle_floor_rounds);
        /// whether it does.
        bool
        enforce_angle_floor(std::vector<QuadMeshOptimizationStep> &history);

        /// The largest distance of a boundary vertex from the input
        /// boundary, in mean edge lengths.
        double
        boundary_deviation() const;

        /// The optimized positions into `tria` (the input mesh).
        void
        write(Triangulation<2, 2> &tria) const;

        double
        mean_edge() const
        {
          return h;
        }

      private:
        void
        read_mesh(const Triangulation<2, 2> &tria,
                  const std::vector<bool>   &fixed);
        void
        find_corners();
        void
        find_slide_ranges();
        void
        make_sparsity();

        Quad
        quad_points(const std::vector<Point<2>>       &p,
                    const std::array<unsigned int, 4> &q) const;
        double
        total_energy(const std::vector<Point<2>> &p,
                     const double                 s,
                     double                      &distortion) const;
        double
        smallest_alpha() const;

        void
        local_step(AffineConstraints<double> &sliding);
        double
        assemble_newton_system(const double s);
        bool
        line_search(const double           s,
                    std::vector<Point<2>> &trial,
                    unsigned int          &halvings) const;
        double
        accept(std::vector<Point<2>> &trial, const double s);

        const QuadMeshOptimizationParameters &prm;
        // Compact numbering of the used vertices: DoFs 2 v + d.
        std::vector<unsigned int>                index;
        std::vector<Point<2>>                    x, x_input, y;
        std::vector<std::array<unsigned int, 4>> quads;
        double                                   area = 0, h = 0;
        double                                   boundary_scale = 0;
        std::vector<Segment>                     boundary;
        std::vector<bool>                        on_boundary, corner, held;
        // Boundary neighbours and segments of each boundary vertex.
        std::map<unsigned int, std::vector<unsigned int>> neighbours,
          segments_at;
        std::vector<std::vector<unsigned int>> slide;
        SparsityPattern                        pattern;
        SparseMatrix<double>                   H;
        Vector<double>                         g, dx;
        // The local step's targets: inverse edge matrices and area weights.
        std::vector<Tensor<2, 2>> W_inverse;
        std::vector<double>       weight;
        // The angle floor's penalty weight (0 until the continuation in s
        // has ended).
        double       floor_mu = 0;
        const double cos_floor;
      };



      RhombicMeshOptimizer::RhombicMeshOptimizer(
        const Triangulation<2, 2>            &tria,
        const QuadMeshOptimizationParameters &prm,
        const std::vector<bool>              &fixed)
        : prm(prm)
        , cos_floor(std::cos(prm.angle_floor))
      {
        read_mesh(tria, fixed);
        find_corners();
        find_slide_ranges();
        make_sparsity();
        boundary_scale = prm.boundary_weight / (h * h * quads.size());
        W_inverse.resize(quads.size());
        weight.resize(quads.size());
        y.resize(x.size());
      }



      void
      RhombicMeshOptimizer::read_mesh(const Triangulation<2, 2> &tria,
                                      const std::vector<bool>   &fixed)
      {
        const std::vector<Point<2>> &all  = tria.get_vertices();
        const std::vector<bool>     &used = tria.get_used_vertices();
        index.assign(all.size(), numbers::invalid_unsigned_int);
        for (unsigned int v = 0; v < all.size(); ++v)
          if (used[v])
            {
              index[v] = x.size();
              x.push_back(all[v]);
            }
        on_boundary.assign(x.size(), false);
        double       edges   = 0;
        unsigned int n_edges = 0;
        for (const auto &cell : tria.active_cell_iterators())
          {
            std::array<unsigned int, 4> q;
            for (unsigned int v = 0; v < 4; ++v)
              q[v] = index[cell->vertex_index(v)];
            quads.push_back(q);
            area += cell->measure();
            for (const unsigned int f : cell->face_indices())
              {
                const auto face = cell->face(f);
                edges += face->measure();
                ++n_edges;
                if (face->at_boundary())
                  {
                    const unsigned int a = index[face->vertex_index(0)],
                                       b = index[face->vertex_index(1)];
                    segments_at[a].push_back(boundary.size());
                    segments_at[b].push_back(boundary.size());
                    boundary.push_back({x[a], x[b]});
                    on_boundary[a] = on_boundary[b] = true;
                    neighbours[a].push_back(b);
                    neighbours[b].push_back(a);
                  }
              }
          }
        h       = edges / n_edges;
        x_input = x;
        // Vertices the caller holds in place.
        held.assign(x.size(), false);
        if (!fixed.empty())
          for (unsigned int v = 0; v < all.size(); ++v)
            if (used[v] && fixed[v])
              held[index[v]] = true;
      }



      // Boundary vertices at corners of the input outline (turning by more
      // than 40 degrees) keep their place (sliding would cut the corner);
      // the others slide along it.
      void
      RhombicMeshOptimizer::find_corners()
      {
        corner.assign(x.size(), false);
        for (const auto &[v, nb] : neighbours)
          if (nb.size() == 2)
            {
              const Tensor<1, 2> a = x[nb[0]] - x[v], b = x[nb[1]] - x[v];
              corner[v] =
                (a * b) / (a.norm() * b.norm()) > -std::cos(M_PI / 4.5);
            }
          else
            corner[v] = true; // a vertex where the boundary touches itself
      }



      // A boundary vertex slides along the boundary near where it started
      // (the segments up to 4 vertices away along the boundary): the
      // closest point of the whole boundary may lie across a narrow slot.
      void
      RhombicMeshOptimizer::find_slide_ranges()
      {
        slide.resize(x.size());
        for (const auto &[v, ignored] : neighbours)
          {
            std::vector<unsigned int> front = {v}, reached = {v};
            for (unsigned int depth = 0; depth < 4; ++depth)
              {
                std::vector<unsigned int> next;
                for (const unsigned int a : front)
                  for (const unsigned int b : neighbours[a])
                    if (std::find(reached.begin(), reached.end(), b) ==
                        reached.end())
                      {
                        reached.push_back(b);
                        next.push_back(b);
                      }
                front.swap(next);
              }
            for (const unsigned int a : reached)
              for (const unsigned int k : segments_at[a])
                if (std::find(slide[v].begin(), slide[v].end(), k) ==
                    slide[v].end())
                  slide[v].push_back(k);
          }
      }



      void
      RhombicMeshOptimizer::make_sparsity()
      {
        const unsigned int     n = 2 * x.size();
        DynamicSparsityPattern dsp(n);
        for (const auto &q : quads)
          for (const unsigned int a : q)
            for (const unsigned int b : q)
              for (unsigned int d = 0; d < 2; ++d)
                for (unsigned int e = 0; e < 2; ++e)
                  dsp.add(2 * a + d, 2 * b + e);
        for (unsigned int i = 0; i < n; ++i)
          dsp.add(i, i);
        pattern.copy_from(dsp);
        H.reinit(pattern);
        g.reinit(n);
        dx.reinit(n);
      }



      Quad
      RhombicMeshOptimizer::quad_points(
        const std::vector<Point<2>>       &p,
        const std::array<unsigned int, 4> &q) const
      {
        Quad f;
        for (unsigned int v = 0; v < 4; ++v)
          f[v] = p[q[v]];
        return f;
      }



      /// E(p; W, y) with the angle floor's penalty; infinite if a quad
      /// folds.
      double
      RhombicMeshOptimizer::total_energy(const std::vector<Point<2>> &p,
                                         const double                 s,
                                         double &distortion) const
      {
        distortion       = 0;
        double penalties = 0; // the angle floor's and the boundary's
        for (unsigned int c = 0; c < quads.size(); ++c)
          {
            const Quad f = quad_points(p, quads[c]);
            for (unsigned int k = 0; k < 4; ++k)
              if (!(corner_sine(f, k) > 0))
                return std::numeric_limits<double>::infinity();
            std::array<Tensor<1, 2, double>, 4> xc;
            for (unsigned int v = 0; v < 4; ++v)
              xc[v] = f[v];
            distortion += quad_energy(xc, W_inverse[c], weight[c], s);
            if (floor_mu > 0)
              penalties += floor_energy(xc, cos_floor, floor_mu * weight[c]);
          }
        for (unsigned int v = 0; v < x.size(); ++v)
          if (on_boundary[v])
            penalties += boundary_scale * (p[v] - y[v]).norm_square();
        return distortion + penalties;
      }



      double
      RhombicMeshOptimizer::smallest_alpha() const
      {
        double a = M_PI;
        for (const auto &q : quads)
          a = std::min(a, fit_rhombus(quad_points(x, q)).alpha);
        return a;
      }



      // Target rhombi (eq. 4.12-4.13) and boundary projections (eq. 4.15).
      // Boundary vertices move along the boundary only: corners not at
      // all, the others along the segment they are on (one coordinate
      // follows the other), so that strong distortion (large s) cannot
      // pull them off.
      void
      RhombicMeshOptimizer::local_step(AffineConstraints<double> &sliding)
      {
        for (unsigned int c = 0; c < quads.size(); ++c)
          {
            const RhombicFit r = fit_rhombus(quad_points(x, quads[c]));
            const double     angle =
              std::clamp(r.angle, prm.min_angle, M_PI - prm.min_angle);
            W_inverse[c] = invert(rhombus_edges(angle, r.area, 1));
            weight[c]    = r.area / area;
          }
        for (unsigned int v = 0; v < x.size(); ++v)
          if (held[v])
            {
              y[v] = x_input[v]; // held: no boundary penalty either
              for (unsigned int d = 0; d < 2; ++d)
                sliding.add_line(2 * v + d);
            }
          else if (on_boundary[v])
            {
              unsigned int k = 0;
              y[v]           = corner[v] ?
                                 x_input[v] :
                                 closest_on_segments(x[v], boundary, slide[v], &k);
              if (corner[v])
                for (unsigned int d = 0; d < 2; ++d)
                  sliding.add_line(2 * v + d);
              else
                {
                  const Tensor<1, 2> t = boundary[k].b - boundary[k].a;
                  // n . dx = 0 with n = (-t1, t0): eliminate the
                  // coordinate with the larger normal component.
                  const unsigned int a =
                    std::abs(t[1]) >= std::abs(t[0]) ? 0 : 1;
                  const unsigned int b = 1 - a;
                  sliding.add_line(2 * v + a);
                  sliding.add_entry(2 * v + a, 2 * v + b, t[a] / t[b]);
                }
            }
        sliding.close();
      }



      /// H and g of E(x; W, y) (per-quad Hessians by Sacado, made positive
      /// semidefinite); returns the largest boundary deviation at x.
      double
      RhombicMeshOptimizer::assemble_newton_system(const double s)
      {
        using AD  = Sacado::Fad::SFad<double, 8>;
        using AD2 = Sacado::Fad::SFad<AD, 8>;
        H         = 0;
        g         = 0;
        FullMatrix<double> Hc(8, 8);
        for (unsigned int c = 0; c < quads.size(); ++c)
          {
            std::array<Tensor<1, 2, AD2>, 4> xc;
            for (unsigned int v = 0; v < 4; ++v)
              for (unsigned int d = 0; d < 2; ++d)
                {
                  const unsigned int j = 2 * v + d;
                  xc[v][d]             = AD2(8, j, AD(8, j, x[quads[c][v]][d]));
                }
            AD2 e = quad_energy(xc, W_inverse[c], weight[c], s);
            if (floor_mu > 0)
              e += floor_energy(xc, cos_floor, floor_mu * weight[c]);
            for (unsigned int i = 0; i < 8; ++i)
              {
                g(2 * quads[c][i / 2] + i % 2) += e.dx(i).val();
                for (unsigned int j = 0; j < 8; ++j)
                  Hc(i, j) = e.dx(i).dx(j);
              }
            project_to_psd(Hc, "quad mesh optimization");
            for (unsigned int i = 0; i < 8; ++i)
              for (unsigned int j = 0; j < 8; ++j)
                H.add(2 * quads[c][i / 2] + i % 2,
                      2 * quads[c][j / 2] + j % 2,
                      Hc(i, j));
          }
        double deviation = 0;
        for (unsigned int v = 0; v < x.size(); ++v)
          if (on_boundary[v])
            {
              for (unsigned int d = 0; d < 2; ++d)
                {
                  g(2 * v + d) += 2 * boundary_scale * (x[v][d] - y[v][d]);
                  H.add(2 * v + d, 2 * v + d, 2 * boundary_scale);
                }
              deviation = std::max(
                deviation,
                closest_on_segments(x[v], boundary, slide[v]).distance(x[v]));
            }
        // A tiny shift keeps the system definite where the projected
        // Hessian of a free mesh is only semidefinite.
        double diagonal = 0;
        for (unsigned int i = 0; i < H.m(); ++i)
          diagonal = std::max(diagonal, H.diag_element(i));
        for (unsigned int i = 0; i < H.m(); ++i)
          H.add(i, i, 1e-10 * diagonal);
        return deviation;
      }



      /// Backtracking along dx until the energy decreases enough without a
      /// folded quad; `trial` holds the accepted positions.
      bool
      RhombicMeshOptimizer::line_search(const double           s,
                                        std::vector<Point<2>> &trial,
                                        unsigned int          &halvings) const
      {
        double       distortion = 0;
        const double E0         = total_energy(x, s, distortion);
        AssertThrow(std::isfinite(E0),
                    ExcMessage("quad mesh optimization: the distortion "
                               "energy overflows at s = " +
                               std::to_string(s) +
                               " (a quad far from its rhombus): use "
                               "smaller Quad mesh/Exponents."));
        const double slope = g * dx;
        double       t     = 1;
        trial.resize(x.size());
        for (halvings = 0; halvings < 40; ++halvings, t *= 0.5)
          {
            for (unsigned int v = 0; v < x.size(); ++v)
              trial[v] = x[v] + t * Tensor<1, 2>({dx(2 * v), dx(2 * v + 1)});
            double d_trial = 0;
            if (total_energy(trial, s, d_trial) <= E0 + 1e-4 * t * slope)
              return true;
          }
        return false;
      }



      /// x = trial, with the boundary vertices put back onto the boundary
      /// unless that folds a quad (the penalty leaves them slightly off
      /// where distortion pulls hard, at large s); returns the largest move.
      double
      RhombicMeshOptimizer::accept(std::vector<Point<2>> &trial, const double s)
      {
        std::vector<Point<2>> projected = trial;
        for (unsigned int v = 0; v < x.size(); ++v)
          if (on_boundary[v] && !held[v])
            projected[v] = corner[v] ?
                             x_input[v] :
                             closest_on_segments(trial[v], boundary, slide[v]);
        double d_projected = 0;
        if (std::isfinite(total_energy(projected, s, d_projected)))
          trial.swap(projected);
        double max_move = 0;
        for (unsigned int v = 0; v < x.size(); ++v)
          max_move = std::max(max_move, trial[v].distance(x[v]));
        x.swap(trial);
        return max_move;
      }



      void
      RhombicMeshOptimizer::run_exponent(
        const double                           s,
        std::vector<QuadMeshOptimizationStep> &history)
      {
        std::vector<Point<2>> trial;
        for (unsigned int it = 0; it < prm.max_iterations; ++it)
          {
            AffineConstraints<double> sliding;
            local_step(sliding);
            // Global step: one projected Newton step on E(x; W, y).
            const double deviation = assemble_newton_system(s);
            dx                     = g;
            dx *= -1;
            sliding.condense(H, dx);
            SparseDirectUMFPACK solver;
            solver.initialize(H);
            solver.solve(dx);
            sliding.distribute(dx);

            unsigned int halvings   = 0;
            const bool   accepted   = line_search(s, trial, halvings);
            const double max_move   = accepted ? accept(trial, s) : 0.;
            double       distortion = 0;
            total_energy(x, s, distortion);
            history.push_back({s,
                               it,
                               distortion,
                               deviation / h,
                               max_move / h,
                               halvings,
                               floor_mu});
            if (!accepted || max_move <= prm.tolerance * h)
              break;
          }
      }



      bool
      RhombicMeshOptimizer::enforce_angle_floor(
        std::vector<QuadMeshOptimizationStep> &history)
      {
        if (!(prm.angle_floor > 0))
          return true;
        const double s          = prm.exponents.back();
        double       distortion = 0;
        floor_mu                = total_energy(x, s, distortion);
        const double target     = prm.angle_floor - prm.angle_floor_tolerance;
        for (unsigned int round = 0;
             round < prm.angle_floor_rounds && smallest_alpha() < target;
             ++round, floor_mu *= 10)
          run_exponent(s, history);
        return smallest_alpha() >= target;
      }



      double
      RhombicMeshOptimizer::boundary_deviation() const
      {
        double deviation = 0;
        for (unsigned int v = 0; v < x.size(); ++v)
          if (on_boundary[v])
            deviation = std::max(
              deviation,
              closest_on_segments(x[v], boundary, slide[v]).distance(x[v]) / h);
        return deviation;
      }



      void
      RhombicMeshOptimizer::write(Triangulation<2, 2> &tria) const
      {
        for (const auto &cell : tria.active_cell_iterators())
          for (unsigned int v = 0; v < 4; ++v)
            cell->vertex(v) = x[index[cell->vertex_index(v)]];
      }
    } // namespace



    QuadMeshOptimizationResult
    optimize_rhombic_mesh(Triangulation<2, 2>                  &tria,
                          const QuadMeshOptimizationParameters &prm,
                          const std::vector<bool>              &fixed)
    {
      AssertThrow(fixed.empty() || fixed.size() == tria.n_vertices(),
                  ExcMessage("quad mesh optimization: one flag per vertex"));
      AssertThrow(tria.n_levels() == 1,
                  ExcMessage("quad mesh optimization needs a mesh without "
                             "refinement levels (flatten it first)."));
      QuadMeshOptimizationResult result;
      result.before = quad_mesh_shape(tria);
      AssertThrow(result.before.min_scaled_jacobian > 0,
                  ExcMessage("quad mesh: the input has an inverted or "
                             "degenerate quad (a corner angle of 180 degrees "
                             "or more)."));
      AssertThrow(!prm.exponents.empty(),
                  ExcMessage("quad mesh optimization: give at least one "
                             "exponent s (Quad mesh/Exponents)."));
      RhombicMeshOptimizer optimizer(tria, prm, fixed);
      result.mean_edge = optimizer.mean_edge();
      for (const double s : prm.exponents)
        optimizer.run_exponent(s, result.history);
      result.angle_floor_met    = optimizer.enforce_angle_floor(result.history);
      result.boundary_deviation = optimizer.boundary_deviation();
      optimizer.write(tria);
      result.after = quad_mesh_shape(tria);
      return result;
    }
  } // namespace rhombic
} // namespace forma
