#ifndef forma_rhombic_quad_mesh_optimization_h
#define forma_rhombic_quad_mesh_optimization_h

#include <deal.II/base/point.h>

#include <array>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
  template <int dim, int spacedim>
  class Triangulation;
} // namespace dealii

namespace forma
{
  namespace rhombic
  {
    /// The `Quad mesh` section's optimization entries (thesis ch. 4.7).
    struct QuadMeshOptimizationParameters
    {
      /// theta_m: target rhombi are not sharper than this (radians), the
      /// smallest angle the microstructure family covers.
      double min_angle = 0.25 * 3.141592653589793;
      /// Smallest fitted angle alpha after optimization (radians; 0: none).
      double angle_floor = 0;
      /// A penalty reaches the floor from below: alpha within this
      /// (radians, 0.006 degrees) of the floor counts as meeting it.
      static constexpr double angle_floor_tolerance = 1e-4;
      /// Rounds of the floor's penalty at most (mu up to 1e11 times the
      /// energy).
      static constexpr unsigned int angle_floor_rounds = 12;
      /// Continuation in s of the exponential energy (eq. 4.14).
      std::vector<double> exponents = {1, 4, 16};
      /// lambda of eq. 4.16 (weight of the boundary term against the
      /// distortion term, both normalized, see optimize_rhombic_mesh()).
      double boundary_weight = 1e4;
      /// Local/global iterations per exponent at most.
      unsigned int max_iterations = 100;
      /// Stop an exponent when no vertex moved more than this times the
      /// mean edge length in an iteration.
      double tolerance = 1e-3;

      static void
      declare(dealii::ParameterHandler &prm);
      void
      parse(dealii::ParameterHandler &prm);
    };

    /**
     * The rhombus that best fits a quad (thesis eq. 4.12-4.13). The quad's
     * vertices are in deal.II's order (v0, v1, v2, v3 at the reference
     * corners (0,0), (1,0), (0,1), (1,1)). The parallelogram T Q fitted by
     * least squares has edge vectors t1 (along v0 -> v1) and t2 (along
     * v0 -> v2) and the angle `angle` between them, at vertex 0.
     */
    struct RhombicFit
    {
      double angle = 0; ///< at vertex 0, in (0, pi)
      double alpha = 0; ///< the rhombus's smaller angle, min(angle, pi - angle)
      double area  = 0; ///< of the fitted parallelogram
      /// Sum of the distances of the quad's vertices to the corners of the
      /// closest rhombus (angle `angle`, best rotation, scale and
      /// translation; thesis ch. 4.8 "rhombic error").
      double error = 0;
    };

    RhombicFit
    fit_rhombus(const std::array<dealii::Point<2>, 4> &quad);

    /// Shape statistics of a quad mesh (per quad and summarized).
    struct QuadMeshShape
    {
      std::vector<double> alpha;          ///< per active cell, radians
      std::vector<double> rhombic_error;  ///< per cell, / sqrt(mean area)
      std::vector<double> smallest_angle; ///< smallest interior angle
      double              min_alpha = 0, mean_alpha = 0;
      double              min_interior_angle = 0;
      double              mean_error = 0, max_error = 0;
      /// |det J| ratio min/max over the corners (1 for parallelograms).
      double min_scaled_jacobian = 0;
    };

    QuadMeshShape
    quad_mesh_shape(const dealii::Triangulation<2, 2> &tria);

    struct QuadMeshOptimizationStep
    {
      double       exponent;
      unsigned int iteration;
      double       energy;    ///< the distortion term (eq. 4.14, normalized)
      double       deviation; ///< largest boundary distance / mean edge
      double       max_move;  ///< largest vertex move / mean edge
      unsigned int line_search_halvings;
      double       floor_weight = 0; ///< the angle floor's penalty (0: off)
    };

    struct QuadMeshOptimizationResult
    {
      /// Every quad's alpha at least the angle floor, to
      /// angle_floor_tolerance (true without a floor).
      bool                                  angle_floor_met = true;
      QuadMeshShape                         before, after;
      std::vector<QuadMeshOptimizationStep> history;
      /// Largest distance of a boundary vertex from the input boundary,
      /// relative to the mean edge length.
      double boundary_deviation = 0;
      double mean_edge          = 0;
    };

    /**
     * Move the vertices of a single-level quad mesh towards rhombic cells
     * (thesis ch. 4.7). Alternates a local step, which fits each quad's
     * target rhombus (eq. 4.12-4.13: angle capped at `min_angle`, the
     * quad's area) and projects the boundary vertices onto the input
     * boundary (closest point on its segments), with a global step: one
     * projected Newton step with an injectivity- and decrease-guarded line
     * search on
     *
     *   E(x) = sum_Q (A_Q / A) avg_g exp(s (D(J_Q,g) - 4))
     *          + lambda sum_{i in boundary} |x_i - y_i|^2 / (h^2 n_Q),
     *
     * D(J) = |J|^2 + |J^-1|^2 the symmetric Dirichlet energy of the map
     * from the target rhombus to the quad at the 2 x 2 Gauss points g (4 at
     * a rhombus, infinite as a cell folds), A the total area, h the mean
     * edge length and n_Q the number of quads; s runs through `exponents`
     * (continuation: the larger s, the closer to minimizing the largest
     * distortion). Vertices flagged in `fixed` (by vertex index; empty: none)
     * do not move. With an `angle_floor`, the continuation ends with
     * rounds at the last s that add mu sum_Q (A_Q / A) max(0, |cos phi_Q|
     * - cos(angle_floor))^2 (phi_Q the angle of the quad's least-squares
     * parallelogram), mu ten times larger each round, until every quad's
     * alpha reaches the floor (at most angle_floor_rounds;
     * `angle_floor_met` says whether it does). After each step the boundary
     * vertices are put back onto the input boundary (the penalty alone lets a
     * strongly distorted quad pull them off by a fraction of an edge); vertices
     * where the boundary turns by more than 40 degrees stay at their corner.
     * Throws (leaving `tria` unchanged) if the input has non-quad or inverted
     * cells or hanging vertices.
     */
    QuadMeshOptimizationResult
    optimize_rhombic_mesh(dealii::Triangulation<2, 2>          &tria,
                          const QuadMeshOptimizationParameters &parameters,
                          const std::vector<bool>              &fixed = {});
  } // namespace rhombic
} // namespace forma

#endif
