#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>

#include <forma/microstructure/hexagonal_laminate.h>

#include "laminate_polygons.h"

#include <cmath>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // The beam pattern across a joint (period = its width): slot centers
    // and widths as fractions of the width, symmetric about the center;
    // 1/p3 slots of width p3 and a remainder slot at the sides.
    std::vector<std::pair<double, double>>
    beam_slots(const double p3)
    {
      std::vector<std::pair<double, double>> slots;
      const unsigned int n = static_cast<unsigned int>(1 / p3 + 1e-9);
      const double       r = 1 - n * p3;
      for (unsigned int k = 0; k < n; ++k)
        slots.emplace_back(-0.5 + r / 2 + (k + 0.5) * p3, p3);
      if (r > 1e-9)
        slots.emplace_back(0.5, r);
      return slots;
    }

    Tensor<1, 2>
    direction(const double angle)
    {
      return Tensor<1, 2>({std::cos(angle), std::sin(angle)});
    }

    struct Tile
    {
      Point<2>              center;
      std::vector<Point<2>> vertices; // counterclockwise
    };

    // The tiles whose scaled copies and joints can reach into the cell.
    std::vector<Tile>
    tiles(const HexagonalLaminate::Family family)
    {
      const Tensor<1, 2> u({0., 1.}), v({std::sqrt(3.) / 2, 0.5});
      const Tensor<1, 2> w = v - u;
      std::vector<Tile>  result;
      for (int j = -3; j <= 5; ++j)
        for (int i = -5; i <= 5; ++i)
          {
            const Point<2> c = Point<2>() + i * u + j * v;
            if (c[0] < -1.5 || c[0] > HexagonalLaminate::width + 1.5 ||
                c[1] < -1.5 || c[1] > HexagonalLaminate::height + 1.5)
              continue;
            if (family == HexagonalLaminate::Family::hexagon)
              {
                Tile t{c, {}};
                for (unsigned int m = 0; m < 6; ++m)
                  t.vertices.push_back(c + direction(m * numbers::PI / 3) /
                                             std::sqrt(3.));
                result.push_back(t);
              }
            else
              {
                // The two triangles of the lattice parallelogram at c.
                for (const auto &tri : {std::vector<Point<2>>{c, c + v, c + u},
                                        std::vector<Point<2>>{c, c + w, c + v}})
                  result.push_back(
                    {Point<2>((tri[0] + tri[1] + tri[2]) / 3.), tri});
              }
          }
      return result;
    }
  } // namespace



  HexagonalLaminate::Family
  HexagonalLaminate::family_from_string(const std::string &name)
  {
    if (name == "hexagon")
      return Family::hexagon;
    if (name == "triangle")
      return Family::triangle;
    AssertThrow(false,
                ExcMessage("unknown structure family '" + name +
                           "' (triangle | hexagon)"));
    return Family::hexagon;
  }



  std::string
  HexagonalLaminate::family_name() const
  {
    return family == Family::hexagon ? "hexagon" : "triangle";
  }



  void
  HexagonalLaminate::check() const
  {
    auto in = [](const std::string &name,
                 const double       value,
                 const double       lo,
                 const double       hi,
                 const bool         open_lo,
                 const bool         open_hi) {
      const bool ok = (open_lo ? value > lo : value >= lo) &&
                      (open_hi ? value < hi : value <= hi);
      AssertThrow(ok,
                  ExcMessage("structure parameter " + name + " = " +
                             std::to_string(value) + " is outside " +
                             (open_lo ? "(" : "[") + std::to_string(lo) + ", " +
                             std::to_string(hi) + (open_hi ? ")" : "]")));
    };
    in("p1", p1, 0, 1, true, true);
    if (limit)
      {
        in("theta", theta, 0, 1, false, false);
        in("alpha", alpha, -numbers::PI / 2, numbers::PI / 2, true, true);
      }
    else
      {
        in("p2", p2, 0, 1, false, false);
        in("p3", p3, 0, 1, true, false);
        in("p4", p4, 0, 1, true, false);
        AssertThrow(1 / p3 <= 1000,
                    ExcMessage(
                      "structure parameter p3 = " + std::to_string(p3) +
                      " asks for more than 1000 beams per joint; "
                      "use a limit structure instead"));
      }
  }



  double
  HexagonalLaminate::volume_fraction_formula() const
  {
    return p1 * p1 + 2 * (limit ? theta : p4) * p1 * (1 - p1);
  }



  double
  HexagonalLaminate::critical_angle() const
  {
    // Joint width / length: hexagon (p1/sqrt3) / (1 - p1), triangle
    // p1 / ((1 - p1)/sqrt3).
    const double ratio = family == Family::hexagon ?
                           p1 / (std::sqrt(3.) * (1 - p1)) :
                           std::sqrt(3.) * p1 / (1 - p1);
    return std::atan(ratio);
  }



  double
  HexagonalLaminate::lamination_angle() const
  {
    return limit ? alpha : std::atan(p2 * std::tan(critical_angle()));
  }



  double
  HexagonalLaminate::min_feature_size() const
  {
    // Joint width W = p1 * tile edge, length L = 2 * apothem * (1 - p1):
    // hexagon edge 1/sqrt(3), apothem 1/2; triangle edge 1, apothem
    // 1/(2 sqrt(3)) (see critical_angle()).
    const bool   hexagon = family == Family::hexagon;
    const double W       = p1 * (hexagon ? 1 / std::sqrt(3.) : 1.);
    const double L       = (1 - p1) * (hexagon ? 1. : 1 / std::sqrt(3.));
    double       size    = L;
    if (!limit)
      {
        const double across = W * std::cos(lamination_angle());
        for (const auto &slot : beam_slots(p3))
          {
            size = std::min(size, p4 * slot.second * across);
            if (p4 < 1)
              size = std::min(size, (1 - p4) * slot.second * across);
          }
      }
    else
      size = std::min(size, W);
    return size;
  }



  std::vector<double>
  HexagonalLaminate::joint_axis_angles() const
  {
    const double d = numbers::PI / 180;
    if (family == Family::hexagon)
      return {30 * d, 90 * d, -30 * d};
    return {0., 60 * d, -60 * d};
  }



  std::array<double, HexagonalLaminate::n_continuous>
  HexagonalLaminate::continuous_parameters() const
  {
    if (limit)
      return {{p1, theta, alpha}};
    return {{p1, p2, p4}};
  }



  void
  HexagonalLaminate::set_continuous_parameters(
    const std::array<double, n_continuous> &q)
  {
    p1                   = q[0];
    (limit ? theta : p2) = q[1];
    (limit ? alpha : p4) = q[2];
  }



  std::vector<std::pair<ConvexPolygon, unsigned int>>
  HexagonalLaminate::polygons() const
  {
    check();
    return internal::structure_polygons(*this, continuous_parameters());
  }



  namespace internal
  {
    template <typename Number>
    std::vector<std::pair<Polygon<Number>, unsigned int>>
    structure_polygons(
      const HexagonalLaminate                                   &s,
      const std::array<Number, HexagonalLaminate::n_continuous> &q)
    {
      using std::tan;
      using P          = Point<2, Number>;
      using T          = Tensor<1, 2, Number>;
      const Number &p1 = q[0];
      // The lamination angle (see lamination_angle(), critical_angle()).
      Number tan_a;
      if (s.limit)
        tan_a = tan(q[2]);
      else if (s.family == HexagonalLaminate::Family::hexagon)
        tan_a = q[1] * p1 / (std::sqrt(3.) * (1. - p1));
      else
        tan_a = q[1] * std::sqrt(3.) * p1 / (1. - p1);
      std::vector<std::pair<Polygon<Number>, unsigned int>> result;
      const std::vector<double> axes = s.joint_axis_angles();
      // The beams across a joint (none in limit structures).
      const std::vector<std::pair<double, double>> slots =
        s.limit ? std::vector<std::pair<double, double>>() : beam_slots(s.p3);
      auto point = [](const Point<2> &x) {
        return P(Number(x[0]), Number(x[1]));
      };
      auto vector = [](const Tensor<1, 2> &x) {
        T t;
        t[0] = x[0];
        t[1] = x[1];
        return t;
      };

      for (const Tile &tile : tiles(s.family))
        {
          Polygon<Number> solid;
          const P         center = point(tile.center);
          for (const auto &v : tile.vertices)
            solid.push_back(center + p1 * vector(v - tile.center));
          result.emplace_back(solid, 0);

          const unsigned int k = tile.vertices.size();
          for (unsigned int e = 0; e < k; ++e)
            {
              const Point<2> &a    = tile.vertices[e],
                             &b    = tile.vertices[(e + 1) % k];
              const Tensor<1, 2> t = (b - a) / (b - a).norm();
              const Tensor<1, 2> n({t[1], -t[0]}); // outward
              // Each joint once: from the tile whose normal points to the
              // half plane angle in (-90, 90] degrees.
              const double angle = std::atan2(n[1], n[0]);
              if (!(angle > -numbers::PI / 2 + 1e-6 &&
                    angle <= numbers::PI / 2 + 1e-6))
                continue;
              unsigned int orientation = 0;
              for (unsigned int o = 0; o < axes.size(); ++o)
                if (std::abs(axes[o] - angle) < 1e-6)
                  orientation = o;
              const double       r      = (0.5 * (a + b) - tile.center) * n;
              const Point<2>     middle = tile.center + r * n;
              const Number       L = 2 * r * (1. - p1), W = p1 * (b - a).norm();
              const Tensor<1, 2> y_axis({-n[1], n[0]});
              auto               global = [&](const P &x) {
                return point(middle) + x[0] * vector(n) + x[1] * vector(y_axis);
              };
              // Joint rectangle in local coordinates (x along the axis).
              const Number          hl = L / 2., hw = W / 2.;
              const Polygon<Number> local = {P(-hl, -hw),
                                             P(hl, -hw),
                                             P(hl, hw),
                                             P(-hl, hw)};
              auto to_global = [&](const Polygon<Number> &polygon) {
                Polygon<Number> g;
                for (const auto &x : polygon)
                  g.push_back(global(x));
                return g;
              };
              if (s.limit)
                {
                  result.emplace_back(to_global(local), 1 + orientation);
                  continue;
                }
              // Beams: stripes |y - x tan(alpha) - c| <= b/2 of the periodic
              // slot pattern, clipped to the joint.
              T up;
              up[0] = -tan_a;
              up[1] = 1;
              for (const auto &[slot_center, size] : slots)
                for (int shift = -2; shift <= 2; ++shift)
                  {
                    const Number    c    = (slot_center + shift) * W;
                    const Number    half = 0.5 * size * q[2] * W;
                    Polygon<Number> beam =
                      clip_polygon(local, P(Number(0), c + half), up);
                    beam = clip_polygon(beam, P(Number(0), c - half), -up);
                    if (!beam.empty() && value(polygon_area(beam)) > 1e-14)
                      result.emplace_back(to_global(beam), 0);
                  }
            }
        }
      return result;
    }



    template std::vector<std::pair<Polygon<double>, unsigned int>>
    structure_polygons(
      const HexagonalLaminate &,
      const std::array<double, HexagonalLaminate::n_continuous> &);
    template std::vector<
      std::pair<Polygon<Sacado::Fad::DFad<double>>, unsigned int>>
    structure_polygons(const HexagonalLaminate &,
                       const std::array<Sacado::Fad::DFad<double>,
                                        HexagonalLaminate::n_continuous> &);
  } // namespace internal



  PhaseRaster
  HexagonalLaminate::rasterize(const unsigned int nx,
                               const unsigned int ny) const
  {
    PhaseRaster raster(nx, ny, width, height, limit ? 4 : 1);
    for (const auto &[polygon, phase] : polygons())
      raster.add(polygon, phase);
    return raster;
  }
} // namespace forma
