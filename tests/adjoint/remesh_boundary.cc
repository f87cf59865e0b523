// Remeshing with Design/Remesh boundary = resample (mesh/boundary_resampling.h)
// on a distorted design of two materials (P2 on triangles): the boundary
// curves and the interface are resampled, so the new mesh is better than
// one that keeps every boundary facet, and still
// - the volume is kept to 1e-3 and every boundary id survives, the fixed
//   (clamped) side keeps its faces;
// - the compliance changes only by discretization error;
// - the adjoint passes the Taylor test on the remeshed design;
// - a second simulator restores the remeshed design from its files.
// The same in 3D on P2 tetrahedra, the surfaces remeshed by CGAL
// (mesh/boundary_resampling.h), the clamped side kept.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include "../tests.h"
#include "shape_tests.h"

#include <filesystem>

using namespace dealii;

namespace
{
  // A 3 x 1 strip of two materials (x < 1.5: 0, else 1), triangles, with
  // the colorized boundary ids of subdivided_hyper_rectangle.
  std::string
  two_material_strip()
  {
    Triangulation<2> quads, tria;
    GridGenerator::subdivided_hyper_rectangle(
      quads, {12, 4}, Point<2>(0, 0), Point<2>(3, 1), true);
    GridGenerator::convert_hypercube_to_simplex_mesh(quads, tria);
    for (const auto &cell : tria.active_cell_iterators())
      cell->set_material_id(cell->center()[0] > 1.5 ? 1 : 0);
    for (const auto &face : tria.active_face_iterators())
      if (face->at_boundary())
        {
          const auto c = face->center();
          face->set_boundary_id(c[0] < 1e-12     ? 0 :
                                c[0] > 3 - 1e-12 ? 1 :
                                c[1] < 1e-12     ? 2 :
                                                   3);
        }
    return written_msh(tria, "two_materials.msh");
  }

  std::string
  prm(const std::string &mesh, const std::string &boundary)
  {
    return "set Dimension = 2\n"
           "subsection Mesh\n set Source = file\n set File = " +
           mesh +
           "\nend\n"
           "subsection Finite element\n set Degree = 2\nend\n"
           "subsection Material\n set Bodies = 0 : E = 1e4, nu = 0.3; "
           "1 : E = 3e4, nu = 0.25\nend\n"
           "subsection Boundary conditions\n set Dirichlet = 0 : xy : 0, 0\n"
           " set Traction = 1 : 0, -50\nend\n"
           "subsection Solver\n set Newton relative tolerance = 1e-12\n"
           " set Newton absolute tolerance = 1e-14\nend\n"
           "subsection Design\n set Parameters = shape\n"
           " set Fixed boundaries = 0\n"
           // Stretches the top and bottom sides unevenly and bends them.
           " set Shape perturbation = 0.1 * sin(2 * pi * x / 3) * "
           "(1 + sin(8 * pi * x / 3)) * (y - 0.5), "
           "0.15 * sin(pi * x / 3) * (y + 0.3)\n"
           " set Remesh boundary = " +
           boundary +
           "\nend\n"
           "subsection Objective\n set Terms = compliance; volume\nend\n";
  }

  template <int dim>
  std::pair<double, double>
  solved(forma::ElasticitySimulator<dim> &s)
  {
    s.set_design(s.design());
    s.solve_design();
    s.objective();
    const auto terms = s.objective_terms();
    return {terms[0].second, terms[1].second};
  }

  template <int dim>
  std::set<types::boundary_id>
  ids(const Triangulation<dim> &tria)
  {
    std::set<types::boundary_id> result;
    for (const auto &face : tria.active_face_iterators())
      if (face->at_boundary())
        result.insert(face->boundary_id());
    return Utilities::MPI::compute_set_union(result, MPI_COMM_WORLD);
  }

  unsigned int
  faces_on(const Triangulation<2> &tria, const types::boundary_id id)
  {
    unsigned int n = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          n +=
            cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == id;
    return Utilities::MPI::sum(n, MPI_COMM_WORLD);
  }

