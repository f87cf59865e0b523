#ifndef forma_adjoint_objective_h
#define forma_adjoint_objective_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>

#include <forma/adjoint/registry.h>
#include <forma/physics/material.h>
#include <forma/physics/time_grid.h>

#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim>
  class FunctionParser;
}

namespace forma
{
  /// Fixed data at an integration point of an objective integrand.
  template <int dim>
  struct IntegrandContext
  {
    dealii::Point<dim>     X; ///< position on the mesh as read (material label)
    dealii::Tensor<1, dim> target; ///< deformed position in the reference run
    dealii::Tensor<1, dim> normal; ///< outer normal (boundary integrals)
    double                 density      = 1;
    double                 time         = 0;
    ConstitutiveModel      model        = ConstitutiveModel::linear_elastic;
    bool                   plane_stress = false;
  };

  /// Value and partial derivatives of an integrand j(x, u, grad u, lambda, mu)
  /// (x: design position, lambda/mu: the Lame parameters of the material),
  /// on boundaries also of the outer normal n.
  template <int dim>
  struct IntegrandValue
  {
    double                 value = 0;
    dealii::Tensor<1, dim> d_x, d_u, d_n; ///< d_n: by the outer normal
    dealii::Tensor<2, dim> d_grad_u;
    double                 d_lambda = 0, d_mu = 0;
  };

  /**
   * One term of an objective (thesis ch. 3.8): a function Phi of a few
   * integrals I_k = int j_k(x, u, grad u, lambda, mu) over the domain or
   * parts of its boundary. The generic volume/boundary shape derivatives of
   * eqs. 3.31 and 3.34 and the adjoint right-hand sides 3.32 and 3.35 follow
   * from the partials of j_k, so a new term only states j_k and Phi.
   */
  template <int dim>
  class ObjectiveTerm
  {
  public:
    struct Integral
    {
      bool                                 boundary = false;
      std::set<dealii::types::boundary_id> boundary_ids; ///< empty: all
      /// Only cells (volume integrals) or faces of cells (boundary
      /// integrals, e.g. one side of a cut interface) with these material
      /// ids; empty: all.
      std::set<dealii::types::material_id> material_ids;
    };

    ObjectiveTerm(const std::string &name, const double weight);
    virtual ~ObjectiveTerm() = default;

    virtual std::vector<Integral>
    integrals() const = 0;

    /// j_k at one point with all partials (`derivatives`) or the value only.
    virtual void
    integrand(const unsigned int            k,
              const IntegrandContext<dim>  &context,
              const dealii::Tensor<1, dim> &x,
              const dealii::Tensor<1, dim> &u,
              const dealii::Tensor<2, dim> &grad_u,
              const double                  lambda,
              const double                  mu,
              const bool                    derivatives,
              IntegrandValue<dim>          &result) const = 0;

    /// Phi(I) and, when `gradient` is given, dPhi/dI_k.
    virtual double
    combine(const std::vector<double> &I,
            std::vector<double>       *gradient) const = 0;

    /// Whether the term reads IntegrandContext::target.
    virtual bool
    needs_reference_run() const
    {
      return false;
    }

    /// Whether restrict_to_material() applies (the `material` key).
    virtual bool
    restrictable() const
    {
      return false;
    }

    /// Integrate only over cells of material `id` (volume terms; others
    /// reject it in the parser).
    virtual void
    restrict_to_material(const dealii::types::material_id)
    {}

    /// A one-sided volume bound above `volume` comes down to it (element
    /// removal keeps the volume it reached); other terms ignore this.
    virtual void
    cap_volume_bound(const double /*volume*/)
    {}

    /// Whether the term depends on the state u (false: on the design
    /// alone, e.g. volume; such terms count once over several load cases).
    virtual bool
    depends_on_state() const
    {
      return true;
    }

    /**
     * Regularization terms are functions of the design alone, evaluated by
     * the simulator that knows the mesh topology: `boundary smoothing`
     * (thesis eq. 3.43, exponent `p`) and `material smoothing` (eq. 3.44).
     * They have no integrals and are not integrated in time.
     */
    enum class Regularization
    {
      none,
      boundary_smoothing,
      material_smoothing
    };
    Regularization regularization = Regularization::none;
    /// p of boundary smoothing and of the contact force
    double exponent = 2;

