// Objective terms on one side of a contact interface (thesis ch. 2.3.5):
// assembly, disassembly and alignment.

#include <forma/adjoint/auto_diff_term.h>
#include <forma/contact/smoothing.h>

#include <cmath>
#include <limits>
#include <memory>

namespace forma
{
  namespace
  {
    using namespace dealii;

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



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    interface_term(const TermRecord<dim>                  &r,
                   const typename InterfaceTerm<dim>::Kind kind)
    {
      using K = typename InterfaceTerm<dim>::Kind;
      Tensor<1, dim> y;
      const char    *axes[3] = {"x", "y", "z"};
      for (unsigned int d = 0; d < dim; ++d)
        y[d] = r.key(axes[d], 0.);
      AssertThrow(y.norm() > 0,
                  ExcMessage(r.where +
                             ": give the disassembly direction (keys x, y" +
                             std::string(dim == 3 ? ", z" : "") + ")."));
      const std::array<double, 3> constants = {
        {kind == K::disassembly ? r.key("tolerance", 0.) : r.key("target", 0.),
         r.key("epsilon", 0.1),
         r.key("beta", 1.)}};
      AssertThrow(constants[1] > 0 && constants[2] >= 0,
                  ExcMessage(r.where + ": need epsilon > 0, beta >= 0."));
      return std::make_unique<InterfaceTerm<dim>>(
        r.name,
        r.weight,
        kind,
        static_cast<types::boundary_id>(r.id("boundary")),
        static_cast<types::material_id>(r.id("material")),
        y,
        constants);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_assembly(const TermRecord<dim> &r)
    {
      return interface_term(r, InterfaceTerm<dim>::Kind::assembly);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_disassembly(const TermRecord<dim> &r)
    {
      return interface_term(r, InterfaceTerm<dim>::Kind::disassembly);
    }

    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_alignment(const TermRecord<dim> &r)
    {
      return interface_term(r, InterfaceTerm<dim>::Kind::alignment);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_assembly,
                              "assembly",
                              "boundary=id, material=id (the side whose "
                              "normals count, the part that stays), x=.., "
                              "y=..[, z=..] (the disassembly direction): "
                              "int max(-n . y, 0)^2 / |Gamma| (eq. 2.17)",
                              16)
FORMA_REGISTER_OBJECTIVE_TERM(make_disassembly,
                              "disassembly",
                              "as assembly, tolerance=u_tol: int max(u . y - "
                              "u_tol, 0)^2 / |Gamma| (eq. 2.18)",
                              17)
FORMA_REGISTER_OBJECTIVE_TERM(make_alignment,
                              "alignment",
                              "as assembly, target=W, epsilon=0.1, beta=1: "
                              "max(W - int g_eps(n . y) / |Gamma|, 0)^2 (eqs. "
                              "2.19-2.20)",
                              18)
