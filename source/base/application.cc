#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <forma/adjoint/registry.h>
#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/parameter_override.h>
#include <forma/base/parameter_reference.h>
#include <forma/base/rank_failure.h>
#include <forma/base/replace_file.h>
#include <forma/base/safe_text.h>

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>

namespace forma
{
  std::string
  error_message(const std::exception &exc)
  {
    // deal.II's writers (DataOut, GridOut) say only "an input/output
    // error" with a page of generic advice.
    if (dynamic_cast<const dealii::StandardExceptions::ExcIO *>(&exc))
      return "an input/output error: a file could not be read or written "
             "in full (is the disk full, or a directory missing or not "
             "writable?)";
    std::string text;
    if (const auto *deal_exc =
          dynamic_cast<const dealii::ExceptionBase *>(&exc))
      {
        std::ostringstream out;
        deal_exc->print_info(out);
        text = out.str();
      }
    else
      text = exc.what();
    // Trim and fold deal.II's indented multi-line messages into one block.
    while (!text.empty() &&
           std::isspace(static_cast<unsigned char>(text.back())))
      text.pop_back();
    const auto first = text.find_first_not_of(" \t\n");
    // Messages quote user data (a mesh file's bytes, a parameter value):
    // escaped and cut, they print and go into summary.json safely.
    return first == std::string::npos ? std::string("unknown error") :
                                        safe_text(text.substr(first), 1000);
  }



  namespace
  {
    void
    declare_common(dealii::ParameterHandler     &prm,
                   const ApplicationDescription &app)
    {
      prm.declare_entry("Dimension",
                        "2",
                        dealii::Patterns::Integer(2, 3),
                        "Space dimension of the problem (2 or 3).");
      prm.declare_entry(
        "Additional shared libraries",
        "",
        dealii::Patterns::Anything(),
        "Shared libraries (comma-separated, relative to the parameter file) "
        "loaded before the parameters are read: plugins that register forms, "
        "parameterizations or objective terms (FORMA_REGISTER_FORM, "
        "FORMA_REGISTER_PARAMETERIZATION, FORMA_REGISTER_OBJECTIVE_TERM), "
        "whose names the parameters may then use.");
      prm.declare_entry(
        "Output directory",
        "output",
        dealii::Patterns::DirectoryName(),
        "Where results go (relative to the working directory). "
        "Results are written only when the run succeeds; a "
        "failed run leaves its files in <Output directory>/failed-run.");
      std::string selection;
      for (const auto &m : app.modes)
        selection += (selection.empty() ? "" : "|") + m.name;
      prm.declare_entry("Mode",
                        app.modes.front().name,
                        dealii::Patterns::Selection(selection),
                        "The job to run.");
      app.declare_parameters(prm);
    }



    /**
     * Load the plugins of `set Additional shared libraries = ...` in the
     * parameter file (top level), before any parameter is declared: the
     * parameters' lists of names come from what they register.
     */
    void
    load_shared_libraries(const std::string &file)
    {
      const std::regex entry(
        R"(^\s*set\s+Additional shared libraries\s*=\s*([^#]*?)\s*(#.*)?$)");
      AssertThrow(registration_conflicts().empty(),
                  dealii::ExcMessage("'" + registration_conflicts().front() +
                                     "' is registered twice (the library or "
                                     "the application)."));
      std::ifstream in(file);
      std::string   line;
      auto          directory = std::filesystem::path(file).parent_path();
      if (directory.empty())
        directory = "."; // a bare name would be searched on the library path
      while (std::getline(in, line))
        {
          std::smatch m;
          if (!std::regex_match(line, m, entry))
            continue;
          for (const auto &name : dealii::Utilities::split_string_list(m[1]))
            {
              const auto path = std::filesystem::path(name).is_absolute() ?
                                  std::filesystem::path(name) :
                                  directory / name;
              AssertThrow(dlopen(path.c_str(), RTLD_NOW) != nullptr,
                          dealii::ExcMessage(
                            "Additional shared libraries: cannot load '" +
                            name + "' (" + std::string(dlerror()) + ")."));
              auto &conflicts = registration_conflicts();
              AssertThrow(conflicts.empty(),
                          dealii::ExcMessage("Additional shared libraries: '" +
                                             name + "' registers '" +
                                             conflicts.front() +
                                             "', a name taken already."));
            }
        }
    }



    void
    print_usage(const ApplicationDescription &app)
    {
      std::cout
        << "Usage: " << app.name
        << " FILE.prm [--set 'Section/Entry=value' ...]\n"
        << "       " << app.name << " --print-parameters\n"
        << "       " << app.name << " --parameter-reference\n"
        << "       " << app.name << " --help\n\n"
        << app.description << "\n\n"
        << "FILE.prm is a deal.II parameter file; it may 'include' other "
           "files, and a later 'set' overrides an earlier one.\n"
        << "--set overrides one entry after FILE.prm is read, e.g. --set "
           "'Output directory=results/run2' or --set "
           "'Optimization/Max iterations=10'.\n"
        << "--print-parameters lists every parameter with its "
           "documentation and default value; --parameter-reference writes "
           "the same as Markdown with the allowed values "
           "(doc/parameters/).\n";
    }
  } // namespace



