// The smallest forma application: reuse the shared driver (command line,
// parameters, output directory, summary.json, error handling) and the
// elasticity simulator, and add one result of its own to the summary.

#include <forma/base/application.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name               = "my_app";
  app.description        = "Reports the compliance of a 2D elastic body.";
  app.modes              = {"simulate"};
  app.declare_parameters = forma::ElasticityParameters::declare;
  app.run                = [](dealii::ParameterHandler &prm,
               const std::string        &dir,
               forma::RunContext        &context) {
    forma::ElasticityParameters parameters;
    parameters.parse(prm, dir);
    forma::ElasticitySimulator<2> simulator(parameters, context.communicator());
    simulator.run(&context);
    const double energy           = simulator.steps().back().elastic_energy;
    context.summary["compliance"] = 2 * energy;
    context.print("compliance: " + std::to_string(2 * energy));
  };
  return forma::run_application(argc, argv, app);
}
