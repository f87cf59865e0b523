#ifndef forma_rhombic_coverage_polygon_h
#define forma_rhombic_coverage_polygon_h

#include <array>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /**
     * The convex region of (E, nu) that a material map serves at one angle
     * (thesis ch. 4.6.2, Fig. 4.13-4.14): at most six lines, two
     * horizontal (E_min, E_max), two vertical (nu_min, nu_max) and two
     * slanted ones s_l, s_r, each slanted line given by its nu at the
     * reference moduli E_0 and E_1 (the sample grid's ends), so that all
     * eight coefficients stay bounded and can be splined over the angle.
     */
    struct CoveragePolygon
    {
      static constexpr unsigned int n_coefficients = 8;

      double                E_min = 0, E_max = 0, nu_min = 0, nu_max = 0;
      std::array<double, 2> left  = {{0, 0}}; ///< nu of s_l at E_0, E_1
      std::array<double, 2> right = {{0, 0}}; ///< nu of s_r at E_0, E_1
      double                E_0 = 0, E_1 = 1;

      /// nu of s_l and s_r at E.
      double
      left_nu(const double E) const;
      double
      right_nu(const double E) const;

      /// The polygon's lines as c_E E + c_nu nu <= d, (c_E, c_nu) a unit
      /// vector; empty if the polygon is.
      std::vector<std::array<double, 3>>
      half_planes() const;

      /// The corners (nu, E), counterclockwise, the first repeated at the
      /// end (a closed outline to plot); empty if the polygon is.
      std::vector<std::array<double, 2>>
      outline() const;

      /// Area in units of the sample grid's extent (1: the whole grid).
      double
      area(const double nu_extent) const;

      std::array<double, n_coefficients>
      coefficients() const;

      static CoveragePolygon
      from_coefficients(const std::array<double, n_coefficients> &c,
                        const double                              E_0,
                        const double                              E_1);
    };

    /**
     * The polygon inscribed in the covered nodes of an (E, nu) grid with
     * the largest area plus `height_weight` times its top E (both relative
     * to the grid's extent), as the thesis builds it: per E row, the
     * covered run of nu values (the longest one) bounds the region; every
     * choice of E_min, E_max, nu_min, nu_max on the grid is tried, and the
     * slanted lines are the best ones that keep every row's boundary point
     * outside (a convex problem in the line: its optimum lies on a line
     * through one of the points, at the best feasible slope, at most twice
     * the grid diagonal's; none if no such line keeps the points). `covered[i *
     * nu.size() + j]` is node (E[i], nu[j]). Returns an empty polygon
     * (E_min > E_max) if no 2 x 2 block of nodes is covered.
     */
    CoveragePolygon
    fit_coverage_polygon(const std::vector<double> &E,
                         const std::vector<double> &nu,
                         const std::vector<bool>   &covered,
                         const double               height_weight);

    /**
     * The covered region as the union of `pieces` polygons stacked in E, a
     * generalization of the thesis's one polygon for coverages that are not
     * convex: a wide base at small E under a narrow stiff column, where one
     * polygon holds much of either but not both. With 1 piece it is
     * fit_coverage_polygon(); with 2 the grid's rows are split at one row
     * (both bands include it), each band gets its own polygon
     * (fit_coverage_polygon() on the band's nodes; `height_weight` for the
     * upper one), and the split with the largest sum of their areas (plus
     * `height_weight` times the top E) wins. Every piece is inscribed in
     * the covered nodes, so their union is; a piece may be empty.
     */
    std::vector<CoveragePolygon>
    fit_coverage_pieces(const std::vector<double> &E,
                        const std::vector<double> &nu,
                        const std::vector<bool>   &covered,
                        const double               height_weight,
                        const unsigned int         pieces);
  } // namespace rhombic
} // namespace forma

#endif
