// forma-contact-assembly: shape optimization of assemblies held together by
// contact and friction (thesis ch. 2). Static linear elasticity with
// smoothed penalty contact (rigid-deformable and deformable-deformable) and
// Coulomb friction, its adjoint shape derivatives and ROL optimization. The
// jobs live in the library (forma/elasticity/jobs.h).

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/parameters.h>

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-contact-assembly";
  app.description = "Static elasticity of assemblies with smoothed penalty "
                    "contact (parts against rigid obstacles and against each "
                    "other along interfaces cut from a conforming mesh) and "
                    "Coulomb friction; adjoint shape derivatives of stress, "
                    "volume and further objectives, Taylor tests and ROL "
                    "shape optimization.";
  app.modes       = forma::elasticity_modes(
    [](dealii::ParameterHandler &prm, const std::string &dir) {
      forma::ElasticityParameters parameters;
      parameters.parse(prm, dir, true); // with penalty contact
      return parameters;
    });
  app.declare_parameters = [](dealii::ParameterHandler &prm) {
    forma::ElasticityParameters::declare(prm);
    forma::ContactParameters::declare(prm);
    forma::declare_elasticity_job_parameters(prm);
  };
  return forma::run_application(argc, argv, app);
}
