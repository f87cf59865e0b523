#ifndef forma_base_rank_strided_h
#define forma_base_rank_strided_h

#include <deal.II/base/mpi.h>

#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <utility>
#include <vector>

namespace forma
{
  /**
   * Independent jobs shared among the ranks of `comm`: job i (of
   * `n_jobs`) runs `job(i)` on rank i % n_ranks, and every rank gets all
   * the results, in job order, so what follows does not depend on the
   * number of ranks. Each job runs on its rank alone (MPI_COMM_SELF
   * solves, e.g. one homogenization); T must be serializable (boost) for
   * the gather (include e.g. boost/serialization/array.hpp for arrays).
   * Collective: every rank calls it with the same n_jobs, and a job must
   * not throw (return its failure instead), or the other ranks would wait.
   */
  template <typename T, typename Job>
  std::vector<T>
  rank_strided(const MPI_Comm comm, const unsigned int n_jobs, Job &&job)
  {
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm),
                       rank    = dealii::Utilities::MPI::this_mpi_process(comm);
    std::vector<std::pair<unsigned int, T>> mine;
    for (unsigned int i = rank; i < n_jobs; i += n_ranks)
      mine.emplace_back(i, job(i));
    std::vector<T> all(n_jobs);
    for (auto &from : dealii::Utilities::MPI::all_gather(comm, mine))
      for (auto &[i, value] : from)
        all[i] = std::move(value);
    return all;
  }
} // namespace forma

#endif
