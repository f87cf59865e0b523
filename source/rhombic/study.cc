#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/adjoint/gradient_check.h>
#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/bounds.h>
#include <forma/homogenization/parallelogram_cell.h>
#include <forma/rhombic/quad_mesh_optimization.h>
#include <forma/rhombic/study.h>

#include <algorithm>
#include <cmath>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    RhombicStructure
    read_structure(ParameterHandler &prm, const Setup &setup)
    {
      RhombicStructure s;
      prm.enter_subsection("Structure");
      s.alpha = prm.get_double("Angle") * numbers::PI / 180;
      const auto p =
        parse_values(prm.get("Parameters"), "Structure/Parameters");
      prm.leave_subsection();
      AssertThrow(p.size() == RhombicStructure::n_parameters,
                  ExcMessage(
                    "Structure/Parameters: " + std::to_string(p.size()) +
                    " values given, the family has 8 (p1..p8)"));
      std::copy(p.begin(), p.end(), s.p.begin());
      s.blending = setup.blending;
      s.check();
      return s;
    }



    void
    check_target_grid(const std::vector<double> &Es,
                      const std::vector<double> &nus,
                      const std::string         &section)
    {
      for (const double E : Es)
        AssertThrow(E > 0 && E < 1,
                    ExcMessage(section + "/Young's moduli: " + sig(E) +
                               " is not in (0, 1) (relative to the base)"));
      for (const double nu : nus)
        AssertThrow(nu > -1 && nu < 1,
                    ExcMessage(section + "/Poisson's ratios: " + sig(nu) +
                               " is not in (-1, 1)"));
    }



    nlohmann::json
    structure_json(const RhombicStructure &s)
    {
      return {{"p", s.p},
              {"angle_degrees", s.alpha * 180 / numbers::PI},
              {"blending", s.blending}};
    }



    nlohmann::json
    sample_json(const Sample &r, const Setup &setup)
    {
      const auto voigt = [](const SymmetricTensor<4, 2> &C) {
        const VoigtMatrix V    = to_voigt(C);
        nlohmann::json    rows = nlohmann::json::array();
        for (unsigned int i = 0; i < 3; ++i)
          rows.push_back({V[i][0], V[i][1], V[i][2]});
        return rows;
      };
      nlohmann::json j = {{"C_voigt", voigt(r.C)},
                          {"C_reference_voigt", voigt(r.C_reference)},
                          {"phi", r.phi},
                          {"E", r.fit.E},
                          {"nu", r.fit.nu},
                          {"E_relative", r.fit.E / setup.base.E},
                          {"E1", r.orthotropic.E1},
                          {"E2", r.orthotropic.E2},
                          {"G12", r.orthotropic.G12},
                          {"nu12", r.orthotropic.nu12},
                          {"a1", r.anisotropy.a1},
                          {"a2", r.anisotropy.a2},
                          {"isotropy_residual", r.anisotropy.residual},
                          {"isotropic",
                           r.anisotropy.a1 <= setup.isotropy_tolerance &&
                             r.anisotropy.a2 <= setup.isotropy_tolerance},
                          {"mesh",
                           {{"vertices", r.vertices},
                            {"cells", r.cells},
                            {"dofs", r.dofs},
                            {"boundary_loops", r.mesh.boundary_loops},
                            {"dropped_islands", r.mesh.dropped_islands},
                            {"dropped_holes", r.mesh.dropped_holes}}}};
      for (const auto &[nu, m] : setup.material.clm_fits(r.C))
        j["clm"].push_back({{"base_nu", nu}, {"E", m.E}, {"nu", m.nu}});
      return j;
    }



    void
    write_structure_png(const std::string      &file_name,
                        const RhombicStructure &structure,
                        const unsigned int      tiles,
                        const unsigned int      pixels)
    {
      const Tensor<2, 2> F = structure.cell_map(), G = invert(F);
      const auto         phi = structure.level_set();
      constexpr double   L   = RhombicStructure::side;
      // The diagonals' extents, `tiles` cells around the cell's center.
      const double c      = std::cos(structure.alpha / 2),
                   s      = std::sin(structure.alpha / 2);
      const double half_x = tiles * L * c / 2 * 1.02,
                   half_y = tiles * L * s / 2 * 1.02;
      const Point<2> center(L * c, 0);
      const double   sin_alpha = std::sin(structure.alpha);
      const int      W         = pixels;
      const int      H = std::max(16, static_cast<int>(W * half_y / half_x));
      const double   pixel = 2 * half_x / W;
      std::vector<unsigned char> rgb(3 * W * H);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          {
            const Point<2>     X(center[0] - half_x + (x + 0.5) * pixel,
                             center[1] + half_y - (y + 0.5) * pixel);
            const Tensor<1, 2> q = G * X;
            Point<2>           wrapped;
            bool               outline = false;
            for (unsigned int d = 0; d < 2; ++d)
              {
                wrapped[d] = q[d] - L * std::floor(q[d] / L);
                // The central cell's sides (in reference units).
                const double other = q[1 - d];
                outline |= other > -0.01 && other < L + 0.01 &&
                           (std::abs(q[d]) < 0.6 * pixel / sin_alpha ||
                            std::abs(q[d] - L) < 0.6 * pixel / sin_alpha);
              }
            std::array<unsigned char, 3> color = {{235, 235, 235}};
            if (phi(wrapped) < 0)
              color = {{45, 55, 70}};
            if (outline)
              color = {{200, 40, 40}};
            std::copy(color.begin(),
                      color.end(),
                      rgb.begin() + 3 * (y * W + x));
          }
      write_image(file_name, W, H, rgb);
    }



    namespace
    {
      /// The `Structure` section.
      void
      declare_structure_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Structure");
        prm.declare_entry(
          "Angle",
          "90",
          Patterns::Double(),
          "Smaller angle alpha of the rhombic cell, degrees, in "
          "[22.5, 90] (the thesis's map covers [45, 90]).");
        prm.declare_entry(
          "Parameters",
          "0.3, 0.3, 0.5, 0.5, 0.2, 0.12, 0.12, 0.12",
          Patterns::Anything(),
          "p1..p8 (thesis Fig. 4.3, see doc/rhombic.md): node 2 barycentric "
          "offsets p1, p2 toward the corners A, B; nodes 3, 4 on the "
          "diagonals at p3, p4 of the way to the corners; radii p5..p8 of "
          "nodes 1..4. Sweep ranges: [0.1, 0.5]^2 x [0.1, 0.9]^2 x "
          "[0.05, 0.3]^4.");
        prm.declare_entry("Blending",
                          "0.01",
                          Patterns::Double(0),
                          "Joint blending length b (the thesis fixes 0.01), "
                          "in units of the cell side 2.");
        prm.leave_subsection();
      }



      /// The `Mesh` section.
      void
      declare_mesh_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Mesh");
        prm.declare_entry(
          "Marching squares grid",
          "128",
          Patterns::Integer(8, 8192),
          "Grid cells per side tracing the boundary (thesis: 256). The "
          "boundary vertices are then projected onto the exact level set, "
          "so the grid only needs to resolve the topology.");
        prm.declare_entry("Element size",
                          "0.05",
                          Patterns::Double(0),
                          "Largest triangle edge (the cell side is 2).");
        prm.declare_entry(
          "Boundary element size",
          "0.0125",
          Patterns::Double(0),
          "Triangle edge along the material boundary, where the stresses "
          "concentrate: it controls the accuracy (doc/rhombic.md has a "
          "table; 0.0125 gives C^H to about 2%).");
        prm.declare_entry("Element degree",
                          "2",
                          Patterns::Integer(1, 4),
                          "Polynomial degree of the triangles (thesis: 2, "
                          "essential for accurate stresses and tensors).");
        prm.declare_entry(
          "Symmetric mesh",
          "true",
          Patterns::Bool(),
          "Mesh the lower half of the cell and add its copy rotated by 180 "
          "degrees about the center (every structure of the family has that "
          "symmetry): the fluctuations are then odd, which halves the "
          "unknowns and the meshing work. false meshes the whole cell.");
        prm.leave_subsection();
      }



      /// The `Solver` section.
      void
      declare_solver_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Solver");
        prm.declare_entry("Type",
                          "auto",
                          Patterns::Selection("auto|direct|cg-amg"),
                          "direct: sparse Cholesky (CHOLMOD) on one rank, KLU "
                          "on several; cg-amg: CG with ML AMG; auto: direct up "
                          "to 400000 unknowns.");
        prm.leave_subsection();
      }



      /// The `Sweep` section.
      void
      declare_sweep_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Sweep");
        const auto  ranges      = RhombicStructure::ranges();
        const char *defaults[8] = {"0.25",
                                   "0.25",
                                   "0.3:0.7:3",
                                   "0.3:0.7:3",
                                   "0.2",
                                   "0.08:0.2:3",
                                   "0.1",
                                   "0.1"};
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          prm.declare_entry(RhombicStructure::parameter_name(i),
                            defaults[i],
                            Patterns::Anything(),
                            "Values of " + RhombicStructure::parameter_name(i) +
                              ": 'a:b:n' (n values from a to b) or a list "
                              "(thesis range [" +
                              std::to_string(ranges[i][0]).substr(0, 4) + ", " +
                              std::to_string(ranges[i][1]).substr(0, 4) +
                              "]).");
        prm.declare_entry("Angles",
                          "90",
                          Patterns::Anything(),
                          "Cell angles alpha in degrees.");
        prm.declare_entry(
          "Resume",
          "false",
          Patterns::Bool(),
          "Reuse the samples of an interrupted sweep from "
          "<Output directory>/sweep_progress.csv (written after every "
          "batch, removed when the sweep completes).");
        prm.declare_entry(
          "Redundancy threshold",
          "0.9",
          Patterns::Double(0, 1),
          "The redundant-parameter test (thesis ch. 4.6.2, Fig. 4.9) on the "
          "isotropic samples at the largest angle: parameters are fixed at "
          "a sweep value, one after the other, while the samples left keep "
          "at least this share of the isotropic coverage (occupied cells of "
          "a 12 x 12 grid over the (nu, E) range).");
        prm.leave_subsection();
      }



      /// The `Inverse` section.
      void
      declare_inverse_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Inverse");
        prm.declare_entry("Target",
                          "isotropic",
                          Patterns::Selection("isotropic|structure"),
                          "isotropic: the tensor of (E, nu) below; structure: "
                          "the C^H of 'Target parameters' on the same cell "
                          "(a reachable target: recovery).");
        prm.declare_entry("Target parameters",
                          "0.3, 0.2, 0.4, 0.6, 0.2, 0.12, 0.1, 0.1",
                          Patterns::Anything(),
                          "p1..p8 of the target structure (Target = "
                          "structure).");
        prm.declare_entry(
          "Target Young's modulus",
          "0.05",
          Patterns::Double(0, 1),
          "Target E relative to the base's 2D Young's modulus.");
        prm.declare_entry("Target Poisson's ratio",
                          "0.3",
                          Patterns::Double(-1, 1),
                          "Target Poisson's ratio (isotropic target).");
        prm.declare_entry("Free parameters",
                          "p1, p2, p3, p4, p5, p6, p7, p8",
                          Patterns::Anything(),
                          "Parameters the optimization varies (within the "
                          "sweep ranges or Parameter bounds); the others keep "
                          "the Structure section's values.");
        prm.declare_entry(
          "Parameter bounds",
          "",
          Patterns::Anything(),
          "Bounds of the free parameters other than the sweep ranges (thesis "
          "ch. 4.10.2), e.g. 'p7 = 0.03:0.3, p8 = 0.03:0.3' (inside what the "
          "geometry allows: offsets [0.01, 0.99], radii [0.01, 0.6]). Below "
          "55 degrees the map needs thinner nodes 3 and 4 than 0.05 to stay "
          "isotropic.");
        prm.declare_entry("Volume weight",
                          "0",
                          Patterns::Double(0),
                          "w_v: regularization by the volume fraction.");
        prm.declare_entry("Proximity weight",
                          "0",
                          Patterns::Double(0),
                          "w_p: regularization by |p - p_start|^2.");
        prm.declare_entry("Tolerance",
                          "0.01",
                          Patterns::Double(0),
                          "Stop when |C^H - C*| / |C*| is at most this.");
        prm.declare_entry("Max iterations",
                          "40",
                          Patterns::Integer(1, 1000),
                          "L-BFGS iterations (ROL, bound constrained).");
        prm.leave_subsection();
      }



      /// The `Map` section.
      void
      declare_map_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Map");
        prm.declare_entry("Map file",
                          "map.json",
                          Patterns::Anything(),
                          "build map: the file written in the output "
                          "directory; query: the map to read (relative to the "
                          ".prm file), e.g. ../../contrib/rhombic/map.json.");
        prm.declare_entry("Young's moduli",
                          "0.03:0.09:4",
                          Patterns::Anything(),
                          "build map: E/E_b of the isotropic targets.");
        prm.declare_entry("Poisson's ratios",
                          "0.1:0.4:4",
                          Patterns::Anything(),
                          "build map: nu of the isotropic targets.");
        prm.declare_entry("Angles",
                          "90",
                          Patterns::Anything(),
                          "build map: cell angles in degrees, continued from "
                          "the largest down.");
        prm.declare_entry("Spline control points",
                          "6, 6, 4",
                          Patterns::Anything(),
                          "Control points along E, nu, alpha (thesis: 12, 12, "
                          "12).");
        prm.declare_entry("Smoothing",
                          "1e-5",
                          Patterns::Double(0),
                          "Weight of the second-difference (Laplacian) "
                          "penalty of the spline fit.");
        prm.declare_entry(
          "Young's modulus axis",
          "linear",
          Patterns::Selection("linear|logarithmic"),
          "The splines' control points along E/E_b: uniform in E, or in "
          "log E for a grid spanning decades (0.01-0.3), where uniform "
          "control points would leave the small moduli, whose structures "
          "change fastest, with one or two.");
        prm.declare_entry(
          "Branch tolerance",
          "0.25",
          Patterns::Double(0),
          "Before the fit, a sample whose parameters differ from the median of "
          "its grid neighbours' (same angle, and the same node at the "
          "neighbouring angles) by more than this (in any parameter) lies on "
          "another branch of solutions: it is dropped and its node uncovered. "
          "0 keeps every sample.");
        prm.declare_entry("Accuracy checks",
                          "8",
                          Patterns::Integer(0, 10000),
                          "build map: points between the samples queried and "
                          "homogenized to measure the map's accuracy.");
        prm.declare_entry(
          "Initial map",
          "continuation",
          Patterns::Selection("continuation|transversal|file"),
          "build map, at the first angle: continuation (outward from the "
          "Structure section's seed), transversal (the thesis's ch. 4.6.2: "
          "H linearized on the parameters left by 'Fixed parameters', "
          "restricted to the subspace V transversal to its level sets, "
          "sampled on a grid and inverted by simplices at every target; each "
          "start is polished by an inverse solve) or file (extend the map "
          "'Initial map file' to smaller angles: its angles above the first "
          "of 'Angles' and their samples are kept, the rest redone, starting "
          "from the smallest kept angle's solutions; same (E, nu) grid; with "
          "'Angles' empty the splines are only refitted, e.g. with other "
          "'Spline control points'). All then grow outward by optimization "
          "and continue over the angles.");
        prm.declare_entry("Initial map file",
                          "",
                          Patterns::Anything(),
                          "Initial map = file: the map to extend (relative to "
                          "the .prm file), e.g. "
                          "../../contrib/rhombic/map_full.json.");
        prm.declare_entry(
          "Resume",
          "false",
          Patterns::Bool(),
          "Continue an interrupted build map from "
          "<Output directory>/map_progress.json (the grid, coverage and "
          "samples of every angle done, written after each angle and removed "
          "when the build completes): its angles are kept and the run goes on "
          "below the last one, with the same settings.");
        prm.declare_entry(
          "Fixed parameters",
          "p1 = 0.25, p2 = 0.225, p5 = 0.23",
          Patterns::Anything(),
          "Initial map = transversal: the redundant parameters and their "
          "values. The default is where the continuation map's structures "
          "sit at 90 degrees (p1, p2, p5 vary by under 0.06 there); the "
          "thesis's p1 = 0.5, p2 = 0.25, p5 = 0.3 give forma's geometry "
          "E/E_b mostly above 0.2. A dense sweep's redundant_parameters is "
          "the principled choice.");
        prm.declare_entry("Sampling ranges",
                          "",
                          Patterns::Anything(),
                          "Initial map = transversal: narrower ranges of free "
                          "parameters for the samples on V' and V, e.g. "
                          "'p7 = 0.05:0.15' (default: the sweep ranges): the "
                          "samples go where the targets' structures are.");
        prm.declare_entry("Subspace samples",
                          "4",
                          Patterns::Integer(2, 50),
                          "Initial map = transversal: samples per free "
                          "parameter for the linear model (thesis: 15).");
        prm.declare_entry("Transversal grid samples",
                          "6",
                          Patterns::Integer(2, 50),
                          "Initial map = transversal: samples per coordinate "
                          "of the grid on V that is inverted.");
        prm.declare_entry(
          "Coverage axis",
          "automatic",
          Patterns::Selection("automatic|linear|logarithmic"),
          "build map: the coverage polygon D(alpha) is convex in (E/E_b, nu) "
          "(linear, the thesis's) or in (log E/E_b, nu) (logarithmic: on a "
          "grid spanning decades the covered nodes form a wide base at small "
          "E under a narrow stiff column, which a polygon in E cannot follow); "
          "automatic: as the Young's modulus axis.");
        prm.declare_entry(
          "Coverage pieces",
          "1",
          Patterns::Integer(1, 2),
          "build map: D(alpha) as one convex polygon (the thesis's) or the "
          "union of two stacked in E, each inscribed in the covered nodes of "
          "its band of rows (for a coverage that is not convex: a wide base "
          "at small E under a narrow stiff column).");
        prm.declare_entry("Coverage height weight",
                          "0",
                          Patterns::Double(0),
                          "build map: the coverage polygon D(alpha) (thesis "
                          "Fig. 4.13-4.14) maximizes its area plus this "
                          "weight times its largest E, both relative to the "
                          "grid: larger values favour stiff materials over a "
                          "wide nu range.");
        prm.leave_subsection();
      }



      /// The `Query` section.
      void
      declare_query_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Query");
        prm.declare_entry("Young's modulus",
                          "0.05",
                          Patterns::Double(0, 1),
                          "E relative to the base's 2D modulus.");
        prm.declare_entry("Poisson's ratio",
                          "0.3",
                          Patterns::Double(-1, 1),
                          "Target Poisson's ratio.");
        prm.declare_entry("Angle",
                          "90",
                          Patterns::Double(),
                          "Cell angle in degrees.");
        prm.leave_subsection();
      }



      /// The `Compound cell` section.
      void
      declare_compound_cell_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Compound cell");
        prm.declare_entry("Study",
                          "non-rhombic",
                          Patterns::Selection("non-rhombic|twist"),
                          "non-rhombic: the center vertex of the grid moves "
                          "towards the upper right corner by each of Values "
                          "(in quad sides, thesis Fig. 4.29); twist: the cross "
                          "of mesh lines through the center turns by each of "
                          "Values (degrees) and the other vertices are "
                          "optimized (Fig. 4.26).");
        prm.declare_entry("Grid",
                          "2",
                          Patterns::Integer(2, 16),
                          "Quads per side of the compound cell (even; the "
                          "twist study needs at least 4).");
        prm.declare_entry(
          "Refinement",
          "0",
          Patterns::Integer(0, 3),
          "Split every quad of the deformed compound cell into "
          "2^r x 2^r quads along its bilinear map, each with the "
          "structure for its own angle (Fig. 4.28): the quads "
          "get closer to parallelograms.");
        prm.declare_entry("Values",
                          "0, 0.1, 0.2, 0.3",
                          Patterns::Anything(),
                          "The offsets or turns of the study.");
        prm.declare_entry("Material",
                          "0.05, 0",
                          Patterns::Anything(),
                          "The target of every quad, 'E/E_b, nu' (thesis: "
                          "E = 0.05, nu = 0).");
        prm.leave_subsection();
      }



      /// The `Pointwise table` section.
      void
      declare_pointwise_table_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Pointwise table");
        prm.declare_entry("Young's moduli",
                          "0.02:0.1:9",
                          Patterns::Anything(),
                          "pointwise table: the targets' E/E_b.");
        prm.declare_entry("Poisson's ratios",
                          "0:0.4:9",
                          Patterns::Anything(),
                          "pointwise table: the targets' nu (every pair with "
                          "the Young's moduli is a target).");
        prm.leave_subsection();
      }



      /// The `Two-scale` section.
      void
      declare_two_scale_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Two-scale");
        prm.declare_entry(
          "Macro problem",
          "",
          Patterns::Anything(),
          "two-scale design: a forma-transient-ipc parameter file (relative to "
          "this one) with the object's supports, loads, objective (e.g. a "
          "'boundary target'), Design/Parameters = cell material and the "
          "Optimization section; its Mesh is replaced by the rhombic mesh, "
          "whose boundary ids come from the Quad mesh file. Materials are "
          "absolute: the base has Base material/Young's modulus.");
        prm.declare_entry(
          "Macro settings",
          "",
          Patterns::Anything(),
          "Overrides of Macro problem entries, 'Section/Entry=value' as "
          "--set on the command line, several separated by '|' (e.g. "
          "'Optimization/Max iterations=8'): variants without a copy of the "
          "file.");
        prm.declare_entry("Coverage weight",
                          "10",
                          Patterns::Double(0),
                          "Weight of the soft constraint that keeps each "
                          "cell's (E/E_b, nu) inside the map's coverage "
                          "D(alpha) of its angle: sum over cells and violated "
                          "edges of (distance / 0.01)^2 / cells, in units of "
                          "the starting objective. Cells still outside at the "
                          "end are projected into D(alpha).");
        prm.declare_entry("Constant material",
                          "",
                          Patterns::Anything(),
                          "Empty: optimize the cells' materials for the macro "
                          "problem. 'E/E_b, nu': give every cell this material "
                          "instead (no optimization), e.g. to check that the "
                          "fine-scale behaviour does not depend on the mesh.");
        prm.declare_entry(
          "Check cell moduli",
          "false",
          Patterns::Bool(),
          "Homogenize every cell's structure (on its rhombus, "
          "with the Mesh section's cell mesh) and report how far "
          "its moduli are from the cell's target: the map's "
          "share of the fine-scale error. A structure the cell "
          "mesher cannot mesh is reported and left out.");
        prm.declare_entry("Fine-scale check",
                          "true",
                          Patterns::Bool(),
                          "Mesh the tiled geometry, simulate it in the base "
                          "material with the macro problem's supports and "
                          "loads, and compare with the homogenized solution.");
        prm.declare_entry(
          "Fine-scale simulation",
          "true",
          Patterns::Bool(),
          "false: mesh the tiled geometry (fine_mesh_*.msh) but "
          "do not simulate it (e.g. to time the pipeline).");
        prm.declare_entry("Compared boundary",
                          "3",
                          Patterns::Integer(0),
                          "Boundary id (of the Quad mesh file) where the "
                          "fine-scale and homogenized displacements are "
                          "compared (e.g. the objective's target boundary).");
        prm.declare_entry(
          "Baselines",
          "remapped square",
          Patterns::MultipleSelection(
            "remapped square|cut grid|pointwise table"),
          "Fine-scale checks of the thesis's baselines (ch. 4.8) besides the "
          "family: 'remapped square' puts the structures made for squares on "
          "the same quads (Fig. 4.22); 'cut grid' optimizes the materials "
          "again on a regular grid of squares (side: the rhombic mesh's mean "
          "edge) cut by the object's outline, gives each square its square "
          "structure and crops the geometry by the outline (Fig. 4.20); "
          "'pointwise table' gives each quad the entry of the Pointwise table "
          "file nearest to its material, mapped onto it (Fig. 4.23).");
        prm.declare_entry("Fine-scale refinement",
                          "0",
                          Patterns::Integer(0, 3),
                          "Split every cell (and every square of the cut "
                          "grid) into 2^r x 2^r cells with the same structure "
                          "before tiling, the materials kept (Fig. 4.21): "
                          "closer to scale separation, 4^r times the fine "
                          "mesh.");
        prm.declare_entry("Merge joints",
                          "true",
                          Patterns::Bool(),
                          "Neighbouring cells share the joints at the "
                          "midpoints of their common sides: where their joint "
                          "radii p5 differ (structures from the pointwise "
                          "table), give both the average (ch. 4.8, merge). "
                          "false: the larger joint wins.");
        prm.declare_entry("Pointwise table",
                          "",
                          Patterns::Anything(),
                          "The table of the 'pointwise table' baseline "
                          "(relative to this file): pointwise_table.json of "
                          "Mode = pointwise table.");
        prm.declare_entry(
          "Fine element size",
          "0.1",
          Patterns::Double(0),
          "Element size of the fine-scale mesh, relative to the "
          "quads' mean size.");
        prm.declare_entry("Fine boundary element size",
                          "0.02",
                          Patterns::Double(0),
                          "Element size along the fine-scale geometry's "
                          "boundary, relative to the quads' mean size.");
        prm.leave_subsection();
      }



      /// The `Quad mesh` section.
      void
      declare_quad_mesh_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Quad mesh");
        prm.declare_entry(
          "File",
          "",
          Patterns::Anything(),
          "The object's quad mesh (thesis ch. 4.7): a Gmsh .msh "
          "file of quadrilaterals, or a 2D Gmsh .geo geometry "
          "meshed into quads (Physical Curves give boundary ids, "
          "Physical Surfaces material ids); relative to the "
          "parameter file.");
        prm.declare_entry("Element size",
                          "0.1",
                          Patterns::Double(0),
                          "Quad edge length when the file is a .geo geometry "
                          "(the size of the microstructure cells).");
        prm.declare_entry("Refinement",
                          "0",
                          Patterns::Integer(0, 6),
                          "Split every quad into 4 this many times before the "
                          "optimization.");
        QuadMeshOptimizationParameters::declare(prm);
        prm.leave_subsection();
      }



      /// The `Output` section.
      void
      declare_output_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Output");
        prm.declare_entry("Write vtu",
                          "true",
                          Patterns::Bool(),
                          "homogenize: write the cell mesh with the "
                          "fluctuations (cell.vtu).");
        prm.declare_entry("SVG cell side",
                          "20",
                          Patterns::Double(1e-3),
                          "homogenize, query: the side of the cell in "
                          "structure.svg, in millimetres (one cell's "
                          "material for a cutter; copies tile).");
        prm.declare_entry("Isotropy tolerance",
                          "0.005",
                          Patterns::Double(0),
                          "A structure with a1 and a2 (eq. 4.10) at most this "
                          "counts as isotropic (thesis ch. 4.6.2: 0.005).");
        prm.leave_subsection();
      }
    } // namespace



    void
    declare_parameters(ParameterHandler &prm)
    {
      BaseMaterial::declare(prm);

      declare_structure_section(prm);
      declare_mesh_section(prm);
      declare_solver_section(prm);
      declare_sweep_section(prm);
      declare_inverse_section(prm);
      GradientCheckParameters::declare(prm);

      declare_map_section(prm);
      declare_query_section(prm);
      declare_compound_cell_section(prm);
      declare_pointwise_table_section(prm);
      declare_two_scale_section(prm);
      declare_quad_mesh_section(prm);
      declare_output_section(prm);
    }



    Setup
    parse_setup(ParameterHandler &prm, RunContext &context)
    {
      Setup setup;
      setup.material = BaseMaterial::parse(prm);
      setup.base     = setup.material.moduli();

      prm.enter_subsection("Structure");
      setup.blending = prm.get_double("Blending");
      prm.leave_subsection();

      prm.enter_subsection("Mesh");
      setup.mesh.grid          = prm.get_integer("Marching squares grid");
      setup.mesh.size          = prm.get_double("Element size");
      setup.mesh.boundary_size = prm.get_double("Boundary element size");
      setup.degree             = prm.get_integer("Element degree");
      setup.symmetric_mesh     = prm.get_bool("Symmetric mesh");
      prm.leave_subsection();
      AssertThrow(setup.mesh.size > 0 && setup.mesh.size <= 0.5 &&
                    setup.mesh.boundary_size > 0 &&
                    setup.mesh.boundary_size <= setup.mesh.size,
                  ExcMessage("Mesh: need 0 < Boundary element size <= "
                             "Element size <= 0.5 (the cell side is 2)"));

      prm.enter_subsection("Solver");
      setup.solver.type = prm.get("Type");
      prm.leave_subsection();

      prm.enter_subsection("Output");
      setup.write_vtu          = prm.get_bool("Write vtu");
      setup.svg_cell_side      = prm.get_double("SVG cell side");
      setup.isotropy_tolerance = prm.get_double("Isotropy tolerance");
      prm.leave_subsection();

      context.summary["base_material"]   = setup.material.summary();
      context.summary["mesh_parameters"] = {
        {"marching_squares_grid", setup.mesh.grid},
        {"element_size", setup.mesh.size},
        {"boundary_element_size", setup.mesh.boundary_size},
        {"degree", setup.degree},
        {"symmetric_mesh", setup.symmetric_mesh}};
      return setup;
    }
  } // namespace rhombic
} // namespace forma
