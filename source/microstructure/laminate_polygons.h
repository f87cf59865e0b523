#ifndef forma_source_microstructure_laminate_polygons_h
#define forma_source_microstructure_laminate_polygons_h

// HexagonalLaminate::polygons() as a function of the continuous parameters,
// for double or forward AD numbers (internal, not installed).

#include <forma/microstructure/hexagonal_laminate.h>

#include "polygon_raster.h"

#include <array>
#include <utility>
#include <vector>

namespace forma
{
  namespace internal
  {
    /// The polygons and phases of `structure` with its continuous
    /// parameters replaced by q (HexagonalLaminate::continuous_parameters()
    /// order); the vertices depend smoothly on q while no beam appears or
    /// vanishes. Instantiated for double and Sacado::Fad::DFad<double>.
    template <typename Number>
    std::vector<std::pair<Polygon<Number>, unsigned int>>
    structure_polygons(
      const HexagonalLaminate                                   &structure,
      const std::array<Number, HexagonalLaminate::n_continuous> &q);
  } // namespace internal
} // namespace forma

#endif
