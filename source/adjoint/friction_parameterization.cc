// The `friction` design block: IPC friction coefficients.

#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>

#include <cmath>

namespace forma
{
  namespace
  {
    using namespace dealii;

    template <int dim>
    class FrictionParameterization : public Parameterization<dim>
    {
    public:
      explicit FrictionParameterization(const DesignContext<dim> &c)
        : friction(c.physical.template find<FrictionCoefficients>())
      {
        AssertThrow(friction,
                    ExcMessage("Design/Parameters: 'friction' needs IPC "
                               "contact (IPC/Enabled = true)."));
        friction->wanted = true;
        start            = friction->value;
      }

      unsigned int
      size() const override
      {
        return start.size();
      }

      std::vector<double>
      initial() const override
      {
        return start;
      }

      void
      scales(const double *q0, const double, double *s) const override
      {
        this->magnitude_scales(q0, s);
      }

      void
      bounds(const double *,
             const double *,
             const double,
             double *lower,
             double *upper) const override
      {
        this->nonnegative_bounds(lower, upper);
      }

      void
      apply(const double *q) override
      {
        friction->value.assign(q, q + size());
      }

      void
      chain(const double *, double *dJ) const override
      {
        std::copy(friction->sensitivity.begin(),
                  friction->sensitivity.end(),
                  dJ);
      }

    private:
      FrictionCoefficients *friction;
      std::vector<double>   start;
    };
  } // namespace
} // namespace forma

using forma::FrictionParameterization;
FORMA_REGISTER_PARAMETERIZATION(
  FrictionParameterization,
  "friction",
  "IPC friction coefficients: IPC/Friction coefficient, then each Friction "
  "pairs record, then each obstacle with its own mu",
  4)
