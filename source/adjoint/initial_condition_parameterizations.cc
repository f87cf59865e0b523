// The initial-condition design blocks of transient problems (thesis ch.
// 3.5.3): a uniform vector, a vector per body, or a value per DoF added to
// the initial displacement or velocity.

#include <forma/adjoint/initial_conditions.h>
#include <forma/adjoint/parameterization.h>

#include <map>

namespace forma
{
  namespace
  {
    using namespace dealii;
    using Vector = InitialConditions::Vector;

    /// Common to the three: the offset vector of the displacement or the
    /// velocity, and its sensitivity.
    template <int dim, bool velocity>
    class InitialOffset : public Parameterization<dim>
    {
    public:
      explicit InitialOffset(const DesignContext<dim> &c, const char *block)
        : initial_conditions(c.physical.template find<InitialConditions>())
      {
        AssertThrow(c.transient && initial_conditions,
                    ExcMessage(std::string("Design/Parameters: '") + block +
                               "' needs a transient problem."));
        initial_conditions->wanted = true;
      }

    protected:
      Vector &
      offset() const
      {
        return velocity ? initial_conditions->velocity :
                          initial_conditions->displacement;
      }

      const Vector &
      sensitivity() const
      {
        return velocity ? initial_conditions->velocity_sensitivity :
                          initial_conditions->displacement_sensitivity;
      }

      InitialConditions *initial_conditions;
    };



    /// A uniform vector.
    template <int dim, bool velocity>
    class Uniform : public InitialOffset<dim, velocity>
    {
    public:
      explicit Uniform(const DesignContext<dim> &c)
        : InitialOffset<dim, velocity>(c,
                                       velocity ? "initial velocity" :
                                                  "initial displacement")
      {}

      unsigned int
      size() const override
      {
        return dim;
      }

      std::vector<double>
      initial() const override
      {
        return std::vector<double>(dim, 0.);
      }

      void
      apply(const double *q) override
      {
        Vector      &x = this->offset();
        const auto  &c = this->initial_conditions->component;
        unsigned int k = 0;
        for (const auto i : x.locally_owned_elements())
          x(i) = x(i) + q[c[k++]];
        x.compress(VectorOperation::insert);
      }

      void
      chain(const double *, double *dJ) const override
      {
        const Vector &g = this->sensitivity();
        const auto   &c = this->initial_conditions->component;
        unsigned int  k = 0;
        for (const auto i : g.locally_owned_elements())
          dJ[c[k++]] += g(i);
      }
    };



    /// A vector per material id of Design/Bodies.
    template <int dim, bool velocity>
    class PerBody : public InitialOffset<dim, velocity>
    {
    public:
      explicit PerBody(const DesignContext<dim> &c)
        : InitialOffset<dim, velocity>(c,
                                       velocity ?
                                         "initial velocity per body" :
                                         "initial displacement per body")
      {
        for (const auto id : c.design_bodies)
          body_index.emplace(id, body_index.size());
      }

      unsigned int
      size() const override
      {
        return dim * body_index.size();
      }

      std::vector<double>
      initial() const override
      {
        return std::vector<double>(size(), 0.);
      }

      void
      apply(const double *q) override
      {
        Vector &x = this->offset();
        for_each_entry([&](const types::global_dof_index i, const unsigned e) {
          x(i) = x(i) + q[e];
        });
        x.compress(VectorOperation::insert);
      }

      void
      chain(const double *, double *dJ) const override
      {
        const Vector &g = this->sensitivity();
        for_each_entry([&](const types::global_dof_index i, const unsigned e) {
          dJ[e] += g(i);
        });
      }

    private:
      /// f(DoF, design entry) for the owned DoFs of design bodies.
      template <typename F>
      void
      for_each_entry(const F &f) const
      {
        const auto  &ic = *this->initial_conditions;
        unsigned int k  = 0;
        for (const auto i : this->offset().locally_owned_elements())
          {
            const auto it = body_index.find(ic.body[k]);
            if (it != body_index.end())
              f(i, dim * it->second + ic.component[k]);
            ++k;
          }
      }

      std::map<types::material_id, unsigned int> body_index;
    };



    /// A value per displacement DoF.
    template <int dim, bool velocity>
    class Field : public InitialOffset<dim, velocity>
    {
    public:
      explicit Field(const DesignContext<dim> &c)
        : InitialOffset<dim, velocity>(c,
                                       velocity ? "initial velocity field" :
                                                  "initial displacement field")
      {}

      unsigned int
      size() const override
      {
        return this->offset().size();
      }

      std::vector<double>
      initial() const override
      {
        return std::vector<double>(size(), 0.);
      }

      void
      apply(const double *q) override
      {
        Vector &x = this->offset();
        for (const auto i : x.locally_owned_elements())
          x(i) = x(i) + q[i];
        x.compress(VectorOperation::insert);
      }

      void
      chain(const double *, double *dJ) const override
      {
        const Vector &g = this->sensitivity();
        for (const auto i : g.locally_owned_elements())
          dJ[i] = g(i);
      }

      bool
      lives_on_mesh() const override
      {
        return true;
      }
    };

    template <int dim>
    using InitialDisplacement = Uniform<dim, false>;
    template <int dim>
    using InitialVelocity = Uniform<dim, true>;
    template <int dim>
    using InitialDisplacementPerBody = PerBody<dim, false>;
    template <int dim>
    using InitialVelocityPerBody = PerBody<dim, true>;
    template <int dim>
    using InitialDisplacementField = Field<dim, false>;
    template <int dim>
    using InitialVelocityField = Field<dim, true>;
  } // namespace
} // namespace forma

using namespace forma;
FORMA_REGISTER_PARAMETERIZATION(InitialDisplacement,
                                "initial displacement",
                                "a uniform vector added to the initial "
                                "displacement",
                                6)
FORMA_REGISTER_PARAMETERIZATION(InitialVelocity,
                                "initial velocity",
                                "a uniform vector added to the initial "
                                "velocity",
                                7)
FORMA_REGISTER_PARAMETERIZATION(InitialDisplacementPerBody,
                                "initial displacement per body",
                                "a vector per material id of Design/Bodies "
                                "added to the initial displacement on that "
                                "body",
                                8)
FORMA_REGISTER_PARAMETERIZATION(InitialVelocityPerBody,
                                "initial velocity per body",
                                "a vector per material id of Design/Bodies "
                                "added to the initial velocity on that body "
                                "(a throw)",
                                9)
FORMA_REGISTER_PARAMETERIZATION(InitialDisplacementField,
                                "initial displacement field",
                                "a value per displacement DoF added to the "
                                "initial displacement",
                                10)
FORMA_REGISTER_PARAMETERIZATION(InitialVelocityField,
                                "initial velocity field",
                                "a value per displacement DoF added to the "
                                "initial velocity",
                                11)