  double
  remeshed_quality(const std::string &mesh, const std::string &boundary)
  {
    const auto p =
      parameters_from_string<forma::ElasticityParameters>(prm(mesh, boundary));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<2>>(p.objective));
    solved(s);
    s.remesh("");
    return s.mesh_quality();
  }

  void
  resampled_2d(const std::string &mesh)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      prm(mesh, "resample"));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    const auto J = std::make_shared<const forma::Objective<2>>(p.objective);
    s.set_objective(J);
    const auto [c0, v0]        = solved(s);
    const auto        ids0     = ids(s.triangulation());
    const auto        clamped0 = faces_on(s.triangulation(), 0);
    const std::string stem =
      (std::filesystem::current_path() / "remeshed").string();
    s.remesh(stem);
    const auto [c1, v1] = solved(s);
    const double J1     = s.objective();

    const double q_keep = remeshed_quality(mesh, "keep");
    deallog << "2D triangles, two materials" << std::endl;
    check("better than a remesh keeping the boundary",
          s.mesh_quality() > q_keep);
    check("volume kept to 1e-3", std::abs(v1 - v0) < 1e-3 * v0);
    check("every boundary id kept", ids(s.triangulation()) == ids0);
    check("the clamped side keeps its faces",
          faces_on(s.triangulation(), 0) == clamped0);
    check("compliance changes by less than 1%", std::abs(c1 - c0) < 0.01 * c0);

    deallog << "  Taylor test on the resampled design: " << taylor_verdict(s)
            << std::endl;

    check("restored from files, same J",
          std::abs(restored_objective(p, J, stem, s.design()) - J1) <
            1e-10 * J1);
  }

  // The tetrahedral bar of shape_tests.h in two materials (x < 1: 0, else
  // 1), with the colorized boundary ids (0: x = 0, 1: x = 2, 2..5: y, z).
  std::string
  two_material_bar()
  {
    Triangulation<3> hexes, tria;
    GridGenerator::subdivided_hyper_rectangle(
      hexes, {6, 3, 3}, Point<3>(0, 0, 0), Point<3>(2, 1, 1), true);
    GridGenerator::convert_hypercube_to_simplex_mesh(hexes, tria);
    for (const auto &cell : tria.active_cell_iterators())
      cell->set_material_id(cell->center()[0] > 1 ? 1 : 0);
    for (const auto &face : tria.active_face_iterators())
      if (face->at_boundary())
        {
          const auto         c  = face->center();
          types::boundary_id id = 0;
          for (unsigned int d = 0; d < 3; ++d)
            if (std::abs(c[d]) < 1e-12)
              id = 2 * d;
            else if (std::abs(c[d] - (d == 0 ? 2 : 1)) < 1e-12)
              id = 2 * d + 1;
          face->set_boundary_id(id);
        }
    return written_msh(tria, "two_material_bar.msh");
  }

  // That bar at P2, its sides stretched and sheared unevenly.
  std::string
  prm_3d(const std::string &mesh, const std::string &boundary)
  {
    std::string prm =
      tetrahedral_bar(" set Shape perturbation = 0.2 * sin(pi * x) * "
                      "(1 + sin(3 * pi * x)) * (y - 0.5), "
                      "0.2 * sin(pi * x / 2) * (y + 0.3) * (z + 0.2), "
                      "0.25 * sin(pi * x) * sin(2 * pi * y) * z\n"
                      " set Remesh boundary = " +
                        boundary + "\n",
                      "compliance; volume");
    const auto replace = [&](const std::string &from, const std::string &to) {
      const auto at = prm.find(from);
      AssertThrow(at != std::string::npos, ExcInternalError());
      prm.replace(at, from.size(), to);
    };
    replace("Degree = 1", "Degree = 2");
    replace("Bodies = * : E = 1e4, nu = 0.3",
            "Bodies = 0 : E = 1e4, nu = 0.3; 1 : E = 3e4, nu = 0.25");
    replace(" set Generator = subdivided_hyper_rectangle\n"
            " set Generator arguments = 6, 3, 3 : 0, 0, 0 : 2, 1, 1 : true\n"
            " set Convert to simplices = true\n",
            " set Source = file\n set File = " + mesh + "\n");
    return prm;
  }

  template <int dim>
  double
  area_of(const Triangulation<dim> &tria, const types::boundary_id id)
  {
    double area = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() &&
              cell->face(f)->boundary_id() == id)
            area += cell->face(f)->measure();
    return Utilities::MPI::sum(area, MPI_COMM_WORLD);
  }

  double
  remeshed_quality_3d(const std::string &mesh, const std::string &boundary)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      prm_3d(mesh, boundary));
    forma::ElasticitySimulator<3> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<3>>(p.objective));
    solved(s);
    s.remesh("");
    return s.mesh_quality();
  }

  void
  resampled_3d(const std::string &mesh)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      prm_3d(mesh, "resample"));
    forma::ElasticitySimulator<3> s(p, MPI_COMM_WORLD);
    s.prepare();
    const auto J = std::make_shared<const forma::Objective<3>>(p.objective);
    s.set_objective(J);
    const auto [c0, v0]   = solved(s);
    const auto   ids0     = ids(s.triangulation());
    const double q0       = s.mesh_quality(),
                 clamped0 = area_of(s.triangulation(), 0);
    const std::string stem =
      (std::filesystem::current_path() / "remeshed_3d").string();
    s.remesh(stem);
    const auto [c1, v1] = solved(s);
    const double J1     = s.objective();

    const double q_keep = remeshed_quality_3d(mesh, "keep");
    deallog << "3D P2 tetrahedra, two materials" << std::endl;
    check("better than the design and than a remesh keeping the boundary",
          s.mesh_quality() > q0 && s.mesh_quality() > q_keep);
    check("volume kept to 1e-3", std::abs(v1 - v0) < 1e-3 * v0);
    check("every boundary id kept", ids(s.triangulation()) == ids0);
    check("the clamped side keeps its area",
          std::abs(area_of(s.triangulation(), 0) - clamped0) < 1e-12);
    check("compliance changes by less than 1%", std::abs(c1 - c0) < 0.01 * c0);
    deallog << "  Taylor test on the resampled design: " << taylor_verdict(s)
            << std::endl;

    check("restored from files, same J",
          std::abs(restored_objective(p, J, stem, s.design()) - J1) <
            1e-10 * J1);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const bool root = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  if (root)
    initlog();
  std::string mesh, bar;
  if (root)
    mesh = two_material_strip(), bar = two_material_bar();
  mesh = Utilities::MPI::broadcast(MPI_COMM_WORLD, mesh, 0);
  bar  = Utilities::MPI::broadcast(MPI_COMM_WORLD, bar, 0);
  resampled_2d(mesh);
  resampled_3d(bar);
}
