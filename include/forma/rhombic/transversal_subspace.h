#ifndef forma_rhombic_transversal_subspace_h
#define forma_rhombic_transversal_subspace_h

#include <optional>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /**
     * The transversal subspace V of thesis ch. 4.6.2 (step 2, "reduce to m
     * dimensions by PCA"): the homogenization map on the p' parameters
     * left free is approximated by a linear map, H(x) ~ Q x + h0 (least
     * squares over samples); the p' - m directions in which that model is
     * constant (the null space of Q, here from its SVD) are the rows of
     * W^T, and V = {x : W^T (x - origin) = 0} is the m-dimensional affine
     * subspace through `origin` perpendicular to them, on which the model
     * is one to one. Points of V are addressed by m of the p' coordinates
     * (`coordinates`); the others (`dependent`, those W^T depends on
     * most) follow from the constraint.
     */
    struct TransversalSubspace
    {
      /// Rows of W^T: orthonormal, p' entries each.
      std::vector<std::vector<double>> normals;
      std::vector<double>              origin;
      std::vector<unsigned int>        coordinates, dependent;
      /// Singular values of Q (outputs scaled to unit spread), descending:
      /// the m-th against the (m+1)-th says how well-defined V is.
      std::vector<double> singular_values;
      /// RMS residual of the linear model relative to the outputs' spread.
      double fit_residual = 0;

      /// The point of V with the given values of `coordinates`.
      std::vector<double>
      point(const std::vector<double> &coordinate_values) const;
    };

    /// Fit V to samples x (p' values each) with outputs h (m values each),
    /// through `origin`. Needs more samples than p' and m < p'.
    TransversalSubspace
    fit_transversal_subspace(const std::vector<std::vector<double>> &x,
                             const std::vector<std::vector<double>> &h,
                             const std::vector<double>              &origin);

    /**
     * The piecewise-linear inverse of a map from R^m to R^m sampled on a
     * regular grid (thesis ch. 4.6.2, "inverse of H' on the isotropic
     * subspace"): every grid cell is split into m! simplices (one per
     * ordering of the axes, Kuhn's split), simplices with a missing or
     * degenerate corner are dropped, and of the others only those whose
     * image has the predominant orientation are kept (the map need not be
     * injective everywhere). preimage(q) finds a kept simplex whose image
     * contains q and interpolates the grid points linearly.
     */
    class SimplexInverse
    {
    public:
      /// `axes`: the grid values along each of the m axes (increasing);
      /// `values`: the map at the grid points, the last axis running
      /// fastest; empty where it is not defined.
      SimplexInverse(
        const std::vector<std::vector<double>>                &axes,
        const std::vector<std::optional<std::vector<double>>> &values);

      /// The grid point x with map(x) = q by linear interpolation on the
      /// simplex containing q (the one with q deepest inside if several
      /// do); empty if no kept simplex does.
      std::optional<std::vector<double>>
      preimage(const std::vector<double> &q) const;

      unsigned int
      n_kept() const
      {
        return simplices.size();
      }

      /// Simplices dropped for the minority orientation.
      unsigned int
      n_flipped() const
      {
        return flipped;
      }

      /// Queries so far whose q lay strictly inside more than one kept
      /// simplex (the thesis observes none).
      unsigned int
      n_ambiguous() const
      {
        return ambiguous;
      }

    private:
      struct Simplex
      {
        /// Grid coordinates of the first corner and the edge vectors.
        std::vector<double> x0, dx;
        /// The image of the first corner and the inverse of the image's
        /// edge matrix (m x m, row-major).
        std::vector<double> h0, inverse;
      };

      unsigned int         dim;
      std::vector<Simplex> simplices;
      unsigned int         flipped   = 0;
      mutable unsigned int ambiguous = 0;
    };
  } // namespace rhombic
} // namespace forma

#endif
