// forma-laminate: hexagonal Triangle/Hexagon laminate microstructures,
// periodic homogenization and Hashin-Shtrikman coverage (thesis ch. 5).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/bounds.h>
#include <forma/homogenization/coverage.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/density_image.h>
#include <forma/microstructure/hexagonal_laminate.h>

#include <cmath>
#include <fstream>
#include <iomanip>
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
    /// Gray pixels: "linear" rho C (thesis eq. 5.8) or "hashin-shtrikman"
    /// (the stiffest physical mixture at fraction rho, eq. 5.1).
    bool hs_pixels = false;
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

  /// Phase tensors, fractions -> the material of every grid cell.
  class RasterMaterial
  {
  public:
    RasterMaterial(PhaseRaster                        raster,
                   std::vector<double>                phase_density,
                   std::vector<SymmetricTensor<4, 2>> phase_tensor,
                   const Setup                       &setup)
      : raster(std::move(raster))
      , density(std::move(phase_density))
      , tensor(std::move(phase_tensor))
      , weak(setup.weak.tensor())
      , hs_pixels(setup.hs_pixels)
      , base(setup.base)
      , weak_moduli(setup.weak)
    {}

    SymmetricTensor<4, 2>
    operator()(const Point<2> &x, const types::material_id) const
    {
      const auto [i, j] = raster.cell_of(x);
      SymmetricTensor<4, 2> C;
      double                rest = 1;
      for (unsigned int k = 1; k < raster.n_phases; ++k)
        {
          const double f = raster.fraction(i, j, k);
          C += f * tensor[k];
          rest -= f;
        }
      // Base material and void share the rest of the pixel.
      rest = std::max(0., rest);
      const double rho =
        std::min(1., raster.fraction(i, j, 0) / std::max(rest, 1e-300));
      if (rest <= 0)
        return C;
      if (!hs_pixels || rho <= 0 || rho >= 1)
        return C + rest * (rho * tensor[0] + (1 - rho) * weak);
      const auto b = hashin_shtrikman(base, weak_moduli, rho);
      return C +
             rest * IsotropicModuli::from_bulk_shear(b.kappa_upper, b.mu_upper)
                      .tensor();
    }

    /// Base-material density of a cell (laminates count their fraction).
    double
    density_at(const Point<2> &x) const
    {
      const auto [i, j] = raster.cell_of(x);
      double rho        = 0;
      for (unsigned int k = 0; k < raster.n_phases; ++k)
        rho += density[k] * raster.fraction(i, j, k);
      return rho;
    }

    double
    volume_fraction() const
    {
      double phi = 0;
      for (unsigned int k = 0; k < raster.n_phases; ++k)
        phi += density[k] * raster.mean(k);
      return phi;
    }

    PhaseRaster                        raster;
    std::vector<double>                density;
    std::vector<SymmetricTensor<4, 2>> tensor;
    SymmetricTensor<4, 2>              weak;
    bool                               hs_pixels;
    IsotropicModuli                    base, weak_moduli;
  };

  RasterMaterial
  structure_material(const HexagonalLaminate &s,
                     const Setup             &setup,
                     const unsigned int       nx,
                     const unsigned int       ny)
  {
    std::vector<double>                density = {1};
    std::vector<SymmetricTensor<4, 2>> tensor  = {setup.base.tensor()};
    if (s.limit)
      for (const double axis : s.joint_axis_angles())
        {
          density.push_back(s.theta);
          tensor.push_back(rank_one_laminate(setup.base.tensor(),
                                             setup.weak.tensor(),
                                             s.theta,
                                             axis + s.lamination_angle()));
        }
    return RasterMaterial(s.rasterize(nx, ny), density, tensor, setup);
  }

  Sample
  evaluate(PeriodicHomogenization<2> &cell,
           const RasterMaterial      &material,
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
    std::unique_ptr<RasterMaterial>            material;
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
          std::make_unique<RasterMaterial>(std::move(raster),
                                           std::vector<double>{1},
                                           std::vector<SymmetricTensor<4, 2>>{
                                             setup.base.tensor()},
                                           setup);
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
        const unsigned int      nx = std::lround(HexagonalLaminate::width * ny);
        material                   = std::make_unique<RasterMaterial>(
          structure_material(s, setup, nx, ny));
        cell = std::make_unique<PeriodicHomogenization<2>>(
          context.communicator(),
          Point<2>(HexagonalLaminate::width, HexagonalLaminate::height),
          std::array<unsigned int, 2>{{nx, ny}},
          setup.solver);
        structure = {{"type", s.family_name()},
                     {"limit", s.limit},
                     {"lamination_angle_degrees",
                      s.lamination_angle() * 180 / numbers::PI},
                     {"critical_angle_degrees",
                      s.critical_angle() * 180 / numbers::PI},
                     {"volume_fraction_formula", s.volume_fraction_formula()}};
        if (s.limit)
          structure.update({{"p1", s.p1},
                            {"theta", s.theta},
                            {"alpha_degrees", s.alpha * 180 / numbers::PI}});
        else
          structure.update({{"p1", s.p1},
                            {"p2", s.p2},
                            {"p3", s.p3},
                            {"p4", s.p4},
                            {"beams_per_joint", 1 / s.p3}});
        context.print("structure: " + s.family_name() +
                      (s.limit ? " limit" : "") + ", volume fraction " +
                      sig(s.volume_fraction_formula()) +
                      " (eq. 5.11), lamination angle " +
                      sig(s.lamination_angle() * 180 / numbers::PI) + " deg");
      }
    context.print("grid: " + std::to_string(cell->n_cells()) + " cells, " +
                  std::to_string(cell->n_dofs()) + " unknowns");
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

  void
  sweep_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
  {
    prm.enter_subsection("Sweep");
    std::vector<HexagonalLaminate::Family> families;
    for (const auto &f : Utilities::split_string_list(prm.get("Families")))
      families.push_back(HexagonalLaminate::family_from_string(f));
    const bool limit = prm.get_bool("Limit structures");
    std::map<std::string, std::vector<double>> v;
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
    const double level = prm.get_double("Coverage level"),
                 band  = prm.get_double("Coverage band");
    prm.leave_subsection();

    // The parameter grid.
    std::vector<HexagonalLaminate> structures;
    for (const auto family : families)
      for (const double p1 : v["p1"])
        if (limit)
          for (const double theta : v["theta"])
            for (const double alpha : v["alpha"])
              {
                HexagonalLaminate s;
                s.family = family, s.limit = true, s.p1 = p1, s.theta = theta,
                s.alpha = alpha * numbers::PI / 180;
                s.check();
                structures.push_back(s);
              }
        else
          for (const double p2 : v["p2"])
            for (const double p3 : v["p3"])
              for (const double p4 : v["p4"])
                {
                  HexagonalLaminate s;
                  s.family = family, s.p1 = p1, s.p2 = p2, s.p3 = p3, s.p4 = p4;
                  s.check();
                  structures.push_back(s);
                }
    const unsigned int ny      = setup.cells_along_height;
    const unsigned int nx      = std::lround(HexagonalLaminate::width * ny);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(
                         context.communicator()),
                       rank = Utilities::MPI::this_mpi_process(
                         context.communicator());
    context.print("sweep: " + std::to_string(structures.size()) +
                  " structures on a " + std::to_string(nx) + " x " +
                  std::to_string(ny) + " grid");

    // Every rank homogenizes its share with its own serial solver.
    PeriodicHomogenization<2> cell(MPI_COMM_SELF,
                                   Point<2>(HexagonalLaminate::width,
                                            HexagonalLaminate::height),
                                   {{nx, ny}},
                                   setup.solver);
    constexpr unsigned int    n_fields = 14;
    std::vector<double>       table(structures.size() * n_fields, 0.);
    const unsigned int        batch =
      std::max<unsigned int>(n_ranks, structures.size() / 10 + 1);
    for (unsigned int start = 0; start < structures.size(); start += batch)
      {
        const unsigned int end =
          std::min<unsigned int>(structures.size(), start + batch);
        for (unsigned int k = start; k < end; ++k)
          if (k % n_ranks == rank)
            {
              const auto material =
                structure_material(structures[k], setup, nx, ny);
              const Sample      r           = evaluate(cell, material, setup);
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
                     V[2][2]};
              std::copy(f, f + n_fields, table.begin() + k * n_fields);
            }
        context.print("sweep: " + std::to_string(end) + "/" +
                      std::to_string(structures.size()) + " structures");
      }
    Utilities::MPI::sum(table, context.communicator(), table);

    // CSV of all samples.
    if (context.is_root())
      {
        std::ofstream csv(context.path("samples.csv"));
        csv << "family,limit,p1,p2,p3,p4,theta,alpha_degrees,beams_per_joint,"
               "phi_formula,phi,E,nu,kappa,mu,a1,a2,isotropy_residual,"
               "hs_violation,C00,C01,C11,C22\n";
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
          s.push_back({{table[k * n_fields + 3],
                        table[k * n_fields + 2] / setup.base.E}});
      return s;
    };
    const auto all      = samples_of([](unsigned int) { return true; });
    const auto coverage = coverage_coefficients(all, setup.base, level, band);
    double     worst = -1e300, max_a = 0;
    for (unsigned int k = 0; k < structures.size(); ++k)
      {
        worst = std::max(worst, table[k * n_fields + 9]);
        max_a =
          std::max({max_a, table[k * n_fields + 6], table[k * n_fields + 7]});
      }
    context.print("coverage at E/Eb = " + sig(level) + ": nu from " +
                  sig(coverage.nu_left) + " to " + sig(coverage.nu_right) +
                  " (" + std::to_string(coverage.n_in_band) +
                  " samples), Delta_L = " + sig(coverage.delta_left) +
                  ", Delta_R = " + sig(coverage.delta_right));
    context.print(
      std::string("all samples inside their Hashin-Shtrikman bounds: ") +
      (worst <= 0 ? "yes" : "NO") + "; largest anisotropy " + sig(max_a, 2));
    nlohmann::json &S                = context.summary;
    S["samples"]                     = structures.size();
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
                                      return structures[k].p3 == p3;
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
                          {{right, {200, 60, 40}, true, 2, "Delta_R"},
                           {left, {31, 90, 180}, true, 2, "Delta_L"},
                           {right, {200, 60, 40}, false, 3, ""},
                           {left, {31, 90, 180}, false, 3, ""}},
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
            phi_min = std::min(phi_min, table[k * n_fields + 1]);
            phi_max = std::max(phi_max, table[k * n_fields + 1]);
          }
        const std::vector<std::array<std::uint8_t, 3>> colors = {{200, 60, 40},
                                                                 {31, 90, 180},
                                                                 {40, 150, 60},
                                                                 {150, 70, 170},
                                                                 {230,
                                                                  150,
                                                                  20}};
        std::vector<PlotSeries>                        series;
        auto bound_curve = [&](const double                       phi,
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
                    const double phi = table[k * n_fields + 1];
                    if (phi >= lo - 1e-12 && (phi < hi || b + 1 == n_bands))
                      s.points.push_back(
                        {{table[k * n_fields + 3],
                          table[k * n_fields + 2] / setup.base.E}});
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
                if (structures[k].family == families[f])
                  s.points.push_back(
                    {{table[k * n_fields + 3],
                      table[k * n_fields + 2] / setup.base.E}});
              series.push_back(s);
            }
        series.push_back(bound_curve(1, {0, 0, 0}, "HS bound phi=1"));
        if (phi_max - phi_min <= 0.05)
          series.push_back(bound_curve(std::min(1., phi_min),
                                       {120, 120, 120},
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
      "Family structures: the 3:sqrt(3) cell gets round(sqrt(3) n) "
      "x n square-ish Q1 cells (148 -> 256 x 148).");
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
      "Solver",
      "auto",
      Patterns::Selection("auto|direct|cg-amg"),
      "direct: UMFPACK on one rank, KLU on several; cg-amg: CG "
      "with ML AMG (slow for strong void contrast); auto: direct "
      "up to 400000 unknowns.");
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
    setup.hs_pixels          = prm.get("Gray pixels") == "hashin-shtrikman";
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
      {"gray_pixels", setup.hs_pixels ? "hashin-shtrikman" : "linear"}};

    const std::string mode = prm.get("Mode");
    if (mode == "homogenize")
      homogenize_mode(prm, prm_directory, setup, context);
    else
      sweep_mode(prm, setup, context);
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
  app.modes       = {"homogenize", "sweep"};
  app.declare_parameters = declare;
  app.run                = run;
  return forma::run_application(argc, argv, app);
}
