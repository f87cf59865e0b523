#ifndef forma_ipc_ipc_parameters_h
#define forma_ipc_ipc_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/types.h>

#include <forma/ipc/distance.h>

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace forma
{
  namespace ipc
  {
    /// A static half-space obstacle: bodies stay on the side the normal
    /// points to.
    struct Plane
    {
      Vec    origin;
      Vec    normal;        ///< unit
      double friction = -1; ///< < 0: the default coefficient
    };

    /// A static obstacle surface read from a file (see read_obstacle_mesh()).
    struct MeshObstacle
    {
      std::string file;
      double      friction = -1; ///< < 0: the default coefficient
    };

    /**
     * The `IPC` section (incremental potential contact, thesis ch. 3.6-3.7,
     * Li et al. 2020): barrier, obstacles, friction, CCD.
     */
    struct IpcParameters
    {
      bool                                 enabled = false;
      std::set<dealii::types::boundary_id> boundaries;        ///< empty: all
      double                               dhat          = 0; ///< 0: automatic
      double                               relative_dhat = 1e-3;
      double                               kappa         = 0; ///< 0: adaptive
      std::vector<Plane>                   planes;
      std::vector<MeshObstacle>            meshes;
      double friction = 0; ///< default coefficient
      /// Coefficients per pair of material ids (sorted pair).
      std::map<
        std::pair<dealii::types::material_id, dealii::types::material_id>,
        double>
                   pair_friction;
      double       friction_velocity     = 1e-3; ///< eps_v (length / time)
      unsigned int friction_iterations   = 1;
      double       ccd_gap               = 0.1;
      double       newton_step_tolerance = 1e-5;

      static void
      declare(dealii::ParameterHandler &prm);
      /// Reads the section; `dim` for the obstacle coordinates, obstacle
      /// files relative to `prm_directory`.
      void
      parse(dealii::ParameterHandler &prm,
            const unsigned int        dim,
            const std::string        &prm_directory);

      bool
      has_friction() const;
    };
  } // namespace ipc
} // namespace forma

#endif
