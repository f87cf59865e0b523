// A forma application written against the installed library: the shared
// driver (command line, parameters, output directory, summary.json, error
// handling), the elasticity jobs (simulate, verify gradient, optimize) and
// pieces of its own that join the adjoint layer by registration
// (elastic_foundation.cc: a form, a parameterization, an objective term).

#include <forma/base/application.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/parameters.h>

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "my_app";
  app.description = "Elastic bodies on an elastic foundation: simulate, "
                    "verify gradients, optimize the shape and the "
                    "foundation.";
  app.modes       = forma::elasticity_modes(
    [](dealii::ParameterHandler &prm, const std::string &dir) {
      forma::ElasticityParameters parameters;
      parameters.parse(prm, dir);
      return parameters;
    });
  app.declare_parameters = [](dealii::ParameterHandler &prm) {
    forma::ElasticityParameters::declare(prm);
    forma::declare_elasticity_job_parameters(prm);
  };
  return forma::run_application(argc, argv, app);
}
