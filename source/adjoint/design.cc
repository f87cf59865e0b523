#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/parameterization.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace forma
{
  using namespace dealii;

  void
  DesignParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Design");
    {
      prm.declare_entry(
        "Parameters",
        "",
        Patterns::List(Patterns::Selection(parameterization_names()), 0),
        "What the design vector holds (comma-separated blocks, in this "
        "order in the vector):\n" +
          parameterization_documentation());
      prm.declare_entry("Material parameterization",
                        "E-nu",
                        Patterns::Selection("E-nu|lambda-mu"),
                        "Variables of the material blocks.");
      prm.declare_entry("Fixed boundaries",
                        "",
                        Patterns::List(Patterns::Integer(0), 0),
                        "Boundary ids whose vertices the shape may not move.");
      prm.declare_entry("Fixed bodies",
                        "",
                        Patterns::List(Patterns::Integer(0, 255), 0),
                        "Material ids of parts the shape may not change "
                        "(thesis Fig. 2.12, right: only some parts of an "
                        "assembly are optimized): every vertex of their "
                        "cells stays, interfaces with them included.");
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
      prm.declare_entry("Min scaled Jacobian",
                        "1e-3",
                        Patterns::Double(0, 1),
                        "A shape whose scaled Jacobian (det J over the "
                        "product of the column lengths, at the quadrature "
                        "points and, with Check corners, the cells' "
                        "corners) falls below this somewhere is rejected as "
                        "inverted or degenerate (thesis ch. 3.9).");
      prm.declare_entry(
        "Check corners",
        "true",
        Patterns::Bool(),
        "Check Min scaled Jacobian at the cells' corners as well as at the "
        "quadrature points (quad/hex meshes). A bilinear cell's Jacobian is "
        "smallest at a corner, and quadrature points alone let a cell fold "
        "there unseen: without this check bridge_stress's design folds a "
        "cell (-0.95 at a corner, 0.200 at its quadrature points). false "
        "reproduces results computed before the check was the default "
        "(Optimization/Outer step = refine checks the corners regardless: "
        "the children of a cell folded at a corner are inverted). In 3D the "
        "corners of a trilinear cell are a stronger check, not a proof.");
      prm.declare_entry(
        "Shape parameterization",
        "vertices",
        Patterns::Selection("vertices|boundary"),
        "vertices: every vertex is a design variable (thesis ch. 3). "
        "boundary: boundary vertices are, interior ones follow by harmonic "
        "extension, which keeps the interior mesh smooth.");
      prm.declare_entry("Bodies",
                        "",
                        Patterns::List(Patterns::Integer(0, 255), 0),
                        "Material ids whose 'per body' blocks are design "
                        "variables (e.g. the thrown object of a scene, not "
                        "its target); empty: every body.");
      prm.declare_entry(
        "Start",
        "",
        Patterns::Anything(),
        "Starting values of design blocks other than shape, records 'block : "
        "v1, v2, ...' separated by ';' (as many values as the block has, in "
        "its order), e.g. 'friction : 0.5 ; initial velocity : 0.5, 0'. The "
        "reference run of a target objective keeps the problem's own values "
        "(Material/Bodies or Objective/Reference bodies, IPC friction, "
        "initial conditions): a recovery starts here and seeks those. Empty: "
        "start at the problem's values.");
      prm.declare_entry(
        "Shape filter radius",
        "0",
        Patterns::Double(0),
        "Filter the shape design (vertex morphing): each vertex moves by the "
        "mean of the design entries within this distance on the mesh (hat "
        "weights, vertices of the same part), so L-BFGS works on a control "
        "field whose gradient is the filtered shape gradient: steps are "
        "smooth at this scale and do not depend on the mesh size, and the "
        "optimized boundary has no kinks for the mesh-quality guard to stop "
        "at. With Shape parameterization = boundary only boundary vertices "
        "are filtered. 0: none (each entry is its vertex's offset). "
        "Hold blocked vertices holds entries of the control field, which "
        "their neighbours still move.");
      prm.declare_entry(
        "Remesh boundary",
        "keep",
        Patterns::Selection("keep|resample"),
        "What a remesh does with the boundary and the interfaces. keep: every "
        "facet stays (only the interior is meshed anew). resample: the free "
        "boundary curves (2D) or surfaces (3D) and interfaces are resampled "
        "along their current shape (Remesh boundary size, Remesh feature "
        "angle), as the thesis's Algorithm 1 remeshes the whole domain; "
        "corners (2D) or feature edges (3D: where boundary ids and "
        "interfaces meet, and sharp edges), fixed boundaries, fixed bodies "
        "and cut interfaces (3D) stay, every part keeps its area or volume, "
        "and a resampling that fails is refused (the design stays on its "
        "mesh). 3D surfaces are remeshed isotropically by CGAL.");
      prm.declare_entry("Remesh boundary size",
                        "0",
                        Patterns::Double(0),
                        "Segment (2D) or edge (3D) length of a resampled "
                        "boundary; 0: the current local length, evened out "
                        "along each curve (2D), or the mean edge length of "
                        "the free surfaces (3D).");
      prm.declare_entry("Remesh feature angle",
                        "30",
                        Patterns::Double(0, 180),
                        "A boundary vertex where the curve turns by more "
                        "than this (degrees) is a corner that resampling "
                        "keeps; in 3D, an edge where the surface bends by "
                        "more is a feature edge that stays.");
      prm.declare_entry("Shape bound",
                        "0",
                        Patterns::Double(0),
                        "Largest displacement of a vertex from the mesh as "
                        "read, per coordinate, for optimizers; 0: none.");
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
      young_poisson        = prm.get("Material parameterization") == "E-nu";
      fixed_boundaries     = prm.get("Fixed boundaries");
      fixed_bodies         = prm.get("Fixed bodies");
      symmetry_planes      = prm.get("Symmetry planes");
      shape_perturbation   = prm.get("Shape perturbation");
      min_scaled_jacobian  = prm.get_double("Min scaled Jacobian");
      check_corners        = prm.get_bool("Check corners");
      shape_bound          = prm.get_double("Shape bound");
      start                = prm.get("Start");
      bodies               = prm.get("Bodies");
      boundary_shape       = prm.get("Shape parameterization") == "boundary";
      resample_boundary    = prm.get("Remesh boundary") == "resample";
      remesh_boundary_size = prm.get_double("Remesh boundary size");
      remesh_feature_angle = prm.get_double("Remesh feature angle");
      shape_filter_radius  = prm.get_double("Shape filter radius");
      AssertThrow(remesh_feature_angle > 0,
                  ExcMessage("Design/Remesh feature angle must be > 0 "
                             "degrees."));
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
