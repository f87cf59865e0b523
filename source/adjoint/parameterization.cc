#include <forma/adjoint/parameterization.h>

#include <cmath>
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



  template <int dim>
  void
  Parameterization<dim>::magnitude_scales(const double *q0, double *scale) const
  {
    for (unsigned int i = 0; i < size(); ++i)
      scale[i] = q0[i] != 0 ? std::abs(q0[i]) : 1.;
  }



  template <int dim>
  void
  Parameterization<dim>::nonnegative_bounds(double *lower, double *upper) const
  {
    std::fill(lower, lower + size(), 0.);
    std::fill(upper, upper + size(), std::numeric_limits<double>::infinity());
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

  template class Registry<Parameterization<2>, const DesignContext<2> &>;
  template class Registry<Parameterization<3>, const DesignContext<3> &>;
  template class Parameterization<2>;
  template class Parameterization<3>;
} // namespace forma
