// forma-laminate: hexagonal Triangle/Hexagon laminate microstructures,
// periodic homogenization and Hashin-Shtrikman coverage (thesis ch. 5).
// The modes live in forma_laminate/ (the library holds the study they run
// on, forma/laminate/study.h); this table is their only list.

#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>

#include "forma_laminate/modes.h"

namespace
{
  using namespace dealii;
  using namespace forma::laminate;

  using Mode = std::function<void(ParameterHandler &,
                                  const std::string &,
                                  const Setup &,
                                  forma::RunContext &)>;

  /// A mode of 2D cells with the common setup (base material, grid).
  forma::ApplicationMode
  mode(const std::string &name, const Mode &run)
  {
    return {name,
            [run](ParameterHandler  &prm,
                  const std::string &prm_directory,
                  forma::RunContext &context) {
              AssertThrow(prm.get_integer("Dimension") == 2,
                          ExcMessage("forma-laminate homogenizes 2D cells: "
                                     "set Dimension = 2"));
              run(prm, prm_directory, parse_setup(prm, context), context);
            }};
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
  app.modes       = {mode("homogenize", homogenize_mode),
                     mode("sweep",
                    [](ParameterHandler &prm,
                       const std::string &,
                       const Setup       &setup,
                       forma::RunContext &context) {
                      sweep_mode(prm, setup, context);
                    }),
                     mode("inverse", inverse_mode),
                     mode("compare meshes",
                    [](ParameterHandler &prm,
                       const std::string &,
                       const Setup       &setup,
                       forma::RunContext &context) {
                      compare_meshes_mode(prm, setup, context);
                    })};
  app.declare_parameters = declare_parameters;
  return forma::run_application(argc, argv, app);
}
