// An MPI rank that fails alone stops all ranks with one message: rank 1's
// mode throws while rank 0 waits for it in a collective. Without the
// driver's RankFailure the job would hang (rank 1 in MPI_Finalize, rank 0
// in the barrier); with it, rank 1 reports the error once and calls
// MPI_Abort, leaving its error in failed-rank-1.json. The test runs
// itself under mpirun (bounded by `timeout`) and checks the exit code, the
// error lines, that nothing was committed, the error file and that the
// run's log is kept; then that a run that succeeds commits and removes the
// error file.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/base/application.h>

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace forma;
using dealii::deallog;

namespace
{
  // Rank 1 fails unless `succeed`.
  int
  child(char *program, const bool succeed)
  {
    const ApplicationMode work{
      "work",
      [succeed](dealii::ParameterHandler &, const std::string &, RunContext &) {
        if (!succeed &&
            dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 1)
          AssertThrow(false, dealii::ExcMessage("rank 1 cannot go on"));
        MPI_Barrier(MPI_COMM_WORLD);
      }};
    const ApplicationDescription app{"rank-failure-test",
                                     "One rank fails alone.",
                                     {work},
                                     [](dealii::ParameterHandler &) {}};
    std::string prm    = FORMA_SOURCE_DIR "/tests/base/one_rank_fails.prm";
    char       *argv[] = {program, prm.data(), nullptr};
    return run_application(2, argv, app);
  }
} // namespace

int
main(int argc, char **argv)
{
  if (argc > 1)
    return child(argv[0], std::string(argv[1]) == "--succeed");

  initlog();
  namespace fs = std::filesystem;
  fs::remove_all("rank_failure_stops_job_output");
  // Run as root (CI), Open MPI wants to be told.
  const std::string command =
    std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                "timeout 300 ") +
    FORMA_MPIEXEC + " -np 2 " + argv[0] + " --child > child.out 2> child.err";
  const int status = std::system(command.c_str());
  deallog << "exit status: " << (WIFEXITED(status) ? "exited" : "signalled")
          << ", code " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
          << " (124 would be a hang)" << std::endl;

  std::ifstream in("child.err");
  std::string   line;
  unsigned int  errors = 0;
  while (std::getline(in, line))
    if (line.find("error:") != std::string::npos)
      {
        ++errors;
        deallog << line << std::endl;
      }
  deallog << errors << " error line(s)" << std::endl;
  deallog << "results committed: "
          << (fs::exists("rank_failure_stops_job_output/summary.json") ? "yes" :
                                                                         "no")
          << std::endl;
  // The failing rank left its error beside the results; the run's files
  // stay in the staging directory, which the next run keeps as
  // interrupted-run/.
  const auto marker =
    nlohmann::json::parse(read_file(
                            "rank_failure_stops_job_output/failed-rank-1.json"),
                          nullptr,
                          false);
  deallog << "failed-rank-1.json: status "
          << (marker.is_object() ? marker.value("status", "-") : "unreadable")
          << ", error '"
          << (marker.is_object() ? marker.value("error", "-") : "-")
          << "', rank "
          << (marker.is_object() ? marker.value("failed_rank", -1) : -1)
          << std::endl;
  deallog << "the run's log kept for the next run: "
          << (fs::exists(
                "rank_failure_stops_job_output/.forma-staging/log.txt") ?
                "yes" :
                "no")
          << std::endl;

  // A run that succeeds removes the error and keeps the failed run's log.
  const int again = std::system(
    (std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                 "timeout 300 ") +
     FORMA_MPIEXEC + " -np 2 " + argv[0] + " --succeed > child.out 2>&1")
      .c_str());
  deallog << "a run that succeeds: exit code "
          << (WIFEXITED(again) ? WEXITSTATUS(again) : -1)
          << ", results committed: "
          << (fs::exists("rank_failure_stops_job_output/summary.json") ? "yes" :
                                                                         "no")
          << ", failed-rank-1.json removed: "
          << (fs::exists("rank_failure_stops_job_output/failed-rank-1.json") ?
                "no" :
                "yes")
          << std::endl;
}
