#ifndef forma_rhombic_redundant_parameters_h
#define forma_rhombic_redundant_parameters_h

#include <array>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /// One isotropic sample of a sweep: its 8 parameters and (nu, E/E_b).
    struct SweepPoint
    {
      std::array<double, 8> p;
      double                nu, E;
    };

    /// A parameter fixed at one of its sweep values, and the share of the
    /// isotropic coverage that the samples with all fixings so far keep.
    struct FixedParameter
    {
      unsigned int index; ///< 0-based: p1 is 0
      double       value;
      double       coverage;
      unsigned int samples;
    };

    /**
     * The redundant-parameter test of thesis ch. 4.6.2 (step 1, Fig. 4.9):
     * coverage is the number of occupied cells of a `bins` x `bins` grid
     * over the (nu, E) box of all isotropic samples. Greedily, the
     * parameter and sweep value whose slice (the samples so far with that
     * value) keeps the most coverage is fixed, while that share of the
     * full coverage stays at least `threshold`; parameters with a single
     * value in the samples left are not candidates. Returns the fixings in
     * order.
     */
    std::vector<FixedParameter>
    find_redundant_parameters(const std::vector<SweepPoint> &isotropic,
                              const unsigned int             bins,
                              const double                   threshold);

    /// Occupied cells of the grid of find_redundant_parameters() spanned
    /// by `box` (nu_min, nu_max, E_min, E_max).
    unsigned int
    occupied_cells(const std::vector<SweepPoint> &points,
                   const std::array<double, 4>   &box,
                   const unsigned int             bins);
  } // namespace rhombic
} // namespace forma

#endif
