// The `loads` design block: a scale factor per load.

#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>

namespace forma
{
  namespace
  {
    using namespace dealii;

    template <int dim>
    class LoadParameterization : public Parameterization<dim>
    {
    public:
      explicit LoadParameterization(const DesignContext<dim> &c)
        : scales_(*c.physical.template find<LoadScales>())
      {
        AssertThrow(!scales_.value.empty(),
                    ExcMessage("Design/Parameters: 'loads' needs tractions, "
                               "pressures, a body force or gravity."));
        scales_.wanted = true;
      }

      unsigned int
      size() const override
      {
        return scales_.value.size();
      }

      std::vector<double>
      initial() const override
      {
        return std::vector<double>(size(), 1.);
      }

      void
      apply(const double *q) override
      {
        scales_.value.assign(q, q + size());
      }

      void
      chain(const double *, double *dJ) const override
      {
        std::copy(scales_.sensitivity.begin(), scales_.sensitivity.end(), dJ);
      }

    private:
      LoadScales &scales_;
    };
  } // namespace
} // namespace forma

using forma::LoadParameterization;
FORMA_REGISTER_PARAMETERIZATION(
  LoadParameterization,
  "loads",
  "a scale factor per traction and pressure record, then the body force and "
  "gravity (those the problem has)",
  5)
