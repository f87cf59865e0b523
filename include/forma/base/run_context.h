#ifndef forma_base_run_context_h
#define forma_base_run_context_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace forma
{
  /**
   * What one application run writes and where. Results are staged in a
   * hidden directory inside the output directory and moved into place only
   * when the run succeeds, so a failing run never leaves half a result over
   * an earlier good one; the failed run's files (with summary.json saying
   * "status": "failed") are kept in `<output directory>/failed-run/`, a
   * killed run's (the staging directory it left) in `interrupted-run/` by the
   * next run; both until a run commits.
   *
   * Progress lines go to stdout (rank 0) and to the log file; the log file
   * may also receive timings, which stdout never does (tests compare stdout).
   */
  class RunContext
  {
  public:
    RunContext(const MPI_Comm comm, const std::string &output_directory);
    ~RunContext();

    /// Directory to write into during the run (the staging directory).
    const std::string &
    directory() const
    {
      return staging_directory;
    }

    /**
     * Path of a file directly in the output directory, outside the staging
     * area: for progress files that must survive a failed or killed run
     * (e.g. a sweep's checkpoint, read back to resume).
     */
    std::string
    persistent_path(const std::string &file_name) const;

    /**
     * Remove the persistent file `file_name` (see persistent_path()) when the
     * run commits, after its results are in place: a progress file the
     * complete result makes obsolete.
     */
    void
    remove_on_commit(const std::string &file_name);

    /// Path of a result file inside the staging directory.
    std::string
    path(const std::string &file_name) const;

    /// One line to stdout and the log (the log only when quiet).
    void
    print(const std::string &line) const;

    /// A quiet context prints to its log only: for runs nested in a job
    /// whose stdout tells the story (e.g. a fine-scale check).
    bool quiet = false;

    /// One line to the log only (timings, solver details).
    void
    log(const std::string &line) const;

    MPI_Comm
    communicator() const
    {
      return comm;
    }

    bool
    is_root() const
    {
      return dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    }

    /// The run summary; written as summary.json by commit() or fail().
    nlohmann::json summary;

    /// Write summary.json with status "ok" and move all results into place.
    void
    commit();

    /// Write summary.json with status "failed" and the error; keep the
    /// earlier results of the output directory untouched.
    void
    fail(const std::string &error);

  private:
    void
    write_summary() const;

    MPI_Comm                               comm;
    std::string                            output_directory;
    std::string                            staging_directory;
    mutable std::unique_ptr<std::ofstream> log_file;
    std::vector<std::string>               obsolete_on_commit;
    bool                                   finished = false;
  };
} // namespace forma

#endif
