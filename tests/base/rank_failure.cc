// A rank that fails alone: RankFailure tells it, after the wait, that the
// others went on (here rank 0 waits in a collective for rank 1, as a healthy
// rank would), so the driver can stop the job instead of hanging; a rank
// that fails later still meets it. Ranks that fail together agree at once.
// (rank_failure_stops_job: the driver's side.)

#include <deal.II/base/mpi.h>

#include <forma/base/rank_failure.h>

#include "../tests.h"

using namespace forma;
using dealii::deallog;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
  if (rank == 0)
    initlog();

  {
    RankFailure together(comm);
    const bool  agreed = together.every_rank_failed(60);
    const auto  ranks  = dealii::Utilities::MPI::sum(agreed ? 1 : 0, comm);
    deallog << "both ranks fail: " << ranks << " of 2 see every rank failed"
            << std::endl;
  }

  {
    RankFailure alone(comm);
    int         went_on = 0;
    if (rank == 1)
      went_on = alone.every_rank_failed(0.2) ? 0 : 1;
    // Rank 0 waits here for rank 1, a healthy rank in a collective.
    MPI_Barrier(comm);
    const bool late   = alone.every_rank_failed(60);
    const auto told   = dealii::Utilities::MPI::sum(went_on, comm);
    const auto agreed = dealii::Utilities::MPI::sum(late ? 1 : 0, comm);
    deallog << "rank 1 fails alone: told the others went on: "
            << (told == 1 ? "yes" : "no") << std::endl;
    deallog << "rank 0 fails later: " << agreed << " of 2 see every rank failed"
            << std::endl;
  }
}
