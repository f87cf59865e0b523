// forma-rhombic: homogenization on rhombic cells and the rhombic
// microstructure family (thesis ch. 4). The modes live in the library
// (forma/rhombic/study.h).

#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/rhombic/pointwise_table.h>
#include <forma/rhombic/study.h>

namespace
{
  using namespace dealii;
  using namespace forma::rhombic;

  void
  run(ParameterHandler  &prm,
      const std::string &prm_directory,
      forma::RunContext &context)
  {
    AssertThrow(prm.get_integer("Dimension") == 2,
                ExcMessage(
                  "forma-rhombic homogenizes 2D cells: set Dimension = 2"));
    const std::string mode = prm.get("Mode");
    if (mode == "rhombic mesh")
      return rhombic_mesh_mode(prm, prm_directory, context);
    const Setup setup = parse_setup(prm, context);
    if (mode == "homogenize")
      homogenize_mode(prm, setup, context);
    else if (mode == "sweep")
      sweep_mode(prm, setup, context);
    else if (mode == "inverse")
      inverse_mode(prm, setup, context);
    else if (mode == "build map")
      build_map_mode(prm, prm_directory, setup, context);
    else if (mode == "compound cell")
      compound_cell_mode(prm, prm_directory, setup, context);
    else if (mode == "two-scale design")
      two_scale_design_mode(prm, prm_directory, setup, context);
    else if (mode == "pointwise table")
      pointwise_table_mode(prm, setup, context);
    else if (mode == "query")
      query_mode(prm, prm_directory, setup, context);
    else
      verify_gradient_mode(prm, setup, context);
  }
} // namespace

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-rhombic";
  app.description = "Homogenization of the rhombic microstructure family on "
                    "parallelogram cells (thesis ch. 4).";
  app.modes       = {"homogenize",
                     "sweep",
                     "inverse",
                     "verify gradient",
                     "build map",
                     "query",
                     "rhombic mesh",
                     "two-scale design",
                     "compound cell",
                     "pointwise table"};
  app.declare_parameters = declare_parameters;
  app.run                = run;
  return forma::run_application(argc, argv, app);
}
