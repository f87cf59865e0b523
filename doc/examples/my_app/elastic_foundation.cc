#include "elastic_foundation.h"

#include <forma/adjoint/auto_diff_term.h>

#include <cmath>

using namespace dealii;

template <int dim>
ElasticFoundation<dim>::ElasticFoundation(const FoundationStiffness &k)
  : k(k)
{}



template <int dim>
void
ElasticFoundation<dim>::cell_terms(const forma::PointStates<dim> &s,
                                   forma::PointTerms<dim>        &t) const
{
  const double kk = k.value[0];
  for (unsigned int q = 0; q < s.size(); ++q)
    {
      t.source[q] += kk * s.u[q];
      if (t.with_tangent)
        t.source_tangent[q] += kk;
      if (t.with_energy)
        t.energy += 0.5 * kk * (s.u[q] * s.u[q]) * s.JxW[q];
    }
}



template <int dim>
void
ElasticFoundation<dim>::cell_products(
  const forma::PointStates<dim>  &s,
  const forma::PointAdjoint<dim> &a,
  forma::PhysicalParameters      &parameters) const
{
  auto *sensitivity = parameters.wanted<FoundationStiffness>();
  if (!sensitivity)
    return;
  for (unsigned int q = 0; q < s.size(); ++q)
    sensitivity->sensitivity[0] += (s.u[q] * a.p[q]) * s.JxW[q];
}



/// `elastic foundation : k=..` in Loads/Additional forms: adds the
/// stiffness to the simulation's physical parameters.
template <int dim>
std::unique_ptr<forma::Form<dim>>
make_elastic_foundation(const forma::FormRecord<dim> &record)
{
  const double k = record.key("k");
  AssertThrow(k > 0, ExcMessage(record.where + ": k must be positive."));
  auto stiffness = std::make_unique<FoundationStiffness>(k);
  return std::make_unique<ElasticFoundation<dim>>(
    record.physical->add(std::move(stiffness)));
}



template <int dim>
FoundationStiffnessParameterization<dim>::FoundationStiffnessParameterization(
  const forma::DesignContext<dim> &context)
  : k([&]() -> FoundationStiffness & {
    auto *p = context.physical.template find<FoundationStiffness>();
    AssertThrow(p,
                ExcMessage("Design/Parameters: 'foundation stiffness' "
                           "needs the form 'elastic foundation' in "
                           "Loads/Additional forms."));
    return *p;
  }())
  , start(k.value[0])
{
  k.wanted = true;
}



template <int dim>
void
FoundationStiffnessParameterization<dim>::scales(const double *q0,
                                                 const double,
                                                 double *scale) const
{
  scale[0] = std::abs(q0[0]);
}



template <int dim>
void
FoundationStiffnessParameterization<dim>::bounds(const double *q0,
                                                 const double *,
                                                 const double,
                                                 double *lower,
                                                 double *upper) const
{
  lower[0] = 1e-3 * q0[0];
  upper[0] = 1e3 * q0[0];
}



template <int dim>
void
FoundationStiffnessParameterization<dim>::apply(const double *q)
{
  AssertThrow(q[0] > 0,
              ExcMessage("Design (foundation stiffness): k must be positive."));
  k.value = {q[0]};
}



template <int dim>
void
FoundationStiffnessParameterization<dim>::chain(const double *,
                                                double *dJ) const
{
  dJ[0] = k.sensitivity[0]; // this rank's part
}



/// A new objective term: int |u|^2, the mean squared deflection. Its
/// partials come from AutoDiffTerm.
template <int dim>
class SquaredDisplacement
  : public forma::AutoDiffTerm<dim, SquaredDisplacement<dim>>
{
public:
  using forma::AutoDiffTerm<dim, SquaredDisplacement<dim>>::AutoDiffTerm;

  template <typename N>
  N
  j(unsigned int,
    const forma::IntegrandContext<dim> &,
    const Tensor<1, dim, N> &,
    const Tensor<1, dim, N> &u,
    const Tensor<2, dim, N> &,
    const N &,
    const N &) const
  {
    return u * u;
  }
};

template <int dim>
std::unique_ptr<forma::ObjectiveTerm<dim>>
make_squared_displacement(const forma::TermRecord<dim> &record)
{
  return std::make_unique<SquaredDisplacement<dim>>(record.name, record.weight);
}

template class ElasticFoundation<2>;
template class ElasticFoundation<3>;

FORMA_REGISTER_FORM(make_elastic_foundation,
                    "elastic foundation",
                    "k=..: a Winkler foundation int k u . v under the body")
FORMA_REGISTER_PARAMETERIZATION(FoundationStiffnessParameterization,
                                "foundation stiffness",
                                "the stiffness k of the elastic foundation",
                                1000)
FORMA_REGISTER_OBJECTIVE_TERM(make_squared_displacement,
                              "squared displacement",
                              "int |u|^2 (my_app)",
                              1000)
