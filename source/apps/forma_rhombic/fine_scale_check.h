#ifndef forma_apps_forma_rhombic_fine_scale_check_h
#define forma_apps_forma_rhombic_fine_scale_check_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/mesh/polygon_domain.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/study.h>
#include <forma/rhombic/tiling.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;

  namespace rhombic
  {
    /// The two-scale design's settings, the fine-scale check of a tiling,
    /// the cells' homogenized moduli and the design's pictures (thesis
    /// ch. 4.8); design_mode.cc runs the pipeline.
    namespace two_scale
    {
      /// The material {phi < 0} of a level set on points, over [lo, hi].
      void
      write_level_set_picture(
        const std::string                                     &file,
        const std::function<double(const dealii::Point<2> &)> &phi,
        const dealii::Point<2>                                &lo,
        const dealii::Point<2>                                &hi);

      /// A mesh (material and boundary ids) for the simulator to read back.
      void
      write_msh(const dealii::Triangulation<2> &tria,
                const std::string              &file,
                const MPI_Comm                  comm);

      /// The Two-scale section, read once; file names relative to the
      /// parameter file's directory.
      struct TwoScaleSettings
      {
        std::string           macro_file, macro_settings, constant_material;
        std::string           table_file;
        double                coverage_weight = 0;
        bool                  fine_check = true, check_moduli = false;
        bool                  fine_simulation = true, merge = true;
        double                fine_size = 0, fine_boundary_size = 0;
        int                   compared_boundary = -1;
        unsigned int          refinement        = 0;
        std::set<std::string> baselines;

        static TwoScaleSettings
        parse(dealii::ParameterHandler &prm, const std::string &prm_directory);
      };

      /// A tiling's fine-scale mesh: boundary ids from the outline and the
      /// compared boundary's vertices.
      struct FineMesh
      {
        dealii::Triangulation<2>                 tria;
        LevelSetMeshInfo                         info;
        std::map<unsigned int, dealii::Point<2>> compared_points;
        std::string                              file;
      };

      /**
       * The fine-scale check of one tiling (ch. 4.8): the tiled geometry
       * meshed and simulated in the base material with the macro problem's
       * supports and loads, against the homogenized solution on the
       * compared boundary.
       */

      class FineScaleCheck
      {
      public:
        FineScaleCheck(const TwoScaleSettings                  &settings,
                       const PolygonDomain                     &domain,
                       const ElasticityParameters              &parameters,
                       const Setup                             &setup,
                       RunContext                              &context,
                       const double                             h,
                       const double                             h_tile,
                       std::function<void(const std::string &)> lap)
          : settings(settings)
          , domain(domain)
          , parameters(parameters)
          , setup(setup)
          , context(context)
          , h(h)
          , h_tile(h_tile)
          , lap(std::move(lap))
        {}

        void
        operator()(
          const std::function<double(const dealii::Point<2> &)> &object,
          const dealii::Point<2>                                &object_lo,
          const dealii::Point<2>                                &object_hi,
          const std::string                                     &name,
          LoadCases<2> &homogenized) const;

      private:
        /// The geometry meshed, written as .msh and its outline as SVG and
        /// DXF (for fabrication).
        void
        mesh(const std::function<double(const dealii::Point<2> &)> &object,
             const dealii::Point<2>                                &object_lo,
             const dealii::Point<2>                                &object_hi,
             const std::string                                     &name,
             FineMesh &result) const;

        /// The base material in the fine mesh under the macro problem's
        /// supports and first load case (loads scaled to the fine
        /// boundary's lengths); its VTU in fine_scale_<name>/.
        std::unique_ptr<ElasticitySimulator<2>>
        simulate(const FineMesh    &fine,
                 const std::string &name,
                 LoadCases<2>      &homogenized) const;

        /// Fine against homogenized displacements on the compared boundary.
        void
        compare(const FineMesh               &fine,
                const ElasticitySimulator<2> &fine_simulator,
                const std::string            &name,
                LoadCases<2>                 &homogenized) const;

        const TwoScaleSettings     &settings;
        const PolygonDomain        &domain;
        const ElasticityParameters &parameters;
        const Setup                &setup;
        RunContext                 &context;
        const double                h, h_tile;
        // By value: it may be a lambda converted at the call (it captures
        // the caller's timer by reference).
        const std::function<void(const std::string &)> lap;
      };

      /**
       * The cells' structures homogenized: how far the map's structures are
       * from their targets (identical structures are homogenized once). A
       * structure the cell mesher cannot mesh is reported and left out:
       * this is a diagnosis, the tiling does not use the cell meshes.
       */
      void
      check_cell_moduli(const std::vector<RhombicStructure> &structures,
                        const std::vector<double>           &E,
                        const std::vector<double>           &nu,
                        const Setup                         &setup,
                        RunContext                          &context);

      /// The design's pictures (materials per cell, the tiled geometry)
      /// and design.vtu (per cell: E, nu, alpha, p1..p8), on the root.
      void
      write_design_outputs(const dealii::Triangulation<2, 2>   &tria,
                           const std::vector<double>           &E,
                           const std::vector<double>           &nu,
                           const std::vector<double>           &alpha,
                           const std::vector<RhombicStructure> &structures,
                           const MaterialMap                   &map,
                           const std::array<double, 4>         &box,
                           const TiledObject                   &tiled,
                           RunContext                          &context);
    } // namespace two_scale
  }   // namespace rhombic
} // namespace forma

#endif
