#ifndef forma_base_rank_failure_h
#define forma_base_rank_failure_h

#include <mpi.h>

namespace forma
{
  /**
   * A failure that some ranks see and the others do not. A rank whose work
   * throws while the others wait for it in a collective operation would leave
   * the job hanging (its MPI_Finalize waits for them too). So a failing rank
   * asks, on a communicator of its own that healthy ranks never touch,
   * whether every rank failed: if all did (the usual case, an error on data
   * every rank shares), they report it together; if the others do not join
   * within a short wait, the failing rank stops the job (the driver calls
   * MPI_Abort after reporting).
   */
  class RankFailure
  {
  public:
    /// Collective over comm (duplicates it). Without MPI, or on one rank,
    /// every failure is every rank's.
    explicit RankFailure(const MPI_Comm comm);

    ~RankFailure();

    RankFailure(const RankFailure &) = delete;
    RankFailure &
    operator=(const RankFailure &) = delete;

    /// Called by a rank that failed: whether every rank of comm has called
    /// this too, waiting at most `wait_seconds` for them. A later call
    /// waits on for the same agreement, so ranks that fail late still meet.
    bool
    every_rank_failed(const double wait_seconds);

  private:
    MPI_Comm    comm    = MPI_COMM_NULL;
    MPI_Request request = MPI_REQUEST_NULL;
    bool        started = false;
    bool        agreed  = false;
  };
} // namespace forma

#endif
