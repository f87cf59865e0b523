// A laminate sweep killed after some batches resumes from its progress file
// (SweepProgress, Sweep/Resume): the structures the file holds are taken
// over (a line cut short by the kill is left out), the rest computed, and
// the samples equal the uninterrupted sweep's bit for bit. A file written
// with other settings is refused, naming the setting; without Resume the
// file starts afresh. (contrib/fuzz/kill_resume.sh kills the app itself.)

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/laminate/study.h>
#include <forma/laminate/sweep_progress.h>

#include "../tests.h"

#include <fstream>
#include <sstream>

using namespace forma;
using dealii::deallog;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  if (root)
    initlog();

  dealii::ParameterHandler prm;
  laminate::declare_parameters(prm);
  prm.parse_input_from_string("subsection Grid\n"
                              "  set Cells along height = 37\n"
                              "end\n"
                              "subsection Sweep\n"
                              "  set Families        = hexagon, triangle\n"
                              "  set p1              = 0.7, 0.9\n"
                              "  set p2              = 0, 0.6\n"
                              "  set Beams per joint = 3\n"
                              "  set p4              = 0.6, 0.9\n"
                              "end\n");
  RunContext context(comm, "results");
  const auto setup = laminate::parse_setup(prm, context);
  const auto grid  = laminate::read_sweep_grid(prm);
  const std::map<std::string, std::string> settings = {
    {"Grid/Cells along height", "37"}, {"Sweep/p1", "0.7, 0.9"}};
  const std::string file  = "sweep_progress.csv";
  const auto        sweep = [&](const bool resume) {
    const laminate::SweepProgress progress(file,
                                           settings,
                                           resume,
                                           grid.structures.size(),
                                           laminate::n_fields,
                                           context);
    deallog << "  taken from the file: " << progress.n_done() << std::endl;
    return laminate::homogenize_all(
      grid.structures, setup, 37, context, &progress);
  };

  deallog << "uninterrupted sweep of " << grid.structures.size()
          << " structures:" << std::endl;
  const auto whole = sweep(false);

  // Killed while writing its third batch: the header, four rows and half a
  // line are left.
  if (root)
    {
      std::ifstream      in(file);
      std::ostringstream kept;
      std::string        line;
      for (unsigned int k = 0; k < 6 && std::getline(in, line); ++k)
        kept << (k < 5 ? line + "\n" : line.substr(0, line.size() / 2));
      in.close();
      std::ofstream(file) << kept.str();
    }
  MPI_Barrier(comm);
  deallog << "resumed:" << std::endl;
  const auto resumed = sweep(true);
  deallog << "  samples equal to the uninterrupted sweep's, bit for bit: "
          << (resumed == whole ? "yes" : "no") << std::endl;
  deallog << "resumed once more (the file is complete):" << std::endl;
  sweep(true);

  auto other                       = settings;
  other["Grid/Cells along height"] = "48";
  try
    {
      laminate::SweepProgress p(
        file, other, true, grid.structures.size(), laminate::n_fields, context);
      deallog << "other settings: taken over, WRONG" << std::endl;
    }
  catch (const std::exception &e)
    {
      deallog << "other settings: " << error_message(e) << std::endl;
    }
  deallog << "without Resume:" << std::endl;
  sweep(false);
}
