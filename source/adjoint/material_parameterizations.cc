// The `material` (per body) and `cell material` (per cell) design blocks:
// (E, nu) or (lambda, mu) pairs that set each cell's Lame pair.

#include <deal.II/grid/tria.h>

#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>

#include <cmath>
#include <sstream>

namespace forma
{
  namespace
  {
    using namespace dealii;

    std::string
    fmt(const double v)
    {
      std::ostringstream s;
      s << v;
      return s.str();
    }

    /// Pairs of (E, nu) or (lambda, mu) setting CellLame; `slot(cell)` says
    /// which pair a cell takes.
    template <int dim>
    class MaterialPairs : public Parameterization<dim>
    {
    public:
      explicit MaterialPairs(const DesignContext<dim> &c)
        : tria(c.triangulation)
        , young_poisson(c.parameters.young_poisson)
        , lame(*c.physical.template find<CellLame>())
      {
        lame.wanted = true;
        for (const auto &b : c.bodies)
          body_index.emplace(b.first, body_index.size());
      }

      void
      scales(const double *q0, const double, double *s) const override
      {
        this->magnitude_scales(q0, s);
      }

      /// E within 1e-3..1e3 of its start, nu within [-0.5, 0.49]; lambda
      /// and mu within 1e-3..1e3 of theirs.
      void
      bounds(const double *q0,
             const double *,
             const double,
             double *lower,
             double *upper) const override
      {
        for (unsigned int i = 0; i < this->size(); ++i)
          if (young_poisson && i % 2 == 1)
            {
              lower[i] = -0.5;
              upper[i] = 0.49;
            }
          else
            {
              lower[i] = 1e-3 * std::abs(q0[i]);
              upper[i] = 1e3 * std::abs(q0[i]);
            }
      }

      void
      apply(const double *q) override
      {
        // Every pair is checked on every rank (a refusal must be
        // collective: optimizers shorten the step on it).
        std::vector<std::array<double, 2>> pairs(this->size() / 2);
        for (unsigned int k = 0; k < pairs.size(); ++k)
          pairs[k] = lame_pair(q[2 * k], q[2 * k + 1], where(k));
        for (const auto &cell : tria.active_cell_iterators())
          if (!cell->is_artificial())
            lame.value[cell->active_cell_index()] = pairs[slot(cell)];
      }

      void
      chain(const double *q, double *dJ) const override
      {
        // Ghost cells carry the regularization's share of their owner.
        for (const auto &cell : tria.active_cell_iterators())
          {
            if (cell->is_artificial())
              continue;
            const unsigned int    k = slot(cell);
            std::array<double, 2> v =
              lame.sensitivity[cell->active_cell_index()];
            if (young_poisson)
              {
                double jac[2][2];
                lame_from_young_poisson(q[2 * k], q[2 * k + 1], jac);
                v = {{v[0] * jac[0][0] + v[1] * jac[1][0],
                      v[0] * jac[0][1] + v[1] * jac[1][1]}};
              }
            dJ[2 * k] += v[0];
            dJ[2 * k + 1] += v[1];
          }
      }

    protected:
      /// The pair of a cell.
      virtual unsigned int
      slot(const typename Triangulation<dim>::active_cell_iterator &cell)
        const = 0;

      /// The pair `k` in errors.
      virtual std::string
      where(const unsigned int k) const = 0;

      std::array<double, 2>
      properties_pair(const MaterialProperties &m) const
      {
        return young_poisson ?
                 std::array<double, 2>{{m.youngs_modulus, m.poisson_ratio}} :
                 std::array<double, 2>{{m.lambda, m.mu}};
      }

      const Triangulation<dim>                  &tria;
      const bool                                 young_poisson;
      CellLame                                  &lame;
      std::map<types::material_id, unsigned int> body_index;

    private:
      std::array<double, 2>
      lame_pair(const double a, const double b, const std::string &w) const
      {
        std::array<double, 2> l = {{a, b}};
        if (young_poisson)
          {
            AssertThrow(a > 0 && b > -1 && b < 0.5,
                        ExcMessage(w + ": inadmissible E = " + fmt(a) +
                                   ", nu = " + fmt(b) +
                                   " (need E > 0, -1 < nu < 0.5)."));
            l = lame_from_young_poisson(a, b);
          }
        AssertThrow(l[1] > 0 && l[0] + 2. * l[1] / dim > 0,
                    ExcMessage(w + ": inadmissible lambda = " + fmt(l[0]) +
                               ", mu = " + fmt(l[1]) + "."));
        return l;
      }
    };



    /// A pair per material id of the mesh.
    template <int dim>
    class BodyMaterial : public MaterialPairs<dim>
    {
    public:
      explicit BodyMaterial(const DesignContext<dim> &c)
        : MaterialPairs<dim>(c)
        , bodies(c.bodies)
      {}

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
          for (const double v : this->properties_pair(b.second))
            q.push_back(v);
        return q;
      }

    private:
      unsigned int
      slot(const typename Triangulation<dim>::active_cell_iterator &cell)
        const override
      {
        return this->body_index.at(cell->material_id());
      }

      std::string
      where(const unsigned int k) const override
      {
        return "Design (material), material id " +
               std::to_string(std::next(bodies.begin(), k)->first);
      }

      const std::map<types::material_id, MaterialProperties> bodies;
    };



    /// A pair per active cell (global active cell index order).
    template <int dim>
    class CellMaterial : public MaterialPairs<dim>
    {
    public:
      explicit CellMaterial(const DesignContext<dim> &c)
        : MaterialPairs<dim>(c)
        , bodies(c.bodies)
        , comm(c.comm)
      {}

      unsigned int
      size() const override
      {
        return 2 * this->tria.n_global_active_cells();
      }

      std::vector<double>
      initial() const override
      {
        std::vector<double> q(size(), 0.);
        for (const auto &cell : this->tria.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto v =
                this->properties_pair(bodies.at(cell->material_id()));
              q[2 * cell->global_active_cell_index()]     = v[0];
              q[2 * cell->global_active_cell_index() + 1] = v[1];
            }
        Utilities::MPI::sum(q, comm, q);
        return q;
      }

      bool
      lives_on_mesh() const override
      {
        return true;
      }

      unsigned int
      entries_per_cell() const override
      {
        return 2;
      }

      DesignBlock::Summary
      summary() const override
      {
        return DesignBlock::Summary::max_change;
      }

    private:
      unsigned int
      slot(const typename Triangulation<dim>::active_cell_iterator &cell)
        const override
      {
        return cell->global_active_cell_index();
      }

      std::string
      where(const unsigned int k) const override
      {
        return "Design (cell material), cell " + std::to_string(k);
      }

      const std::map<types::material_id, MaterialProperties> bodies;
      const MPI_Comm                                         comm;
    };
  } // namespace
} // namespace forma

using forma::BodyMaterial;
using forma::CellMaterial;
FORMA_REGISTER_PARAMETERIZATION(
  CellMaterial,
  "cell material",
  "per-cell Lame pair or (E, nu) (Design/Material parameterization)",
  1)
FORMA_REGISTER_PARAMETERIZATION(BodyMaterial,
                                "material",
                                "Lame pair or (E, nu) per material id",
                                2)
