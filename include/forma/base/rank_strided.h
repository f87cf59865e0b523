#ifndef forma_base_rank_strided_h
#define forma_base_rank_strided_h

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/base/application.h>

#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <algorithm>
#include <string>
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
   * Collective: every rank calls it with the same n_jobs. A job that
   * throws does not leave the other ranks waiting: all jobs finish, then
   * every rank throws the error of the first failed job.
   */
  template <typename T, typename Job>
  std::vector<T>
  rank_strided(const MPI_Comm comm, const unsigned int n_jobs, Job &&job)
  {
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm),
                       rank    = dealii::Utilities::MPI::this_mpi_process(comm);
    std::vector<std::pair<unsigned int, T>> mine;
    std::pair<unsigned int, std::string>    error{n_jobs, ""};
    for (unsigned int i = rank; i < n_jobs; i += n_ranks)
      try
        {
          mine.emplace_back(i, job(i));
        }
      catch (const std::exception &e)
        {
          if (error.first == n_jobs)
            error = {i, error_message(e)};
        }
    for (const auto &e : dealii::Utilities::MPI::all_gather(comm, error))
      if (e.first < error.first)
        error = e;
    AssertThrow(error.first == n_jobs, dealii::ExcMessage(error.second));
    std::vector<T> all(n_jobs);
    for (auto &from : dealii::Utilities::MPI::all_gather(comm, mine))
      for (auto &[i, value] : from)
        all[i] = std::move(value);
    return all;
  }



  /**
   * How many of `n_jobs` to give rank_strided() at a time so that a run
   * reports progress about `n_steps` times: a multiple of the ranks, since
   * the ranks wait for each other at every batch's end and a batch of
   * 7 on 2 ranks leaves one idle for a job.
   */
  inline unsigned int
  progress_batch_size(const unsigned int n_jobs,
                      const unsigned int n_steps,
                      const unsigned int n_ranks)
  {
    const unsigned int jobs = n_jobs / std::max(1u, n_steps) + 1;
    return (jobs + n_ranks - 1) / n_ranks * n_ranks;
  }
} // namespace forma

#endif