    /**
     * `contact force : p=2[, material=id]` (IPC runs): |R|^p at every step,
     * integrated in time like the other terms, R the resultant of the
     * barrier (normal) contact forces on the body `material` (all bodies:
     * the obstacles' push, as pairs between bodies cancel). Evaluated by
     * the simulator from its IPC contact, with `exponent` p; no integrals.
     */
    bool contact_force = false;
    /// The body of a contact force term; empty: all.
    std::set<dealii::types::material_id> contact_bodies;

    /// Algorithm 1's weight schedule (thesis Table 2.2, "a/b"): the weight
    /// goes linearly from `first_weight` (first outer iteration) to
    /// `last_weight` (the last one); `final weight=b` in Objective/Terms.
    void
    ramp_weight(const double progress)
    {
      weight = first_weight + progress * (last_weight - first_weight);
    }

    const std::string name;
    double            weight;
    double            first_weight, last_weight;
  };

  /**
   * One record of Objective/Terms, `name : key=value, ...`, as a term's
   * factory reads it.
   */
  template <int dim>
  struct TermRecord : KeyValueRecord
  {
    double weight = 1;
    /// Objective/Target (null: the reference run's states).
    std::shared_ptr<dealii::FunctionParser<dim>> target;
  };

  /// Objective terms by name: `Objective/Terms` lists them.
  template <int dim>
  using ObjectiveTermRegistry =
    Registry<ObjectiveTerm<dim>, const TermRecord<dim> &>;
  extern template class Registry<ObjectiveTerm<2>, const TermRecord<2> &>;
  extern template class Registry<ObjectiveTerm<3>, const TermRecord<3> &>;

  /// The `Objective` section (see Objective).
  struct ObjectiveParameters
  {
    std::string terms;
    std::string time_weighting = "integral"; ///< integral | final
    std::string target;                      ///< expressions or empty
    std::string reference_bodies;
    /// Standard deviation of the Gaussian noise added to every displacement
    /// DoF of the reference run's states (a synthetic recording).
    double target_noise = 0;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);
  };

  /**
   * The objective J = sum_t weight_t Phi_t(I_t) (thesis eq. 3.10), for
   * transient runs integrated in time (eq. 3.14) or taken at the final step.
   * Read from the `Objective` section:
   *   set Terms = stress : p=4, weight=1 ; volume bound : bound=0.8
   */
  template <int dim>
  class Objective
  {
  public:
    using Parameters = ObjectiveParameters;

    /// `state_terms_only`: keep only the terms that depend on the state
    /// (the objective of a further load case); the list may then be empty.
    explicit Objective(const Parameters &parameters,
                       const bool        state_terms_only = false);

    const std::vector<std::unique_ptr<ObjectiveTerm<dim>>> &
    terms() const
    {
      return term_list;
    }

    /// Time-quadrature weight of level i of `grid`.
    double
    step_weight(const unsigned int i, const TimeGrid &grid) const;

    bool
    needs_reference_run() const;

    const Parameters parameters;

  private:
    std::vector<std::unique_ptr<ObjectiveTerm<dim>>> term_list;
  };
} // namespace forma

/**
 * Register objective terms: `factory` is a function template
 * `template <int dim> std::unique_ptr<ObjectiveTerm<dim>>
 * factory(const TermRecord<dim> &)`, `name` the term's name in
 * Objective/Terms, `documentation` its keys and meaning, `rank` its place in
 * the documentation.
 */
#define FORMA_REGISTER_OBJECTIVE_TERM(factory, name, documentation, rank) \
  namespace                                                               \
  {                                                                       \
    struct FORMA_CONCAT(ObjectiveTermRegistration, __LINE__)              \
    {                                                                     \
      FORMA_CONCAT(ObjectiveTermRegistration, __LINE__)()                 \
      {                                                                   \
        forma::ObjectiveTermRegistry<2>::instance().add(name,             \
                                                        documentation,    \
                                                        &factory<2>,      \
                                                        rank);            \
        forma::ObjectiveTermRegistry<3>::instance().add(name,             \
                                                        documentation,    \
                                                        &factory<3>,      \
                                                        rank);            \
      }                                                                   \
    } const FORMA_CONCAT(objective_term_registration_, __LINE__);         \
  }

#endif
