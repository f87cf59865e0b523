#include <deal.II/base/exceptions.h>

#include <forma/base/on_root.h>
#include <forma/base/run_context.h>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace forma
{
  namespace fs = std::filesystem;

  namespace
  {
    /// Whether `directory` takes another block: a probe written, closed
    /// and removed (a space query would misjudge blocks reserved for root,
    /// quotas and network file systems).
    bool
    room_left(const fs::path &directory)
    {
      const fs::path probe = directory / ".forma-space-probe";
      std::ofstream  out(probe, std::ios::binary);
      out << std::string(4096, '\0');
      out.close();
      const bool      written = !out.fail();
      std::error_code ignored;
      fs::remove(probe, ignored);
      return written;
    }
  } // namespace



  RunContext::RunContext(const MPI_Comm comm, const std::string &dir)
    : comm(comm)
    , output_directory(dir)
    , staging_directory((fs::path(dir) / ".forma-staging").string())
  {
    on_root_or_throw(
      comm,
      [&]() {
        fs::create_directories(output_directory);
        // A staging directory left behind is from a run that did not
        // finish (killed, typically; a failed one renames its own):
        // kept for inspection, its log above all, unless it is empty.
        if (fs::exists(staging_directory) && !fs::is_empty(staging_directory))
          {
            const fs::path interrupted =
              fs::path(output_directory) / "interrupted-run";
            fs::remove_all(interrupted);
            fs::rename(staging_directory, interrupted);
          }
        fs::remove_all(staging_directory);
        fs::create_directories(staging_directory);
        log_file = std::make_unique<std::ofstream>(path("log.txt").c_str());
        AssertThrow(*log_file, dealii::ExcMessage("log.txt cannot be written"));
      },
      "cannot use the output directory '" + dir + "'");
    summary["status"] = "running";
  }



  RunContext::~RunContext()
  {
    // An exception that bypassed fail() must still not touch earlier
    // results; the staging directory is left for inspection.
  }



  std::string
  RunContext::persistent_path(const std::string &file_name) const
  {
    return (fs::path(output_directory) / file_name).string();
  }



  void
  RunContext::remove_on_commit(const std::string &file_name)
  {
    obsolete_on_commit.push_back(file_name);
  }



  std::string
  RunContext::path(const std::string &file_name) const
  {
    return (fs::path(staging_directory) / file_name).string();
  }



  void
  RunContext::print(const std::string &line) const
  {
    if (is_root())
      {
        if (!quiet)
          std::cout << line << std::endl;
        if (log_file)
          *log_file << line << std::endl;
      }
  }



  void
  RunContext::log(const std::string &line) const
  {
    if (is_root() && log_file)
      *log_file << line << std::endl;
  }



  void
  RunContext::write_summary() const
  {
    if (is_root())
      {
        // Invalid UTF-8 in a string (say, from a user's file) is replaced,
        // not thrown: summary.json is written on the error path too.
        std::ofstream out(path("summary.json").c_str());
        out << summary.dump(2,
                            ' ',
                            false,
                            nlohmann::json::error_handler_t::replace)
            << std::endl;
      }
  }



  void
  RunContext::commit()
  {
    summary["status"] = "ok";
    write_summary();
    // Moved on root, failed on all ranks (a throw on root alone would leave
    // the others waiting).
    on_root_or_throw(
      comm,
      [&]() {
        log_file.reset();
        // Most writers do not check their streams, so a full disk would
        // pass unseen: results written onto one may be cut short, and do
        // not replace earlier ones.
        AssertThrow(room_left(staging_directory),
                    dealii::ExcMessage(
                      "the disk is full, so the results may be incomplete; "
                      "earlier results are kept"));
        fs::remove_all(fs::path(output_directory) / "failed-run");
        fs::remove_all(fs::path(output_directory) / "interrupted-run");
        // The errors of ranks that failed alone in earlier runs.
        for (const auto &entry : fs::directory_iterator(output_directory))
          {
            const std::string name = entry.path().filename().string();
            if (name.rfind("failed-rank-", 0) == 0)
              fs::remove(entry.path());
          }
        for (const auto &entry : fs::directory_iterator(staging_directory))
          {
            const fs::path target =
              fs::path(output_directory) / entry.path().filename();
            fs::remove_all(target);
            fs::rename(entry.path(), target);
          }
        fs::remove_all(staging_directory);
        // Only now that the results are in place: a kill before this
        // leaves e.g. a progress file to resume from.
        for (const auto &file : obsolete_on_commit)
          {
            std::error_code ignored;
            fs::remove(persistent_path(file), ignored);
          }
      },
      "cannot move the results into '" + output_directory + "'");
    finished = true;
  }



  void
  RunContext::fail(const std::string &error)
  {
    summary["status"] = "failed";
    summary["error"]  = error;
    try
      {
        write_summary();
      }
    catch (...)
      {
        // A full disk: the message on stderr is all there is.
      }
    if (is_root())
      {
        log_file.reset();
        // Never throw from here (it runs while an error is reported): a
        // staging directory removed meanwhile (e.g. by a second run into
        // the same directory) leaves nothing to keep.
        const fs::path  failed = fs::path(output_directory) / "failed-run";
        std::error_code ignored;
        fs::remove_all(failed, ignored);
        fs::rename(staging_directory, failed, ignored);
      }
    finished = true;
  }
} // namespace forma
