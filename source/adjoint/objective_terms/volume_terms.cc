// Objective terms of the volume: the volume, its bound and its target
// (thesis eqs. 3.40-3.41, 2.16).

#include <forma/adjoint/auto_diff_term.h>

#include <cmath>
#include <limits>
#include <memory>

namespace forma
{
  namespace
  {
    using namespace dealii;
    const double none = std::numeric_limits<double>::quiet_NaN();

    // Volume, its upper-bound penalty phi(V - V_t) (eqs. 3.40-3.41), or
    // the two-sided (V - V_t)^2 of a target volume (eq. 2.16).
    template <int dim>
    class Volume : public AutoDiffTerm<dim, Volume<dim>>
    {
    public:
      Volume(const std::string &name,
             const double       weight,
             const double       bound,
             const bool         two_sided = false)
        : AutoDiffTerm<dim, Volume<dim>>(name, weight)
        , bound(bound)
        , two_sided(two_sided)
      {}
      bool
      depends_on_state() const override
      {
        return false;
      }
      void
      cap_volume_bound(const double volume) override
      {
        if (!std::isnan(bound) && !two_sided)
          bound = std::min(bound, volume);
      }
      template <typename N>
      N
      j(unsigned int,
        const IntegrandContext<dim> &,
        const Tensor<1, dim, N> &,
        const Tensor<1, dim, N> &,
        const Tensor<2, dim, N> &,
        const N &,
        const N &) const
      {
        return N(1.);
      }
      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        if (std::isnan(bound))
          {
            if (grad)
              *grad = {1.};
            return I[0];
          }
        const double z = I[0] - bound;
        if (grad)
          *grad = {z > 0 || two_sided ? 2. * z : 0.};
        return two_sided ? z * z : positive_part_squared(z);
      }

    private:
      double     bound; ///< NaN: the plain volume
      const bool two_sided;
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_volume(const TermRecord<dim> &r)
    {
      return std::make_unique<Volume<dim>>(r.name, r.weight, none);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_volume_bound(const TermRecord<dim> &r)
    {
      return std::make_unique<Volume<dim>>(r.name, r.weight, r.key("bound"));
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_volume_target(const TermRecord<dim> &r)
    {
      return std::make_unique<Volume<dim>>(r.name,
                                           r.weight,
                                           r.key("target"),
                                           true);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_volume,
                              "volume",
                              "the volume (area) of the design",
                              5)
FORMA_REGISTER_OBJECTIVE_TERM(make_volume_bound,
                              "volume bound",
                              "bound=V: max(V - bound, 0)^2 (eq. 3.40)",
                              6)
FORMA_REGISTER_OBJECTIVE_TERM(make_volume_target,
                              "volume target",
                              "target=V: (V - target)^2 (eq. 2.16)",
                              7)
