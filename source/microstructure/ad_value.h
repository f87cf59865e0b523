#ifndef forma_source_microstructure_ad_value_h
#define forma_source_microstructure_ad_value_h

// The value of a double or of a Sacado forward AD number, for the branch
// decisions of code templated on both (internal, not installed).

#include <Sacado.hpp>

namespace forma
{
  namespace internal
  {
    inline double
    value_of(const double x)
    {
      return x;
    }

    inline double
    value_of(const Sacado::Fad::DFad<double> &x)
    {
      return x.val();
    }
  } // namespace internal
} // namespace forma

#endif
