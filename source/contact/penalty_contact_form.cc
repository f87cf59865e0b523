#include <forma/adjoint/shape_field.h>
#include <forma/contact/penalty_contact_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  PenaltyContactForm<dim>::PenaltyContactForm(
    const PenaltyContact<dim>        &contact,
    const hp::MappingCollection<dim> &mapping)
    : contact(contact)
    , mapping(mapping)
  {}



  template <int dim>
  void
  PenaltyContactForm<dim>::add_couplings(
    const typename Form<dim>::Constraints &constraints,
    TrilinosWrappers::SparsityPattern     &pattern) const
  {
    contact.add_couplings(constraints, pattern);
  }



  template <int dim>
  void
  PenaltyContactForm<dim>::assemble_global(GlobalAssembly &a) const
  {
    // Contact faces are few: serially, after the cells; a state already
    // rejected by the cells is not evaluated.
    if (!a.cells_admissible || !contact.active())
      return;
    bool evaluated = true;
    a.energy += contact.assemble(mapping,
                                 a.u_ghost,
                                 a.constraints,
                                 a.transpose,
                                 a.matrix,
                                 a.residual,
                                 a.raw,
                                 evaluated);
    a.admissible &= evaluated;
  }



  template <int dim>
  void
  PenaltyContactForm<dim>::global_products(const GlobalAdjoint &a,
                                           PhysicalParameters &parameters) const
  {
    auto *shape = parameters.wanted<ShapeField<dim>>();
    if (!shape || !contact.active())
      return;
    contact.add_shape_products(mapping,
                               a.u_ghost,
                               a.p_ghost,
                               shape->dof_handler,
                               shape->constraints,
                               shape->sensitivity);
  }

  template class PenaltyContactForm<2>;
  template class PenaltyContactForm<3>;
} // namespace forma
