// Objective terms of the center of mass of the deformed body: its distance to
// a target and its height (thesis eqs. 3.38-3.39).

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

    // Center of mass of the deformed body: distance to a target (eq. 3.38)
    // or minus its height (eq. 3.39, last coordinate).
    template <int dim>
    class CenterOfMass : public AutoDiffTerm<dim, CenterOfMass<dim>>
    {
    public:
      CenterOfMass(const std::string    &name,
                   const double          weight,
                   const bool            height,
                   const Tensor<1, dim> &target)
        : AutoDiffTerm<dim, CenterOfMass<dim>>(name, weight)
        , height(height)
        , target(target)
      {}
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        std::vector<typename ObjectiveTerm<dim>::Integral> i(dim + 1);
        for (auto &integral : i)
          integral.material_ids = this->materials; // material=id: one body
        return i;
      }
      // k = 0: mass; k = 1..dim: first moments of the deformed positions.
      template <typename N>
      N
      j(unsigned int                 k,
        const IntegrandContext<dim> &c,
        const Tensor<1, dim, N>     &x,
        const Tensor<1, dim, N>     &u,
        const Tensor<2, dim, N> &,
        const N &,
        const N &) const
      {
        return k == 0 ? N(c.density) : N(c.density) * (x[k - 1] + u[k - 1]);
      }
      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        const double m = I[0];
        if (height)
          {
            if (grad)
              {
                grad->assign(dim + 1, 0.);
                (*grad)[0]   = I[dim] / (m * m);
                (*grad)[dim] = -1. / m;
              }
            return -I[dim] / m;
          }
        double value = 0;
        if (grad)
          grad->assign(dim + 1, 0.);
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double e = I[d + 1] / m - target[d];
            value += e * e;
            if (grad)
              {
                (*grad)[d + 1] = 2. * e / m;
                (*grad)[0] -= 2. * e * I[d + 1] / (m * m);
              }
          }
        return value;
      }

    private:
      const bool           height;
      const Tensor<1, dim> target;
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_center_of_mass(const TermRecord<dim> &r)
    {
      return std::make_unique<CenterOfMass<dim>>(r.name,
                                                 r.weight,
                                                 false,
                                                 axis_keys<dim>(r));
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_height(const TermRecord<dim> &r)
    {
      return std::make_unique<CenterOfMass<dim>>(r.name,
                                                 r.weight,
                                                 true,
                                                 Tensor<1, dim>());
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_center_of_mass,
                              "center of mass",
                              "x=.., y=..[, z=..]: the squared distance of the "
                              "deformed center of mass to (x, y, z) (eq. "
                              "3.38)",
                              10)
FORMA_REGISTER_OBJECTIVE_TERM(make_height,
                              "height",
                              "minus the height (last coordinate) of the "
                              "deformed center of mass (eq. 3.39)",
                              11)
