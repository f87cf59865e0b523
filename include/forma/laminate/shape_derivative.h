#ifndef forma_laminate_shape_derivative_h
#define forma_laminate_shape_derivative_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/hexagonal_laminate.h>

#include <vector>

namespace forma
{
  namespace laminate
  {
    /**
     * Thesis ch. 5.5's objective J = 1/2 |S^H - S*|_F^2, S^H = (C^H)^-1 the
     * compliance and S* that of the isotropic target (E*, nu*) (2D moduli),
     * with dJ = derivative(C) :: dC^H (dS = -S : dC : S).
     */
    struct ComplianceMisfit
    {
      ComplianceMisfit(const double E_star, const double nu_star);

      double
      value(const dealii::SymmetricTensor<4, 2> &C) const;

      dealii::SymmetricTensor<4, 2>
      derivative(const dealii::SymmetricTensor<4, 2> &C) const;

      dealii::SymmetricTensor<4, 2> S_star;
    };

    /**
     * The shape derivative of J on a conforming mesh with respect to the
     * positions of the vertices on the solid-void interface (thesis ch. 5.5,
     * Table 5.1: "with respect to positions of all points on the shape
     * boundary"), the exact derivative of the discrete J
     * (PeriodicHomogenization::vertex_shape_gradient()). Vertices on the
     * cell's box stay out (the box is fixed).
     */
    struct InterfaceShapeDerivative
    {
      dealii::SymmetricTensor<4, 2>     C;
      double                            J = 0;
      std::vector<unsigned int>         vertices; ///< triangulation indices
      std::vector<dealii::Point<2>>     points;
      std::vector<dealii::Tensor<1, 2>> derivative;  ///< dJ/dX per vertex
      double                            norm    = 0; ///< |dJ/dX|_2
      unsigned int                      n_cells = 0;
    };

    /// The structure's polygons meshed by Gmsh with periodic sides
    /// (triangles of `size`; material id 0 the void, k + 1 phase k).
    void
    conforming_mesh(const HexagonalLaminate     &structure,
                    const double                 size,
                    dealii::Triangulation<2, 2> &mesh,
                    const MPI_Comm               comm = MPI_COMM_SELF);

    /// On `mesh` (material id 0 the void, k + 1 phase k of `phases`).
    InterfaceShapeDerivative
    interface_shape_derivative(
      const dealii::Triangulation<2, 2>                 &mesh,
      const std::vector<dealii::SymmetricTensor<4, 2>>  &phases,
      const dealii::SymmetricTensor<4, 2>               &void_tensor,
      const PeriodicHomogenization<2>::SolverParameters &solver,
      const unsigned int                                 degree,
      const ComplianceMisfit                            &misfit);

    /// The share of |dJ/dX|^2 carried by vertices within `radius` of a
    /// corner of the structure (a polygon vertex not inside another
    /// polygon; the thesis: "almost entirely close to sharp corners").
    double
    corner_share(const InterfaceShapeDerivative &d,
                 const HexagonalLaminate        &structure,
                 const double                    radius);
  } // namespace laminate
} // namespace forma

#endif
