// Shared by the shape-design tests of this directory (remesh,
// remesh_boundary, shape_filter): the Taylor verdict they log, the 3D
// tetrahedral cantilever they run and the meshes they write.
#ifndef forma_tests_adjoint_shape_tests_h
#define forma_tests_adjoint_shape_tests_h

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
