// forma-rhombic: homogenization on rhombic cells and the rhombic
// microstructure family (thesis ch. 4). The modes live in forma_rhombic/
// (the library holds the study they run on, forma/rhombic/study.h); this
// table is their only list.

#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>

#include "forma_rhombic/modes.h"
#include "forma_rhombic/pointwise_table.h"

namespace
{
  using namespace dealii;
  using namespace forma::rhombic;

  void
  check_dimension(ParameterHandler &prm)
  {
    AssertThrow(prm.get_integer("Dimension") == 2,
                ExcMessage(
                  "forma-rhombic homogenizes 2D cells: set Dimension = 2"));
  }

  using Mode = std::function<void(ParameterHandler &,
                                  const std::string &,
                                  const Setup &,
                                  forma::RunContext &)>;

  /// A mode of 2D cells with the common setup (base material, cell mesh).
  forma::ApplicationMode
  mode(const std::string &name, const Mode &run)
  {
    return {name,
            [run](ParameterHandler  &prm,
                  const std::string &prm_directory,
                  forma::RunContext &context) {
              check_dimension(prm);
              run(prm, prm_directory, parse_setup(prm, context), context);
            }};
  }

  /// The same for modes that read no file besides the parameters.
  forma::ApplicationMode
  mode(const std::string &name,
       void (*run)(ParameterHandler &, const Setup &, forma::RunContext &))
  {
    return mode(name,
                [run](ParameterHandler &prm,
                      const std::string &,
                      const Setup       &setup,
                      forma::RunContext &context) {
                  run(prm, setup, context);
                });
  }
} // namespace

int
main(int argc, char **argv)
{
  forma::ApplicationDescription app;
  app.name        = "forma-rhombic";
  app.description = "Homogenization of the rhombic microstructure family on "
                    "parallelogram cells (thesis ch. 4).";
  app.modes       = {mode("homogenize", homogenize_mode),
                     mode("sweep", sweep_mode),
                     mode("inverse", inverse_mode),
                     mode("verify gradient", verify_gradient_mode),
                     mode("build map", build_map_mode),
                     mode("query", query_mode),
                     // The quad mesh alone: no cell setup.
                     {"rhombic mesh",
                      [](ParameterHandler  &prm,
                   const std::string &prm_directory,
                   forma::RunContext &context) {
                  check_dimension(prm);
                  rhombic_mesh_mode(prm, prm_directory, context);
                }},
                     mode("two-scale design", two_scale_design_mode),
                     mode("compound cell", compound_cell_mode),
                     mode("pointwise table", pointwise_table_mode)};
  app.declare_parameters = declare_parameters;
  return forma::run_application(argc, argv, app);
}
