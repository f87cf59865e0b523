#ifndef forma_adjoint_parameterization_h
#define forma_adjoint_parameterization_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/types.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/registry.h>
#include <forma/physics/material.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  class PhysicalParameters;
  template <int dim>
  class HarmonicExtension;

  /// What a parameterization may build on: the simulation's physical
  /// parameters, its mesh and its bodies.
  template <int dim>
  struct DesignContext
  {
    const DesignParameters                &parameters;
    PhysicalParameters                    &physical;
    const dealii::Triangulation<dim, dim> &triangulation;
    MPI_Comm                               comm;
    bool                                   transient;
    /// Material ids of the mesh (every rank), and their properties as given.
    const std::map<dealii::types::material_id, MaterialProperties> &bodies;
    /// Design/Bodies (default: every material id).
    const std::vector<dealii::types::material_id> &design_bodies;
    /// Interior moves by harmonic extension (boundary shapes), or null.
    HarmonicExtension<dim> *extension;
    /// The starting shape design (Design/Shape perturbation), per shape DoF.
    std::function<std::vector<double>()> shape_start;
  };

  /**
   * One block of the design vector q (thesis eq. 3.3): how its entries set
   * physical parameters and how the sensitivities of those parameters chain
   * back to the entries. Register a class with
   * FORMA_REGISTER_PARAMETERIZATION; `Design/Parameters` lists the names.
   */
  template <int dim>
  class Parameterization
  {
  public:
    using Context               = DesignContext<dim>;
    virtual ~Parameterization() = default;

    /// The number of entries.
    virtual unsigned int
    size() const = 0;

    /// The starting values: the problem as given.
    virtual std::vector<double>
    initial() const = 0;

    /// Per entry, the size of a meaningful move (optimizers and Taylor
    /// tests scale by it; `length` is the mesh's cell size).
    virtual void
    scales(const double *q0, const double length, double *scale) const;

    /// Admissible bounds around the start q0 (default: free). `center`
    /// and `bound` are the shape's (Design/Shape bound).
    virtual void
    bounds(const double *q0,
           const double *center,
           const double  bound,
           double       *lower,
           double       *upper) const;

    /// Set the physical parameters from q; throws with a message naming
    /// the entry where q is inadmissible.
    virtual void
    apply(const double *q) = 0;

    /// Add this rank's part of dJ/dq (summed over ranks by the caller) from
    /// the sensitivities of the physical parameters at q.
    virtual void
    chain(const double *q, double *dJ) const = 0;

    /// Blocks that live on the mesh (per cell, per DoF) cannot be carried
    /// over a remesh.
    virtual bool
    lives_on_mesh() const
    {
      return false;
    }

    /// Blocks of this many entries per active cell (in global active cell
    /// index order) are carried over a refinement: a refined cell's
    /// children take its entries. 0: not such a block.
    virtual unsigned int
    entries_per_cell() const
    {
      return 0;
    }

    /// How reports summarize the block.
    virtual DesignBlock::Summary
    summary() const
    {
      return DesignBlock::Summary::values;
    }

    /// Shape blocks start at zero on a remeshed mesh (its vertices are the
    /// current shape); after a refinement, at the shape carried over.
    virtual bool
    restarts_on_remesh() const
    {
      return false;
    }

    /// Whether Design/Start may set the block.
    virtual bool
    has_start_values() const
    {
      return true;
    }

  protected:
    /// scales(): the magnitude of the start (1 where it is zero).
    void
    magnitude_scales(const double *q0, double *scale) const;

    /// bounds(): at least zero, no upper bound.
    void
    nonnegative_bounds(double *lower, double *upper) const;
  };

  template <int dim>
  using ParameterizationRegistry =
    Registry<Parameterization<dim>, const DesignContext<dim> &>;
  extern template class Registry<Parameterization<2>, const DesignContext<2> &>;
  extern template class Registry<Parameterization<3>, const DesignContext<3> &>;

  /// Names and documentation of the registered parameterizations (the same
  /// for 2D and 3D).
  std::string
  parameterization_names(const std::string &separator = "|");
  std::string
  parameterization_documentation();
} // namespace forma

/**
 * Register `Class` (a template on dim with a constructor from
 * DesignContext<dim>) as the design block `name`; `rank` orders blocks in
 * the design vector (built-in blocks: 0-11; new ones: 1000 unless given).
 */
#define FORMA_REGISTER_PARAMETERIZATION(Class, name, documentation, rank) \
  namespace                                                               \
  {                                                                       \
    template <int dim>                                                    \
    struct Class##Registration                                            \
    {                                                                     \
      Class##Registration()                                               \
      {                                                                   \
        forma::ParameterizationRegistry<dim>::instance().add(             \
          name,                                                           \
          documentation,                                                  \
          [](const forma::DesignContext<dim> &c) {                        \
            return std::unique_ptr<forma::Parameterization<dim>>(         \
              new Class<dim>(c));                                         \
          },                                                              \
          rank);                                                          \
      }                                                                   \
    };                                                                    \
    const Class##Registration<2> Class##_registration_2d;                 \
    const Class##Registration<3> Class##_registration_3d;                 \
  }

#endif
