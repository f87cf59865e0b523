#ifndef forma_ipc_ipc_contact_form_h
#define forma_ipc_ipc_contact_form_h

#include <forma/adjoint/form.h>
#include <forma/ipc/ipc_contact.h>

#include <functional>

namespace forma
{
  template <int dim>
  class ShapeField;

  namespace ipc
  {
    /**
     * Incremental potential contact (IpcContact: the log barrier and lagged
     * friction, thesis ch. 3.6-3.7) as a global form: a potential whose
     * Newton Jacobian is convexified (adjoints assemble the exact one), with
     * continuous collision detection as its step bound and lagged friction
     * coupling each step to the previous one. Products: the shape (through
     * the collision mesh's rest positions) and the friction coefficients.
     */
    template <int dim>
    class IpcContactForm : public Form<dim>
    {
    public:
      using typename Form<dim>::Vector;
      using typename Form<dim>::GlobalAssembly;
      using typename Form<dim>::GlobalAdjoint;

      /// `friction_eta`: the slip smoothing of the current problem.
      IpcContactForm(IpcContact<dim>               &contact,
                     const std::function<double()> &friction_eta);

      std::string
      name() const override
      {
        return "ipc contact";
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
      update_state(const Vector &u, const Vector *du) override;

      double
      max_step(const Vector &u, const Vector &du, const double gap) override;

      bool
      newton_jacobian_is_exact() const override
      {
        return false;
      }

      bool
      prepare_adjoint_step(const Vector &u, const Vector *u_lagged) override;

      void
      global_products(const GlobalAdjoint &a,
                      PhysicalParameters  &parameters) const override;

      /// Add dJ/d(rest positions of the collision vertices) to the shape's
      /// sensitivity (the transpose of the upsampling to the collision mesh).
      void
      add_rest_gradient(const std::vector<Vec> &rest,
                        ShapeField<dim>        &shape) const;

    private:
      IpcContact<dim>              &contact;
      const std::function<double()> friction_eta;
    };
  } // namespace ipc
} // namespace forma

#endif
