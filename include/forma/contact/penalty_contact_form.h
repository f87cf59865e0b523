#ifndef forma_contact_penalty_contact_form_h
#define forma_contact_penalty_contact_form_h

#include <forma/adjoint/form.h>
#include <forma/contact/penalty_contact.h>

namespace forma
{
  /**
   * Smoothed penalty contact and Coulomb friction (thesis ch. 2, see
   * PenaltyContact) as a global form: it assembles its contact faces into
   * the global system; with friction it is neither a potential nor
   * symmetric, so adjoints assemble its transpose. Products: the shape.
   */
  template <int dim>
  class PenaltyContactForm : public Form<dim>
  {
  public:
    using typename Form<dim>::GlobalAssembly;
    using typename Form<dim>::GlobalAdjoint;

    /// `contact` set up, `mapping` the current design's shape.
    PenaltyContactForm(const PenaltyContact<dim>                &contact,
                       const dealii::hp::MappingCollection<dim> &mapping);

    std::string
    name() const override
    {
      return "penalty contact";
    }

    void
    add_couplings(
      const typename Form<dim>::Constraints     &constraints,
      dealii::TrilinosWrappers::SparsityPattern &pattern) const override;

    void
    assemble_global(GlobalAssembly &a) const override;

    bool
    has_global_terms() const override
    {
      return true;
    }

    bool
    is_potential() const override
    {
      return !contact.has_friction();
    }

    bool
    is_symmetric() const override
    {
      return !contact.has_friction();
    }

    void
    global_products(const GlobalAdjoint &a,
                    PhysicalParameters  &parameters) const override;

  private:
    const PenaltyContact<dim>                &contact;
    const dealii::hp::MappingCollection<dim> &mapping;
  };
} // namespace forma

#endif
