#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/adjoint/design.h>

#include <algorithm>

namespace forma
{
  using namespace dealii;

  namespace
  {
    const char *block_names =
      "shape|cell material|material|damping|loads|initial displacement|"
      "initial velocity";
  }

  void
  DesignParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Design");
    {
      prm.declare_entry(
        "Parameters",
        "",
        Patterns::List(Patterns::Selection(block_names), 0),
        "What the design vector holds (comma-separated): shape (vertex "
        "positions), cell material (per-cell Lame or E/nu), material (per "
        "material id), damping (shear and bulk per material id), loads (scale "
        "factors of tractions, body force, gravity), initial displacement, "
        "initial velocity (uniform vectors).");
      prm.declare_entry("Material parameterization",
                        "E-nu",
                        Patterns::Selection("E-nu|lambda-mu"),
                        "Variables of the material blocks.");
      prm.declare_entry("Fixed boundaries",
                        "",
                        Patterns::List(Patterns::Integer(0), 0),
                        "Boundary ids whose vertices the shape may not move.");
      prm.declare_entry("Symmetry planes",
                        "",
                        Patterns::Anything(),
                        "Records 'id : axis' (axis x, y or z): vertices on "
                        "boundary id keep that coordinate, e.g. '3 : x'.");
      prm.declare_entry(
        "Shape perturbation",
        "",
        Patterns::Anything(),
        "Displacement of the vertices of the initial design from the mesh as "
        "read, one expression per component in x, y (, z); used to start a "
        "shape recovery away from the true shape. Empty: none.");
    }
    prm.leave_subsection();
  }



  void
  DesignParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Design");
    {
      blocks.clear();
      for (const auto &b :
           Utilities::split_string_list(prm.get("Parameters"), ','))
        {
          AssertThrow(std::find(blocks.begin(), blocks.end(), b) ==
                        blocks.end(),
                      ExcMessage("Design/Parameters lists '" + b + "' twice."));
          blocks.push_back(b);
        }
      young_poisson      = prm.get("Material parameterization") == "E-nu";
      fixed_boundaries   = prm.get("Fixed boundaries");
      symmetry_planes    = prm.get("Symmetry planes");
      shape_perturbation = prm.get("Shape perturbation");
    }
    prm.leave_subsection();
  }



  bool
  DesignParameters::has(const std::string &block) const
  {
    return std::find(blocks.begin(), blocks.end(), block) != blocks.end();
  }



  unsigned int
  DesignLayout::size() const
  {
    return blocks.empty() ? 0 : blocks.back().offset + blocks.back().size;
  }



  const DesignBlock *
  DesignLayout::find(const std::string &name) const
  {
    for (const auto &b : blocks)
      if (b.name == name)
        return &b;
    return nullptr;
  }
} // namespace forma
