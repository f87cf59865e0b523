#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/rank_strided.h>
#include <forma/base/run_context.h>
#include <forma/laminate/study.h>
#include <forma/laminate/sweep_progress.h>

#include <boost/serialization/array.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    Sample
    evaluate(PeriodicHomogenization<2> &cell,
             const PixelMaterial       &material,
             const Setup               &setup)
    {
      Sample r;
      r.phi = material.volume_fraction();
      AssertThrow(r.phi > 1e-6,
                  ExcMessage("the structure has no material (volume fraction " +
                             sig(r.phi) + "): nothing to homogenize"));
      r.C          = cell.homogenize(std::cref(material)).C;
      r.fit        = isotropic_fit(r.C);
      r.anisotropy = anisotropy(r.C);
      r.hs = hashin_shtrikman(setup.base, setup.weak, std::min(1., r.phi));
      r.hs_violation = r.hs.violation(r.fit);
      return r;
    }

    /// Cells along the sqrt(3) x 1 rectangle for ny along its height: the
    /// even number nearest sqrt(3) ny (near-square cells; even, so that the
    /// primitive half cell is a grid).
    unsigned int
    grid_nx(const unsigned int ny)
    {
      return 2 * std::lround(HexagonalLaminate::width * ny / 2);
    }

    /**
     * The homogenization grid of the family structures on ny cells along the
     * height (nx = grid_nx(ny) along the rectangle). With `Use
     * symmetry`: when nx and ny are even, the primitive half [0, sqrt(3)/2] x
     * [0, 1] of the rectangle with the hexagonal lattice's shift (0, 1/2),
     * and odd fluctuations about the origin: the rectangle's C^H with a
     * quarter of the unknowns.
     */
    std::unique_ptr<PeriodicHomogenization<2>>
    family_grid(const MPI_Comm comm, const Setup &setup, const unsigned int ny)
    {
      const unsigned int nx = grid_nx(ny);
      // Every family structure is symmetric under the rotation by pi about
      // the lattice point at the origin (a grid vertex): odd fluctuations.
      // The multigrid solver takes the whole rectangle, without symmetry.
      const bool symmetry = setup.symmetry && setup.solver.type != "multigrid";
      PeriodicHomogenization<2>::GridLattice lattice;
      lattice.inversion = symmetry;
      if (symmetry && ny % 2 == 0)
        {
          lattice.shift = Tensor<1, 2>({0., HexagonalLaminate::height / 2});
          return std::make_unique<PeriodicHomogenization<2>>(
            comm,
            Point<2>(HexagonalLaminate::width / 2, HexagonalLaminate::height),
            std::array<unsigned int, 2>{{nx / 2, ny}},
            setup.solver,
            1,
            lattice);
        }
      return std::make_unique<PeriodicHomogenization<2>>(
        comm,
        Point<2>(HexagonalLaminate::width, HexagonalLaminate::height),
        std::array<unsigned int, 2>{{nx, ny}},
        setup.solver,
        1,
        lattice);
    }

    HexagonalLaminate
    read_structure(ParameterHandler &prm)
    {
      HexagonalLaminate s;
      prm.enter_subsection("Structure");
      s.family = HexagonalLaminate::family_from_string(prm.get("Type"));
      s.limit  = prm.get_bool("Limit structure");
      s.p1     = prm.get_double("p1");
      s.p2     = prm.get_double("p2");
      s.p3     = prm.get_double("p3");
      s.p4     = prm.get_double("p4");
      s.theta  = prm.get_double("theta");
      s.alpha  = prm.get_double("alpha") * numbers::PI / 180;
      prm.leave_subsection();
      s.check();
      return s;
    }

    nlohmann::json
    structure_json(const HexagonalLaminate &s)
    {
      nlohmann::json j = {
        {"type", s.family_name()},
        {"limit", s.limit},
        {"lamination_angle_degrees", s.lamination_angle() * 180 / numbers::PI},
        {"critical_angle_degrees", s.critical_angle() * 180 / numbers::PI},
        {"volume_fraction_formula", s.volume_fraction_formula()}};
      if (s.limit)
        j.update({{"p1", s.p1},
                  {"theta", s.theta},
                  {"alpha_degrees", s.alpha * 180 / numbers::PI}});
      else
        j.update({{"p1", s.p1},
                  {"p2", s.p2},
                  {"p3", s.p3},
                  {"p4", s.p4},
                  {"beams_per_joint", 1 / s.p3}});
      return j;
    }

    nlohmann::json
    sample_json(const Sample &r, const Setup &setup)
    {
      nlohmann::json    j;
      const VoigtMatrix V   = to_voigt(r.C);
      j["C_voigt"]          = {{V[0][0], V[0][1], V[0][2]},
                               {V[1][0], V[1][1], V[1][2]},
                               {V[2][0], V[2][1], V[2][2]}};
      j["E"]                = r.fit.E;
      j["nu"]               = r.fit.nu;
      j["kappa"]            = r.fit.kappa;
      j["mu"]               = r.fit.mu;
      j["volume_fraction"]  = r.phi;
      j["anisotropy"]       = {{"a1", r.anisotropy.a1},
                               {"a2", r.anisotropy.a2},
                               {"residual", r.anisotropy.residual}};
      j["hashin_shtrikman"] = {{"volume_fraction", std::min(1., r.phi)},
                               {"kappa_upper", r.hs.kappa_upper},
                               {"mu_upper", r.hs.mu_upper},
                               {"kappa_lower", r.hs.kappa_lower},
                               {"mu_lower", r.hs.mu_lower},
                               {"E_max_at_nu",
                                r.hs.max_young_modulus(r.fit.nu)},
                               {"inside", r.hs_violation <= 0},
                               {"violation", r.hs_violation}};
      // The same structure made of other base Poisson's ratios (CLM).
      for (const auto &[nu, m] : setup.material.clm_fits(r.C))
        j["clm"].push_back({{"base_nu", nu}, {"E", m.E}, {"nu", m.nu}});
      return j;
    }

    SweepGrid
    read_sweep_grid(ParameterHandler &prm)
    {
      SweepGrid g;
      prm.enter_subsection("Sweep");
      for (const auto &f : Utilities::split_string_list(prm.get("Families")))
        {
          const auto family = HexagonalLaminate::family_from_string(f);
          if (std::find(g.families.begin(), g.families.end(), family) ==
              g.families.end())
            g.families.push_back(family);
        }
      g.limit = prm.get_bool("Limit structures");
      auto &v = g.values;
      for (const char *name : {"p1", "p2", "p3", "p4", "theta", "alpha"})
        v[name] = parse_values(prm.get(name), std::string("Sweep/") + name);
      const std::string beams = Utilities::trim(prm.get("Beams per joint"));
      if (!beams.empty())
        {
          v["p3"].clear();
          for (const double n : parse_values(beams, "Sweep/Beams per joint"))
            {
              AssertThrow(n >= 1,
                          ExcMessage("Sweep/Beams per joint: " + sig(n) +
                                     " is less than one beam"));
              v["p3"].push_back(1 / n);
            }
        }
      g.level = prm.get_double("Coverage level");
      g.band  = prm.get_double("Coverage band");
      prm.leave_subsection();

      for (const auto family : g.families)
        for (const double p1 : v["p1"])
          if (g.limit)
            for (const double theta : v["theta"])
              for (const double alpha : v["alpha"])
                {
                  HexagonalLaminate s;
                  s.family = family, s.limit = true, s.p1 = p1, s.theta = theta,
                  s.alpha = alpha * numbers::PI / 180;
                  s.check();
                  g.structures.push_back(s);
                }
          else
            for (const double p2 : v["p2"])
              for (const double p3 : v["p3"])
                for (const double p4 : v["p4"])
                  {
                    HexagonalLaminate s;
                    s.family = family, s.p1 = p1, s.p2 = p2, s.p3 = p3,
                    s.p4 = p4;
                    s.check();
                    g.structures.push_back(s);
                  }
      return g;
    }


    /**
     * Homogenize `structures` on an nx x ny grid, round-robin over the ranks
     * (each with its own serial solver), with a progress line per batch.
     * Returns n_fields values per structure on every rank.
     */
    namespace
    {
      // One structure's sample fields (see Field); structure k of the
      // sweep, for the error message.
      std::array<double, n_fields>
      homogenize_one(const std::vector<HexagonalLaminate> &structures,
                     const unsigned int                    k,
                     const Setup                          &setup,
                     PeriodicHomogenization<2>            &cell,
                     const unsigned int                    nx,
                     const unsigned int                    ny)
      {
        try
          {
            const auto material = pixel_material(
              structures[k], setup.base, setup.weak, setup.gray, nx, ny);
            const Sample      r = evaluate(cell, material, setup);
            const VoigtMatrix V = to_voigt(r.C);
            return {{structures[k].volume_fraction_formula(),
                     r.phi,
                     r.fit.E,
                     r.fit.nu,
                     r.fit.kappa,
                     r.fit.mu,
                     r.anisotropy.a1,
                     r.anisotropy.a2,
                     r.anisotropy.residual,
                     r.hs_violation,
                     V[0][0],
                     V[0][1],
                     V[1][1],
                     V[2][2],
                     structures[k].min_feature_size() * ny /
                       HexagonalLaminate::height}};
          }
        catch (const std::exception &e)
          {
            AssertThrow(false,
                        ExcMessage("sweep: structure " + std::to_string(k + 1) +
                                   " (" + structures[k].family_name() +
                                   ", p1 = " + sig(structures[k].p1) +
                                   "): " + error_message(e)));
            return {};
          }
      }
    } // namespace



    std::vector<double>
    homogenize_all(const std::vector<HexagonalLaminate> &structures,
                   const Setup                          &setup,
                   const unsigned int                    ny,
                   RunContext                           &context,
                   const SweepProgress                  *progress)
    {
      const unsigned int nx = grid_nx(ny);
      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(context.communicator());
      const auto cell = family_grid(MPI_COMM_SELF, setup, ny);
      context.print(
        "sweep: " + std::to_string(structures.size()) + " structures on a " +
        std::to_string(nx) + " x " + std::to_string(ny) + " grid" +
        (cell->n_cells() < nx * ny ? " (the primitive half cell)" : ""));
      std::vector<double> table(structures.size() * n_fields, 0.);
      // Structures an interrupted sweep finished.
      std::vector<bool> taken(structures.size(), false);
      if (progress != nullptr && progress->n_done() > 0)
        {
          unsigned int n_taken = 0;
          for (unsigned int k = 0; k < structures.size(); ++k)
            if (const auto *v = progress->done(k); v && v->size() == n_fields)
              {
                std::copy(v->begin(), v->end(), table.begin() + k * n_fields);
                taken[k] = true;
                ++n_taken;
              }
          context.print("sweep: " + std::to_string(n_taken) +
                        " structures taken from sweep_progress.csv");
        }
      const unsigned int batch =
        progress_batch_size(structures.size(), 10, n_ranks);
      for (unsigned int start = 0; start < structures.size(); start += batch)
        {
          const unsigned int end =
            std::min<unsigned int>(structures.size(), start + batch);
          std::vector<unsigned int> pending;
          for (unsigned int k = start; k < end; ++k)
            if (!taken[k])
              pending.push_back(k);
          // A failed structure stops the sweep on every rank (rank_strided
          // rethrows the first failure).
          const auto results = rank_strided<std::array<double, n_fields>>(
            context.communicator(), pending.size(), [&](const unsigned int i) {
              return homogenize_one(
                structures, pending[i], setup, *cell, nx, ny);
            });
          for (unsigned int i = 0; i < results.size(); ++i)
            std::copy(results[i].begin(),
                      results[i].end(),
                      table.begin() + pending[i] * n_fields);
          if (progress != nullptr)
            progress->append(pending, table);
          context.print("sweep: " + std::to_string(end) + "/" +
                        std::to_string(structures.size()) + " structures");
        }
      return table;
    }

    namespace
    {
      /// The `Base material` section.
      void
      declare_base_material_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Base material");
        prm.declare_entry(
          "Void stiffness ratio",
          "1e-6",
          Patterns::Double(0, 1),
          "Void is a weak phase: this fraction of the base tensor "
          "(thesis: 1e-6).");
        prm.leave_subsection();
      }



      /// The `Grid` section.
      void
      declare_grid_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Grid");
        prm.declare_entry(
          "Cells along height",
          "148",
          Patterns::Integer(2, 4000),
          "Family structures: the 3:sqrt(3) cell gets m x n near-square Q1 "
          "cells, m the even number nearest sqrt(3) n (148 -> 256 x 148). "
          "Even n lets the symmetry use the primitive half cell.");
        prm.declare_entry(
          "Gray pixels",
          "hashin-shtrikman",
          Patterns::Selection("linear|hashin-shtrikman"),
          "Tensor of a partly covered cell with solid fraction rho: "
          "linear = rho C (thesis eq. 5.8; the Voigt bound, so "
          "under-resolved gaps can make results exceed the HS "
          "bounds), hashin-shtrikman = the HS upper bound at rho "
          "(the stiffest physical mixture: results stay "
          "attainable).");
        prm.declare_entry(
          "Minimum feature cells",
          "3",
          Patterns::Double(0),
          "A structure whose thinnest beam, gap between beams or joint "
          "(across the beams) spans fewer grid cells is under-resolved: gray "
          "pixels bridge the gaps, so it comes out too stiff. homogenize warns; "
          "sweep keeps it in samples.csv (min_feature_cells), draws it gray "
          "and leaves it out of the coverage.");
        prm.declare_entry(
          "Isotropy tolerance",
          "0.05",
          Patterns::Double(0),
          "Every family structure is isotropic, so an isotropy residual "
          "|C - iso(C)| / |C| above this is discretization error (e.g. at the "
          "acute hinges of chiral beams): homogenize warns, sweep leaves the "
          "sample out of the coverage (as an under-resolved one).");
        prm.declare_entry(
          "Use symmetry",
          "true",
          Patterns::Bool(),
          "Family structures: use their symmetries, with the same C^H: odd "
          "fluctuations about a lattice point (rotation by pi, on one "
          "process), and, when n is even, only the primitive "
          "half [0, sqrt(3)/2] x [0, 1] of the rectangle (periodic with the "
          "hexagonal lattice's shift). About 5x faster. false: the whole "
          "rectangle, no symmetry.");
        prm.declare_entry(
          "Solver",
          "auto",
          Patterns::Selection("auto|direct|cg-amg|multigrid"),
          "direct: sparse Cholesky (CHOLMOD) on one rank, KLU on "
          "several; cg-amg: CG with ML AMG (slow for strong void "
          "contrast); auto: direct up to 400000 unknowns (after the "
          "symmetry and periodicity constraints). multigrid: no matrix, CG "
          "with a Galerkin multigrid on the pixel grid, the same C^H to "
          "1e-8 in a fraction of the memory (the whole rectangle: Use "
          "symmetry is ignored; conforming meshes use auto).");
        prm.declare_entry(
          "Adaptive cycles",
          "0",
          Patterns::Integer(0, 30),
          "homogenize: after the grid's C^H, refine the Refine fraction of "
          "the cells with the largest stress jumps of the cell problems (the "
          "energy-norm error, which is C^H's own) and homogenize again, this "
          "many times: hanging nodes, periodicity kept; the pixels stay the "
          "geometry, the finer cells resolve the fields at corners and thin "
          "features. Needs Solver direct, cg-amg or auto; homogenize then "
          "does not use the symmetry.");
        prm.declare_entry("Refine fraction",
                          "0.2",
                          Patterns::Double(0, 1),
                          "Adaptive cycles: the fraction of the cells refined "
                          "in each cycle.");
        prm.declare_entry(
          "Solver tolerance",
          "1e-10",
          Patterns::Double(1e-14, 1e-2),
          "Relative residual of the iterative solvers (cg-amg, multigrid). "
          "C^H's error is about its square, a derivative's about itself: "
          "multigrid with 1e-6 gives C^H to 1e-10 in fewer steps, but "
          "derivatives (inverse design) only to about 1e-6.");
        prm.leave_subsection();
      }



      /// The `Structure` section.
      void
      declare_structure_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Structure");
        prm.declare_entry(
          "Type",
          "hexagon",
          Patterns::Selection("hexagon|triangle|image"),
          "A Triangle/Hexagon family structure, or a user image.");
        prm.declare_entry(
          "Limit structure",
          "false",
          Patterns::Bool(),
          "Two-scale limit structure: joints are rank-one laminates "
          "(p1, theta, alpha) instead of beams (p1..p4).");
        prm.declare_entry("p1",
                          "0.75",
                          Patterns::Double(),
                          "Tile size in (0, 1).");
        prm.declare_entry(
          "p2",
          "0",
          Patterns::Double(),
          "Chirality in [0, 1]: sideways shift of a beam across its "
          "joint, as a fraction of the joint width (1 = diagonal).");
        prm.declare_entry(
          "p3",
          "0.2",
          Patterns::Double(),
          "Beam period as a fraction of the joint width, in (0, 1] "
          "(1/p3 beams; a remainder makes a thinner beam).");
        prm.declare_entry("p4",
                          "0.8",
                          Patterns::Double(),
                          "Beam width as a fraction of the period, in (0, 1].");
        prm.declare_entry(
          "theta",
          "0.8",
          Patterns::Double(),
          "Limit structures: strong fraction of the joint laminate.");
        prm.declare_entry(
          "alpha",
          "0",
          Patterns::Double(),
          "Limit structures: layer angle to the joint axis, degrees.");
        prm.declare_entry(
          "Image file",
          "",
          Patterns::Anything(),
          "Type = image: a grayscale PGM (P2/P5), PNG (1-16 bits) or TIFF "
          "(1-16 bits or floats in [0, 1]; the first image) image, or "
          "a CSV matrix of densities in [0, 1]; relative to the .prm file.");
        prm.declare_entry("Image width",
                          "1",
                          Patterns::Double(0),
                          "Width of the cell the image covers.");
        prm.declare_entry("Image height",
                          "1",
                          Patterns::Double(0),
                          "Height of the cell the image covers.");
        prm.declare_entry("Invert image",
                          "false",
                          Patterns::Bool(),
                          "true: black = solid (density = 1 - gray).");
        prm.leave_subsection();
      }



      /// The `Sweep` section.
      void
      declare_sweep_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Sweep");
        prm.declare_entry("Families",
                          "hexagon, triangle",
                          Patterns::Anything(),
                          "Structure families to sweep.");
        prm.declare_entry("Limit structures",
                          "false",
                          Patterns::Bool(),
                          "Sweep limit structures over p1, theta, alpha.");
        prm.declare_entry("p1",
                          "0.6:0.9:4",
                          Patterns::Anything(),
                          "Values: 'a:b:n' (n values from a to b) or a list.");
        prm.declare_entry("p2",
                          "0, 0.5, 1",
                          Patterns::Anything(),
                          "Values of p2.");
        prm.declare_entry("p3", "0.25", Patterns::Anything(), "Values of p3.");
        prm.declare_entry("Beams per joint",
                          "",
                          Patterns::Anything(),
                          "If set, values of n = 1/p3 (replaces p3).");
        prm.declare_entry("p4",
                          "0.3:0.9:4",
                          Patterns::Anything(),
                          "Values of p4.");
        prm.declare_entry("theta",
                          "0.5:0.95:4",
                          Patterns::Anything(),
                          "Values of theta (limit structures).");
        prm.declare_entry("alpha",
                          "0, 30, 60",
                          Patterns::Anything(),
                          "Values of alpha in degrees (limit structures).");
        prm.declare_entry("Coverage level",
                          "0.5",
                          Patterns::Double(0, 1),
                          "E/Eb at which Delta_R and Delta_L are measured.");
        prm.declare_entry(
          "Coverage band",
          "0.02",
          Patterns::Double(0, 1),
          "Samples with |E/Eb - level| <= band count for Delta.");
        prm.declare_entry(
          "Resume",
          "false",
          Patterns::Bool(),
          "Continue a killed sweep from <Output directory>/"
          "sweep_progress.csv: the structures it finished are taken over, "
          "the rest computed, and the samples are the uninterrupted sweep's. "
          "The file records the Base material, Grid and Sweep settings (but "
          "Coverage level and band); a sweep with others is refused.");
        prm.leave_subsection();
      }



      /// The `Inverse` section.
      void
      declare_inverse_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Inverse");
        prm.declare_entry(
          "Target Young's modulus",
          "0.3",
          Patterns::Double(0, 1),
          "Target E relative to the base's 2D Young's modulus.");
        prm.declare_entry("Target Poisson's ratio",
                          "0.3",
                          Patterns::Double(-1, 1),
                          "Target Poisson's ratio.");
        prm.declare_entry(
          "Table file",
          "",
          Patterns::Anything(),
          "samples.csv of an earlier sweep (same Base material), relative to "
          "the .prm file; empty: the Sweep section's grid is homogenized first "
          "on 'Table cells along height'.");
        prm.declare_entry(
          "Table cells along height",
          "48",
          Patterns::Integer(2, 4000),
          "Resolution of the table sweep when there is no table "
          "file.");
        prm.declare_entry("Candidates",
                          "3",
                          Patterns::Integer(1, 100),
                          "Nearest table samples refined by optimization (in "
                          "this order, until one reaches the tolerance).");
        prm.declare_entry("Max iterations",
                          "30",
                          Patterns::Integer(1, 1000),
                          "L-BFGS iterations per candidate.");
        prm.declare_entry(
          "Tolerance",
          "1e-3",
          Patterns::Double(0),
          "Stop when sqrt((E/E* - 1)^2 + (nu - nu*)^2) is below (Objective "
          "= moduli).");
        prm.declare_entry(
          "Objective",
          "moduli",
          Patterns::Selection("moduli|compliance"),
          "moduli: J = (E/E* - 1)^2 + (nu - nu*)^2. compliance: thesis ch. "
          "5.5's J = 1/2 |S^H - S*|_F^2, S^H = (C^H)^-1 and S* the compliance "
          "of the isotropic target; with a target on the Hashin-Shtrikman bound "
          "the run ends where the family's parameters stop improving J (thesis "
          "Table 5.1), not at Tolerance.");
        prm.declare_entry(
          "Report shape derivative",
          "false",
          Patterns::Bool(),
          "Thesis Table 5.1: at every accepted iterate, mesh the structure with "
          "Gmsh (Conforming mesh section), homogenize it and report the norm "
          "of the shape derivative of the compliance J with respect to the "
          "positions of all vertices on the solid-void interface (exact for "
          "the discrete J), and the share of its square within one element "
          "size of the polygons' corners. Needs Objective = compliance.");
        prm.leave_subsection();
      }



      /// The `Conforming mesh` section.
      void
      declare_conforming_mesh_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Conforming mesh");
        prm.declare_entry("Element size",
                          "0.01",
                          Patterns::Double(0),
                          "compare meshes, Inverse/Report shape derivative: "
                          "target triangle size (the cell is sqrt(3) x 1).");
        prm.declare_entry("Degree",
                          "2",
                          Patterns::Integer(1, 3),
                          "compare meshes, Inverse/Report shape derivative: "
                          "polynomial degree on the triangles.");
        prm.leave_subsection();
      }



      /// The `Output` section.
      void
      declare_output_section(ParameterHandler &prm)
      {
        prm.enter_subsection("Output");
        prm.declare_entry(
          "Write vtu",
          "true",
          Patterns::Bool(),
          "homogenize: write the density and the three fluctuation "
          "fields (fields.vtu).");
        prm.leave_subsection();
      }
    } // namespace



    void
    declare_parameters(ParameterHandler &prm)
    {
      BaseMaterial::declare(prm);
      declare_base_material_section(prm);
      declare_grid_section(prm);
      declare_structure_section(prm);
      declare_sweep_section(prm);
      declare_inverse_section(prm);
      declare_conforming_mesh_section(prm);
      declare_output_section(prm);
    }



    Setup
    parse_setup(ParameterHandler &prm, RunContext &context)
    {
      Setup setup;
      setup.material = BaseMaterial::parse(prm);
      prm.enter_subsection("Base material");
      setup.weak_ratio = prm.get_double("Void stiffness ratio");
      prm.leave_subsection();
      AssertThrow(setup.weak_ratio > 0,
                  ExcMessage(
                    "Base material/Void stiffness ratio must be positive "
                    "(the void is a weak phase)"));
      setup.base = setup.material.moduli();
      setup.weak =
        IsotropicModuli::from_bulk_shear(setup.weak_ratio * setup.base.kappa,
                                         setup.weak_ratio * setup.base.mu);
      prm.enter_subsection("Grid");
      setup.cells_along_height = prm.get_integer("Cells along height");
      setup.solver.type        = prm.get("Solver");
      setup.solver.tolerance   = prm.get_double("Solver tolerance");
      setup.symmetry           = prm.get_bool("Use symmetry");
      setup.min_feature_cells  = prm.get_double("Minimum feature cells");
      setup.isotropy_tolerance = prm.get_double("Isotropy tolerance");
      setup.adaptive_cycles    = prm.get_integer("Adaptive cycles");
      setup.refine_fraction    = prm.get_double("Refine fraction");
      AssertThrow(setup.adaptive_cycles == 0 ||
                    setup.solver.type != "multigrid",
                  ExcMessage("Grid/Adaptive cycles: the multigrid solver "
                             "works on the uniform pixel grid; use Solver = "
                             "auto, direct or cg-amg."));
      AssertThrow(setup.adaptive_cycles == 0 || setup.refine_fraction > 0,
                  ExcMessage("Grid/Adaptive cycles needs a positive Refine "
                             "fraction."));
      setup.gray = prm.get("Gray pixels") == "linear" ?
                     GrayPixels::linear :
                     GrayPixels::hashin_shtrikman;
      prm.leave_subsection();
      prm.enter_subsection("Output");
      setup.write_vtu = prm.get_bool("Write vtu");
      prm.leave_subsection();
      context.summary["base_material"] = setup.material.summary();
      context.summary["base_material"]["void_stiffness_ratio"] =
        setup.weak_ratio;
      context.summary["base_material"]["gray_pixels"] =
        setup.gray == GrayPixels::linear ? "linear" : "hashin-shtrikman";

      return setup;
    }
  } // namespace laminate
} // namespace forma
