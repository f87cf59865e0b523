// Remeshing a design shape (Gmsh, mesh/remesh.h) keeps what an optimization
// relies on:
// - the geometry: every boundary and interface vertex stays, so the volume
//   of the current shape is unchanged, and the mesh quality improves;
// - the material coordinates: loads, supports and targets still refer to
//   the mesh as read. A target run remeshed at the undeformed design gives
//   J = 0; J of a distorted design changes only by discretization error;
// - the adjoint: the Taylor test passes on the remeshed design (shape and
//   material blocks, two materials with an interface);
// - the files: a second simulator restores the remeshed design from them.
// 2D quads with two materials, 3D tetrahedra; a hexahedral mesh is refused.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include "../tests.h"
#include "shape_tests.h"

#include <filesystem>

using namespace dealii;

namespace
{
  std::string
  prm_2d(const std::string &mesh,
         const std::string &perturbation,
         const std::string &terms)
  {
    return two_material_strip_prm(mesh, "shape, material", perturbation, terms);
  }

  void
  distorted_2d(const std::string &mesh)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      prm_2d(mesh,
             "0.45 * sin(2 * pi * x / 3) * sin(pi * y), "
             "0.1 * y * sin(2 * pi * x / 3)",
             "compliance; target"));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    const auto J = std::make_shared<const forma::Objective<2>>(p.objective);
    s.set_objective(J);

    const double q0 = s.mesh_quality();
    value(s);
    const auto   terms0 = s.objective_terms();
    const double off0   = s.max_shape_offset();
    const auto   stem =
      (std::filesystem::current_path() / "remeshed_2d").string();
    s.remesh(stem);
    const double q1     = s.mesh_quality();
    const double J1     = value(s);
    const auto   terms1 = s.objective_terms();
    const double off1   = s.max_shape_offset();

    deallog << "2D quads, two materials: quality " << rounded(q0, 2)
            << " -> better: " << yes(q1 > q0 + 0.1) << std::endl;
    deallog << "  remeshes: " << s.n_remeshes() << std::endl;
    // The target term measures x - X, whose bilinear interpolation on the
    // new cells differs from the old one by O(h^2): a few percent here.
    const double limits[] = {0.001, 0.06};
    for (unsigned int k = 0; k < terms0.size(); ++k)
      deallog << "  " << terms0[k].first << " changes by less than "
              << 100 * limits[k] << "%: "
              << yes(std::abs(terms1[k].second / terms0[k].second - 1) <
                     limits[k])
              << std::endl;
    {
      // Back at the material positions, the design is the mesh as read and
      // the target run's solution is reproduced exactly.
      auto       q = s.design();
      const auto c = s.material_offsets();
      for (unsigned int i = 0; i < q.size(); ++i)
        q[i] += c[i];
      s.set_design(q);
      s.solve_design();
      s.objective();
      deallog << "  design moved to the material positions: target J is zero: "
              << yes(std::abs(s.objective_terms()[1].second) < 1e-16)
              << std::endl;
      for (unsigned int i = 0; i < q.size(); ++i)
        q[i] -= c[i];
      s.set_design(q);
      s.solve_design();
    }
    deallog << "  max offset from the mesh as read within 5%: "
            << yes(std::abs(off1 - off0) < 0.05 * off0) << std::endl;
    deallog << "  Taylor test on the remeshed design: " << taylor_verdict(s)
            << std::endl;

    deallog << "  restored from files, same J: "
            << yes(std::abs(restored_objective(p, J, stem, s.design()) - J1) <
                   1e-10 * std::abs(J1))
            << std::endl;
  }

  void
  undeformed_2d(const std::string &mesh)
  {
    // Remeshing the undeformed strip: the target run on the new mesh must
    // see the same material points, so J = 0 there.
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      prm_2d(mesh, "0, 0", "target; volume"));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<2>>(p.objective));
    value(s);
    const double volume0 = s.objective_terms()[1].second;
    s.remesh("");
    value(s);
    const auto terms = s.objective_terms();
    deallog << "2D undeformed: target J after remeshing is zero: "
            << yes(std::abs(terms[0].second) < 1e-16) << std::endl;
    deallog << "  volume " << rounded(volume0, 8) << " -> "
            << rounded(terms[1].second, 8) << std::endl;
  }

  void
  tetrahedra_3d()
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      tetrahedral_bar(" set Shape perturbation = 0.3 * sin(pi * y) * "
                      "sin(pi * z) * x, 0.1 * sin(pi * x) * z, 0\n",
                      "compliance; volume"));
    forma::ElasticitySimulator<3> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<3>>(p.objective));
    value(s);
    const auto   terms0 = s.objective_terms();
    const double q0     = s.mesh_quality();
    s.remesh("");
    value(s);
    const auto terms1 = s.objective_terms();
    deallog << "3D tetrahedra: quality " << rounded(q0, 2)
            << " -> better: " << yes(s.mesh_quality() > q0 + 0.05) << std::endl;
    deallog << "  volume " << rounded(terms0[1].second, 8) << " -> "
            << rounded(terms1[1].second, 8) << std::endl;
    // P1 on a coarse mesh: the new mesh (sized by its boundary) changes
    // the discretization error more than in 2D.
    deallog << "  compliance changes by less than 10%: "
            << yes(std::abs(terms1[0].second - terms0[0].second) <
                   0.1 * terms0[0].second)
            << std::endl;
    deallog << "  Taylor test on the remeshed design: " << taylor_verdict(s)
            << std::endl;
  }

  void
  hexahedra_refused()
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      "set Dimension = 3\n"
      "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
      " set Generator arguments = 2, 1, 1 : 0, 0, 0 : 2, 1, 1 : true\nend\n"
      "subsection Material\n set Bodies = * : E = 1e4, nu = 0.3\nend\n"
      "subsection Boundary conditions\n set Dirichlet = 0 : xyz : 0, 0, 0\n"
      "end\nsubsection Design\n set Parameters = shape\nend\n"
      "subsection Objective\n set Terms = volume\nend\n");
    forma::ElasticitySimulator<3> s(p, MPI_COMM_WORLD);
    s.prepare();
    try
      {
        s.remesh("");
        deallog << "3D hexahedra: NOT refused" << std::endl;
      }
    catch (const ExceptionBase &e)
      {
        const std::string what = e.what();
        deallog << "3D hexahedra refused with a message: "
                << yes(what.find("remeshing: hexahedral meshes cannot be "
                                 "remeshed") != std::string::npos)
                << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    initlog();
  std::string mesh;
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    mesh = two_material_strip(24, 8, "two_materials.msh");
  mesh = Utilities::MPI::broadcast(MPI_COMM_WORLD, mesh, 0);
  distorted_2d(mesh);
  undeformed_2d(mesh);
  tetrahedra_3d();
  hexahedra_refused();
}
