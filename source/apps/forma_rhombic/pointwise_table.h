#ifndef forma_apps_forma_rhombic_pointwise_table_h
#define forma_apps_forma_rhombic_pointwise_table_h

#include <deal.II/base/parameter_handler.h>

#include <forma/microstructure/rhombic_structure.h>

#include <string>
#include <vector>

namespace forma
{
  class RunContext;

  namespace rhombic
  {
    struct Setup;

    /**
     * The thesis's pointwise-inverse-homogenization baseline (ch. 4.8,
     * Fig. 4.23, after Panetta et al. 2017): a table of structures, each
     * optimized on its own for one target (E, nu) from the same start, with
     * no relation to its neighbours (their joints p5 need not match); a
     * cell takes the entry whose homogenized (E, nu) is nearest to its
     * target.
     */
    struct PointwiseTable
    {
      struct Entry
      {
        double           target_E = 0, target_nu = 0; ///< E relative to E_b
        double           E = 0, nu = 0; ///< what the structure achieves
        double           misfit = 0;    ///< |C^H - C*| / |C*|
        RhombicStructure structure;
      };
      /// The entries that reached the tolerance.
      std::vector<Entry> entries;
      /// Poisson's ratio of the base material the table was built for.
      double base_nu = 0;

      /// The entry nearest to (E/E_b, nu) in the achieved moduli, each axis
      /// scaled by the table's span.
      const Entry &
      nearest(const double E, const double nu) const;

      /// A table written by pointwise_table_mode(); throws a clear error
      /// for a missing or malformed file.
      static PointwiseTable
      read(const std::string &file);
    };

    /// The table for the Pointwise table section's targets, each by
    /// inverse homogenization (Inverse section; start: Structure section),
    /// the targets spread over the MPI ranks -> pointwise_table.json.
    void
    pointwise_table_mode(dealii::ParameterHandler &prm,
                         const Setup              &setup,
                         RunContext               &context);
  } // namespace rhombic
} // namespace forma

#endif
