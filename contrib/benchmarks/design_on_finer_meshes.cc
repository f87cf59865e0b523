// The objective of an optimization's final design on its own mesh and on
// uniformly refined copies of it (issue 46, item 4): how accurate the J an
// optimization reports is, and what the design is worth. Reads the run's
// parameter file and its checkpoint (the last accepted design, and the
// refinement or remesh files if the run changed its mesh). The shape field is
// bilinear, so refined copies carry the same shape.
//   design_on_finer_meshes <file.prm> <output directory> <levels>
// Prints one line: n_dofs J, then n_dofs J per uniform refinement.

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/tria.h>

#include <forma/adjoint/objective.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

using namespace dealii;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  try
    {
      AssertThrow(argc == 4,
                  ExcMessage("usage: design_on_finer_meshes <file.prm> "
                             "<output directory> <levels>"));
      const std::string file = argv[1], directory = argv[2];
      const int         levels = std::stoi(argv[3]);
      ParameterHandler  prm;
      prm.declare_entry("Dimension", "2", Patterns::Integer(2, 3));
      prm.declare_entry("Output directory", "", Patterns::Anything());
      prm.declare_entry("Mode", "simulate", Patterns::Anything());
      forma::ElasticityParameters::declare(prm);
      prm.parse_input(file, "", true); // other apps' sections skipped
      forma::ElasticityParameters p;
      p.parse(prm, std::filesystem::path(file).parent_path().string());
      p.adaptivity = "h"; // a mesh that refines in place

      nlohmann::json checkpoint;
      std::ifstream(directory + "/optimization.checkpoint.json") >> checkpoint;
      forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
      s.prepare();
      s.set_objective(std::make_shared<const forma::Objective<2>>(p.objective));
      const std::string mesh = checkpoint.at("mesh");
      const std::string stem = directory + "/" + mesh;
      if (!mesh.empty() && std::filesystem::exists(stem + ".refinement.json"))
        s.load_refinement(stem);
      else if (!mesh.empty())
        s.load_remeshed(stem);
      s.set_design(checkpoint.at("design").get<std::vector<double>>());
      std::cout << std::setprecision(10);
      s.solve_design();
      std::cerr << "quality at quadrature points " << s.mesh_quality();
      s.guard_cell_corners(true);
      std::cerr << ", with corners " << s.mesh_quality() << std::endl;
      for (int level = 0;; ++level)
        {
          s.solve_design();
          std::cout << (level > 0 ? " " : "") << s.n_dofs() << ' '
                    << s.objective();
          if (level == levels)
            break;
          std::vector<std::string> all; // serial: every cell is here
          for (const auto &cell : s.triangulation().active_cell_iterators())
            all.push_back(cell->id().to_string());
          s.refine_design(all, "");
        }
      std::cout << std::endl;
    }
  catch (const std::exception &e)
    {
      std::cerr << "design_on_finer_meshes: " << e.what() << std::endl;
      return 1;
    }
}
