#ifndef forma_adjoint_form_h
#define forma_adjoint_form_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <forma/adjoint/registry.h>
#include <forma/physics/material.h>

#include <map>
#include <string>
#include <vector>

namespace dealii
{
  template <typename>
  class AffineConstraints;
  namespace TrilinosWrappers
  {
    class SparseMatrix;
    class SparsityPattern;
    namespace MPI
    {
      class Vector;
    }
  } // namespace TrilinosWrappers
} // namespace dealii

namespace forma
{
  class PhysicalParameters;

  /// The cell a form is evaluated on (what forms may know of it).
  struct CellInfo
  {
    unsigned int               active_index = 0; ///< active_cell_index()
    dealii::types::material_id material_id  = 0;
    dealii::types::boundary_id boundary_id  = 0; ///< faces only
  };

  /**
   * The state at the quadrature points of one cell (or boundary face), in
   * the current design's shape. Which fields are filled follows the forms'
   * needs(): grad_u and X always.
   */
  template <int dim>
  struct PointStates
  {
    CellInfo                            cell;
    std::vector<dealii::Tensor<2, dim>> grad_u;
    std::vector<dealii::Tensor<2, dim>> grad_u_old; ///< previous step
    std::vector<dealii::Tensor<1, dim>> u;
    std::vector<dealii::Tensor<1, dim>> w;      ///< BDF history (transient)
    std::vector<dealii::Point<dim>>     X;      ///< material coordinates
    std::vector<dealii::Tensor<1, dim>> normal; ///< faces: outer normal
    std::vector<double>                 JxW;
    double                              time = 0;
    double dt             = 0; ///< transient step, 0 for static problems
    double inertia_factor = 0; ///< 1 / (beta dt)^2 (transient)

    unsigned int
    size() const
    {
      return grad_u.size();
    }
  };

  /**
   * What forms add at the quadrature points of a cell: the residual
   *   h_i = sum_q (flux_q : grad phi_i + source_q . phi_i) JxW_q,
   * its derivatives in the state (flux_tangent = d flux / d grad u,
   * source_tangent s with d source / d u = s I), the derivative of the flux
   * in the previous step's gradient (damping; adjoint only) and the
   * energy whose gradient is h (the merit of the Newton line search).
   * Forms add to the fields; the caller zeroes them.
   */
  template <int dim>
  struct PointTerms
  {
    bool with_tangent     = false; ///< fill the tangents
    bool with_old_tangent = false; ///< fill flux_tangent_old
    bool with_energy      = false; ///< add to `energy`

    std::vector<dealii::Tensor<2, dim>> flux;
    std::vector<dealii::Tensor<1, dim>> source;
    std::vector<dealii::Tensor<4, dim>> flux_tangent;
    std::vector<dealii::Tensor<4, dim>> flux_tangent_old;
    std::vector<double>                 source_tangent;
    double                              energy = 0; ///< integrated (JxW)
    /// False: the state is outside the form's domain (an inverted element).
    bool admissible = true;
  };

  /// The adjoint p at the quadrature points, with its gradient G.
  template <int dim>
  struct PointAdjoint
  {
    std::vector<dealii::Tensor<1, dim>> p;
    std::vector<dealii::Tensor<2, dim>> G;
  };

  /// What a transient form couples into the previous steps' adjoint right
  /// hand side (see Form::history_terms()).
  template <int dim>
  struct HistoryStates
  {
    CellInfo                            cell;
    std::vector<dealii::Tensor<1, dim>> z; ///< BDF-weighted adjoints
    /// Next step's adjoint gradient and states (empty: no next step).
    std::vector<dealii::Tensor<2, dim>> G_next, grad_u_next, grad_u_prev;
    std::vector<double>                 JxW;
    double                              dt = 0;
  };

