// forma-transient-ipc: differentiable static and transient elasticity
// (thesis ch. 3). This version: the forward simulator with IPC contact and
// friction, and its adjoint gradients (shape, materials, damping, loads,
// initial conditions; without contact so far) with a Taylor test. The jobs live
// in the library (forma/elasticity/jobs.h).

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/parameters.h>

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-transient-ipc";
  app.description = "Static and transient elasticity (linear or Neo-Hookean, "
                    "BDF1-6 with damping, h/hp-adaptive, MPI-parallel) with "
                    "adjoint gradients of objectives with respect to shape, "
                    "materials, damping, loads and initial conditions. IPC "
                    "contact arrives in a later version.";
  app.modes       = {"simulate", "verify gradient", "optimize"};
  app.declare_parameters = [](dealii::ParameterHandler &prm) {
    forma::ElasticityParameters::declare(prm);
    forma::ipc::IpcParameters::declare(prm);
    forma::declare_elasticity_job_parameters(prm);
  };
  app.run = [](dealii::ParameterHandler &prm,
               const std::string        &dir,
               forma::RunContext        &context) {
    forma::ElasticityParameters parameters;
    parameters.parse(prm, dir, false, true);
    forma::run_elasticity_job(prm.get("Mode"), parameters, prm, context);
  };
  return forma::run_application(argc, argv, app);
}
