#ifndef forma_rhombic_parameter_ranges_h
#define forma_rhombic_parameter_ranges_h

#include <forma/microstructure/rhombic_structure.h>

#include <array>
#include <optional>
#include <string>

namespace forma
{
  namespace rhombic
  {
    using ParameterRanges =
      std::array<std::array<double, 2>, RhombicStructure::n_parameters>;

    /// "p1 = a, p5 = b" -> the texts a, b at indices 0, 4 (errors name
    /// `entry`).
    std::array<std::optional<std::string>, RhombicStructure::n_parameters>
    parse_parameter_assignments(const std::string &text,
                                const std::string &entry);

    /// "p7 = 0.03:0.3, p8 = 0.03:0.3": `defaults` with those replaced,
    /// each an increasing range inside `within`.
    ParameterRanges
    parse_parameter_ranges(const std::string     &text,
                           const std::string     &entry,
                           const ParameterRanges &defaults,
                           const ParameterRanges &within);
  } // namespace rhombic
} // namespace forma

#endif