  /**
   * A force term h^k(u, m) of the discrete problem h(u, q) = sum_k h^k = 0
   * (thesis ch. 3.3, eq. 3.23): elastic, inertia, damping, loads, contact.
   * The simulator's assembly and its static and transient adjoints loop
   * over forms and do not know which ones exist.
   *
   * A form acts through one or both of
   * - point terms: integrands over cells and boundary faces, functions of
   *   the state and the material coordinates. The simulator contracts them
   *   with the shape functions and differentiates them in the shape (the
   *   transport of eq. 3.24) itself; forms add the products with the
   *   parameters they own.
   * - global terms: non-local forces (contact) that assemble into the
   *   global residual and Jacobian and provide their own products.
   *
   * Physical parameters (materials, load scales, the shape, friction) live
   * in PhysicalParameters: forms read their values there and add their
   * adjoint products p^T dh/dm to the sensitivities the design asks for.
   */
  template <int dim>
  class Form
  {
  public:
    using Vector      = dealii::TrilinosWrappers::MPI::Vector;
    using Matrix      = dealii::TrilinosWrappers::SparseMatrix;
    using Constraints = dealii::AffineConstraints<double>;
    virtual ~Form()   = default;

    /// The name it is registered and reported under.
    virtual std::string
    name() const = 0;

    /// Forms of transient problems only (inertia, damping): left out of
    /// static assemblies.
    virtual bool
    transient_only() const
    {
      return false;
    }

    /// The state fields point terms read (flags of PointStates).
    enum Needs : unsigned int
    {
      none          = 0,
      values        = 1, ///< u
      history       = 2, ///< w
      old_gradients = 4  ///< grad_u_old
    };
    virtual unsigned int
    needs() const
    {
      return none;
    }

    /// Called before an assembly or a products pass at time `t` (serial:
    /// point terms are evaluated by several threads).
    virtual void
    set_time(const double)
    {}

    /// @name Point terms
    //@{
    virtual bool
    has_cell_terms() const
    {
      return false;
    }

    virtual void
    cell_terms(const PointStates<dim> &, PointTerms<dim> &) const
    {}

    /// Whether the form integrates over boundary faces with this id.
    virtual bool
    acts_on_boundary(const dealii::types::boundary_id) const
    {
      return false;
    }

    /// Face terms: only `source` (and its tangent, energy) are read.
    virtual void
    face_terms(const PointStates<dim> &, PointTerms<dim> &) const
    {}

    /// Add p^T dh/dm of the cell's point terms to the requested
    /// sensitivities of `parameters` (the shape's is the caller's).
    virtual void
    cell_products(const PointStates<dim> &,
                  const PointAdjoint<dim> &,
                  PhysicalParameters &) const
    {}

    /**
     * Face products: the parameter sensitivities, and per quadrature point
     * the shape kernel W with p^T dh/dx theta = sum_q W_q : grad theta
     * (theta a shape velocity), added to `shape_kernel`.
     */
    virtual void
    face_products(const PointStates<dim> &,
                  const PointAdjoint<dim> &,
                  std::vector<dealii::Tensor<2, dim>> &,
                  PhysicalParameters &) const
    {}

    /**
     * Transient forms whose step residual h_i depends on earlier steps:
     * the coefficients (flux, source) of the terms they add to the adjoint
     * right-hand side of step i: inertia M z, damping
     * (d h_{i+1} / d u^i)^T p_{i+1}.
     */
    virtual void
    history_terms(const HistoryStates<dim> &, PointTerms<dim> &) const
    {}
    //@}

    /// @name Global terms
    //@{
    /// Add the form's couplings to the Jacobian's pattern.
    virtual void
    add_couplings(const Constraints &,
                  dealii::TrilinosWrappers::SparsityPattern &) const
    {}

