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
  /// One job of an application (a value of `Mode`) and how to run it;
  /// `prm_directory` resolves relative file names.
  struct ApplicationMode
  {
    std::string name;
    std::function<void(dealii::ParameterHandler &,
                       const std::string &prm_directory,
                       RunContext &)>
      run;
  };

  /**
   * What a forma application tells the shared driver: its name, a short
   * description, its jobs (`Mode`, the first is the default) and how to
   * declare its parameters. The driver handles the command line (`--help`,
   * `--print-parameters`, `FILE.prm`), MPI, parameter parsing, the output
   * directory, summary.json and every error path, so all apps behave alike.
   * The list of modes is the only one: `Mode`'s pattern comes from it.
   */
  struct ApplicationDescription
  {
    std::string                                     name;
    std::string                                     description;
    std::vector<ApplicationMode>                    modes;
    std::function<void(dealii::ParameterHandler &)> declare_parameters;
  };

  int
  run_application(int argc, char **argv, const ApplicationDescription &app);

  /// The message of an exception without deal.II's source locations.
  std::string
  error_message(const std::exception &exc);
} // namespace forma

#endif
