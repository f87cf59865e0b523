// Objective terms of a target motion: the distance of the deformed points
// to targets over the volume or a boundary (thesis eq. 3.37).

#include <deal.II/base/function_parser.h>
#include <deal.II/lac/vector.h>

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

    // int |x + u - x_trg|^2 over the volume or the boundary (eq. 3.37).
    template <int dim>
    class Target : public AutoDiffTerm<dim, Target<dim>>
    {
    public:
      Target(const std::string                          &name,
             const double                                weight,
             const bool                                  boundary,
             const std::set<types::boundary_id>         &ids,
             const std::shared_ptr<FunctionParser<dim>> &expression)
        : AutoDiffTerm<dim, Target<dim>>(name, weight)
        , boundary(boundary)
        , ids(ids)
        , expression(expression)
      {}
      /// Its integrals ignore `materials`: no `material` key.
      bool
      restrictable() const override
      {
        return false;
      }
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        typename ObjectiveTerm<dim>::Integral i;
        i.boundary     = boundary;
        i.boundary_ids = ids;
        return {i};
      }
      bool
      needs_reference_run() const override
      {
        return !expression;
      }
      template <typename N>
      N
      j(unsigned int,
        const IntegrandContext<dim> &c,
        const Tensor<1, dim, N>     &x,
        const Tensor<1, dim, N>     &u,
        const Tensor<2, dim, N> &,
        const N &,
        const N &) const
      {
        Tensor<1, dim> target = c.target;
        if (expression)
          {
            Vector<double> v(dim);
            expression->set_time(c.time);
            expression->vector_value(c.X, v);
            for (unsigned int d = 0; d < dim; ++d)
              target[d] = v[d];
          }
        N r = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const N e = x[d] + u[d] - N(target[d]);
            r += e * e;
          }
        return r;
      }

    private:
      const bool                           boundary;
      const std::set<types::boundary_id>   ids;
      std::shared_ptr<FunctionParser<dim>> expression;
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    target_term(const TermRecord<dim> &r, const bool boundary)
    {
      std::set<types::boundary_id> ids;
      if (r.keys.count("boundary"))
        ids.insert(static_cast<types::boundary_id>(r.key("boundary")));
      return std::make_unique<Target<dim>>(
        r.name, r.weight, boundary, ids, r.target);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_target(const TermRecord<dim> &r)
    {
      return target_term(r, false);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_boundary_target(const TermRecord<dim> &r)
    {
      return target_term(r, true);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_target,
                              "target",
                              "int |x + u - x_target|^2 over the volume (eq. "
                              "3.37; the target is Objective/Target, or the "
                              "reference run's motion)",
                              8)
FORMA_REGISTER_OBJECTIVE_TERM(make_boundary_target,
                              "boundary target",
                              "boundary=id: the same over a boundary (all "
                              "boundaries without an id)",
                              9)
