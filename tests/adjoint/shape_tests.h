// Shared by the shape-design tests of this directory (remesh,
// remesh_boundary, shape_filter, refine_design): the Taylor verdict they
// log, the two-material strip and the 3D tetrahedral cantilever they run,
// and the meshes they write.
#ifndef forma_tests_adjoint_shape_tests_h
#define forma_tests_adjoint_shape_tests_h

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>

#include <forma/elasticity/taylor_test.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

/// `tria` written as Gmsh `name` in the working directory (with its
/// boundary ids); returns the file's path.
template <int dim>
std::string
written_msh(const dealii::Triangulation<dim> &tria, const std::string &name)
{
  const std::string file = (std::filesystem::current_path() / name).string();
  std::ofstream     out(file);
  dealii::GridOut   grid_out;
  grid_out.set_flags(dealii::GridOutFlags::Msh(true));
  grid_out.write_msh(tria, out);
  return file;
}

/// A 3 x 1 strip of nx x ny cells and two materials (x < 1.5: 0, else 1)
/// with the colorized boundary ids of subdivided_hyper_rectangle, written
/// as `name`; returns the file's path.
inline std::string
two_material_strip(const unsigned int nx,
                   const unsigned int ny,
                   const std::string &name)
{
  dealii::Triangulation<2> tria;
  dealii::GridGenerator::subdivided_hyper_rectangle(
    tria, {nx, ny}, dealii::Point<2>(0, 0), dealii::Point<2>(3, 1), true);
  for (const auto &cell : tria.active_cell_iterators())
    cell->set_material_id(cell->center()[0] > 1.5 ? 1 : 0);
  return written_msh(tria, name);
}

/// The strip's problem: Q2 (plus `fe`, more Finite element entries),
/// clamped at x = 0, a traction at x = 3 and a pressure on top; the design
/// `blocks` from `perturbation`, Objective/Terms `terms`.
inline std::string
two_material_strip_prm(const std::string &mesh,
                       const std::string &blocks,
                       const std::string &perturbation,
                       const std::string &terms,
                       const std::string &fe = "")
{
  return "set Dimension = 2\n"
         "subsection Mesh\n set Source = file\n set File = " +
         mesh +
         "\nend\n"
         "subsection Finite element\n set Degree = 2\n" +
         fe +
         "end\n"
         "subsection Material\n set Bodies = 0 : E = 1e4, nu = 0.3; "
         "1 : E = 3e4, nu = 0.25\nend\n"
         "subsection Boundary conditions\n set Dirichlet = 0 : xy : 0, 0\n"
         " set Traction = 1 : 0, -50\n set Pressure = 3 : 20\nend\n"
         "subsection Solver\n set Newton relative tolerance = 1e-12\n"
         " set Newton absolute tolerance = 1e-14\nend\n"
         "subsection Design\n set Parameters = " +
         blocks + "\n set Fixed boundaries = 0\n set Shape perturbation = " +
         perturbation + "\nend\nsubsection Objective\n set Terms = " + terms +
         "\nend\n";
}

inline std::string
yes(const bool b)
{
  return b ? "yes" : "NO";
}

/// J at the simulator's design, solved anew.
template <int dim>
double
value(forma::ElasticitySimulator<dim> &s)
{
  s.set_design(s.design());
  s.solve_design();
  return s.objective();
}

/// "rate >= 1.9" or "FAILED, rates ..." of a 4-row Taylor test at the
/// simulator's design.
template <int dim>
std::string
taylor_verdict(forma::ElasticitySimulator<dim> &s)
{
  forma::GradientCheckParameters gc;
  gc.n_steps         = 4;
  const auto  r      = forma::taylor_test(s, gc);
  std::string result = r.min_rate >= 1.9 ? "rate >= 1.9" : "FAILED, rates";
  if (!(r.min_rate >= 1.9))
    for (const double x : r.rates)
      result += " " + std::to_string(x);
  return result;
}

/// J of `design` on the remeshed design that a second simulator restores
/// from the files of `stem` (what a resumed run does).
template <int dim>
double
restored_objective(const forma::ElasticityParameters                  &p,
                   const std::shared_ptr<const forma::Objective<dim>> &J,
                   const std::string                                  &stem,
                   const std::vector<double>                          &design)
{
  forma::ElasticitySimulator<dim> r(p, MPI_COMM_WORLD);
  r.prepare();
  r.set_objective(J);
  r.load_remeshed(stem);
  r.set_design(design);
  r.solve_design();
  return r.objective();
}

/// A 2 x 1 x 1 bar of P1 tetrahedra clamped at x = 0 (id 0), pulled down
/// at x = 2 (id 1), with a shape design; `design` adds entries to its
/// Design section, `terms` is Objective/Terms.
inline std::string
tetrahedral_bar(const std::string &design, const std::string &terms)
{
  return "set Dimension = 3\n"
         "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
         " set Generator arguments = 6, 3, 3 : 0, 0, 0 : 2, 1, 1 : true\n"
         " set Convert to simplices = true\nend\n"
         "subsection Finite element\n set Degree = 1\nend\n"
         "subsection Material\n set Bodies = * : E = 1e4, nu = 0.3\nend\n"
         "subsection Boundary conditions\n set Dirichlet = 0 : xyz : 0, 0, 0\n"
         " set Traction = 1 : 0, 0, -20\nend\n"
         "subsection Solver\n set Newton relative tolerance = 1e-12\n"
         " set Newton absolute tolerance = 1e-14\nend\n"
         "subsection Design\n set Parameters = shape\n"
         " set Fixed boundaries = 0\n" +
         design + "end\nsubsection Objective\n set Terms = " + terms +
         "\nend\n";
}

#endif
