#ifndef forma_base_application_h
#define forma_base_application_h

#include <deal.II/base/parameter_handler.h>

#include <forma/base/run_context.h>

#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace forma
{
  /**
   * What a forma application tells the shared driver: its name, a short
   * description, its jobs (`Mode`), how to declare its parameters, and how to
   * run one job. The driver handles the command line (`--help`,
   * `--print-parameters`, `FILE.prm`), MPI, parameter parsing, the output
   * directory, summary.json and every error path, so all apps behave alike.
   */
  struct ApplicationDescription
  {
    std::string                                     name;
    std::string                                     description;
    std::vector<std::string>                        modes;
    std::function<void(dealii::ParameterHandler &)> declare_parameters;
    /// Runs the job; `prm_directory` resolves relative file names.
    std::function<void(dealii::ParameterHandler &,
                       const std::string &prm_directory,
                       RunContext &)>
      run;
  };

  int
  run_application(int argc, char **argv, const ApplicationDescription &app);

  /// The message of an exception without deal.II's source locations.
  std::string
  error_message(const std::exception &exc);
} // namespace forma

#endif
