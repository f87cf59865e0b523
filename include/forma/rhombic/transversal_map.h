#ifndef forma_rhombic_transversal_map_h
#define forma_rhombic_transversal_map_h

#include <forma/microstructure/rhombic_structure.h>

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace forma
{
  class RunContext;

  namespace rhombic
  {
    struct Setup;

    /// The Map section's entries for the thesis's initial map.
    struct TransversalMapParameters
    {
      /// The redundant parameters and their values (V' in the thesis).
      std::array<std::optional<double>, RhombicStructure::n_parameters> fixed;
      /// The box sampled on V' and V (default: the sweep ranges).
      std::array<std::array<double, 2>, RhombicStructure::n_parameters> ranges =
        RhombicStructure::ranges();
      /// Samples per free parameter for the linear model on V'.
      unsigned int subspace_samples = 4;
      /// Samples per coordinate of the grid on V.
      unsigned int grid_samples = 6;

      /// Parse "p1 = 0.5, p2 = 0.25, p5 = 0.3" (errors name `entry`).
      static std::array<std::optional<double>, RhombicStructure::n_parameters>
      parse_fixed(const std::string &text, const std::string &entry);

      /// Parse "p7 = 0.05:0.15, p8 = 0.05:0.2": the sweep ranges with
      /// those replaced (each inside its sweep range).
      static std::array<std::array<double, 2>, RhombicStructure::n_parameters>
      parse_ranges(const std::string &text, const std::string &entry);
    };

    /**
     * The thesis's initial material-to-geometry map at one angle
     * (ch. 4.6.2): on V' (the `fixed` parameters at their values, the
     * others over `ranges`), H is sampled on a grid and V fitted
     * (fit_transversal_subspace(); origin: the mean of the tenth of the
     * samples nearest to a target's tensor); H' (the orthotropic moduli C1111,
     * C2222, C1122, C1212 / E_b) is sampled on a grid over V's
     * coordinates and inverted by simplices (SimplexInverse) at the
     * isotropic tensor of every (E, nu) target. Returns the parameters
     * per target, empty where the inversion does not reach it; records V
     * and the counts in the log and in the summary ("transversal").
     * Samples are shared among the ranks of the context's communicator.
     */
    std::vector<
      std::optional<std::array<double, RhombicStructure::n_parameters>>>
    transversal_initial_map(
      const TransversalMapParameters               &parameters,
      const std::vector<std::pair<double, double>> &targets,
      const RhombicStructure                       &structure,
      const Setup                                  &setup,
      RunContext                                   &context);
  } // namespace rhombic
} // namespace forma

#endif
