#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>
#include <deal.II/differentiation/ad/sacado_math.h>
#include <deal.II/differentiation/ad/sacado_number_types.h>
#include <deal.II/differentiation/ad/sacado_product_types.h>
#include <deal.II/lac/vector.h>

#include <forma/adjoint/objective.h>
#include <forma/base/records.h>
#include <forma/contact/smoothing.h>

#include <Sacado.hpp>

#include <cmath>

namespace forma
{
  using namespace dealii;

  template <int dim>
  ObjectiveTerm<dim>::ObjectiveTerm(const std::string &name,
                                    const double       weight)
    : name(name)
    , weight(weight)
  {}

  namespace
  {
    /**
     * Terms state their integrand once, generic in the number type; the
     * partials come from forward-mode AD over (x, u, grad u, lambda, mu).
     */
    template <int dim, typename Derived>
    class AutoDiffTerm : public ObjectiveTerm<dim>
    {
    public:
      using ObjectiveTerm<dim>::ObjectiveTerm;

      // Default: one volume integral (over `materials`, empty: all),
      // J = I.
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        typename ObjectiveTerm<dim>::Integral i;
        i.material_ids = materials;
        return {i};
      }

      void
      restrict_to_material(const types::material_id id) override
      {
        materials = {id};
      }

      std::set<types::material_id> materials;

      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        if (grad)
          *grad = {1.};
        return I[0];
      }