  namespace
  {
    // How long a failing rank waits for the others to fail as well (the same
    // error, reached a little later) before it stops the job alone.
    constexpr double rank_failure_wait_seconds = 10;



    /// An error on rank 0 (every rank meets the same one here).
    void
    report(const ApplicationDescription &app, const std::string &msg)
    {
      if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
        std::cerr << app.name << ": error: " << msg << std::endl;
    }



    /// Usage, --help, --parameter-reference and --print-parameters: the exit
    /// code if argv asks for one of them (or is malformed), else nothing.
    std::optional<int>
    informational(int argc, char **argv, const ApplicationDescription &app)
    {
      const bool root =
        dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
      if (argc < 2 || argc % 2 != 0)
        {
          if (root)
            print_usage(app);
          return 1;
        }
      const std::string        arg = argv[1];
      dealii::ParameterHandler prm;
      if (arg == "--help" || arg == "-h")
        {
          if (root)
            print_usage(app);
          return 0;
        }
      if (arg == "--parameter-reference")
        {
          declare_common(prm, app);
          if (root)
            write_parameter_reference(std::cout,
                                      prm,
                                      app.name,
                                      app.description);
          return 0;
        }
      if (arg == "--print-parameters")
        {
          declare_common(prm, app);
          if (root)
            prm.print_parameters(
              std::cout,
              dealii::ParameterHandler::KeepDeclarationOrder |
                dealii::ParameterHandler::PRM);
          return 0;
        }
      return std::nullopt;
    }



    /// Load the file's plugins and declare every parameter. Collective: a
    /// rank that cannot load a plugin stops every rank (the first such rank
    /// says why).
    bool
    declared(dealii::ParameterHandler     &prm,
             const std::string            &file,
             const ApplicationDescription &app)
    {
      const MPI_Comm comm = MPI_COMM_WORLD;
      std::string    load_error;
      try
        {
          load_shared_libraries(file);
          declare_common(prm, app);
        }
      catch (const std::exception &exc)
        {
          load_error = error_message(exc);
        }
      const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
      const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
      const unsigned int first_failed =
        dealii::Utilities::MPI::min(load_error.empty() ? ranks : rank, comm);
      if (rank == first_failed)
        std::cerr << app.name << ": error: " << load_error << std::endl;
      return first_failed == ranks;
    }



    /// The parameter file, then the command line's --set overrides
    /// ('Section/Sub/Entry=value'); false after reporting an error.
    bool
    read_parameters(dealii::ParameterHandler     &prm,
                    int                           argc,
                    char                        **argv,
                    const ApplicationDescription &app)
    {
      const std::string file = argv[1];
      try
        {
          prm.parse_input(file,
                          "",
                          /*skip_undefined=*/false,
                          /*assert_mandatory=*/true);
        }
      catch (const std::exception &exc)
        {
          report(app,
                 "in parameter file '" + file + "': " + error_message(exc));
          return false;
        }
      for (int k = 2; k + 1 < argc; k += 2)
        {
          const std::string flag = argv[k], assignment = argv[k + 1];
          if (flag != "--set" || assignment.find('=') == std::string::npos)
            {
              report(app,
                     "expected --set 'Section/Entry=value' after the "
                     "parameter file, got '" +
                       flag + " " + assignment + "'.");
              return false;
            }
          try
            {
              set_entry(prm, assignment);
            }
          catch (const std::exception &exc)
            {
              report(app, "--set " + error_message(exc));
              return false;
            }
        }
      return true;
    }



    /// A rank other than the root that fails alone leaves its error in
    /// `<Output directory>/failed-rank-<rank>.json` (written whole, to a
    /// name no other rank writes). The staging directory is left alone: the
    /// root may still be writing into it, or fail a moment later and move
    /// it to failed-run/ itself; otherwise the next run keeps it as
    /// interrupted-run/. Never throws: it runs while an error is reported.
    void
    keep_rank_error(RunContext &context, const std::string &msg) noexcept
    {
      try
        {
          const unsigned int rank =
            dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
          const nlohmann::json marker = {{"status", "failed"},
                                         {"error", msg},
                                         {"failed_rank", rank},
                                         {"aborted", true}};
          replace_file_text(
            context.persistent_path("failed-rank-" + std::to_string(rank) +
                                    ".json"),
            marker.dump(
              2, ' ', false, nlohmann::json::error_handler_t::replace) +
              "\n");
        }
      catch (...)
        {
          // The message on stderr is all there is.
        }
    }



