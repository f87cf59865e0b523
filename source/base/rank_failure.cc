#include <deal.II/base/mpi.h>

#include <forma/base/rank_failure.h>

#include <chrono>
#include <thread>

namespace forma
{
  RankFailure::RankFailure(const MPI_Comm world)
  {
    if (dealii::Utilities::MPI::job_supports_mpi() &&
        dealii::Utilities::MPI::n_mpi_processes(world) > 1)
      MPI_Comm_dup(world, &comm);
  }



  RankFailure::~RankFailure()
  {
    // A barrier still open (the others went on) is left with its
    // communicator: that rank is about to stop the job anyway.
    if (comm != MPI_COMM_NULL && (!started || agreed))
      MPI_Comm_free(&comm);
  }



  bool
  RankFailure::every_rank_failed(const double wait_seconds)
  {
    if (comm == MPI_COMM_NULL || agreed)
      return true;
    if (!started)
      {
        MPI_Ibarrier(comm, &request);
        started = true;
      }
    // Polled, not waited for: a healthy rank never enters this barrier.
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration<double>(wait_seconds);
    do
      {
        int done = 0;
        MPI_Test(&request, &done, MPI_STATUS_IGNORE);
        if (done)
          return agreed = true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    } while (std::chrono::steady_clock::now() < deadline);
    return false;
  }
} // namespace forma
