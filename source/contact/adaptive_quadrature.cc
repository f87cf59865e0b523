#include <deal.II/base/exceptions.h>
#include <deal.II/base/quadrature_lib.h>

#include <forma/contact/adaptive_quadrature.h>

#include <array>
#include <cmath>

namespace forma
{
  namespace contact
  {
    using namespace dealii;

    int
    contact_regime(const double gap,
                   const double slip,
                   const double eta,
                   const double eta_n,
                   const bool   friction)
    {
      const int g = gap <= -eta ? 0 : (gap >= eta ? 2 : 1);
      if (!friction || g == 0)
        return g;
      return g + 3 * (slip >= eta_n ? 1 : 0);
    }

    namespace
    {
      // An affine piece of the reference face: x = origin + sum_k xi_k e_k
      // over the reference segment, triangle or square.
      template <int d>
      struct Piece
      {
        Point<d>                    origin;
        std::array<Tensor<1, d>, d> e;
      };

      template <int d>
      Point<d>
      map(const Piece<d> &p, const Point<d> &xi)
      {
        Point<d> x = p.origin;
        for (unsigned int k = 0; k < d; ++k)
          x += xi[k] * p.e[k];
        return x;
      }

      template <int d>
      double
      measure_factor(const Piece<d> &p)
      {
        Tensor<2, d> J;
        for (unsigned int k = 0; k < d; ++k)
          for (unsigned int c = 0; c < d; ++c)
            J[c][k] = p.e[k][c];
        return std::abs(determinant(J));
      }

      // The 2^d (segment, square) or 4 (triangle) children of a piece.
      template <int d>
      std::vector<Piece<d>>
      children(const Piece<d> &p, const bool simplex)
      {
        std::vector<Piece<d>> c;
        Piece<d>              half = p;
        for (unsigned int k = 0; k < d; ++k)
          half.e[k] = p.e[k] / 2.;
        if constexpr (d == 2)
          if (simplex)
            {
              c.assign(4, half);
              c[1].origin = p.origin + half.e[0];
              c[2].origin = p.origin + half.e[1];
              // The middle one, turned: origin at the midpoint of the
              // hypotenuse, edges back to the other two midpoints.
              c[3].origin = p.origin + half.e[0] + half.e[1];
              c[3].e[0]   = -half.e[0];
              c[3].e[1]   = -half.e[1];
              return c;
            }
        for (unsigned int m = 0; m < (1u << d); ++m)
          {
            Piece<d> q = half;
            for (unsigned int k = 0; k < d; ++k)
              if (m & (1u << k))
                q.origin += half.e[k];
            c.push_back(q);
          }
        return c;
      }

      // Evenly spread sample points of the reference piece, corners
      // included.
      template <int d>
      std::vector<Point<d>>
      sample_points(const unsigned int n, const bool simplex)
      {
        std::vector<Point<d>> s;
        const unsigned int    m = std::max(n, 2u);
        if constexpr (d == 1)
          for (unsigned int i = 0; i < m; ++i)
            s.emplace_back(double(i) / (m - 1));
        else
          for (unsigned int i = 0; i < m; ++i)
            for (unsigned int j = 0; j < m; ++j)
              if (!simplex || i + j < m)
                s.emplace_back(double(i) / (m - 1), double(j) / (m - 1));
        return s;
      }

      // Gauss rule of n points per direction on the reference piece.
      template <int d>
      Quadrature<d>
      reference_rule(const unsigned int n, const bool simplex)
      {
        if constexpr (d == 2)
          if (simplex)
            {
              // Collapsed square: xi = (u (1 - v), v), weight (1 - v).
              const QGauss<1>       g(n);
              std::vector<Point<2>> x;
              std::vector<double>   w;
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < n; ++j)
                  {
                    const double u = g.point(i)[0], v = g.point(j)[0];
                    x.emplace_back(u * (1 - v), v);
                    w.push_back(g.weight(i) * g.weight(j) * (1 - v));
                  }
              return Quadrature<2>(x, w);
            }
        return QGauss<d>(n);
      }
    } // namespace



    template <int face_dim>
    Quadrature<face_dim>
    adaptive_quadrature(const bool                                simplex,
                        const std::function<std::vector<int>(
                          const std::vector<Point<face_dim>> &)> &regime,
                        const unsigned int                        n_gauss,
                        const unsigned int                        max_depth,
                        const unsigned int                        samples)
    {
      AssertThrow(!simplex || face_dim == 2, ExcInternalError());
      const auto reference = reference_rule<face_dim>(n_gauss, simplex);
      const auto sample    = sample_points<face_dim>(samples, simplex);
      std::vector<Point<face_dim>> points;
      std::vector<double>          weights;

      Piece<face_dim> root;
      for (unsigned int k = 0; k < face_dim; ++k)
        root.e[k][k] = 1.;
      std::vector<std::pair<Piece<face_dim>, unsigned int>> stack = {{root, 0}};
      while (!stack.empty())
        {
          const auto [piece, depth] = stack.back();
          stack.pop_back();
          bool uniform = true;
          if (depth < max_depth)
            {
              std::vector<Point<face_dim>> x;
              for (const auto &s : sample)
                x.push_back(map(piece, s));
              const auto codes = regime(x);
              for (const int c : codes)
                uniform &= c == codes[0];
            }
          if (!uniform)
            {
              for (const auto &c : children(piece, simplex))
                stack.emplace_back(c, depth + 1);
              continue;
            }
          const double factor = measure_factor(piece);
          for (unsigned int q = 0; q < reference.size(); ++q)
            {
              points.push_back(map(piece, reference.point(q)));
              weights.push_back(reference.weight(q) * factor);
            }
        }
      return Quadrature<face_dim>(points, weights);
    }

    template Quadrature<1>
    adaptive_quadrature<1>(
      const bool,
      const std::function<std::vector<int>(const std::vector<Point<1>> &)> &,
      const unsigned int,
      const unsigned int,
      const unsigned int);
    template Quadrature<2>
    adaptive_quadrature<2>(
      const bool,
      const std::function<std::vector<int>(const std::vector<Point<2>> &)> &,
      const unsigned int,
      const unsigned int,
      const unsigned int);
  } // namespace contact
} // namespace forma
