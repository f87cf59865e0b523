#ifndef forma_elasticity_parameters_h
#define forma_elasticity_parameters_h

#include <deal.II/base/parameter_handler.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/objective.h>
#include <forma/contact/contact_parameters.h>
#include <forma/ipc/ipc_parameters.h>
#include <forma/mesh/mesh.h>
#include <forma/physics/material.h>
#include <forma/solvers/linear_solver.h>

#include <map>
#include <string>

namespace forma
{
  /**
   * Everything the elasticity simulator reads from a `.prm` file. Entries are
   * dimension-independent strings where they hold vectors or expressions;
   * the simulator checks them against the dimension.
   */
  struct ElasticityParameters
  {
    unsigned int   dim = 2;
    MeshParameters mesh;

    // Finite element
    unsigned int degree           = 1;
    std::string  adaptivity       = "none";  ///< none | h | hp
    std::string  error_indicator  = "kelly"; ///< kelly | goal
    bool         goal_estimate    = false;   ///< report J and its estimate
    bool         contact_residual = true;    ///< kelly + contact faces
    unsigned int max_degree       = 4;
    unsigned int adaptive_cycles  = 0;
    double       refine_fraction  = 0.3;
    double       coarsen_fraction = 0.0;
    /// cell count | error fraction: what Refine/Coarsen fraction measure.
    std::string marking = "cell count";
    /// Transient problems: adapt the mesh every this many accepted steps.
    unsigned int adapt_every = 10;
    /// Transient problems: levels a cell may gain over the starting mesh.
    unsigned int max_refinement_level = 2;

    // Material
    ConstitutiveModel model        = ConstitutiveModel::linear_elastic;
    bool              plane_stress = false;
    /// Damping's strain rate from the BDF velocity (Material/Damping rate
    /// = bdf) instead of the thesis's backward difference.
    bool        bdf_damping_rate = false;
    std::string bodies;

    // Boundary conditions and loads
    std::string dirichlet;
    std::string traction;
    std::string load_cases; ///< alternative Traction records, '|' between
    std::string pressure;
    std::string gravity;
    std::string body_force;
    std::string additional_forms; ///< records 'name : key=value'
    std::string constants;

    // Time
    std::string  problem                 = "static"; ///< static | transient
    double       end_time                = 1;
    double       time_step               = 0.1;
    unsigned int bdf_order               = 2;
    unsigned int load_steps              = 1;
    std::string  time_integrator         = "fixed"; ///< fixed | adaptive
    bool         variable_order          = false;   ///< adaptive: per step
    double       time_tolerance          = 1e-4;    ///< adaptive: relative
    double       absolute_time_tolerance = 0;       ///< 0: from the mesh
    double       minimum_time_step       = 0;       ///< 0: 1e-10 End time
    double       maximum_time_step       = 0;       ///< 0: End time
    std::string  initial_displacement;
    std::string  initial_velocity;

    // Solvers
    LinearSolver::Parameters linear_solver;
    double                   newton_relative_tolerance = 1e-9;
    double                   newton_absolute_tolerance = 1e-12;
    unsigned int             max_newton_iterations     = 30;
    unsigned int             max_line_search_halvings  = 12;

    // Smoothed penalty contact (declared by apps that offer it)
    ContactParameters contact;
    // Incremental potential contact (declared by apps that offer it)
    ipc::IpcParameters ipc;

    // Gradients (adjoint layer)
    DesignParameters    design;
    ObjectiveParameters objective;

    // Output
    bool         write_vtu    = true;
    unsigned int output_every = 1;
    std::string  points;

    /// Apps with contact declare ContactParameters (IpcParameters) too
    /// and parse `with_contact` (`with_ipc`).
    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm,
          const std::string        &prm_directory,
          const bool                with_contact = false,
          const bool                with_ipc     = false);
  };
} // namespace forma

#endif
