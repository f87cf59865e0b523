#ifndef forma_base_outline_h
#define forma_base_outline_h

#include <array>
#include <string>
#include <vector>

namespace forma
{
  /**
   * @name Outlines for fabrication
   *
   * Closed polygons (outer boundaries and holes alike, the material between
   * them by the even-odd rule), one unit a millimetre, y up: e.g. a
   * microstructured object's outline for a laser cutter or a CAD program.
   * Written whole or not at all.
   */
  /** @{ */

  /// One SVG path (filled even-odd, stroke `stroke` mm wide), the page
  /// sized in mm.
  void
  write_polygons_svg(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const double                                           stroke);

  /// An ASCII DXF (R12, read by every CAD and cutter program): one closed
  /// POLYLINE per polygon on layer "outline"; coordinates in millimetres
  /// (R12 files do not say their unit: import them as mm).
  void
  write_polygons_dxf(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons);

  /** @} */
} // namespace forma

#endif
