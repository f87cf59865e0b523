#include <forma/adjoint/parameterization.h>

#include <limits>

namespace forma
{
  template <int dim>
  void
  Parameterization<dim>::scales(const double *,
                                const double,
                                double *scale) const
  {
    std::fill(scale, scale + size(), 1.);
  }



  template <int dim>
  void
  Parameterization<dim>::bounds(const double *,
                                const double *,
                                const double,
                                double *lower,
                                double *upper) const
  {
    const double inf = std::numeric_limits<double>::infinity();
    std::fill(lower, lower + size(), -inf);
    std::fill(upper, upper + size(), inf);
  }



  std::string
  parameterization_names(const std::string &separator)
  {
    return ParameterizationRegistry<2>::instance().names(separator);
  }



  std::string
  parameterization_documentation()
  {
    return ParameterizationRegistry<2>::instance().documentation();
  }

  template class Parameterization<2>;
  template class Parameterization<3>;
} // namespace forma
