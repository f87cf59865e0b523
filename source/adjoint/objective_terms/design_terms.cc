// Objective terms the simulator evaluates from the design and its contact
// (no integrals): boundary and material smoothing (thesis eqs. 3.43-3.44)
// and the IPC contact force.

#include <forma/adjoint/auto_diff_term.h>

#include <cmath>
#include <limits>
#include <memory>

namespace forma
{
  namespace
  {
    using namespace dealii;

    // Placeholder of a regularization term (see ObjectiveTerm).
    template <int dim>
    class RegularizationTerm : public ObjectiveTerm<dim>
    {
    public:
      RegularizationTerm(const std::string &name,
                         const double       weight,
                         const typename ObjectiveTerm<dim>::Regularization r,
                         const double                                      p)
        : ObjectiveTerm<dim>(name, weight)
      {
        this->regularization = r;
        this->exponent       = p;
      }
      bool
      depends_on_state() const override
      {
        return false;
      }
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        return {};
      }
      void
      integrand(const unsigned int,
                const IntegrandContext<dim> &,
                const Tensor<1, dim> &,
                const Tensor<1, dim> &,
                const Tensor<2, dim> &,
                const double,
                const double,
                const bool,
                IntegrandValue<dim> &) const override
      {}
      double
      combine(const std::vector<double> &, std::vector<double> *) const override
      {
        return 0;
      }
    };


    /// The contact force term (see ObjectiveTerm::contact_force): no
    /// integrals like the regularization terms, but a function of the state
    /// at every step (not a regularization).
    template <int dim>
    class ContactForceTerm : public RegularizationTerm<dim>
    {
    public:
      ContactForceTerm(const std::string &name,
                       const double       weight,
                       const double       p)
        : RegularizationTerm<dim>(name,
                                  weight,
                                  ObjectiveTerm<dim>::Regularization::none,
                                  p)
      {
        this->contact_force = true;
      }
      bool
      depends_on_state() const override
      {
        return true;
      }
      bool
      restrictable() const override
      {
        return true;
      }
      void
      restrict_to_material(const types::material_id id) override
      {
        this->contact_bodies = {id};
      }
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    smoothing(const TermRecord<dim>                            &r,
              const typename ObjectiveTerm<dim>::Regularization kind)
    {
      const double p = r.key("p", 2.);
      AssertThrow(p >= 1, ExcMessage(r.where + ": p must be at least 1."));
      return std::make_unique<RegularizationTerm<dim>>(r.name,
                                                       r.weight,
                                                       kind,
                                                       p);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_boundary_smoothing(const TermRecord<dim> &r)
    {
      return smoothing(r,
                       ObjectiveTerm<dim>::Regularization::boundary_smoothing);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_material_smoothing(const TermRecord<dim> &r)
    {
      return smoothing(r,
                       ObjectiveTerm<dim>::Regularization::material_smoothing);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_contact_force(const TermRecord<dim> &r)
    {
      const double p = r.key("p", 2.);
      AssertThrow(p >= 2,
                  ExcMessage(r.where + ": p must be at least 2 (got " +
                             std::to_string(p) + ")."));
      return std::make_unique<ContactForceTerm<dim>>(r.name, r.weight, p);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_boundary_smoothing,
                              "boundary smoothing",
                              "p=2: the smoothness of the boundary (eq. 3.43; "
                              "needs the shape block)",
                              12)
FORMA_REGISTER_OBJECTIVE_TERM(make_material_smoothing,
                              "material smoothing",
                              "jumps of per-cell Lame parameters between "
                              "neighbours (eq. 3.44)",
                              13)
FORMA_REGISTER_OBJECTIVE_TERM(make_contact_force,
                              "contact force",
                              "p=2 (IPC): |R|^p of the resultant R of the "
                              "barrier contact forces on a body (material=id) "
                              "or, without material, of the obstacles' push on "
                              "all bodies",
                              14)
