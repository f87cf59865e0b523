// forma-transient-ipc: differentiable static and transient elasticity with
// IPC contact and friction (thesis ch. 3): simulation, adjoint gradients of
// any objective with respect to shape, materials, damping, friction, loads
// and initial conditions (Taylor-tested), and optimization. The jobs live in
// the library (forma/elasticity/jobs.h).

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
                    "IPC contact and friction, and adjoint gradients of "
                    "objectives with respect to shape, materials, damping, "
                    "friction, loads and initial conditions, through "
                    "contact; optimization with ROL.";
  app.modes       = forma::elasticity_modes(
    [](dealii::ParameterHandler &prm, const std::string &dir) {
      forma::ElasticityParameters parameters;
      parameters.parse(prm, dir, false, true); // with IPC
      return parameters;
    });
  app.declare_parameters = [](dealii::ParameterHandler &prm) {
    forma::ElasticityParameters::declare(prm);
    forma::ipc::IpcParameters::declare(prm);
    forma::declare_elasticity_job_parameters(prm);
  };
  return forma::run_application(argc, argv, app);
}
