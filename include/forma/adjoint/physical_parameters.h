#ifndef forma_adjoint_physical_parameters_h
#define forma_adjoint_physical_parameters_h

#include <deal.II/base/exceptions.h>

#include <array>
#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

namespace forma
{
  /**
   * A physical parameter of the discrete problem (thesis eq. 3.3): what
   * forms read (a material field, load scales, friction coefficients, the
   * shape) and parameterizations set from the design. It also holds its
   * sensitivity dJ/dm = p^T dh/dm + dJ/dm, which forms and objective terms
   * add to during a gradient and parameterizations chain back to the design.
   */
  class PhysicalParameter
  {
  public:
    virtual ~PhysicalParameter() = default;

    /// Zero the sensitivity (the start of a gradient).
    virtual void
    clear_sensitivity() = 0;

    /// Back to the problem's own value, before any design applies (the
    /// simulator resets its built-in parameters itself).
    virtual void
    reset()
    {}

    /// Whether a parameterization reads the sensitivity: forms skip the
    /// products of the others.
    bool wanted = false;
  };

  /// A pair of coefficients per active cell, by active_cell_index().
  class CellPairs : public PhysicalParameter
  {
  public:
    std::vector<std::array<double, 2>> value, sensitivity;

    void
    clear_sensitivity() override
    {
      sensitivity.assign(value.size(), {{0., 0.}});
    }
  };

  /// The Lame pair (lambda, mu) of every cell, as given to Material (before
  /// the plane-stress reduction).
  class CellLame : public CellPairs
  {};

  /// The strain-rate damping pair (shear, bulk) of every cell.
  class CellDamping : public CellPairs
  {};

  /// A short list of scalars.
  class Scalars : public PhysicalParameter
  {
  public:
    std::vector<double> value, sensitivity;

    void
    clear_sensitivity() override
    {
      sensitivity.assign(value.size(), 0.);
    }
  };

  /// Scale factors of the loads: tractions and pressures in record order,
  /// then the body force and gravity where the problem has them. Each load
  /// form knows its `first` entry.
  class LoadScales : public Scalars
  {};

  /// Friction coefficients of IPC contact (one per friction source).
  class FrictionCoefficients : public Scalars
  {};

  /**
   * The physical parameters of one simulation, at most one of each type.
   * Forms and parameterizations find them by type, so a new form can bring
   * a parameter of its own and a new parameterization can set it.
   */
  class PhysicalParameters
  {
  public:
    /// Take `parameter`; returns it.
    template <class T>
    T &
    add(std::unique_ptr<T> parameter)
    {
      AssertThrow(find<T>() == nullptr,
                  dealii::ExcMessage(std::string("a physical parameter of "
                                                 "type ") +
                                     typeid(T).name() + " exists already."));
      T &result = *parameter;
      list.push_back(std::move(parameter));
      return result;
    }

    /// The parameter of type T, or null.
    template <class T>
    T *
    find() const
    {
      for (const auto &p : list)
        if (auto *t = dynamic_cast<T *>(p.get()))
          return t;
      return nullptr;
    }

    /// The sensitivity of type T where a parameterization wants it, else
    /// null: forms add their products through this.
    template <class T>
    T *
    wanted() const
    {
      T *t = find<T>();
      return t && t->wanted ? t : nullptr;
    }

    void
    clear_sensitivities()
    {
      for (const auto &p : list)
        p->clear_sensitivity();
    }

    void
    reset()
    {
      for (const auto &p : list)
        p->reset();
    }

    /// No sensitivity wanted (before the design's blocks are built).
    void
    clear_wanted()
    {
      for (const auto &p : list)
        p->wanted = false;
    }

  private:
    std::vector<std::unique_ptr<PhysicalParameter>> list;
  };
} // namespace forma

#endif
