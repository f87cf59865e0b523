#ifndef forma_rhombic_coverage_region_h
#define forma_rhombic_coverage_region_h

#include <forma/rhombic/half_plane_region.h>

#include <array>

namespace forma
{
  namespace rhombic
  {
    /**
     * The covered region D(alpha) of a material map at one angle, for one
     * base material (thesis ch. 4.6.2-4.6.3): a convex polygon, or the
     * union of a few (fit_coverage_pieces()), in the map's coverage
     * coordinates w = (x, nu - s E), with x = E/E_b on a linear
     * coverage axis and log(E/E_b) on a logarithmic one, and s the base's
     * Poisson's ratio (eq. 4.11 backwards). Materials m = (E/E_b, nu) go in
     * and come out; distances, the projection and the penalty are measured
     * in w, where on the logarithmic axis 0.01 along x is 1% in E. On the
     * linear axis the shear is folded into the half-planes, so there w is
     * (E/E_b, nu) itself.
     *
     * Why a logarithmic axis and pieces: a family's covered nodes over
     * E/E_b 0.01-0.3 form a wide base (auxetic to nu 0.7 at small E) under
     * a narrow stiff column; no convex polygon in (E, nu) holds much of
     * both, one in (log E, nu) holds more, and two stacked ones hold both.
     */
    class CoverageRegion
    {
    public:
      /// The empty region: covers nothing.
      CoverageRegion() = default;

      /// The union of `pieces`, each convex and nonempty, as half-planes
      /// in (x, nu - base_nu E), unit normals or not; pieces without
      /// half-planes are left out.
      CoverageRegion(const std::vector<HalfPlaneRegion> &pieces,
                     const bool                          logarithmic,
                     const double                        base_nu);

      bool
      empty() const
      {
        return convex_pieces.empty();
      }

      bool
      logarithmic() const
      {
        return log_E;
      }

      /// The convex pieces' half-planes in w, unit normals.
      const std::vector<HalfPlaneRegion> &
      pieces() const
      {
        return convex_pieces;
      }

      /// w of a material m = (E/E_b, nu).
      std::array<double, 2>
      coordinates(const std::array<double, 2> &m) const;

      /// The material at w.
      std::array<double, 2>
      material(const std::array<double, 2> &w) const;

      /// Over the pieces, the least of the largest signed distance in w of
      /// m past a piece's line (<= 0 inside); 0 for the empty region.
      double
      violation(const std::array<double, 2> &m) const;

      /// Whether m lies in the (nonempty) region, up to `tolerance` in w.
      bool
      contains(const std::array<double, 2> &m,
               const double                 tolerance = 1e-9) const;

      /// The material whose w is closest to m's in the region (exact: the
      /// nearest of the pieces' closest_point() in w); throws if the
      /// region is empty.
      std::array<double, 2>
      closest_point(const std::array<double, 2> &m) const;

      /**
       * The soft constraint of two-scale design: the sum over the violated
       * half-planes h of ((h.c . w - h.d) / tau)^2 (a distance in w in
       * units of tau, squared; C^1 for one piece), for the piece where it
       * is least (continuous, with kinks where the least piece changes).
       * Its gradient with respect to m is added to `gradient`.
       */
      double
      penalty(const std::array<double, 2> &m,
              const double                 tau,
              std::array<double, 2>       &gradient) const;

    private:
      std::vector<HalfPlaneRegion> convex_pieces;
      bool                         log_E = false;
      double                       shear = 0;
    };
  } // namespace rhombic
} // namespace forma

#endif