      void
      integrand(const unsigned int           k,
                const IntegrandContext<dim> &c,
                const Tensor<1, dim>        &x,
                const Tensor<1, dim>        &u,
                const Tensor<2, dim>        &grad_u,
                const double                 lambda,
                const double                 mu,
                const bool                   derivatives,
                IntegrandValue<dim>         &r) const override
      {
        const auto &self = static_cast<const Derived &>(*this);
        if (!derivatives)
          {
            r.value = self.template j<double>(k, c, x, u, grad_u, lambda, mu);
            return;
          }
        constexpr int n = 2 * dim + dim * dim + 2;
        using AD = Sacado::Fad::DFad<double>; // what deal.II tensors support
        Tensor<1, dim, AD> xa, ua;
        Tensor<2, dim, AD> ga;
        int                i = 0;
        for (unsigned int d = 0; d < dim; ++d)
          xa[d] = AD(n, i++, x[d]);
        for (unsigned int d = 0; d < dim; ++d)
          ua[d] = AD(n, i++, u[d]);
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int e = 0; e < dim; ++e)
            ga[d][e] = AD(n, i++, grad_u[d][e]);
        const AD la(n, i++, lambda);
        const AD ma(n, i++, mu);
        const AD v = self.template j<AD>(k, c, xa, ua, ga, la, ma);
        r.value    = v.val();
        i          = 0;
        for (unsigned int d = 0; d < dim; ++d)
          r.d_x[d] = v.dx(i++);
        for (unsigned int d = 0; d < dim; ++d)
          r.d_u[d] = v.dx(i++);
        for (unsigned int d = 0; d < dim; ++d)
          for (unsigned int e = 0; e < dim; ++e)
            r.d_grad_u[d][e] = v.dx(i++);
        r.d_lambda = v.dx(i++);
        r.d_mu     = v.dx(i++);
      }
    };

    /// The stress f(grad u) of the forces, with the plane-stress reduction.
    template <int dim, typename Number>
    Tensor<2, dim, Number>
    stress(const IntegrandContext<dim>  &c,
           const Tensor<2, dim, Number> &grad_u,
           const Number                 &lambda,
           const Number                 &mu)
    {
      const Number l =
        c.plane_stress ? Number(2. * lambda * mu / (lambda + 2. * mu)) : lambda;
      return first_piola_kirchhoff<dim, Number>(c.model, grad_u, l, mu);
    }

    /// Squared stress measure: Frobenius, or von Mises (plane problems embed
    /// the in-plane tensor with zero out-of-plane components).
    template <int dim, typename Number>
    Number
    stress_measure_squared(const Tensor<2, dim, Number> &s,
                           const bool                    von_mises)
    {
      Number ss = 0, tr = 0;
      for (unsigned int i = 0; i < dim; ++i)
        {
          tr += s[i][i];
          for (unsigned int j = 0; j < dim; ++j)
            ss += s[i][j] * s[i][j];
        }
      return von_mises ? Number(1.5) * (ss - tr * tr / Number(3.)) : ss;
    }

    // Penalty phi(z) = max(z, 0)^2 of thesis eq. 3.41.
    template <typename Number>
    Number
    positive_part_squared(const Number &z)
    {
      return z > 0 ? z * z : Number(0.);
    }

    double
    key(const std::map<std::string, double> &kv,
        const std::string                   &name,
        const double                         fallback,
        const std::string                   &where)
    {
      if (kv.count(name))
        return kv.at(name);
      AssertThrow(!std::isnan(fallback),
                  ExcMessage(where + ": the key '" + name + "' is required."));
      return fallback;
    }



    // A stress measure s (Frobenius or von Mises of f(grad u)): its L^p norm
    // (int s^p)^(1/p) (eq. 3.36), or with a bound s_t the penalty
    // int phi(s - s_t) (eq. 3.42).
    template <int dim>
    class StressTerm : public AutoDiffTerm<dim, StressTerm<dim>>
    {
    public:
      StressTerm(const std::string &name,
                 const double       weight,
                 const bool         von_mises,
                 const double       p,
                 const double       bound)
        : AutoDiffTerm<dim, StressTerm<dim>>(name, weight)
        , von_mises(von_mises)
        , p(p)
        , bound(bound)
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
          stress_measure_squared<dim, N>(stress<dim, N>(c, g, l, m), von_mises);
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
        const double v = std::pow(std::max(I[0], 0.), 1. / p);
        if (grad)
          *grad = {I[0] > 0 ? v / (p * I[0]) : 0.};
        return v;
      }

    private:
      const bool   von_mises;
      const double p;
      const double bound; ///< NaN: the L^p norm
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
        return scalar_product(stress<dim, N>(c, g, l, m), g);
      }
    };

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
    /**
     * The connection objectives of thesis ch. 2.3.5 on one side Gamma_S of
     * a contact interface (boundary id, material id of the side), for a
     * disassembly direction y (unit):
     * - assembly (eq. 2.17): int phi(-n . y) / |Gamma_S|;
     * - disassembly (eq. 2.18): int phi(u . y - u_tol) / |Gamma_S|;
     * - alignment (eq. 2.19): phi(W - int g_eps(n . y) / |Gamma_S|).
     * Integral 0 is the numerator, integral 1 the area |Gamma_S|.
     */
    template <int dim>
    class InterfaceTerm : public ObjectiveTerm<dim>
    {
    public:
      enum class Kind
      {
        assembly,
        disassembly,
        alignment
      };
      InterfaceTerm(const std::string           &name,
                    const double                 weight,
                    const Kind                   kind,
                    const types::boundary_id     boundary,
                    const types::material_id     material,
                    const Tensor<1, dim>        &direction,
                    const std::array<double, 3> &constants)
        : ObjectiveTerm<dim>(name, weight)
        , kind(kind)
        , boundary(boundary)
        , material(material)
        , y(direction / direction.norm())
        , constants(constants)
      {}
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        typename ObjectiveTerm<dim>::Integral i;
        i.boundary     = true;
        i.boundary_ids = {boundary};
        i.material_ids = {material};
        return {i, i};
      }
      bool
      depends_on_state() const override
      {
        return kind == Kind::disassembly;
      }
      void
      integrand(const unsigned int           k,
                const IntegrandContext<dim> &c,
                const Tensor<1, dim> &,
                const Tensor<1, dim> &u,
                const Tensor<2, dim> &,
                const double,
                const double,
                const bool           derivatives,
                IntegrandValue<dim> &r) const override
      {
        r = IntegrandValue<dim>();
        if (k == 1)
          {
            r.value = 1.;
            return;
          }
        // phi(z) = max(z, 0)^2 (eq. 2.16), phi'(z) = 2 max(z, 0).
        if (kind == Kind::assembly)
          {
            const double z = std::max(-(c.normal * y), 0.);
            r.value        = z * z;
            if (derivatives)
              r.d_n = -2. * z * y;
          }
        else if (kind == Kind::disassembly)
          {
            const double z = std::max(u * y - constants[0], 0.);
            r.value        = z * z;
            if (derivatives)
              r.d_u = 2. * z * y;
          }
        else
          {
            using AD   = Sacado::Fad::DFad<double>;
            const AD g = contact::alignment_g(AD(1, 0, c.normal * y),
                                              constants[1],
                                              constants[2]);
            r.value    = g.val();
            if (derivatives)
              r.d_n = g.dx(0) * y;
          }
      }
      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        AssertThrow(I[1] > 0,
                    ExcMessage(this->name + ": the interface side (boundary " +
                               std::to_string(boundary) + ", material " +
                               std::to_string(material) + ") has no area."));
        const double ratio = I[0] / I[1];
        if (kind != Kind::alignment)
          {
            if (grad)
              *grad = {1. / I[1], -ratio / I[1]};
            return ratio;
          }
        const double z = std::max(constants[0] - ratio, 0.);
        if (grad)
          *grad = {-2. * z / I[1], 2. * z * ratio / I[1]};
        return z * z;
      }

    private:
      const Kind                  kind;
      const types::boundary_id    boundary;
      const types::material_id    material;
      const Tensor<1, dim>        y;
      const std::array<double, 3> constants; ///< u_tol or (W, epsilon, beta)
    };

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
      void
      restrict_to_material(const types::material_id id) override
      {
        this->contact_bodies = {id};
      }
    };
  } // namespace



  void
  ObjectiveParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Objective");
    {
      prm.declare_entry(
        "Terms",
        "",
        Patterns::Anything(),
        "Records 'name : key=value, ...' separated by ';', all with an "
        "optional weight (default 1): 'stress : p=2' (L^p norm of the "
        "Frobenius stress, eq. 3.36), 'von mises : p=6', 'compliance', "
        "'volume', 'volume bound : bound=V' (eq. 3.40), 'volume target : "
        "target=V' ((V - target)^2, eq. 2.16), 'stress bound : "
        "bound=s' and 'von mises bound : bound=s' (eq. 3.42), 'target' and "
        "'boundary target : boundary=id' (eq. 3.37, see Target), 'center "
        "of mass : x=.., y=.., z=..' (eq. 3.38), 'height' (eq. 3.39), "
        "'boundary smoothing : p=2' (eq. 3.43, needs the shape block), "
        "'contact force : p=2' (IPC: |R|^p of the resultant R of the "
        "barrier contact forces on a body (material=id) or, without "
        "material, of the obstacles' push on all bodies), "
        "'material smoothing' (eq. 3.44, on per-cell Lame parameters), and on "
        "one side of a contact interface (boundary=id, material=id of the "
        "side whose normals count, the part that stays while the other is "
        "removed along the disassembly direction x=.., y=.., z=..): "
        "'assembly' (eq. 2.17), "
        "'disassembly : tolerance=u_tol' (eq. 2.18), 'alignment : "
        "target=W, epsilon=0.1, beta=1' (eqs. 2.19-2.20). The stress, "
        "compliance, volume, center of mass and height terms take "
        "'material=id' to integrate over one part only (e.g. the printed "
        "connectors of an assembly, the object a throw pushes).");
      prm.declare_entry("Time weighting",
                        "integral",
                        Patterns::Selection("integral|final"),
                        "Transient runs: integrate the terms over time "
                        "(trapezoidal rule, eq. 3.14) or take the final step.");
      prm.declare_entry(
        "Target",
        "",
        Patterns::Anything(),
        "Target deformed position of the material point (X, Y[, Z]) of the "
        "mesh as read, expressions in x, y[, z], t. Empty: the deformed "
        "positions of a reference run (the mesh without Design/Shape "
        "perturbation, with Reference bodies).");
      prm.declare_entry(
        "Target noise",
        "0",
        Patterns::Double(0),
        "Standard deviation (a length) of Gaussian noise added to every "
        "displacement value of the reference run's trajectory, the same for "
        "every run and rank count: a synthetic noisy recording for recovery "
        "studies. 0: exact targets.");
      prm.declare_entry(
        "Reference bodies",
        "",
        Patterns::Anything(),
        "Material records (as Material/Bodies) of the reference run; empty: "
        "Material/Bodies. Material recovery starts from Material/Bodies and "
        "seeks these.");
    }
    prm.leave_subsection();
  }



  void
  ObjectiveParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Objective");
    terms            = prm.get("Terms");
    time_weighting   = prm.get("Time weighting");
    target           = prm.get("Target");
    reference_bodies = prm.get("Reference bodies");
    target_noise     = prm.get_double("Target noise");
    prm.leave_subsection();
  }



  template <int dim>
  Objective<dim>::Objective(const Parameters &parameters,
                            const bool        state_terms_only)
    : parameters(parameters)
  {
    const std::string                    entry = "Objective/Terms";
    std::shared_ptr<FunctionParser<dim>> target;
    if (!parameters.target.empty())
      target = make_function<dim>(split_top_level(parameters.target, ','),
                                  std::vector<bool>(dim, true),
                                  {},
                                  "Objective/Target");
    const double none = std::numeric_limits<double>::quiet_NaN();
    for (const auto &record : split_top_level(parameters.terms, ';'))
      {
        if (Utilities::trim(record).empty())
          continue;
        const auto        colon = record.find(':');
        const std::string name  = Utilities::trim(record.substr(0, colon));
        const auto        kv    = parse_key_values(
          colon == std::string::npos ? "" : record.substr(colon + 1), entry);
        const std::string where = entry + ", term '" + name + "'";
        const double      w     = key(kv, "weight", 1., where);
        std::unique_ptr<ObjectiveTerm<dim>> t;
        if (name == "stress" || name == "von mises")
          {
            const double p = key(kv, "p", 2., where);
            AssertThrow(p >= 2,
                        ExcMessage(where + ": p must be at least 2 (got " +
                                   std::to_string(p) + ")."));
            t = std::make_unique<StressTerm<dim>>(
              name, w, name == "von mises", p, none);
          }
        else if (name == "compliance")
          t = std::make_unique<Compliance<dim>>(name, w);
        else if (name == "volume")
          t = std::make_unique<Volume<dim>>(name, w, none);
        else if (name == "volume bound")
          t = std::make_unique<Volume<dim>>(name,
                                            w,
                                            key(kv, "bound", none, where));
        else if (name == "volume target")
          t = std::make_unique<Volume<dim>>(name,
                                            w,
                                            key(kv, "target", none, where),
                                            true);
        else if (name == "stress bound" || name == "von mises bound")
          t = std::make_unique<StressTerm<dim>>(name,
                                                w,
                                                name == "von mises bound",
                                                2.,
                                                key(kv, "bound", none, where));
        else if (name == "target" || name == "boundary target")
          {
            std::set<types::boundary_id> ids;
            if (kv.count("boundary"))
              ids.insert(static_cast<types::boundary_id>(kv.at("boundary")));
            t = std::make_unique<Target<dim>>(
              name, w, name == "boundary target", ids, target);
          }
        else if (name == "boundary smoothing" || name == "material smoothing")
          {
            using R        = typename ObjectiveTerm<dim>::Regularization;
            const double p = key(kv, "p", 2., where);
            AssertThrow(p >= 1, ExcMessage(where + ": p must be at least 1."));
            t = std::make_unique<RegularizationTerm<dim>>(
              name,
              w,
              name == "boundary smoothing" ? R::boundary_smoothing :
                                             R::material_smoothing,
              p);
          }
        else if (name == "contact force")
          {
            const double p = key(kv, "p", 2., where);
            AssertThrow(p >= 2,
                        ExcMessage(where + ": p must be at least 2 (got " +
                                   std::to_string(p) + ")."));
            t = std::make_unique<ContactForceTerm<dim>>(name, w, p);
          }
        else if (name == "center of mass" || name == "height")
          {
            Tensor<1, dim> c;
            const char    *axes[3] = {"x", "y", "z"};
            if (name == "center of mass")
              for (unsigned int d = 0; d < dim; ++d)
                c[d] = key(kv, axes[d], none, where);
            t =
              std::make_unique<CenterOfMass<dim>>(name, w, name == "height", c);
          }
        else if (name == "assembly" || name == "disassembly" ||
                 name == "alignment")
          {
            using K = typename InterfaceTerm<dim>::Kind;
            Tensor<1, dim> y;
            const char    *axes[3] = {"x", "y", "z"};
            for (unsigned int d = 0; d < dim; ++d)
              y[d] = key(kv, axes[d], 0., where);
            AssertThrow(y.norm() > 0,
                        ExcMessage(where +
                                   ": give the disassembly direction "
                                   "(keys x, y" +
                                   std::string(dim == 3 ? ", z" : "") + ")."));
            const K kind = name == "assembly"    ? K::assembly :
                           name == "disassembly" ? K::disassembly :
                                                   K::alignment;
            const std::array<double, 3> constants = {
              {kind == K::disassembly ? key(kv, "tolerance", 0., where) :
                                        key(kv, "target", 0., where),
               key(kv, "epsilon", 0.1, where),
               key(kv, "beta", 1., where)}};
            AssertThrow(constants[1] > 0 && constants[2] >= 0,
                        ExcMessage(where + ": need epsilon > 0, beta >= 0."));
            auto id = [&](const std::string &k, const double top) {
              const double v = key(kv, k, none, where);
              AssertThrow(v >= 0 && v < top && v == std::floor(v),
                          ExcMessage(where + ": '" + k +
                                     "' must be an id (an integer >= 0)."));
              return static_cast<unsigned int>(v);
            };
            t = std::make_unique<InterfaceTerm<dim>>(
              name,
              w,
              kind,
              static_cast<types::boundary_id>(id("boundary", 255)),
              static_cast<types::material_id>(id("material", 255)),
              y,
              constants);
          }
        else
          AssertThrow(false,
                      ExcMessage(entry + ": unknown term '" + name +
                                 "' (see --print-parameters for the list)."));
        if (kv.count("material") && name != "assembly" &&
            name != "disassembly" && name != "alignment")
          {
            const double m = kv.at("material");
            AssertThrow(m >= 0 && m < 255 && m == std::floor(m),
                        ExcMessage(where + ": 'material' must be a material "
                                           "id (an integer >= 0)."));
            const bool volume_term =
              name == "stress" || name == "von mises" || name == "compliance" ||
              name == "volume" || name == "volume bound" ||
              name == "volume target" || name == "stress bound" ||
              name == "von mises bound" || name == "center of mass" ||
              name == "height" || name == "contact force";
            AssertThrow(volume_term,
                        ExcMessage(where + ": 'material' is not available "
                                           "for this term."));
            t->restrict_to_material(static_cast<types::material_id>(m));
          }
        if (!state_terms_only || t->depends_on_state())
          term_list.push_back(std::move(t));
      }
    AssertThrow(!term_list.empty() || state_terms_only,
                ExcMessage(entry + " is empty: give at least one term."));
  }



  template <int dim>
  double
  Objective<dim>::step_weight(const unsigned int i,
                              const unsigned int n,
                              const double       dt) const
  {
    if (parameters.time_weighting == "final")
      return i == n ? 1. : 0.;
    return (i == 0 || i == n) ? 0.5 * dt : dt;
  }



  template <int dim>
  bool
  Objective<dim>::needs_reference_run() const
  {
    for (const auto &t : term_list)
      if (t->needs_reference_run())
        return true;
    return false;
  }

  template class ObjectiveTerm<2>;
  template class ObjectiveTerm<3>;
  template class Objective<2>;
  template class Objective<3>;
} // namespace forma
