#ifndef forma_apps_forma_laminate_modes_h
#define forma_apps_forma_laminate_modes_h

// forma-laminate's modes (the application's own code, not the library's):
// each reads its sections and runs on the library's laminate study
// (forma/laminate/study.h).

#include <forma/base/run_context.h>
#include <forma/laminate/study.h>

#include <string>

namespace forma
{
  namespace laminate
  {
    /// One structure (family or image) -> summary.json, fields.vtu.
    void
    homogenize_mode(dealii::ParameterHandler &prm,
                    const std::string        &prm_directory,
                    const Setup              &setup,
                    RunContext               &context);

    /// A parameter grid -> samples.csv, coverage, plots.
    void
    sweep_mode(dealii::ParameterHandler &prm,
               const Setup              &setup,
               RunContext               &context);

    /// A target (E, nu) -> structure parameters.
    void
    inverse_mode(dealii::ParameterHandler &prm,
                 const std::string        &prm_directory,
                 const Setup              &setup,
                 RunContext               &context);

    /// Regular grid vs conforming periodic mesh (Table 5.2).
    void
    compare_meshes_mode(dealii::ParameterHandler &prm,
                        const Setup              &setup,
                        RunContext               &context);
  } // namespace laminate
} // namespace forma

#endif
