// forma-laminate: hexagonal Triangle/Hexagon laminate microstructures,
// periodic homogenization and Hashin-Shtrikman coverage (thesis ch. 5).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/bounds.h>
#include <forma/homogenization/coverage.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/periodic_phase_mesh.h>
#include <forma/microstructure/density_image.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>
#include <forma/optimization/optimizer.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace
{
  using namespace dealii;
  using namespace forma;

  std::string
  sig(const double x, const int digits = 4)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
    return s.str();
  }

  // "a:b:n" (n values from a to b) or a comma separated list.
  std::vector<double>
  parse_values(const std::string &text, const std::string &name)
  {
    std::vector<double> values;
    auto                number = [&](const std::string &t) {
      std::size_t used = 0;
      double      v    = 0;
      try
        {
          v = std::stod(t, &used);
        }
      catch (...)
        {
          used = 0;
        }
      AssertThrow(used == t.size() && !t.empty(),
                  ExcMessage("Sweep/" + name + ": '" + t +
                             "' is not a number (use 'a:b:n' or a list)"));
      return v;
    };
    const std::string trimmed = Utilities::trim(text);
    if (trimmed.find(':') != std::string::npos)
      {
        const auto parts = Utilities::split_string_list(trimmed, ':');
        AssertThrow(parts.size() == 3,
                    ExcMessage("Sweep/" + name + ": a range is 'a:b:n', got '" +
                               trimmed + "'"));
        const double       a = number(parts[0]), b = number(parts[1]);
        const double       nd = number(parts[2]);
        const unsigned int n  = static_cast<unsigned int>(nd);
        AssertThrow(n >= 1 && n == nd,
                    ExcMessage("Sweep/" + name + ": the count in '" + trimmed +
                               "' must be a positive integer"));
        for (unsigned int k = 0; k < n; ++k)
          values.push_back(n == 1 ? a : a + (b - a) * k / (n - 1));
      }
    else
      for (const auto &t : Utilities::split_string_list(trimmed, ','))
        values.push_back(number(t));
    AssertThrow(!values.empty(), ExcMessage("Sweep/" + name + " is empty"));
    return values;
  }

  struct Setup
  {
    IsotropicModuli     base, weak;
    PlaneModel          plane  = PlaneModel::plane_stress;
    double              base_E = 1, base_nu = 0, weak_ratio = 1e-6;
    std::vector<double> clm_poisson;
    unsigned int        cells_along_height = 148;
    PeriodicHomogenization<2>::SolverParameters solver;
    bool                                        write_vtu = true;
    GrayPixels gray     = GrayPixels::hashin_shtrikman;
    bool       symmetry = true;
    /// Structures with thinner beams, gaps or joints are under-resolved.
    double min_feature_cells = 3;
  };

  /// What one homogenized structure gives.
  struct Sample
  {
    double                phi = 0, phi_formula = 0;
    SymmetricTensor<4, 2> C;
    IsotropicModuli       fit;
    Anisotropy            anisotropy;
    HashinShtrikmanBounds hs;
    double                hs_violation = 0;
  };

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
    PeriodicHomogenization<2>::GridLattice lattice;
    lattice.inversion = setup.symmetry;
    if (setup.symmetry && ny % 2 == 0)
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
                             {"E_max_at_nu", r.hs.max_young_modulus(r.fit.nu)},
                             {"inside", r.hs_violation <= 0},
                             {"violation", r.hs_violation}};
    // The same structure made of other base Poisson's ratios (CLM).
    for (const double nu : setup.clm_poisson)
      {
        const auto to =
          IsotropicModuli::of_material(setup.base_E, nu, setup.plane);
        const auto moved = isotropic_fit(clm_transform(r.C, setup.base, to));
        j["clm"].push_back({{"base_nu", nu}, {"E", moved.E}, {"nu", moved.nu}});
      }
    return j;
  }

  void
  homogenize_mode(ParameterHandler  &prm,
                  const std::string &prm_directory,
                  const Setup       &setup,
                  RunContext        &context)
  {
    prm.enter_subsection("Structure");
    const std::string type = prm.get("Type");
    prm.leave_subsection();

    std::unique_ptr<PeriodicHomogenization<2>> cell;
    std::unique_ptr<PixelMaterial>             material;
    nlohmann::json                             structure;
    if (type == "image")
      {
        prm.enter_subsection("Structure");
        std::string  file   = prm.get("Image file");
        const double width  = prm.get_double("Image width"),
                     height = prm.get_double("Image height");
        const bool invert   = prm.get_bool("Invert image");
        prm.leave_subsection();
        AssertThrow(!file.empty(),
                    ExcMessage(
                      "Structure/Type = image needs Structure/Image file"));
        if (file[0] != '/')
          file = prm_directory + "/" + file;
        const DensityImage image = DensityImage::read(file, invert);
        AssertThrow(image.mean() > 1e-6,
                    ExcMessage("the structure image '" + file +
                               "' is empty (all densities are 0): nothing to "
                               "homogenize"));
        // One grid cell per pixel; the raster is the image.
        PhaseRaster raster(image.nx, image.ny, width, height, 1);
        for (unsigned int j = 0; j < image.ny; ++j)
          for (unsigned int i = 0; i < image.nx; ++i)
            {
              const double x0 = width * i / image.nx,
                           x1 = width * (i + 1) / image.nx,
                           y0 = height * j / image.ny,
                           y1 = height * (j + 1) / image.ny;
              const double d  = image.density(i, j);
              if (d > 0)
                {
                  // A rectangle of area d inside the pixel.
                  raster.add({Point<2>(x0, y0),
                              Point<2>(x0 + d * (x1 - x0), y0),
                              Point<2>(x0 + d * (x1 - x0), y1),
                              Point<2>(x0, y1)},
                             0);
                }
            }
        material =
          std::make_unique<PixelMaterial>(std::move(raster),
                                          std::vector<double>{1},
                                          std::vector<SymmetricTensor<4, 2>>{
                                            setup.base.tensor()},
                                          setup.base,
                                          setup.weak,
                                          setup.gray);
        cell = std::make_unique<PeriodicHomogenization<2>>(
          context.communicator(),
          Point<2>(width, height),
          std::array<unsigned int, 2>{{image.nx, image.ny}},
          setup.solver);
        structure = {{"type", "image"},
                     {"pixels", {image.nx, image.ny}},
                     {"width", width},
                     {"height", height}};
        context.print("structure: image " + std::to_string(image.nx) + " x " +
                      std::to_string(image.ny) + " pixels");
      }
    else
      {
        const HexagonalLaminate s  = read_structure(prm);
        const unsigned int      ny = setup.cells_along_height;
        const unsigned int      nx = grid_nx(ny);
        material                   = std::make_unique<PixelMaterial>(
          pixel_material(s, setup.base, setup.weak, setup.gray, nx, ny));
        cell                 = family_grid(context.communicator(), setup, ny);
        structure            = structure_json(s);
        const double feature = s.min_feature_size() * ny / s.height;
        structure["min_feature_cells"] = feature;
        if (feature < setup.min_feature_cells)
          context.print("warning: the thinnest beam, gap or joint spans " +
                        sig(feature, 2) +
                        " grid cells: under-resolved, the result is too "
                        "stiff (refine Grid/Cells along height)");
        context.print("structure: " + s.family_name() +
                      (s.limit ? " limit" : "") + ", volume fraction " +
                      sig(s.volume_fraction_formula()) +
                      " (eq. 5.11), lamination angle " +
                      sig(s.lamination_angle() * 180 / numbers::PI) + " deg");
      }
    const bool half =
      type != "image" && cell->volume() < 0.75 * HexagonalLaminate::width *
                                            HexagonalLaminate::height;
    context.print("grid: " + std::to_string(cell->n_cells()) + " cells, " +
                  std::to_string(cell->n_dofs()) + " unknowns" +
                  (half ? " (the primitive half cell)" : ""));
    Timer        timer;
    const Sample r = evaluate(*cell, *material, setup);
    context.log("homogenization: " + sig(timer.wall_time()) + " s wall");
    context.print("E = " + sig(r.fit.E) + ", nu = " + sig(r.fit.nu) +
                  ", kappa = " + sig(r.fit.kappa) + ", mu = " + sig(r.fit.mu) +
                  ", volume fraction " + sig(r.phi));
    context.print("anisotropy a1 = " + sig(r.anisotropy.a1, 2) + ", a2 = " +
                  sig(r.anisotropy.a2, 2) + "; Hashin-Shtrikman: E_max(nu) = " +
                  sig(r.hs.max_young_modulus(r.fit.nu)) +
                  (r.hs_violation <= 0 ? ", inside" : ", OUTSIDE"));
    context.summary["structure"] = structure;
    context.summary["grid"]      = {{"cells", cell->n_cells()},
                                    {"unknowns", cell->n_dofs()}};
    context.summary["result"]    = sample_json(r, setup);
    if (setup.write_vtu)
      cell->write_vtu(context.path("fields"),
                      {"density"},
                      [&](const Point<2> &x, const types::material_id) {
                        return std::vector<double>{material->density_at(x)};
                      });
  }

  /// The Sweep section: families and a parameter grid.
  struct SweepGrid
  {
    std::vector<HexagonalLaminate::Family>     families;
    bool                                       limit = false;
    std::map<std::string, std::vector<double>> values;
    std::vector<HexagonalLaminate>             structures;
    double                                     level = 0.5, band = 0.02;
  };

  SweepGrid
  read_sweep_grid(ParameterHandler &prm)
  {
    SweepGrid g;
    prm.enter_subsection("Sweep");
    for (const auto &f : Utilities::split_string_list(prm.get("Families")))
      g.families.push_back(HexagonalLaminate::family_from_string(f));
    g.limit = prm.get_bool("Limit structures");
    auto &v = g.values;
    for (const char *name : {"p1", "p2", "p3", "p4", "theta", "alpha"})
      v[name] = parse_values(prm.get(name), name);
    const std::string beams = Utilities::trim(prm.get("Beams per joint"));
    if (!beams.empty())
      {
        v["p3"].clear();
        for (const double n : parse_values(beams, "Beams per joint"))
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
                  s.family = family, s.p1 = p1, s.p2 = p2, s.p3 = p3, s.p4 = p4;
                  s.check();
                  g.structures.push_back(s);
                }
    return g;
  }

  /// Columns of the sample table (after the structure parameters).
  constexpr unsigned int n_fields = 15;
  enum Field
  {
    f_phi_formula,
    f_phi,
    f_E,
    f_nu,
    f_kappa,
    f_mu,
    f_a1,
    f_a2,
    f_residual,
    f_hs_violation,
    f_C00,
    f_C01,
    f_C11,
    f_C22,
    f_min_feature_cells
  };

  /**
   * Homogenize `structures` on an nx x ny grid, round-robin over the ranks
   * (each with its own serial solver), with a progress line per batch.
   * Returns n_fields values per structure on every rank.
   */
  std::vector<double>
  homogenize_all(const std::vector<HexagonalLaminate> &structures,
                 const Setup                          &setup,
                 const unsigned int                    ny,
                 RunContext                           &context)
  {
    const unsigned int nx      = grid_nx(ny);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(
                         context.communicator()),
                       rank = Utilities::MPI::this_mpi_process(
                         context.communicator());
    const auto cell = family_grid(MPI_COMM_SELF, setup, ny);
    context.print(
      "sweep: " + std::to_string(structures.size()) + " structures on a " +
      std::to_string(nx) + " x " + std::to_string(ny) + " grid" +
      (cell->n_cells() < nx * ny ? " (the primitive half cell)" : ""));
    std::vector<double> table(structures.size() * n_fields, 0.);
    const unsigned int  batch =
      std::max<unsigned int>(n_ranks, structures.size() / 10 + 1);
    for (unsigned int start = 0; start < structures.size(); start += batch)
      {
        const unsigned int end =
          std::min<unsigned int>(structures.size(), start + batch);
        for (unsigned int k = start; k < end; ++k)
          if (k % n_ranks == rank)
            {
              const auto material = pixel_material(
                structures[k], setup.base, setup.weak, setup.gray, nx, ny);
              const Sample      r           = evaluate(*cell, material, setup);
              const VoigtMatrix V           = to_voigt(r.C);
              const double      f[n_fields] = {
                     structures[k].volume_fraction_formula(),
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
                       HexagonalLaminate::height};
              std::copy(f, f + n_fields, table.begin() + k * n_fields);
            }
        context.print("sweep: " + std::to_string(end) + "/" +
                      std::to_string(structures.size()) + " structures");
      }
    Utilities::MPI::sum(table, context.communicator(), table);
    return table;
  }

  void
  sweep_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
  {
    SweepGrid                 grid       = read_sweep_grid(prm);
    const auto               &families   = grid.families;
    const bool                limit      = grid.limit;
    auto                     &v          = grid.values;
    const auto               &structures = grid.structures;
    const double              level = grid.level, band = grid.band;
    const unsigned int        ny = setup.cells_along_height;
    const unsigned int        nx = grid_nx(ny);
    const std::vector<double> table =
      homogenize_all(structures, setup, ny, context);

    // CSV of all samples.
    if (context.is_root())
      {
        std::ofstream csv(context.path("samples.csv"));
        csv << "family,limit,p1,p2,p3,p4,theta,alpha_degrees,beams_per_joint,"
               "phi_formula,phi,E,nu,kappa,mu,a1,a2,isotropy_residual,"
               "hs_violation,C00,C01,C11,C22,min_feature_cells\n";
        csv << std::setprecision(8);
        for (unsigned int k = 0; k < structures.size(); ++k)
          {
            const auto &s = structures[k];
            csv << s.family_name() << ',' << s.limit << ',' << s.p1 << ','
                << (s.limit ? 0 : s.p2) << ',' << (s.limit ? 0 : s.p3) << ','
                << (s.limit ? 0 : s.p4) << ',' << (s.limit ? s.theta : 0) << ','
                << s.lamination_angle() * 180 / numbers::PI << ','
                << (s.limit ? 0 : 1 / s.p3);
            for (unsigned int f = 0; f < n_fields; ++f)
              csv << ',' << table[k * n_fields + f];
            csv << '\n';
          }
      }

    // Coverage (E normalized by the base's 2D Young's modulus).
    auto samples_of = [&](const std::function<bool(unsigned int)> &take) {
      std::vector<std::array<double, 2>> s;
      for (unsigned int k = 0; k < structures.size(); ++k)
        if (take(k))
          s.push_back({{table[k * n_fields + f_nu],
                        table[k * n_fields + f_E] / setup.base.E}});
      return s;
    };
    // Samples whose beams or gaps the grid does not resolve are too stiff
    // (gray pixels bridge the gaps): they stay in samples.csv but not in
    // the coverage.
    const auto resolved = [&](const unsigned int k) {
      return table[k * n_fields + f_min_feature_cells] >=
             setup.min_feature_cells;
    };
    const auto all      = samples_of(resolved);
    const auto coverage = coverage_coefficients(all, setup.base, level, band);
    const auto n_unresolved = structures.size() - samples_of(resolved).size();
    if (n_unresolved > 0)
      context.print("coverage leaves out " + std::to_string(n_unresolved) +
                    " under-resolved samples (beams, gaps or joints under " +
                    sig(setup.min_feature_cells) + " cells)");
    double worst = -1e300, max_a = 0;
    for (unsigned int k = 0; k < structures.size(); ++k)
      {
        worst = std::max(worst, table[k * n_fields + f_hs_violation]);
        // The anisotropy measures are relative: near-mechanisms (E at the
        // void's level) carry the grid's lack of hexagonal symmetry.
        if (table[k * n_fields + f_E] >= 1e-3 * setup.base.E)
          max_a = std::max({max_a,
                            std::abs(table[k * n_fields + f_a1]),
                            std::abs(table[k * n_fields + f_a2])});
      }
    if (coverage.n_in_band == 0)
      context.print("coverage at E/Eb = " + sig(level) +
                    ": no resolved sample within the band " + sig(band));
    else
      context.print("coverage at E/Eb = " + sig(level) + ": nu from " +
                    sig(coverage.nu_left) + " to " + sig(coverage.nu_right) +
                    " (" + std::to_string(coverage.n_in_band) +
                    " samples), Delta_L = " + sig(coverage.delta_left) +
                    ", Delta_R = " + sig(coverage.delta_right));
    context.print(
      std::string("all samples inside their Hashin-Shtrikman bounds: ") +
      (worst <= 0 ? "yes" : "NO") + "; largest anisotropy " + sig(max_a, 2) +
      " (samples with E/Eb >= 1e-3)");
    nlohmann::json &S                = context.summary;
    S["samples"]                     = structures.size();
    S["under_resolved_samples"]      = n_unresolved;
    S["grid"]                        = {nx, ny};
    S["coverage"]                    = {{"level", level},
                                        {"band", band},
                                        {"samples_in_band", coverage.n_in_band},
                                        {"nu_right", coverage.nu_right},
                                        {"nu_left", coverage.nu_left},
                                        {"limit_right", coverage.limit_right},
                                        {"limit_left", coverage.limit_left},
                                        {"delta_R", coverage.delta_right},
                                        {"delta_L", coverage.delta_left}};
    S["all_inside_hashin_shtrikman"] = worst <= 0;
    S["largest_hs_violation"]        = worst;
    S["largest_anisotropy"]          = max_a;
    const auto envelope              = upper_envelope(all, -1, 0, 20);
    if (envelope.size() >= 3)
      {
        const auto c             = fit_boundary_polynomial(envelope);
        S["boundary_polynomial"] = {{"c1", c[0]},
                                    {"c2", c[1]},
                                    {"c3", c[2]},
                                    {"envelope_points", envelope.size()}};
      }

    // Coverage per number of beams (Fig. 5.6C, 5.7A).
    std::vector<double> beam_counts;
    if (!limit && v["p3"].size() > 1)
      {
        std::vector<std::array<double, 2>> right, left;
        for (const double p3 : v["p3"])
          {
            const auto c =
              coverage_coefficients(samples_of([&](unsigned int k) {
                                      return resolved(k) &&
                                             structures[k].p3 == p3;
                                    }),
                                    setup.base,
                                    level,
                                    band);
            S["coverage_by_beams"].push_back({{"beams", 1 / p3},
                                              {"delta_R", c.delta_right},
                                              {"delta_L", c.delta_left}});
            if (std::isfinite(c.delta_right))
              {
                right.push_back({{1 / p3, c.delta_right}});
                left.push_back({{1 / p3, c.delta_left}});
              }
          }
        if (context.is_root() && right.size() >= 2)
          {
            double n_max = 0;
            for (const auto &p : right)
              n_max = std::max(n_max, p[0]);
            write_xy_plot(context.path("coverage_by_beams.png"),
                          {{right, {{200, 60, 40}}, true, 2, "Delta_R"},
                           {left, {{31, 90, 180}}, true, 2, "Delta_L"},
                           {right, {{200, 60, 40}}, false, 3, ""},
                           {left, {{31, 90, 180}}, false, 3, ""}},
                          "Coverage vs beams per joint",
                          "beams per joint n",
                          "Delta",
                          {{0, n_max * 1.05}},
                          {{0, 1.05}});
          }
      }

    // (nu, E) coverage plot against the HS bounds; samples colored by
    // volume fraction band when it varies, by family otherwise.
    if (context.is_root())
      {
        double phi_min = 1, phi_max = 0;
        for (unsigned int k = 0; k < structures.size(); ++k)
          {
            phi_min = std::min(phi_min, table[k * n_fields + f_phi]);
            phi_max = std::max(phi_max, table[k * n_fields + f_phi]);
          }
        const std::vector<std::array<std::uint8_t, 3>> colors = {
          {{200, 60, 40}},
          {{31, 90, 180}},
          {{40, 150, 60}},
          {{150, 70, 170}},
          {{230, 150, 20}}};
        std::vector<PlotSeries> series;
        auto                    bound_curve = [&](const double                       phi,
                               const std::array<std::uint8_t, 3> &c,
                               const std::string                 &label) {
          const auto b = hashin_shtrikman(setup.base, setup.weak, phi);
          PlotSeries s;
          s.line = true, s.color = c, s.label = label;
          for (int k = 0; k <= 400; ++k)
            {
              const double nu = -1 + k / 200.;
              s.points.push_back(
                {{nu, b.max_young_modulus(nu) / setup.base.E}});
            }
          return s;
        };
        if (phi_max - phi_min > 0.05)
          {
            const unsigned int n_bands = 4;
            for (unsigned int b = 0; b < n_bands; ++b)
              {
                const double lo = phi_min + (phi_max - phi_min) * b / n_bands,
                             hi = phi_min +
                                  (phi_max - phi_min) * (b + 1) / n_bands;
                PlotSeries s;
                s.color = colors[b];
                s.label = "phi " + sig(lo, 2) + "-" + sig(hi, 2);
                for (unsigned int k = 0; k < structures.size(); ++k)
                  {
                    const double phi = table[k * n_fields + f_phi];
                    if (resolved(k) && phi >= lo - 1e-12 &&
                        (phi < hi || b + 1 == n_bands))
                      s.points.push_back(
                        {{table[k * n_fields + f_nu],
                          table[k * n_fields + f_E] / setup.base.E}});
                  }
                series.push_back(s);
                series.push_back(bound_curve(hi, colors[b], ""));
              }
          }
        else
          for (unsigned int f = 0; f < families.size(); ++f)
            {
              PlotSeries s;
              s.color = colors[f];
              HexagonalLaminate named;
              named.family = families[f];
              s.label      = named.family_name() + (limit ? " limit" : "");
              for (unsigned int k = 0; k < structures.size(); ++k)
                if (resolved(k) && structures[k].family == families[f])
                  s.points.push_back(
                    {{table[k * n_fields + f_nu],
                      table[k * n_fields + f_E] / setup.base.E}});
              series.push_back(s);
            }
        if (n_unresolved > 0)
          {
            PlotSeries s;
            s.color = {{170, 170, 170}};
            s.label = "under-resolved";
            for (unsigned int k = 0; k < structures.size(); ++k)
              if (!resolved(k))
                s.points.push_back(
                  {{table[k * n_fields + f_nu],
                    table[k * n_fields + f_E] / setup.base.E}});
            series.insert(series.begin(), s);
          }
        series.push_back(bound_curve(1, {{0, 0, 0}}, "HS bound phi=1"));
        if (phi_max - phi_min <= 0.05)
          series.push_back(bound_curve(std::min(1., phi_min),
                                       {{120, 120, 120}},
                                       "HS bound phi=" + sig(phi_min, 3)));
        write_xy_plot(context.path("coverage.png"),
                      series,
                      "Coverage of the HS bounds",
                      "Poisson's ratio nu",
                      "E / Eb",
                      {{-1, 1}},
                      {{0, 1.05}});
      }
  }

  /// One row of a sample table: a structure and its (E, nu).
  struct TableSample
  {
    HexagonalLaminate structure;
    double            E = 0, nu = 0;
  };

  /// The samples of a sweep's samples.csv (columns found by name).
  std::vector<TableSample>
  read_sample_table(const std::string &file)
  {
    std::ifstream in(file);
    AssertThrow(in,
                ExcMessage("Inverse/Table file: cannot open '" + file + "'"));
    std::string line;
    std::getline(in, line);
    const auto names = Utilities::split_string_list(line);
    std::map<std::string, unsigned int> column;
    for (unsigned int c = 0; c < names.size(); ++c)
      column[names[c]] = c;
    for (const char *name : {"family",
                             "limit",
                             "p1",
                             "p2",
                             "p3",
                             "p4",
                             "theta",
                             "alpha_degrees",
                             "E",
                             "nu"})
      AssertThrow(column.count(name),
                  ExcMessage("Inverse/Table file '" + file +
                             "' has no column '" + name +
                             "' (expected the samples.csv of a sweep)"));
    std::vector<TableSample> table;
    unsigned int             row = 1;
    while (std::getline(in, line))
      {
        ++row;
        if (Utilities::trim(line).empty())
          continue;
        const auto f = Utilities::split_string_list(line);
        AssertThrow(f.size() == names.size(),
                    ExcMessage("Inverse/Table file '" + file + "', line " +
                               std::to_string(row) + ": " +
                               std::to_string(f.size()) + " fields, expected " +
                               std::to_string(names.size())));
        TableSample t;
        try
          {
            auto value = [&](const char *name) {
              return std::stod(f[column[name]]);
            };
            auto &s = t.structure;
            s.family =
              HexagonalLaminate::family_from_string(f[column["family"]]);
            s.limit = value("limit") != 0;
            s.p1    = value("p1");
            if (s.limit)
              s.theta = value("theta"),
              s.alpha = value("alpha_degrees") * numbers::PI / 180;
            else
              s.p2 = value("p2"), s.p3 = value("p3"), s.p4 = value("p4");
            t.E  = value("E");
            t.nu = value("nu");
            s.check();
          }
        catch (const std::exception &e)
          {
            AssertThrow(false,
                        ExcMessage("Inverse/Table file '" + file + "', line " +
                                   std::to_string(row) + ": " +
                                   error_message(e)));
          }
        table.push_back(t);
      }
    AssertThrow(!table.empty(),
                ExcMessage("Inverse/Table file '" + file + "' has no samples"));
    return table;
  }

  /**
   * Inverse design: the structure of a family whose (E, nu) is a target.
   * The nearest samples of a table (a sweep's samples.csv, or the Sweep grid
   * homogenized here on a coarse grid) start bound-constrained L-BFGS runs
   * (ROL, optimize()) on J = (E/E* - 1)^2 + (nu - nu*)^2 over the
   * continuous parameters (p1, p2, p4 or p1, theta, alpha; p3 keeps its
   * beam count) at the Grid resolution. The anti-aliased rasterization is
   * exact in areas, so E and nu are continuous, piecewise smooth functions
   * of the parameters and central differences give their gradient.
   */
  void
  inverse_mode(ParameterHandler  &prm,
               const std::string &prm_directory,
               const Setup       &setup,
               RunContext        &context)
  {
    prm.enter_subsection("Inverse");
    const double       target_E   = prm.get_double("Target Young's modulus");
    const double       target_nu  = prm.get_double("Target Poisson's ratio");
    std::string        table_file = prm.get("Table file");
    const unsigned int table_ny   = prm.get_integer("Table cells along height");
    const unsigned int n_candidates = prm.get_integer("Candidates");
    OptimizationParameters op;
    op.max_iterations      = prm.get_integer("Max iterations");
    const double tolerance = prm.get_double("Tolerance");
    prm.leave_subsection();
    op.value_target       = tolerance * tolerance;
    op.relative_decrease  = 1e-6;
    op.decrease_window    = 3;
    op.gradient_tolerance = 1e-8;
    op.print_iterations   = false;
    // E is relative to the base's 2D Young's modulus.
    const double E_star = target_E * setup.base.E;
    {
      const auto hs = hashin_shtrikman(setup.base, setup.weak, 1);
      AssertThrow(E_star <= hs.max_young_modulus(target_nu) && target_nu > -1 &&
                    target_nu < 1,
                  ExcMessage(
                    "Inverse: the target (E/Eb, nu) = (" + sig(target_E) +
                    ", " + sig(target_nu) +
                    ") lies outside the Hashin-Shtrikman bounds "
                    "(E/Eb <= " +
                    sig(hs.max_young_modulus(target_nu) / setup.base.E) +
                    " at this nu): no structure reaches it"));
    }
    const SweepGrid grid = read_sweep_grid(prm);

    // The table: given, or the Sweep grid on a coarse grid.
    std::vector<TableSample> table;
    if (!table_file.empty())
      {
        if (table_file[0] != '/')
          table_file = prm_directory + "/" + table_file;
        table = read_sample_table(table_file);
        context.print("inverse: " + std::to_string(table.size()) +
                      " samples from the table file");
      }
    else
      {
        const auto values =
          homogenize_all(grid.structures, setup, table_ny, context);
        for (unsigned int k = 0; k < grid.structures.size(); ++k)
          table.push_back({grid.structures[k],
                           values[k * n_fields + f_E],
                           values[k * n_fields + f_nu]});
      }

    auto misfit = [&](const double E, const double nu) {
      return std::pow(E / E_star - 1, 2) + std::pow(nu - target_nu, 2);
    };
    std::vector<std::pair<double, unsigned int>> ranked;
    for (unsigned int k = 0; k < table.size(); ++k)
      if (std::count(grid.families.begin(),
                     grid.families.end(),
                     table[k].structure.family) > 0 &&
          table[k].structure.limit == grid.limit)
        ranked.push_back({misfit(table[k].E, table[k].nu), k});
    AssertThrow(!ranked.empty(),
                ExcMessage("Inverse: the table has no sample of the "
                           "families (and Limit structures setting) of the "
                           "Sweep section"));
    std::sort(ranked.begin(), ranked.end());
    ranked.resize(std::min<std::size_t>(ranked.size(), n_candidates));

    // Refinement on the Grid resolution.
    const unsigned int ny   = setup.cells_along_height;
    const unsigned int nx   = grid_nx(ny);
    const auto         cell = family_grid(MPI_COMM_SELF, setup, ny);
    // Every rank refines the same candidates (the runs are short, and the
    // optimizer's collective output stays consistent).
    auto with = [](HexagonalLaminate s, const std::vector<double> &q) {
      if (s.limit)
        s.p1 = q[0], s.theta = q[1], s.alpha = q[2] * numbers::PI / 180;
      else
        s.p1 = q[0], s.p2 = q[1], s.p4 = q[2];
      s.check();
      return s;
    };
    auto moduli = [&](const HexagonalLaminate &s) {
      const auto r =
        evaluate(*cell,
                 pixel_material(s, setup.base, setup.weak, setup.gray, nx, ny),
                 setup);
      return r;
    };

    nlohmann::json    candidates = nlohmann::json::array();
    double            best_J     = std::numeric_limits<double>::max();
    HexagonalLaminate best;
    Sample            best_sample;
    for (unsigned int c = 0; c < ranked.size(); ++c)
      {
        const TableSample &start = table[ranked[c].second];
        const auto        &s0    = start.structure;
        context.print("inverse: candidate " + std::to_string(c + 1) + "/" +
                      std::to_string(ranked.size()) + ": " + s0.family_name() +
                      (s0.limit ?
                         " limit p1 = " + sig(s0.p1) +
                           ", theta = " + sig(s0.theta) +
                           ", alpha = " + sig(s0.alpha * 180 / numbers::PI) :
                         " p1 = " + sig(s0.p1) + ", p2 = " + sig(s0.p2) +
                           ", p3 = " + sig(s0.p3) + ", p4 = " + sig(s0.p4)) +
                      " (table: E/Eb = " + sig(start.E / setup.base.E) +
                      ", nu = " + sig(start.nu) + ")");
        DesignModel model;
        if (s0.limit)
          {
            model.initial = {s0.p1, s0.theta, s0.alpha * 180 / numbers::PI};
            model.scale   = {0.1, 0.1, 10};
            model.lower   = {0.02, 0, -89};
            model.upper   = {0.98, 1, 89};
          }
        else
          {
            model.initial = {s0.p1, s0.p2, s0.p4};
            model.scale   = {0.1, 0.1, 0.1};
            model.lower   = {0.02, 0, 0.02};
            model.upper   = {0.98, 1, 1};
          }
        auto J = [&](const std::vector<double> &q) {
          const Sample r = moduli(with(s0, q));
          return misfit(r.fit.E, r.fit.nu);
        };
        model.value    = J;
        model.gradient = [&](const std::vector<double> &q,
                             std::vector<double>       &dJ) {
          // Central differences, one-sided at the bounds.
          dJ.assign(q.size(), 0);
          for (unsigned int i = 0; i < q.size(); ++i)
            {
              const double h  = 1e-3 * model.scale[i];
              auto         qp = q, qm = q;
              qp[i] = std::min(q[i] + h, model.upper[i]);
              qm[i] = std::max(q[i] - h, model.lower[i]);
              dJ[i] = (J(qp) - J(qm)) / (qp[i] - qm[i]);
            }
          return J(q);
        };
        model.accepted = [](unsigned int, const std::vector<double> &, double) {
        };
        const auto   result = optimize(model, op, context);
        const auto   s      = with(s0, result.design);
        const auto   r      = moduli(s);
        const double Jc     = misfit(r.fit.E, r.fit.nu);
        context.print("inverse: candidate " + std::to_string(c + 1) +
                      " reaches E/Eb = " + sig(r.fit.E / setup.base.E) +
                      ", nu = " + sig(r.fit.nu) + " (" + result.stop_reason +
                      ")");
        nlohmann::json j = structure_json(s);
        j["E_over_Eb"]   = r.fit.E / setup.base.E;
        j["nu"]          = r.fit.nu;
        j["misfit"]      = Jc;
        j["iterations"]  = result.history.size() - 1;
        j["stop_reason"] = result.stop_reason;
        candidates.push_back(j);
        if (Jc < best_J)
          best_J = Jc, best = s, best_sample = r;
        if (Jc <= op.value_target)
          break;
      }
    context.print("inverse: target E/Eb = " + sig(target_E) +
                  ", nu = " + sig(target_nu) +
                  "; achieved E/Eb = " + sig(best_sample.fit.E / setup.base.E) +
                  ", nu = " + sig(best_sample.fit.nu) + " (misfit " +
                  sig(std::sqrt(best_J), 2) + ")");
    context.summary["target"]    = {{"E_over_Eb", target_E}, {"nu", target_nu}};
    context.summary["structure"] = structure_json(best);
    context.summary["result"]    = sample_json(best_sample, setup);
    context.summary["misfit"]    = std::sqrt(best_J);
    context.summary["reached"]   = best_J <= op.value_target;
    context.summary["candidates"] = candidates;
    context.summary["grid"]       = {nx, ny};
  }

  /**
   * Regular grid vs conforming mesh (thesis Table 5.2): the structure's
   * polygons meshed by Gmsh with periodic sides (P`degree` triangles),
   * then on the regular grid at the same parameters, then on the grid
   * with p4 (theta for limit structures) adjusted until E matches the
   * conforming result, comparing nu.
   */
  void
  compare_meshes_mode(ParameterHandler &prm,
                      const Setup      &setup,
                      RunContext       &context)
  {
    const HexagonalLaminate s = read_structure(prm);
    prm.enter_subsection("Conforming mesh");
    const double       size   = prm.get_double("Element size");
    const unsigned int degree = prm.get_integer("Degree");
    prm.leave_subsection();
    const Point<2> box(HexagonalLaminate::width, HexagonalLaminate::height);
    context.print("structure: " + s.family_name() + (s.limit ? " limit" : "") +
                  ", volume fraction " + sig(s.volume_fraction_formula()));

    // Conforming mesh: material id 0 is void, k + 1 phase k.
    Triangulation<2> mesh;
    {
      std::vector<std::pair<std::vector<Point<2>>, unsigned int>> polygons;
      for (const auto &p : s.polygons())
        polygons.push_back(p);
      periodic_phase_mesh(polygons, box, size, mesh);
    }
    std::vector<double> density;
    const auto tensor   = phase_tensors(s, setup.base, setup.weak, density);
    const auto weak     = setup.weak.tensor();
    auto phase_material = [&](const Point<2> &, const types::material_id id) {
      AssertThrow(id <= tensor.size(), ExcInternalError());
      return id == 0 ? weak : tensor[id - 1];
    };
    PeriodicHomogenization<2> conforming(context.communicator(),
                                         mesh,
                                         setup.solver,
                                         degree);
    Timer                     timer;
    const auto                C_mesh = conforming.homogenize(phase_material).C;
    context.log("conforming mesh homogenization: " + sig(timer.wall_time()) +
                " s wall");
    double phi_mesh = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->material_id() > 0)
        phi_mesh += density[cell->material_id() - 1] * cell->measure();
    phi_mesh /= box[0] * box[1];
    const auto mesh_fit = isotropic_fit(C_mesh);
    context.print("conforming mesh: " + std::to_string(conforming.n_cells()) +
                  " P" + std::to_string(degree) + " triangles, " +
                  std::to_string(conforming.n_dofs()) +
                  " unknowns: E/Eb = " + sig(mesh_fit.E / setup.base.E) +
                  ", nu = " + sig(mesh_fit.nu) + ", volume fraction " +
                  sig(phi_mesh));

    // The regular grid at the same parameters.
    const unsigned int ny   = setup.cells_along_height;
    const unsigned int nx   = grid_nx(ny);
    const auto         grid = family_grid(MPI_COMM_SELF, setup, ny);
    auto               at   = [&](const double value) {
      HexagonalLaminate t        = s;
      (t.limit ? t.theta : t.p4) = value;
      t.check();
      return evaluate(
        *grid,
        pixel_material(t, setup.base, setup.weak, setup.gray, nx, ny),
        setup);
    };
    const std::string name  = s.limit ? "theta" : "p4";
    const double      value = s.limit ? s.theta : s.p4;
    const Sample      same  = at(value);
    context.print("regular " + std::to_string(nx) + " x " + std::to_string(ny) +
                  " grid: E/Eb = " + sig(same.fit.E / setup.base.E) +
                  ", nu = " + sig(same.fit.nu) + ", volume fraction " +
                  sig(same.phi));

    // Match E by adjusting the beam width: secant steps kept inside a
    // bracket (E grows with it).
    const double target = mesh_fit.E;
    double       lo = 0.02, hi = 1, x = value;
    Sample       r      = same;
    double       x_prev = value, f_prev = same.fit.E - target;
    x = std::clamp(value + (f_prev > 0 ? -0.02 : 0.02), lo, hi);
    unsigned int iterations = 0;
    for (; iterations < 30; ++iterations)
      {
        r                 = at(x);
        const double f    = r.fit.E - target;
        (f > 0 ? hi : lo) = x;
        if (std::abs(f) <= 1e-5 * target || hi - lo < 1e-9)
          break;
        double next = x - f * (x - x_prev) / (f - f_prev);
        if (!(next > lo && next < hi) || !std::isfinite(next))
          next = 0.5 * (lo + hi);
        x_prev = x, f_prev = f, x = next;
      }
    const bool matched = std::abs(r.fit.E - target) <= 1e-3 * target;
    context.print("grid matching E: " + name + " = " + sig(x) + " (mesh " +
                  sig(value) + "): E/Eb = " + sig(r.fit.E / setup.base.E) +
                  ", nu = " + sig(r.fit.nu) +
                  "; nu(grid) - nu(mesh) = " + sig(r.fit.nu - mesh_fit.nu, 2) +
                  (matched ? "" : " (E NOT matched in [0.02, 1])"));

    context.summary["structure"]       = structure_json(s);
    context.summary["conforming_mesh"] = {
      {"element_size", size},
      {"degree", degree},
      {"cells", conforming.n_cells()},
      {"unknowns", conforming.n_dofs()},
      {"volume_fraction", phi_mesh},
      {"result",
       sample_json(
         {phi_mesh,
          phi_mesh,
          C_mesh,
          mesh_fit,
          anisotropy(C_mesh),
          hashin_shtrikman(setup.base, setup.weak, std::min(1., phi_mesh)),
          hashin_shtrikman(setup.base, setup.weak, std::min(1., phi_mesh))
            .violation(mesh_fit)},
         setup)}};
    context.summary["grid"]         = {{"cells", {nx, ny}},
                                       {"result", sample_json(same, setup)}};
    context.summary["matched_grid"] = {{"parameter", name},
                                       {"value", x},
                                       {"matched", matched},
                                       {"E", r.fit.E},
                                       {"nu", r.fit.nu},
                                       {"nu_difference",
                                        r.fit.nu - mesh_fit.nu},
                                       {"iterations", iterations + 1}};
    if (setup.write_vtu)
      conforming.write_vtu(context.path("fields_mesh"),
                           {"material_id", "density"},
                           [&](const Point<2> &, const types::material_id id) {
                             return std::vector<double>{
                               double(id), id == 0 ? 0. : density[id - 1]};
                           });
  }

  void
  declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Base material");
    prm.declare_entry(
      "Young's modulus",
      "1",
      Patterns::Double(0),
      "E of the printable base material; results scale with it.");
    prm.declare_entry("Poisson's ratio",
                      "0",
                      Patterns::Double(-1, 0.5),
                      "nu of the base material (3D); the thesis uses 0.");
    prm.declare_entry("Plane model",
                      "plane stress",
                      Patterns::Selection("plane stress|plane strain"),
                      "2D model of the base material. Results are 2D moduli "
                      "(see doc/laminate.md).");
    prm.declare_entry("Void stiffness ratio",
                      "1e-6",
                      Patterns::Double(0, 1),
                      "Void is a weak phase: this fraction of the base tensor "
                      "(thesis: 1e-6).");
    prm.declare_entry(
      "CLM Poisson's ratios",
      "",
      Patterns::Anything(),
      "Comma separated base Poisson's ratios for which homogenize "
      "also reports (E, nu) by the CLM transform (eq. 4.11).");
    prm.leave_subsection();

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
      Patterns::Selection("auto|direct|cg-amg"),
      "direct: sparse Cholesky (CHOLMOD) on one rank, KLU on "
      "several; cg-amg: CG with ML AMG (slow for strong void "
      "contrast); auto: direct up to 400000 unknowns (after the "
      "symmetry and periodicity constraints).");
    prm.leave_subsection();

    prm.enter_subsection("Structure");
    prm.declare_entry("Type",
                      "hexagon",
                      Patterns::Selection("hexagon|triangle|image"),
                      "A Triangle/Hexagon family structure, or a user image.");
    prm.declare_entry(
      "Limit structure",
      "false",
      Patterns::Bool(),
      "Two-scale limit structure: joints are rank-one laminates "
      "(p1, theta, alpha) instead of beams (p1..p4).");
    prm.declare_entry("p1", "0.75", Patterns::Double(), "Tile size in (0, 1).");
    prm.declare_entry(
      "p2",
      "0",
      Patterns::Double(),
      "Chirality in [0, 1]: sideways shift of a beam across its "
      "joint, as a fraction of the joint width (1 = diagonal).");
    prm.declare_entry("p3",
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
    prm.declare_entry("Image file",
                      "",
                      Patterns::Anything(),
                      "Type = image: a PGM (P2/P5) or CSV matrix of densities "
                      "in [0, 1], relative to the .prm file.");
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
    prm.declare_entry("p2", "0, 0.5, 1", Patterns::Anything(), "Values of p2.");
    prm.declare_entry("p3", "0.25", Patterns::Anything(), "Values of p3.");
    prm.declare_entry("Beams per joint",
                      "",
                      Patterns::Anything(),
                      "If set, values of n = 1/p3 (replaces p3).");
    prm.declare_entry("p4", "0.3:0.9:4", Patterns::Anything(), "Values of p4.");
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
    prm.declare_entry("Coverage band",
                      "0.02",
                      Patterns::Double(0, 1),
                      "Samples with |E/Eb - level| <= band count for Delta.");
    prm.leave_subsection();

    prm.enter_subsection("Inverse");
    prm.declare_entry("Target Young's modulus",
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
    prm.declare_entry("Table cells along height",
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
    prm.declare_entry("Tolerance",
                      "1e-3",
                      Patterns::Double(0),
                      "Stop when sqrt((E/E* - 1)^2 + (nu - nu*)^2) is below.");
    prm.leave_subsection();

    prm.enter_subsection("Conforming mesh");
    prm.declare_entry("Element size",
                      "0.01",
                      Patterns::Double(0),
                      "compare meshes: target triangle size (the cell is "
                      "sqrt(3) x 1).");
    prm.declare_entry("Degree",
                      "2",
                      Patterns::Integer(1, 3),
                      "compare meshes: polynomial degree on the triangles.");
    prm.leave_subsection();

    prm.enter_subsection("Output");
    prm.declare_entry("Write vtu",
                      "true",
                      Patterns::Bool(),
                      "homogenize: write the density and the three fluctuation "
                      "fields (fields.vtu).");
    prm.leave_subsection();
  }

  void
  run(ParameterHandler  &prm,
      const std::string &prm_directory,
      RunContext        &context)
  {
    AssertThrow(prm.get_integer("Dimension") == 2,
                ExcMessage(
                  "forma-laminate homogenizes 2D cells: set Dimension = 2"));
    Setup setup;
    prm.enter_subsection("Base material");
    setup.base_E     = prm.get_double("Young's modulus");
    setup.base_nu    = prm.get_double("Poisson's ratio");
    setup.plane      = plane_model_from_string(prm.get("Plane model"));
    setup.weak_ratio = prm.get_double("Void stiffness ratio");
    for (const auto &t :
         Utilities::split_string_list(prm.get("CLM Poisson's ratios")))
      setup.clm_poisson.push_back(parse_values(t, "CLM Poisson's ratios")[0]);
    prm.leave_subsection();
    AssertThrow(setup.weak_ratio > 0,
                ExcMessage(
                  "Base material/Void stiffness ratio must be positive "
                  "(the void is a weak phase)"));
    setup.base =
      IsotropicModuli::of_material(setup.base_E, setup.base_nu, setup.plane);
    setup.weak =
      IsotropicModuli::from_bulk_shear(setup.weak_ratio * setup.base.kappa,
                                       setup.weak_ratio * setup.base.mu);
    prm.enter_subsection("Grid");
    setup.cells_along_height = prm.get_integer("Cells along height");
    setup.solver.type        = prm.get("Solver");
    setup.symmetry           = prm.get_bool("Use symmetry");
    setup.min_feature_cells  = prm.get_double("Minimum feature cells");
    setup.gray               = prm.get("Gray pixels") == "linear" ?
                                 GrayPixels::linear :
                                 GrayPixels::hashin_shtrikman;
    prm.leave_subsection();
    prm.enter_subsection("Output");
    setup.write_vtu = prm.get_bool("Write vtu");
    prm.leave_subsection();
    context.summary["base_material"] = {
      {"E", setup.base_E},
      {"nu", setup.base_nu},
      {"plane_model",
       setup.plane == PlaneModel::plane_stress ? "plane stress" :
                                                 "plane strain"},
      {"E_2d", setup.base.E},
      {"nu_2d", setup.base.nu},
      {"void_stiffness_ratio", setup.weak_ratio},
      {"gray_pixels",
       setup.gray == GrayPixels::linear ? "linear" : "hashin-shtrikman"}};

    const std::string mode = prm.get("Mode");
    if (mode == "homogenize")
      homogenize_mode(prm, prm_directory, setup, context);
    else if (mode == "sweep")
      sweep_mode(prm, setup, context);
    else if (mode == "inverse")
      inverse_mode(prm, prm_directory, setup, context);
    else
      compare_meshes_mode(prm, setup, context);
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
  app.modes       = {"homogenize", "sweep", "inverse", "compare meshes"};
  app.declare_parameters = declare;
  app.run                = run;
  return forma::run_application(argc, argv, app);
}
