// forma-transient-ipc: differentiable static and transient elasticity
// (thesis ch. 3). This step adds the forward simulator without contact.

#include <forma/base/application.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>

namespace
{
  template <int dim>
  void
  simulate(const forma::ElasticityParameters &parameters,
           forma::RunContext                 &context)
  {
    forma::ElasticitySimulator<dim> simulator(parameters,
                                              context.communicator());
    simulator.run(&context);
  }
} // namespace

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-transient-ipc";
  app.description = "Static and transient elasticity (linear or Neo-Hookean, "
                    "BDF1-6 with damping, h/hp-adaptive, MPI-parallel). "
                    "IPC contact and gradients arrive in later versions.";
  app.modes       = {"simulate"};
  app.declare_parameters = forma::ElasticityParameters::declare;
  app.run                = [](dealii::ParameterHandler &prm,
               const std::string        &dir,
               forma::RunContext        &context) {
    forma::ElasticityParameters parameters;
    parameters.parse(prm, dir);
    if (parameters.dim == 2)
      simulate<2>(parameters, context);
    else
      simulate<3>(parameters, context);
  };
  return forma::run_application(argc, argv, app);
}
