// Thesis ch. 5.5 (Table 5.1): how far a structure's shape could still
// lower J = 1/2 |S^H - S*|^2 once its parameters are optimal, measured by
// the shape derivative with respect to every vertex on the solid-void
// interface of a conforming mesh.

#include <deal.II/grid/tria.h>

#include <forma/laminate/shape_derivative.h>
#include <forma/mesh/periodic_phase_mesh.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    ComplianceMisfit::ComplianceMisfit(const double E_star,
                                       const double nu_star)
      : S_star(
          invert(IsotropicModuli::from_young_poisson(E_star, nu_star).tensor()))
    {}



    double
    ComplianceMisfit::value(const SymmetricTensor<4, 2> &C) const
    {
      const SymmetricTensor<4, 2> D = invert(C) - S_star;
      return 0.5 * full_contraction(D, D);
    }



    SymmetricTensor<4, 2>
    ComplianceMisfit::derivative(const SymmetricTensor<4, 2> &C) const
    {
      // dJ = (S - S*) :: dS = -(S (S - S*) S) :: dC (S has major symmetry).
      const SymmetricTensor<4, 2> S = invert(C);
      return -(S * (S - S_star) * S);
    }



    void
    conforming_mesh(const HexagonalLaminate &structure,
                    const double             size,
                    Triangulation<2, 2>     &mesh,
                    const MPI_Comm           comm)
    {
      std::vector<std::pair<std::vector<Point<2>>, unsigned int>> polygons;
      for (const auto &p : structure.polygons())
        polygons.push_back(p);
      periodic_phase_mesh(polygons,
                          Point<2>(HexagonalLaminate::width,
                                   HexagonalLaminate::height),
                          size,
                          mesh,
                          comm);
    }



    InterfaceShapeDerivative
    interface_shape_derivative(
      const Triangulation<2, 2>                         &mesh,
      const std::vector<SymmetricTensor<4, 2>>          &phases,
      const SymmetricTensor<4, 2>                       &void_tensor,
      const PeriodicHomogenization<2>::SolverParameters &solver,
      const unsigned int                                 degree,
      const ComplianceMisfit                            &misfit)
    {
      PeriodicHomogenization<2> cell(MPI_COMM_SELF, mesh, solver, degree);
      InterfaceShapeDerivative  d;
      d.C = cell
              .homogenize([&](const Point<2> &, const types::material_id id) {
                AssertThrow(id <= phases.size(), ExcInternalError());
                return id == 0 ? void_tensor : phases[id - 1];
              })
              .C;
      d.J                               = misfit.value(d.C);
      d.n_cells                         = mesh.n_active_cells();
      const SymmetricTensor<4, 2> G     = misfit.derivative(d.C);
      const auto                  dC_dX = cell.vertex_shape_gradient();

      // Interface vertices: on a void and a solid cell, off the box.
      std::vector<unsigned char> touches(mesh.n_vertices(), 0);
      Point<2>                   lo(1e300, 1e300), hi(-1e300, -1e300);
      for (const auto &c : mesh.active_cell_iterators())
        for (const unsigned int v : c->vertex_indices())
          {
            touches[c->vertex_index(v)] |= c->material_id() == 0 ? 1 : 2;
            for (unsigned int k = 0; k < 2; ++k)
              lo[k] = std::min(lo[k], c->vertex(v)[k]),
              hi[k] = std::max(hi[k], c->vertex(v)[k]);
          }
      const double tol      = 1e-10 * (hi - lo).norm();
      const auto  &vertices = mesh.get_vertices();
      double       sum      = 0;
      for (unsigned int v = 0; v < vertices.size(); ++v)
        {
          const Point<2> &x = vertices[v];
          if (touches[v] != 3 || x[0] < lo[0] + tol || x[0] > hi[0] - tol ||
              x[1] < lo[1] + tol || x[1] > hi[1] - tol)
            continue;
          Tensor<1, 2> g;
          for (unsigned int k = 0; k < 2; ++k)
            g[k] = full_contraction(G, dC_dX[v][k]);
          d.vertices.push_back(v);
          d.points.push_back(x);
          d.derivative.push_back(g);
          sum += g.norm_square();
        }
      d.norm = std::sqrt(sum);
      return d;
    }



    namespace
    {
      // Whether x lies inside the convex polygon p, off its edges.
      bool
      strictly_inside(const std::vector<Point<2>> &p, const Point<2> &x)
      {
        int sign = 0;
        for (unsigned int i = 0; i < p.size(); ++i)
          {
            const Tensor<1, 2> e = p[(i + 1) % p.size()] - p[i];
            const Tensor<1, 2> r = x - p[i];
            const double       c = e[0] * r[1] - e[1] * r[0];
            if (std::abs(c) <= 1e-9 * e.norm())
              return false;
            const int s = c > 0 ? 1 : -1;
            if (sign != 0 && s != sign)
              return false;
            sign = s;
          }
        return true;
      }
    } // namespace



    double
    corner_share(const InterfaceShapeDerivative &d,
                 const HexagonalLaminate        &structure,
                 const double                    radius)
    {
      // The polygons' vertices that are corners of their union: a joint's
      // corner inside a tile is not one.
      const auto            polygons = structure.polygons();
      std::vector<Point<2>> corners;
      for (const auto &[polygon, phase] : polygons)
        for (const auto &c : polygon)
          if (std::none_of(polygons.begin(),
                           polygons.end(),
                           [&](const auto &other) {
                             return strictly_inside(other.first, c);
                           }))
            corners.push_back(c);
      double near = 0, all = 0;
      for (unsigned int i = 0; i < d.points.size(); ++i)
        {
          const double g2 = d.derivative[i].norm_square();
          all += g2;
          if (std::any_of(corners.begin(), corners.end(), [&](const auto &c) {
                return c.distance(d.points[i]) <= radius;
              }))
            near += g2;
        }
      return all > 0 ? near / all : 0;
    }
  } // namespace laminate
} // namespace forma
