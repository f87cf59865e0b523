// What 2D and 3D boundary resampling share: the refusal of a result that
// changes a region's size (area or volume) by more than allowed.
#ifndef forma_source_mesh_resampling_check_h
#define forma_source_mesh_resampling_check_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/types.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>

namespace forma
{
  namespace internal
  {
    /// Three significant digits.
    inline std::string
    fmt3(const double x)
    {
      std::ostringstream s;
      s.precision(3);
      s << x;
      return s.str();
    }

    /// Throws if a region's `measure` ("area", "volume") changes from
    /// `before` to `after` by more than `max_change` (relative); `hint`
    /// ends the message.
    inline void
    check_region_change(
      const std::map<dealii::types::material_id, double> &before,
      const std::map<dealii::types::material_id, double> &after,
      const double                                        max_change,
      const std::string                                  &measure,
      const std::string                                  &hint)
    {
      for (const auto &[m, size] : before)
        {
          const auto   it     = after.find(m);
          const double change = it == after.end() ?
                                  1. :
                                  std::abs(it->second - size) / std::abs(size);
          AssertThrow(change <= max_change,
                      dealii::ExcMessage("boundary resampling: the " + measure +
                                         " of material " + std::to_string(m) +
                                         " would change by " +
                                         fmt3(100 * change) + "% (more than " +
                                         fmt3(100 * max_change) + "%); " +
                                         hint));
        }
    }
  } // namespace internal
} // namespace forma

#endif
