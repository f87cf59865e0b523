// forma-laminate: hexagonal Triangle/Hexagon laminate microstructures,
// periodic homogenization and Hashin-Shtrikman coverage (thesis ch. 5).
// The modes live in the library (forma/laminate/study.h).

#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/laminate/study.h>

namespace
{
  using namespace dealii;
  using namespace forma::laminate;

  void
  run(ParameterHandler  &prm,
      const std::string &prm_directory,
      forma::RunContext &context)
  {
    AssertThrow(prm.get_integer("Dimension") == 2,
                ExcMessage(
                  "forma-laminate homogenizes 2D cells: set Dimension = 2"));
    const Setup       setup = parse_setup(prm, context);
    const std::string mode  = prm.get("Mode");
    if (mode == "homogenize")
      homogenize_mode(prm, prm_directory, setup, context);
    else if (mode == "sweep")
      sweep_mode(prm, setup, context);
    else if (mode == "inverse")
      inverse_mode(prm, prm_directory, setup, context);
    else
      compare_meshes_mode(prm, setup, context);
  }
} // namespace

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-laminate";
  app.description = "Homogenization of hexagonal Triangle/Hexagon laminate "
                    "microstructures and their Hashin-Shtrikman coverage "
                    "(thesis ch. 5).";
  app.modes       = {"homogenize", "sweep", "inverse", "compare meshes"};
  app.declare_parameters = declare_parameters;
  app.run                = run;
  return forma::run_application(argc, argv, app);
}
