#ifndef forma_elasticity_load_cases_h
#define forma_elasticity_load_cases_h

#include <deal.II/base/mpi.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/objective.h>
#include <forma/elasticity/parameters.h>

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;
  template <int dim>
  class ElasticitySimulator;

  /**
   * Several static load cases on one design (thesis ch. 2.6, Fig. 2.10):
   * one simulator per case of `Boundary conditions/Load cases` (or the one
   * case of Traction), all on the same mesh and design. The objective is
   * the sum over the cases of the state-dependent terms plus, once, the
   * terms of the design alone; its gradient is the sum of the cases'
   * adjoint gradients. Remeshing remeshes the first case and moves the
   * others onto its mesh. The interface mirrors ElasticitySimulator's
   * adjoint layer, so the optimization and gradient-check jobs drive either.
   */
  template <int dim>
  class LoadCases
  {
  public:
    LoadCases(const ElasticityParameters &parameters, const MPI_Comm comm);
    ~LoadCases();

    unsigned int
    n_cases() const;

    ElasticitySimulator<dim> &
    operator[](const unsigned int k);

    /// Set up every case; `context` prints for the first.
    void
    prepare(RunContext *context);

    /// Case 0 with the whole objective, the others with its
    /// state-dependent terms.
    void
    set_objective(const ObjectiveParameters &parameters);

    /// Thesis Algorithm 1's weight schedule: every term's weight at
    /// `progress` in [0, 1] of its ramp (0: the first outer iteration).
    /// Returns whether any term ramps ('final weight').
    bool
    ramp_objective_weights(const double progress);

    /// The terms whose weights ramp, with their current weights.
    std::vector<std::pair<std::string, double>>
    ramped_weights() const;

    const DesignLayout &
    design_layout() const;
    const std::vector<double> &
    design() const;
    void
    set_design(const std::vector<double> &q);
    void
    solve_design();
    /// See ElasticitySimulator::freeze_time_steps().
    void
    freeze_time_steps(const bool freeze);
    bool
    adaptive_time_steps() const;
    double
    objective() const;
    /// Weighted terms summed over the cases, by name.
    std::vector<std::pair<std::string, double>>
    objective_terms() const;
    double
    gradient(std::vector<double> &dJ) const;

    /// VTU of the first case.
    void
    write_state(const unsigned int index, RunContext &context);
    /// The first case's statistics with the largest stresses over all
    /// cases, and per case (`load_cases`) when there are several.
    nlohmann::json
    state_statistics() const;
    /// Forward and adjoint statistics of the first case, with the number
    /// of cases.
    nlohmann::json
    adjoint_statistics() const;

    double
    max_shape_offset() const;
    double
    cell_size() const;
    double
    mesh_quality() const;
    std::vector<unsigned int>
    degenerate_shape_entries(const double threshold) const;
    bool
    remesh_improves(std::string &reason);
    std::string
    remesh(const std::string &file_stem);
    void
    load_remeshed(const std::string &file_stem);
    /// ElasticitySimulator::undo_remesh() and commit_remesh() for every
    /// case.
    bool
    undo_remesh();
    void
    commit_remesh();
    void
    cap_volume_bounds();
    /// The largest mean cell stress over the cases.
    std::vector<double>
    cell_mean_stress() const;
    std::string
    remesh_without(const std::string         &file_stem,
                   const std::vector<bool>   &removed,
                   dealii::types::boundary_id open_id);
    std::vector<double>
    material_offsets() const;
    std::vector<double>
    design_scales(const std::vector<double> &q0) const;
    void
    design_bounds(const std::vector<double> &q0,
                  const double               shape_bound,
                  std::vector<double>       &lower,
                  std::vector<double>       &upper) const;
    unsigned int
    n_remeshes() const;
    /// Refine where the cases' indicators, each over its sum, are largest
    /// (ElasticitySimulator::refine_design()); every case refines the
    /// same cells. Needs the current design solved.
    std::string
    refine_design(const std::string &file_stem);
    void
    load_refinement(const std::string &file_stem);
    void
    guard_cell_corners(const bool on);

  private:
    std::vector<std::unique_ptr<ElasticitySimulator<dim>>> cases;
    /// The cases' objectives (shared with them), for the weight ramps.
    std::vector<std::shared_ptr<const Objective<dim>>> objectives;
  };
} // namespace forma

#endif
