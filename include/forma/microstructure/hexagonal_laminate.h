#ifndef forma_microstructure_hexagonal_laminate_h
#define forma_microstructure_hexagonal_laminate_h

#include <forma/microstructure/raster.h>

#include <array>
#include <string>
#include <vector>

namespace forma
{
  /**
   * The Triangle and Hexagon laminate structures of thesis ch. 5.3
   * (Fig. 5.4): solid regular tiles (triangles or hexagons) scaled by p1
   * about their centers, joined across every tile edge by a rectangular
   * laminate area as wide as the scaled edge. Every structure is invariant
   * under rotations by pi/3 about the lattice points and by pi about the
   * joint centers, so its homogenized tensor is isotropic (reflections are
   * not needed, so the beams may be chiral).
   *
   * The periodic cell is the rectangle [0, sqrt(3)] x [0, 1] holding two
   * hexagonal base cells (Fig. 5.5C); the rotation centers form the
   * triangular lattice spanned by (0, 1) and (sqrt(3)/2, 1/2).
   *
   * Finite structures (4 parameters, each relative to the previous one):
   *  - p1 in (0, 1): tile size (fraction of the tiling);
   *  - p2 in [0, 1]: chirality: a beam crosses the joint shifted sideways
   *    by p2 times the joint width (p2 = 1: along the joint's diagonal),
   *    i.e. tan(alpha) = p2 * width / length;
   *  - p3 in (0, 1]: beam period as a fraction of the joint width; if
   *    1/p3 is not an integer the remainder forms a thinner beam at the
   *    sides of the joint;
   *  - p4 in (0, 1]: beam width as a fraction of its period.
   * The beams are a laminate of period p3 * width cut out of the joint, so
   * every cross-section holds the fraction p4 and the volume fraction is
   * exactly phi = p1^2 + 2 p4 p1 (1 - p1) (eq. 5.11).
   *
   * Limit (two-scale) structures (3 parameters p1, theta, alpha): each
   * joint is a rank-one laminate of strong fraction theta with layers at
   * angle alpha from the joint axis (eq. 5.9); phi = p1^2 + 2 theta p1
   * (1 - p1) (eq. 5.12).
   */
  struct HexagonalLaminate
  {
    enum class Family
    {
      triangle,
      hexagon
    };

    Family family = Family::hexagon;
    bool   limit  = false;
    double p1 = 0.5, p2 = 0, p3 = 0.2, p4 = 0.5;
    double theta = 0.5, alpha = 0; ///< limit structures; alpha in radians

    static constexpr double width  = 1.7320508075688772; // sqrt(3)
    static constexpr double height = 1;

    static Family
    family_from_string(const std::string &name);
    std::string
    family_name() const;

    /// The continuous parameters: (p1, p2, p4) for finite structures,
    /// (p1, theta, alpha) with alpha in radians for limit ones (p3 sets a
    /// beam count, so it is not one).
    static constexpr unsigned int n_continuous = 3;

    std::array<double, n_continuous>
    continuous_parameters() const;

    void
    set_continuous_parameters(const std::array<double, n_continuous> &q);

    /// Throw a clear error if a parameter is outside its range.
    void
    check() const;

    /// Eq. 5.11 (finite) or 5.12 (limit).
    double
    volume_fraction_formula() const;

    /// Angle of the beams (layers) to the joint axis, radians.
    double
    lamination_angle() const;

    /// Lamination angles below which a joint still connects its two tiles:
    /// atan(width / length) of the joint (p2 = 1); eq. 5.13.
    double
    critical_angle() const;

    /**
     * The smallest length a grid must resolve: the joint length (the gap
     * between tiles) and, for finite structures, the thickness of the
     * beams and of the gaps between them, measured across the beams
     * (p4 p3 W cos(alpha) and (1 - p4) p3 W cos(alpha) for joint width W
     * and lamination angle alpha; the remainder beam likewise). Chiral
     * beams get thin as alpha approaches the critical angle.
     */
    double
    min_feature_size() const;

    /// Axis angles of the three joint orientations (radians).
    std::vector<double>
    joint_axis_angles() const;

    /**
     * Solid polygons (phase 0: tiles and, for finite structures, beams)
     * and, for limit structures, the joint rectangles as phases 1..3 in the
     * order of joint_axis_angles(), including the periodic images that
     * overlap the cell.
     */
    std::vector<std::pair<ConvexPolygon, unsigned int>>
    polygons() const;

    /// Anti-aliased phase fractions on an nx x ny grid of the cell.
    PhaseRaster
    rasterize(const unsigned int nx, const unsigned int ny) const;
  };
} // namespace forma

#endif