    /// The global assembly's in- and outputs.
    struct GlobalAssembly
    {
      const Vector      &u_owned;
      const Vector      &u_ghost;
      const Constraints &constraints;
      Matrix            *matrix;           ///< null: residual only
      Vector            &residual;         ///< condensed
      Vector            *raw;              ///< uncondensed (reactions) or null
      bool               transpose;        ///< assemble the transposed Jacobian
      bool               exact;            ///< no convexification (adjoints)
      bool               cells_admissible; ///< the point terms' verdict
      double             energy     = 0;
      bool               admissible = true;
    };
    /// Collective: called on every rank for every assembly.
    virtual void
    assemble_global(GlobalAssembly &) const
    {}

    /// Whether assemble_global() adds anything (contact): a matrix-free
    /// Jacobian has no place for it.
    virtual bool
    has_global_terms() const
    {
      return false;
    }

    /// The state changed (or will move by `du`): update what depends on
    /// it; true if the Jacobian's pattern must be rebuilt. Collective.
    virtual bool
    update_state(const Vector &, const Vector *)
    {
      return false;
    }

    /// The largest fraction in (0, 1] of the step du that keeps the form
    /// defined (continuous collision detection), with a relative `gap`.
    virtual double
    max_step(const Vector &, const Vector &, const double)
    {
      return 1.;
    }

    /// Whether the force is the gradient of the energy it reports.
    virtual bool
    is_potential() const
    {
      return true;
    }

    /// Whether its Jacobian is symmetric.
    virtual bool
    is_symmetric() const
    {
      return true;
    }

    /// Whether its Newton Jacobian is its exact derivative (a convexified
    /// one is not; adjoints then assemble again with `exact`).
    virtual bool
    newton_jacobian_is_exact() const
    {
      return true;
    }

    /**
     * The state of stored step `step` for the adjoint (the forward lagged
     * state: the previous step's displacement, null for static problems);
     * true if the Jacobian's pattern must be rebuilt. Collective.
     */
    virtual bool
    prepare_adjoint_step(const Vector &, const Vector *)
    {
      return false;
    }

    /// The global adjoint products in- and outputs.
    struct GlobalAdjoint
    {
      const Vector      &u_owned;
      const Vector      &u_ghost;
      const Vector      &p_owned;
      const Vector      &p_ghost;
      const Constraints &constraints;
      /// (d h / d u^{i-1})^T p of lagged terms, or null (static).
      Vector *lagged;
    };
    /// Collective.
    virtual void
    global_products(const GlobalAdjoint &, PhysicalParameters &) const
    {}
    //@}
  };

  /**
   * A record of Loads/Additional forms (`name : key=value, ...`) as a
   * form's factory reads it, with the simulation it joins: a form may add
   * physical parameters of its own to `physical` for a parameterization to
   * set.
   */
  template <int dim>
  struct FormRecord : KeyValueRecord
  {
    PhysicalParameters                                             *physical;
    const std::map<dealii::types::material_id, MaterialProperties> *bodies;
    bool transient = false;
  };

  /// Forms by name: Loads/Additional forms lists them.
  template <int dim>
  using FormRegistry = Registry<Form<dim>, const FormRecord<dim> &>;
  extern template class Registry<Form<2>, const FormRecord<2> &>;
  extern template class Registry<Form<3>, const FormRecord<3> &>;
} // namespace forma

/**
 * Register a form: `factory` is a function template `template <int dim>
 * std::unique_ptr<Form<dim>> factory(const FormRecord<dim> &)`.
 */
#define FORMA_REGISTER_FORM(factory, name, documentation)     \
  namespace                                                   \
  {                                                           \
    struct FORMA_CONCAT(FormRegistration, __LINE__)           \
    {                                                         \
      FORMA_CONCAT(FormRegistration, __LINE__)()              \
      {                                                       \
        forma::FormRegistry<2>::instance().add(name,          \
                                               documentation, \
                                               &factory<2>);  \
        forma::FormRegistry<3>::instance().add(name,          \
                                               documentation, \
                                               &factory<3>);  \
      }                                                       \
    } const FORMA_CONCAT(form_registration_, __LINE__);       \
  }

#endif
