// The mean displacement along a direction over the volume or a boundary: a
// linear functional of the state (a tip deflection, say), the classic goal
// of goal-oriented refinement.

#include <forma/adjoint/auto_diff_term.h>

#include <memory>

namespace forma
{
  namespace
  {
    using namespace dealii;

    // int u . d / int 1 over the volume or the faces with one boundary id.
    template <int dim>
    class MeanDisplacement : public AutoDiffTerm<dim, MeanDisplacement<dim>>
    {
    public:
      MeanDisplacement(const std::string                  &name,
                       const double                        weight,
                       const std::set<types::boundary_id> &ids,
                       const Tensor<1, dim>               &direction)
        : AutoDiffTerm<dim, MeanDisplacement<dim>>(name, weight)
        , ids(ids)
        , direction(direction)
      {}
      std::vector<typename ObjectiveTerm<dim>::Integral>
      integrals() const override
      {
        std::vector<typename ObjectiveTerm<dim>::Integral> i(2);
        for (auto &integral : i)
          {
            integral.boundary     = !ids.empty();
            integral.boundary_ids = ids;
            integral.material_ids = this->materials;
          }
        return i;
      }
      // k = 0: u . d; k = 1: the measure.
      template <typename N>
      N
      j(unsigned int k,
        const IntegrandContext<dim> &,
        const Tensor<1, dim, N> &,
        const Tensor<1, dim, N> &u,
        const Tensor<2, dim, N> &,
        const N &,
        const N &) const
      {
        if (k == 1)
          return N(1.);
        N v = N(0.);
        for (unsigned int d = 0; d < dim; ++d)
          v += u[d] * direction[d];
        return v;
      }
      double
      combine(const std::vector<double> &I,
              std::vector<double>       *grad) const override
      {
        if (grad)
          *grad = {1. / I[1], -I[0] / (I[1] * I[1])};
        return I[0] / I[1];
      }

    private:
      const std::set<types::boundary_id> ids;
      const Tensor<1, dim>               direction;
    };



    template <int dim>
    std::unique_ptr<ObjectiveTerm<dim>>
    make_mean_displacement(const TermRecord<dim> &r)
    {
      const Tensor<1, dim> d = axis_keys<dim>(r, 0.);
      AssertThrow(d.norm() > 0,
                  ExcMessage(r.where +
                             ": give the direction, e.g. y=-1 (x, y, z "
                             "default to 0)."));
      std::set<types::boundary_id> ids;
      if (r.keys.count("boundary"))
        ids.insert(static_cast<types::boundary_id>(r.id("boundary")));
      return std::make_unique<MeanDisplacement<dim>>(r.name, r.weight, ids, d);
    }
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_OBJECTIVE_TERM(make_mean_displacement,
                              "mean displacement",
                              "x=.., y=..[, z=..][, boundary=id]: the mean of "
                              "u . (x, y, z) over the volume or a boundary "
                              "(a linear goal, e.g. a tip deflection)",
                              19)
