// Objective terms of the stress: L^p norms and bounds of the Frobenius or von
// Mises stress (thesis eqs. 3.36, 3.42), compliance.

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

    // A stress measure s (Frobenius or von Mises of f(grad u)): its L^p norm
    // S = (int s^p)^(1/p) (eq. 3.36), with a bound s_t the penalty
    // int phi(s - s_t) (eq. 3.42), or with a norm bound S_t the penalty
    // phi(S - S_t) of the norm (one of the ways to hold the stress while
    // the volume is minimized).
    template <int dim>
    class StressTerm : public AutoDiffTerm<dim, StressTerm<dim>>
    {
    public:
      StressTerm(const std::string &name,
                 const double       weight,
                 const bool         von_mises,
                 const double       p,
                 const double       bound,
                 const double       norm_bound = none)
        : AutoDiffTerm<dim, StressTerm<dim>>(name, weight)
        , von_mises(von_mises)
        , p(p)
        , bound(bound)
        , norm_bound(norm_bound)
      {}
      template <typename N>
      N
      j(unsigned int,
        const IntegrandContext<dim> &c,
        const Tensor<1, dim, N> &,
        const Tensor<1, dim, N> &,
        const Tensor<2, dim, N> &g,
        const N                 &l,
        const N                 &m) const
      {
        using std::pow;
        using std::sqrt;
        const N s2 =
          stress_measure_squared<dim, N>(integrand_stress<dim, N>(c, g, l, m),
                                         von_mises);
        if (std::isnan(bound))
          return s2 > 0 ? N(pow(s2, 0.5 * p)) : N(0.);
        if (!(s2 > bound * bound))
          return N(0.);
        return positive_part_squared<N>(N(sqrt(s2)) - N(bound));
      }
      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        if (!std::isnan(bound))
          return AutoDiffTerm<dim, StressTerm<dim>>::combine(I, grad);
        const double v  = std::pow(std::max(I[0], 0.), 1. / p);
        const double dv = I[0] > 0 ? v / (p * I[0]) : 0.;
        if (std::isnan(norm_bound))
          {
            if (grad)
              *grad = {dv};
            return v;
          }
        const double over = v - norm_bound;
        if (grad)
          *grad = {over > 0 ? 2 * over * dv : 0.};
        return positive_part_squared(over);
      }

    private:
      const bool   von_mises;
      const double p;
      const double bound;      ///< NaN: the L^p norm
      const double norm_bound; ///< NaN: no bound on the L^p norm
    };

    // int f(grad u) : grad u, twice the stored energy for linear elasticity
    // (the work of the loads at equilibrium under homogeneous supports).
    template <int dim>
    class Compliance : public AutoDiffTerm<dim, Compliance<dim>>
    {
    public:
      using AutoDiffTerm<dim, Compliance<dim>>::AutoDiffTerm;
      template <typename N>
      N
      j(unsigned int,
        const IntegrandContext<dim> &c,
        const Tensor<1, dim, N> &,
        const Tensor<1, dim, N> &,
        const Tensor<2, dim, N> &g,
        const N                 &l,
        const N                 &m) const
      {
        return scalar_product(integrand_stress<dim, N>(c, g, l, m), g);
      }
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    stress_norm(const TermRecord<dim> &r, const bool von_mises)
    {
      const double p = r.key("p", 2.);
      AssertThrow(p >= 2,
                  ExcMessage(r.where + ": p must be at least 2 (got " +
                             std::to_string(p) + ")."));
      return std::make_unique<StressTerm<dim>>(
        r.name, r.weight, von_mises, p, none);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_stress(const TermRecord<dim> &r)
    {
      return stress_norm(r, false);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_von_mises(const TermRecord<dim> &r)
    {
      return stress_norm(r, true);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_stress_bound(const TermRecord<dim> &r)
    {
      return std::make_unique<StressTerm<dim>>(
        r.name, r.weight, false, 2., r.key("bound"));
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_von_mises_bound(const TermRecord<dim> &r)
    {
      return std::make_unique<StressTerm<dim>>(
        r.name, r.weight, true, 2., r.key("bound"));
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    stress_norm_bound(const TermRecord<dim> &r, const bool von_mises)
    {
      const double p = r.key("p", 2.);
      AssertThrow(p >= 2,
                  ExcMessage(r.where + ": p must be at least 2 (got " +
                             std::to_string(p) + ")."));
      const double bound = r.key("bound");
      AssertThrow(bound >= 0,
                  ExcMessage(r.where + ": the bound must not be negative."));
      return std::make_unique<StressTerm<dim>>(
        r.name, r.weight, von_mises, p, none, bound);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_stress_norm_bound(const TermRecord<dim> &r)
    {
      return stress_norm_bound(r, false);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_von_mises_norm_bound(const TermRecord<dim> &r)
    {
      return stress_norm_bound(r, true);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_compliance(const TermRecord<dim> &r)
    {
      return std::make_unique<Compliance<dim>>(r.name, r.weight);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_stress,
                              "stress",
                              "p=2: the L^p norm of the Frobenius stress "
                              "(eq. 3.36; p >= 2)",
                              0)
FORMA_REGISTER_OBJECTIVE_TERM(make_von_mises,
                              "von mises",
                              "p=2: the L^p norm of the von Mises stress",
                              1)
FORMA_REGISTER_OBJECTIVE_TERM(make_stress_bound,
                              "stress bound",
                              "bound=s: int max(|sigma| - s, 0)^2 of the "
                              "Frobenius stress (eq. 3.42)",
                              2)
FORMA_REGISTER_OBJECTIVE_TERM(make_von_mises_bound,
                              "von mises bound",
                              "bound=s: the same of the von Mises stress",
                              3)
FORMA_REGISTER_OBJECTIVE_TERM(make_stress_norm_bound,
                              "stress norm bound",
                              "p=2, bound=S: max(S - bound, 0)^2 of the L^p "
                              "norm S of the Frobenius stress (the stress "
                              "held while the volume is minimized)",
                              2)
FORMA_REGISTER_OBJECTIVE_TERM(make_von_mises_norm_bound,
                              "von mises norm bound",
                              "p=2, bound=S: the same of the von Mises stress",
                              3)
FORMA_REGISTER_OBJECTIVE_TERM(make_compliance,
                              "compliance",
                              "int f(grad u) : grad u (twice the stored "
                              "energy for linear elasticity)",
                              4)
