// A new force term, parameter and parameterization for forma, written
// outside the library: a Winkler foundation that supports the whole body,
//   h_i += int k u . phi_i,
// with a designable stiffness k.

#ifndef my_app_elastic_foundation_h
#define my_app_elastic_foundation_h

#include <forma/adjoint/form.h>
#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>

/// The foundation's stiffness k as a physical parameter (one value), with
/// its sensitivity dJ/dk.
class FoundationStiffness : public forma::Scalars
{
public:
  explicit FoundationStiffness(const double k)
    : problem_value(k)
  {
    value = {k};
  }

  /// The reference run of a recovery uses the problem's k.
  void
  reset() override
  {
    value = {problem_value};
  }

private:
  const double problem_value;
};

/// The form. Point terms only: forma contracts them with the shape
/// functions and differentiates them in the shape itself.
template <int dim>
class ElasticFoundation : public forma::Form<dim>
{
public:
  explicit ElasticFoundation(const FoundationStiffness &k);

  std::string
  name() const override
  {
    return "elastic foundation";
  }

  unsigned int
  needs() const override
  {
    return forma::Form<dim>::values;
  }

  bool
  has_cell_terms() const override
  {
    return true;
  }

  /// source k u, its tangent k, energy k |u|^2 / 2.
  void
  cell_terms(const forma::PointStates<dim> &s,
             forma::PointTerms<dim>        &t) const override;

  /// p^T dh/dk = int u . p.
  void
  cell_products(const forma::PointStates<dim>  &s,
                const forma::PointAdjoint<dim> &a,
                forma::PhysicalParameters      &parameters) const override;

private:
  const FoundationStiffness &k;
};

/// The design block `foundation stiffness`: k itself (k > 0).
template <int dim>
class FoundationStiffnessParameterization : public forma::Parameterization<dim>
{
public:
  explicit FoundationStiffnessParameterization(
    const forma::DesignContext<dim> &context);

  unsigned int
  size() const override
  {
    return 1;
  }

  std::vector<double>
  initial() const override
  {
    return {start};
  }

  void
  scales(const double *q0, const double, double *scale) const override;

  void
  bounds(const double *q0,
         const double *,
         const double,
         double *lower,
         double *upper) const override;

  void
  apply(const double *q) override;

  void
  chain(const double *, double *dJ) const override;

private:
  FoundationStiffness &k;
  const double         start;
};

#endif
