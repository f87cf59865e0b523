// The `damping` design block: (shear, bulk) damping per material id.

#include <deal.II/grid/tria.h>

#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>

#include <cmath>

namespace forma
{
  namespace
  {
    using namespace dealii;

    template <int dim>
    class DampingParameterization : public Parameterization<dim>
    {
    public:
      explicit DampingParameterization(const DesignContext<dim> &c)
        : tria(c.triangulation)
        , bodies(c.bodies)
        , damping(*c.physical.template find<CellDamping>())
      {
        AssertThrow(c.transient,
                    ExcMessage("Design/Parameters: 'damping' needs a "
                               "transient problem."));
        damping.wanted = true;
        for (const auto &b : bodies)
          body_index.emplace(b.first, body_index.size());
      }

      unsigned int
      size() const override
      {
        return 2 * bodies.size();
      }

      std::vector<double>
      initial() const override
      {
        std::vector<double> q;
        for (const auto &b : bodies)
          {
            q.push_back(b.second.damping_shear);
            q.push_back(b.second.damping_bulk);
          }
        return q;
      }

      void
      scales(const double *q0, const double, double *s) const override
      {
        this->magnitude_scales(q0, s);
      }

      void
      bounds(const double *,
             const double *,
             const double,
             double *lower,
             double *upper) const override
      {
        this->nonnegative_bounds(lower, upper);
      }

      void
      apply(const double *q) override
      {
        for (const auto &[id, k] : body_index)
          AssertThrow(q[2 * k] >= 0 && q[2 * k + 1] >= 0,
                      ExcMessage("Design (damping), material id " +
                                 std::to_string(id) +
                                 ": damping must be >= 0."));
        for (const auto &cell : tria.active_cell_iterators())
          if (!cell->is_artificial())
            {
              const unsigned int k = body_index.at(cell->material_id());
              damping.value[cell->active_cell_index()] = {
                {q[2 * k], q[2 * k + 1]}};
            }
      }

      void
      chain(const double *, double *dJ) const override
      {
        for (const auto &cell : tria.active_cell_iterators())
          if (!cell->is_artificial())
            {
              const unsigned int k = body_index.at(cell->material_id());
              const auto &v = damping.sensitivity[cell->active_cell_index()];
              dJ[2 * k] += v[0];
              dJ[2 * k + 1] += v[1];
            }
      }

    private:
      const Triangulation<dim>                              &tria;
      const std::map<types::material_id, MaterialProperties> bodies;
      CellDamping                                           &damping;
      std::map<types::material_id, unsigned int>             body_index;
    };
  } // namespace
} // namespace forma

using forma::DampingParameterization;
FORMA_REGISTER_PARAMETERIZATION(
  DampingParameterization,
  "damping",
  "strain-rate damping (shear, bulk) per material id (transient problems)",
  3)
