#ifndef forma_rhombic_material_map_h
#define forma_rhombic_material_map_h

#include <forma/microstructure/rhombic_structure.h>
#include <forma/rhombic/coverage_polygon.h>
#include <forma/rhombic/coverage_region.h>

#include <nlohmann/json.hpp>

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /**
     * A smooth function on a box in R^d as a tensor-product uniform cubic
     * B-spline, fitted to scattered samples by least squares with a
     * second-difference penalty on the control net (the "Laplacian
     * regularization" of thesis ch. 4.6.2-4.6.3, as in P-splines): the
     * penalty makes the fit smooth and fills the control points no sample
     * reaches.
     */
    class TensorSpline
    {
    public:
      TensorSpline() = default;

      /// n[k] >= 4 control points along [lower[k], upper[k]], uniform in
      /// x[k], or in log x[k] where `logarithmic[k]` (bounds > 0; empty:
      /// none): a quantity spanning decades (E/E_b 0.01-0.3) gets as many
      /// control points per decade at its small end as at its large one.
      TensorSpline(const std::vector<double>       &lower,
                   const std::vector<double>       &upper,
                   const std::vector<unsigned int> &n,
                   const std::vector<bool>         &logarithmic = {});

      /// Least squares on (x_s, y_s) plus `smoothing` times the squared
      /// second differences of the control values.
      void
      fit(const std::vector<std::vector<double>> &x,
          const std::vector<double>              &y,
          const double                            smoothing);

      double
      value(const std::vector<double> &x) const;

      nlohmann::json
      to_json() const;

      static TensorSpline
      from_json(const nlohmann::json &j);

      unsigned int
      n_coefficients() const
      {
        return coefficients.size();
      }

      /// Whether direction k is uniform in log x (false for a spline not
      /// set up yet, e.g. a build's progress map).
      bool
      is_logarithmic(const unsigned int k) const
      {
        return k < logarithmic.size() && logarithmic[k];
      }

    private:
      /// Nonzero basis functions at x along direction k: first index and
      /// the 4 values (x clamped to the box).
      std::pair<int, std::array<double, 4>>
      basis(const unsigned int k, const double x) const;

      std::vector<double>       lower, upper;
      std::vector<unsigned int> n;
      std::vector<bool>         logarithmic;
      std::vector<double>       coefficients;
    };

    /**
     * The material-to-geometry map P(E, nu; alpha) (thesis ch. 4.6): the
     * 8 parameters of the rhombic family as splines over (E/E_b, nu, alpha
     * in degrees) for a base material with Poisson's ratio 0, and the
     * samples' coverage per angle (the (E, nu) grid nodes where the
     * construction reached its target). Other base materials by the CLM
     * transform (eq. 4.11).
     */
    struct MaterialMap
    {
      std::array<TensorSpline, RhombicStructure::n_parameters> parameters;
      /// Grid of the construction: E/E_b values, nu values, angles.
      std::vector<double> E, nu, angles;
      /// covered[a][i * nu.size() + j]: sample (E[i], nu[j]) at angles[a].
      std::vector<std::vector<bool>> covered;
      double                         blending = 0.01;
      /// The samples the splines were fitted to: E, nu, angle, p1..p8.
      std::vector<std::array<double, 11>> samples;
      /**
       * The coverage polygons, per piece of the covered region (1, or 2
       * stacked in E: fit_coverage_pieces()) at each angle (empty where
       * fewer than 2 x 2 nodes are covered), and each piece's 8
       * coefficients over the angles from the largest down to the last one
       * with a polygon (increasing), as 1D splines: monotone piecewise
       * cubics (PCHIP), since a polygon can change abruptly from one angle
       * to the next and a fitted cubic would overshoot both.
       */
      struct PolygonSplines
      {
        std::vector<double>                                              angles;
        std::array<std::vector<double>, CoveragePolygon::n_coefficients> values;
        std::array<double, 2> range = {{1, 0}}; ///< empty if lo > hi
      };
      unsigned int                              coverage_pieces = 1;
      std::vector<std::vector<CoveragePolygon>> polygons; ///< [piece][angle]
      std::vector<PolygonSplines>               polygon_splines; ///< per piece
      /// Whether the polygons live in (log E/E_b, nu) rather than (E/E_b,
      /// nu): their E_min, E_max and reference moduli are then logs
      /// (coverage_coordinate()). CoverageRegion says why.
      bool log_coverage = false;
      /// The settings that decided a build's samples ("Section/Entry" ->
      /// value; empty for maps built before they were recorded): a resumed
      /// build checks them.
      nlohmann::json build_settings = nlohmann::json::object();

      /// The polygons' coordinate of the modulus E/E_b: E or log E.
      double
      coverage_coordinate(const double E_relative) const;

      /**
       * Fit the coverage polygons to `covered` (fit_coverage_pieces() per
       * angle over the grid's coverage_coordinate() with coverage_pieces,
       * `height_weight` as there) and spline their coefficients.
       */
      void
      fit_coverage_polygons(const double height_weight = 0);

      /**
       * Drop the samples that lie on another branch of solutions than
       * their neighbours (an inverse solve that converged elsewhere): those
       * whose parameters differ from the median of their neighbours' (the
       * grid nodes next to theirs at the same angle, and the same node at
       * the neighbouring angles; at least 3 of them) by more than
       * `tolerance` in some parameter. A single such sample makes the
       * fitted splines swing for several grid cells around it. Their nodes
       * become uncovered. Returns how many were dropped.
       */
      unsigned int
      drop_branch_jumps(const double tolerance);

      /// Only the splines, from the polygons as they are (a map read).
      void
      fit_polygon_splines();

      /**
       * The structure for (E, nu) relative to a base of Poisson's ratio
       * `base_nu` (E relative to the base's modulus) at `alpha_degrees`.
       * `inside` tells whether the point lies in the covered region
       * (coverage()). The node positions p1..p4 are clamped to the
       * samples' range, which the splines can overshoot near the coverage's
       * edges; the radii only a little inside the geometry's limits.
       */
      RhombicStructure
      query(const double E,
            const double nu,
            const double alpha_degrees,
            const double base_nu,
            bool        &inside) const;

      using HalfPlane = rhombic::HalfPlane;

      /// A piece's coverage polygon at `alpha_degrees` (for a base with nu =
      /// 0): its 8 coefficients from the angle's splines; empty outside the
      /// piece's angles.
      CoveragePolygon
      coverage_polygon(const double       alpha_degrees,
                       const unsigned int piece = 0) const;

      /**
       * The covered region D(alpha) for a base of Poisson's ratio `base_nu`
       * (thesis ch. 4.6.2-4.6.3): the pieces' coverage_polygon() on the
       * map's coverage axis, sheared by eq. 4.11 (empty outside the
       * polygons' angles). It is C^1 in alpha, its coefficients between those
       * of the neighbouring construction angles, and at those angles inscribed
       * in the covered nodes. query()'s `inside` is membership in this region.
       */
      CoverageRegion
      coverage(const double alpha_degrees, const double base_nu) const;

      /// The smallest and largest angle (degrees) with a covered region
      /// D(alpha) (coverage() is empty outside); throws if the map covers
      /// none.
      std::array<double, 2>
      covered_angles() const;

      void
      write(const std::string &file_name) const;

      /**
       * Parameter surfaces (Fig. 4.17) at one angle (degrees), PNG, SVG or
       * PDF by the file name, with their numbers in a CSV beside it: p1..p4
       * in the top row, p5..p8 below; nu along x, E up over the map's grid;
       * blue (low) to red (high) over each parameter's range (written under
       * it), gray outside the coverage.
       */
      void
      write_parameter_surfaces(const std::string &file_name,
                               const double       angle) const;

      /// The covered grid nodes and the coverage polygons D(alpha) of each
      /// construction angle (of those in `only`, if given: a map of many
      /// angles is unreadable in one plot) in the (nu, E/E_b) plane (Fig.
      /// 4.14), with the plotted numbers beside it (write_xy_plot()).
      void
      write_coverage_plot(const std::string         &file_name,
                          const std::vector<double> &only = {}) const;

      /**
       * A map written by write(). `with_splines` false reads a build's
       * progress file (grid, coverage and samples; its splines are not fitted
       * yet): the map can be extended, not queried.
       */
      static MaterialMap
      read(const std::string &file_name, const bool with_splines = true);

      /// The same from a stream (e.g. a file's text one rank read and
      /// broadcast); `file_name` names it in errors.
      static MaterialMap
      read(std::istream      &in,
           const std::string &file_name,
           const bool         with_splines = true);
    };

  } // namespace rhombic
} // namespace forma

#endif
