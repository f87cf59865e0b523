// The `shape` design block: vertex moves of the shape field.

#include <deal.II/dofs/dof_handler.h>

#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/shape_field.h>
#include <forma/adjoint/shape_filter.h>
#include <forma/mesh/harmonic_extension.h>

#include <memory>
#include <vector>

namespace forma
{
  namespace
  {
    using namespace dealii;

    /// One entry per shape DoF: its offset from the mesh; with a harmonic
    /// extension only the boundary entries count. With Design/Shape filter
    /// radius the entries are a control field whose filtered values
    /// (ShapeFilter) are the offsets.
    template <int dim>
    class ShapeParameterization : public Parameterization<dim>
    {
    public:
      explicit ShapeParameterization(const DesignContext<dim> &c)
        : shape(*c.physical.template find<ShapeField<dim>>())
        , extension(c.extension)
        , start(c.shape_start())
      {
        shape.wanted = true;
        if (const double r = c.parameters.shape_filter_radius; r > 0)
          filter = std::make_unique<ShapeFilter<dim>>(
            shape.dof_handler,
            r,
            [this](const types::global_dof_index i) {
              return !extension || extension->is_boundary(i);
            },
            [this](const types::global_dof_index i) {
              const auto *e = shape.constraints.get_constraint_entries(i);
              return e && e->empty() &&
                     shape.constraints.get_inhomogeneity(i) == 0;
            },
            c.comm);
        // The start (Design/Shape perturbation) is the shape it says: the
        // filter moves the vertices by A (q - start) from there.
        if (filter)
          {
            shift.resize(start.size());
            for (const auto i : shape.offset.locally_owned_elements())
              shift[i] = start[i] - filter->value(start.data(), i);
          }
      }

      unsigned int
      size() const override
      {
        return shape.dof_handler.n_dofs();
      }

      std::vector<double>
      initial() const override
      {
        return start;
      }

      void
      scales(const double *, const double length, double *s) const override
      {
        std::fill(s, s + size(), length);
      }

      void
      bounds(const double *,
             const double *center,
             const double  bound,
             double       *lower,
             double       *upper) const override
      {
        for (unsigned int i = 0; i < size(); ++i)
          {
            lower[i] = center[i] - bound;
            upper[i] = center[i] + bound;
          }
      }

      void
      apply(const double *q) override
      {
        for (const auto i : shape.offset.locally_owned_elements())
          shape.offset(i) = filter ? filter->value(q, i) + shift[i] : q[i];
        shape.offset.compress(VectorOperation::insert);
        if (extension)
          extension->extend(shape.offset); // the interior follows
      }

      void
      chain(const double *, double *dJ) const override
      {
        typename ShapeField<dim>::Vector g(shape.sensitivity);
        if (extension)
          extension->extend_transpose(g);
        for (const auto i : g.locally_owned_elements())
          if (filter)
            filter->add_transpose(i, g(i), dJ);
          else
            dJ[i] = g(i);
      }

      bool
      restarts_on_remesh() const override
      {
        return true;
      }

      DesignBlock::Summary
      summary() const override
      {
        return DesignBlock::Summary::vertex_offset;
      }

      bool
      has_start_values() const override
      {
        return false;
      }

    private:
      ShapeField<dim>                  &shape;
      HarmonicExtension<dim>           *extension;
      const std::vector<double>         start;
      std::unique_ptr<ShapeFilter<dim>> filter;
      /// start - A start: the filtered start is the start.
      std::vector<double> shift;
    };
  } // namespace
} // namespace forma

using forma::ShapeParameterization;
FORMA_REGISTER_PARAMETERIZATION(
  ShapeParameterization,
  "shape",
  "vertex positions of the shape field (offsets from the mesh)",
  0)