    /// A failed mode: reported together if every rank failed, else the
    /// failing rank stops the job (rank_failure.h).
    int
    fail(const ApplicationDescription &app,
         RankFailure                  &rank_failure,
         RunContext                   &context,
         const std::string            &msg)
    {
      if (!rank_failure.every_rank_failed(rank_failure_wait_seconds))
        {
          const MPI_Comm comm = MPI_COMM_WORLD;
          std::cerr << app.name << ": error: " << msg << " (rank "
                    << dealii::Utilities::MPI::this_mpi_process(comm) << " of "
                    << dealii::Utilities::MPI::n_mpi_processes(comm)
                    << "; the other ranks went on, so the job is stopped)"
                    << std::endl;
          if (context.is_root())
            context.fail(msg);
          else
            keep_rank_error(context, msg);
          MPI_Abort(comm, 1);
        }
      report(app, msg);
      context.fail(msg);
      return 1;
    }



    /// Run the selected mode and commit its results; the exit code.
    int
    run_mode(dealii::ParameterHandler     &prm,
             const std::string            &file,
             const ApplicationDescription &app,
             RunContext                   &context)
    {
      // A rank that fails alone stops the job instead of leaving the others
      // waiting for it.
      RankFailure rank_failure(MPI_COMM_WORLD);
      try
        {
          const std::string dir =
            std::filesystem::path(file).parent_path().string();
          const std::string mode = prm.get("Mode");
          const auto        it =
            std::find_if(app.modes.begin(),
                         app.modes.end(),
                         [&](const auto &m) { return m.name == mode; });
          // The pattern of Mode admits only these names.
          AssertThrow(it != app.modes.end(), dealii::ExcInternalError());
          it->run(prm, dir.empty() ? std::string(".") : dir, context);
          // No rank commits while another may still fail: a rank that does
          // stops the job in this barrier.
          if (internal::several_ranks(MPI_COMM_WORLD))
            MPI_Barrier(MPI_COMM_WORLD);
          context.commit();
          return 0;
        }
      catch (const std::exception &exc)
        {
          return fail(app, rank_failure, context, error_message(exc));
        }
      catch (...) // e.g. an int thrown by a solver library
        {
          return fail(app, rank_failure, context, "unknown internal failure");
        }
    }



    int
    run_checked(int argc, char **argv, const ApplicationDescription &app)
    {
      if (const auto code = informational(argc, argv, app))
        return *code;
      const std::string file = argv[1];
      if (!std::filesystem::exists(file))
        {
          report(app, "parameter file '" + file + "' does not exist.");
          return 1;
        }
      dealii::ParameterHandler prm;
      if (!declared(prm, file, app) || !read_parameters(prm, argc, argv, app))
        return 1;

      std::unique_ptr<RunContext> context;
      try
        {
          context = std::make_unique<RunContext>(MPI_COMM_WORLD,
                                                 prm.get("Output directory"));
        }
      catch (const std::exception &exc)
        {
          report(app, error_message(exc));
          return 1;
        }
      // Values are the user's bytes: kept as text if they are not UTF-8.
      std::ostringstream echoed;
      prm.print_parameters(echoed, dealii::ParameterHandler::JSON);
      auto parameters = nlohmann::json::parse(echoed.str(), nullptr, false);
      context->summary["parameters"] =
        parameters.is_discarded() ? nlohmann::json(safe_text(echoed.str())) :
                                    parameters;
      context->summary["application"] = app.name;
      return run_mode(prm, file, app, *context);
    }
  } // namespace



  int
  run_application(int argc, char **argv, const ApplicationDescription &app)
  {
    // Started without mpirun, Open MPI's singleton start spawns an `orted`
    // daemon, 0.2 s of every run here; one process needs none. An explicit
    // setting wins; other MPI libraries ignore the variable.
    if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr &&
        std::getenv("PMIX_RANK") == nullptr)
      ::setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite*/ 0);
    // Outside the try below: MPI is finalized after an error too (deal.II
    // skips MPI_Finalize while an exception is in flight).
    dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    // Last resort: whatever escapes the error handling of run_checked() (an
    // exception from a destructor or from a noexcept function) ends in one
    // line and exit code 1, never in an abort with a stack trace.
    static std::string name;
    name = app.name;
    std::set_terminate([] {
      std::cerr << name << ": error: internal failure (std::terminate)"
                << std::endl;
      std::_Exit(1);
    });
    try
      {
        return run_checked(argc, argv, app);
      }
    catch (const std::exception &exc)
      {
        std::cerr << app.name << ": error: " << error_message(exc) << std::endl;
      }
    catch (...)
      {
        std::cerr << app.name << ": error: unknown internal failure"
                  << std::endl;
      }
    return 1;
  }
} // namespace forma
