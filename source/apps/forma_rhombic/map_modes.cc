#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/rank_strided.h>
#include <forma/base/replace_file.h>
#include <forma/base/run_context.h>
#include <forma/optimization/optimizer.h>
#include <forma/rhombic/grid_growth.h>
#include <forma/rhombic/inverse_problem.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/transversal_map.h>

#include "modes.h"
#include <boost/serialization/array.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      using Parameters = std::array<double, RhombicStructure::n_parameters>;

      /// One inverse solve of the construction: a grid node at an angle
      /// from a start.
      struct Job
      {
        unsigned int node = 0;
        Parameters   start{};
      };

      struct Outcome
      {
        unsigned int node    = 0;
        bool         reached = false;
        Parameters   p{};
        double       misfit = 0, E = 0, nu = 0;

        template <class Archive>
        void
        serialize(Archive &ar, const unsigned int)
        {
          ar &node &reached &p &misfit &E &nu;
        }
      };

      /**
       * The entries that decide a map build's samples, "Section/Entry" ->
       * value as written (prm at the top level; compared as text, so a
       * reformatted value counts as changed). Not the ones that act after
       * the sampling (branch drop, splines, accuracy checks, output) nor
       * Map/Angles: a resumed build may change those. The initial map's
       * entries only for the kind of initial map chosen.
       */
      nlohmann::json
      sampling_settings(ParameterHandler &prm)
      {
        using Section = std::pair<std::string, std::vector<std::string>>;
        std::vector<Section> sections = {
          {"Base material",
           {"Young's modulus", "Poisson's ratio", "Plane model"}},
          {"Structure", {"Parameters", "Blending"}},
          {"Mesh",
           {"Marching squares grid",
            "Element size",
            "Boundary element size",
            "Element degree",
            "Symmetric mesh"}},
          {"Inverse",
           {"Free parameters",
            "Parameter bounds",
            "Volume weight",
            "Proximity weight",
            "Tolerance",
            "Max iterations"}},
          {"Map", {"Young's moduli", "Poisson's ratios", "Initial map"}}};
        prm.enter_subsection("Map");
        const std::string initial = prm.get("Initial map");
        prm.leave_subsection();
        auto &map_entries = sections.back().second;
        if (initial == "file")
          map_entries.emplace_back("Initial map file");
        else if (initial == "transversal")
          map_entries.insert(map_entries.end(),
                             {"Fixed parameters",
                              "Sampling ranges",
                              "Subspace samples",
                              "Transversal grid samples"});
        nlohmann::json settings = nlohmann::json::object();
        for (const auto &[section, names] : sections)
          {
            prm.enter_subsection(section);
            for (const auto &name : names)
              settings[section + "/" + name] = prm.get(name);
            prm.leave_subsection();
          }
        return settings;
      }
    } // namespace



    /**
     * The material-to-geometry map by continuation (thesis ch. 4.6.2-4.6.3,
     * our construction; see doc/rhombic.md): isotropic targets on an
     * (E, nu) grid are reached by inverse homogenization, each started from
     * its solved neighbours (at the first angle, outward from a seed) or
     * from the same node at the previous angle, with the proximity term
     * keeping the parameters close to the start, so that they vary
     * smoothly; then one tensor-product spline per parameter over
     * (E, nu, alpha) is fitted with Laplacian regularization.
     */
    void
    build_map_mode(ParameterHandler  &prm,
                   const std::string &prm_directory,
                   const Setup       &setup,
                   RunContext        &context)
    {
      const MPI_Comm         comm     = context.communicator();
      const nlohmann::json   settings = sampling_settings(prm);
      const RhombicStructure seed     = read_structure(prm, setup);
      const InverseProblem base = InverseProblem::read(prm, setup, seed, comm);
      OptimizationParameters op;
      prm.enter_subsection("Inverse");
      op.max_iterations = prm.get_integer("Max iterations");
      prm.leave_subsection();
      op.relative_decrease  = 1e-5;
      op.decrease_window    = 3;
      op.gradient_tolerance = 1e-6;
      op.print_iterations   = false;
      op.checkpoint         = false;

      prm.enter_subsection("Map");
      auto Es = parse_values(prm.get("Young's moduli"), "Map/Young's moduli");
      auto nus =
        parse_values(prm.get("Poisson's ratios"), "Map/Poisson's ratios");
      // An extension with no new angle refits the map's splines only.
      const bool refit = prm.get("Initial map") == "file" &&
                         Utilities::trim(prm.get("Angles")).empty();
      auto         angles    = refit ? std::vector<double>() :
                                       parse_values(prm.get("Angles"), "Map/Angles");
      const auto   controls  = parse_values(prm.get("Spline control points"),
                                         "Map/Spline control points");
      const double smoothing = prm.get_double("Smoothing");
      const bool   log_E     = prm.get("Young's modulus axis") == "logarithmic";
      const double branch_tolerance = prm.get_double("Branch tolerance");
      const std::string  map_file   = prm.get("Map file");
      const unsigned int n_checks   = prm.get_integer("Accuracy checks");
      const double height_weight    = prm.get_double("Coverage height weight");
      const bool   log_coverage     = prm.get("Coverage axis") == "automatic" ?
                                        log_E :
                                        prm.get("Coverage axis") == "logarithmic";
      const unsigned int coverage_pieces = prm.get_integer("Coverage pieces");
      const bool         transversal = prm.get("Initial map") == "transversal";
      const bool         resume      = prm.get_bool("Resume");
      // Initial map = file: the map being extended to smaller angles.
      std::optional<MaterialMap> extended;
      if (prm.get("Initial map") == "file")
        {
          const std::string file = prm.get("Initial map file");
          AssertThrow(!file.empty(),
                      ExcMessage("Map/Initial map = file needs Map/Initial "
                                 "map file"));
          extended = MaterialMap::read(path_relative_to(prm_directory, file));
          if (extended->parameters[0].is_logarithmic(0) != log_E)
            context.print(std::string("map: note: the splines are fitted ") +
                          (log_E ? "uniform in log E" : "uniform in E") +
                          " (Map/Young's modulus axis), the initial map's " +
                          "were not");
        }
      TransversalMapParameters transversal_parameters;
      if (transversal)
        {
          transversal_parameters.fixed =
            TransversalMapParameters::parse_fixed(prm.get("Fixed parameters"),
                                                  "Map/Fixed parameters");
          transversal_parameters.ranges =
            TransversalMapParameters::parse_ranges(prm.get("Sampling ranges"),
                                                   "Map/Sampling ranges");
          transversal_parameters.subspace_samples =
            prm.get_integer("Subspace samples");
          transversal_parameters.grid_samples =
            prm.get_integer("Transversal grid samples");
        }
      prm.leave_subsection();
      AssertThrow(controls.size() == 3 &&
                    std::all_of(controls.begin(),
                                controls.end(),
                                [](const double c) {
                                  return c >= 4 && c == std::floor(c);
                                }),
                  ExcMessage("Map/Spline control points: three integers >= 4 "
                             "(along E, nu, alpha)"));
      check_target_grid(Es, nus, "Map");
      AssertThrow(setup.material.poisson == 0,
                  ExcMessage("build map: the map is built for a base with "
                             "Poisson's ratio 0 (other bases follow by the "
                             "CLM transform when it is queried)"));
      // Ascending grids (descending angles), no repeated values.
      std::sort(Es.begin(), Es.end());
      std::sort(nus.begin(), nus.end());
      std::sort(angles.begin(), angles.end(), std::greater<double>());
      for (const auto *list : {&Es, &nus, &angles})
        AssertThrow(std::adjacent_find(list->begin(), list->end()) ==
                      list->end(),
                    ExcMessage("Map: the Young's moduli, Poisson's ratios "
                               "and angles must not repeat a value"));
      // The accuracy checks cover the angles this run was asked for (all of
      // a refit's), also when it resumes below some of them.
      const double first_new_angle = angles.empty() ?
                                       std::numeric_limits<double>::infinity() :
                                       angles.front();
      // Resume: the progress file holds every angle done so far (an
      // extension's kept ones too) and stands for the initial map. Root
      // reads it for all ranks, so that they take the same branches.
      const std::string progress = context.persistent_path("map_progress.json");
      std::string       progress_text;
      if (resume && !refit && context.is_root() &&
          std::filesystem::exists(progress))
        {
          std::ifstream in(progress);
          progress_text.assign(std::istreambuf_iterator<char>(in), {});
        }
      progress_text = Utilities::MPI::broadcast(comm, progress_text);
      if (resume && !refit && progress_text.empty())
        context.print("map: Map/Resume: no map_progress.json, starting afresh");
      if (!progress_text.empty())
        {
          std::istringstream in(progress_text);
          extended = MaterialMap::read(in, progress, false);
          AssertThrow(!extended->angles.empty(),
                      ExcMessage("Map/Resume: " + progress +
                                 " holds no angle"));
          // Samples of other settings would be continued as if they were
          // this build's.
          std::string changed;
          for (const auto &[name, value] : settings.items())
            if (extended->build_settings.contains(name) &&
                extended->build_settings[name] != value)
              changed += "\n  " + name + " = " +
                         extended->build_settings[name].dump() + " (now " +
                         value.dump() + ")";
          AssertThrow(changed.empty(),
                      ExcMessage("Map/Resume: " + progress +
                                 " was built with other settings:" + changed +
                                 "\nRestore them, or remove the file to "
                                 "start afresh."));
          const double last = extended->angles.back();
          angles.erase(std::remove_if(angles.begin(),
                                      angles.end(),
                                      [&](const double a) {
                                        return a >= last - 1e-9;
                                      }),
                       angles.end());
          context.print("map: resuming from map_progress.json: " +
                        std::to_string(extended->samples.size()) +
                        " samples at angles " + sig(extended->angles.front()) +
                        " ... " + sig(last) + "; " +
                        std::to_string(angles.size()) + " angles left");
        }
      if (extended)
        {
          const auto same = [](const std::vector<double> &a,
                               const std::vector<double> &b) {
            return a.size() == b.size() &&
                   std::equal(a.begin(),
                              a.end(),
                              b.begin(),
                              [](const double x, const double y) {
                                return std::abs(x - y) < 1e-9;
                              });
          };
          AssertThrow(same(extended->E, Es) && same(extended->nu, nus),
                      ExcMessage("Map/Initial map file: its (E, nu) grid "
                                 "differs from Map/Young's moduli and "
                                 "Poisson's ratios; an extension keeps the "
                                 "grid"));
          AssertThrow(std::abs(extended->blending - setup.blending) < 1e-12,
                      ExcMessage("Map/Initial map file: built with blending " +
                                 sig(extended->blending) +
                                 ", Structure/Blending is " +
                                 sig(setup.blending)));
          // Trailing angles that cover nothing (where an earlier build
          // gave up), and those at or below the first new angle, are
          // dropped with their samples: the extension redoes them from
          // the last angle kept.
          while (!extended->covered.empty() &&
                 (std::none_of(extended->covered.back().begin(),
                               extended->covered.back().end(),
                               [](const bool b) { return b; }) ||
                  (!angles.empty() &&
                   extended->angles.back() <= angles.front() + 1e-9)))
            {
              const double dropped = extended->angles.back();
              extended->covered.pop_back();
              extended->angles.pop_back();
              extended->samples.erase(std::remove_if(extended->samples.begin(),
                                                     extended->samples.end(),
                                                     [&](const auto &sample) {
                                                       return std::abs(
                                                                sample[2] -
                                                                dropped) < 1e-9;
                                                     }),
                                      extended->samples.end());
            }
          AssertThrow(!extended->angles.empty(),
                      ExcMessage("Map/Initial map file: the map covers no "
                                 "node at an angle above the first of "
                                 "Map/Angles, nothing to continue from"));
        }
      const unsigned int n_nodes = Es.size() * nus.size();
      const auto         node_E  = [&](const unsigned int n) {
        return Es[n / nus.size()];
      };
      const auto node_nu = [&](const unsigned int n) {
        return nus[n % nus.size()];
      };
      const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);

      // Whether the inverse problem treats a structure and its mirror image
      // alike (the swapped parameters both free or both fixed at one value,
      // with the same bounds): only then can a sample be mirrored.
      const bool mirror_symmetric = [&]() {
        const auto is_free = [&](const unsigned int i) {
          return std::count(base.free.begin(), base.free.end(), i) > 0;
        };
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          {
            const unsigned int j      = RhombicStructure::mirror_partner(i);
            const bool         free_i = is_free(i), free_j = is_free(j);
            if (free_i != free_j || base.bounds[i] != base.bounds[j] ||
                (!free_i && seed.p[i] != seed.p[j]))
              return false;
          }
        return true;
      }();

      // Solve jobs at one angle, shared among the ranks.
      const auto solve = [&](const double angle, const std::vector<Job> &jobs) {
        return rank_strided<Outcome>(
          comm, jobs.size(), [&](const unsigned int k) {
            Outcome o;
            o.node                 = jobs[k].node;
            InverseProblem problem = base;
            problem.target_E       = node_E(o.node);
            problem.target_nu      = node_nu(o.node);
            problem.target =
              IsotropicModuli::from_young_poisson(problem.target_E *
                                                    setup.base.E,
                                                  problem.target_nu)
                .tensor();
            problem.start      = jobs[k].start;
            RhombicStructure s = seed;
            s.alpha            = angle * M_PI / 180;
            s.p                = jobs[k].start;
            // Within the bounds InverseProblem sets (node 2 kept inside
            // its triangle when both of its offsets vary).
            const auto &ranges = base.bounds;
            const bool  offsets_free =
              std::count_if(base.free.begin(),
                            base.free.end(),
                            [](const unsigned int i) { return i < 2; }) == 2;
            for (unsigned int i = 0; i < s.p.size(); ++i)
              s.p[i] = std::clamp(s.p[i],
                                  ranges[i][0],
                                  i < 2 && offsets_free ?
                                    std::min(ranges[i][1], 0.49) :
                                    ranges[i][1]);
            try
              {
                const auto r =
                  problem.solve(s, setup, MPI_COMM_SELF, op, context);
                o.reached = r.reached;
                o.p       = r.structure.p;
                // On the square cell a structure and its mirror image have
                // the same moduli: a solve may land on either. Samples keep
                // p3 <= p4, so that neighbours lie on one branch (the wide
                // map's growth otherwise crossed to the mirror branch between
                // two rows of E, a jump of up to 0.46 in six parameters that
                // the branch test cannot see along a whole row).
                if (mirror_symmetric && std::abs(angle - 90) < 1e-9 &&
                    o.p[2] > o.p[3])
                  o.p = r.structure.mirrored().p;
                o.misfit = r.misfit;
                o.E      = r.sample.fit.E / setup.base.E;
                o.nu     = r.sample.fit.nu;
              }
            catch (const std::exception &e)
              {
                context.log("map: node " + std::to_string(o.node) +
                            " failed: " + error_message(e));
              }
            return o;
          });
      };

      MaterialMap map;
      map.E              = Es;
      map.nu             = nus;
      map.angles         = angles;
      map.blending       = setup.blending;
      map.build_settings = settings;
      std::vector<Parameters> previous(n_nodes);
      std::vector<bool>       previous_solved(n_nodes, false);
      unsigned int            n_solves = 0;
      // An extension keeps the map's angles and samples; its smallest
      // angle's samples are where the continuation starts.
      if (extended)
        {
          map.angles = extended->angles;
          map.angles.insert(map.angles.end(), angles.begin(), angles.end());
          map.covered = extended->covered;
          map.samples = extended->samples;
          for (const auto &s : extended->samples)
            if (std::abs(s[2] - extended->angles.back()) < 1e-9)
              for (unsigned int n = 0; n < n_nodes; ++n)
                if (std::abs(node_E(n) - s[0]) < 1e-9 &&
                    std::abs(node_nu(n) - s[1]) < 1e-9)
                  {
                    previous_solved[n] = true;
                    std::copy(s.begin() + 3, s.end(), previous[n].begin());
                  }
          AssertThrow(std::count(previous_solved.begin(),
                                 previous_solved.end(),
                                 true) > 0,
                      ExcMessage("Map/Initial map file: no samples at " +
                                 sig(extended->angles.back()) +
                                 " degrees to continue from (a map "
                                 "written without its samples?)"));
          context.print("map: extending a map of " +
                        std::to_string(map.samples.size()) +
                        " samples at angles " + sig(map.angles.front()) +
                        " ... " + sig(extended->angles.back()) + " from " +
                        std::to_string(std::count(previous_solved.begin(),
                                                  previous_solved.end(),
                                                  true)) +
                        " nodes");
        }
      for (unsigned int a = 0; a < angles.size(); ++a)
        {
          GridGrowth growth(Es.size(), nus.size());
          const auto take = [&](const std::vector<Outcome> &out) {
            unsigned int reached = 0;
            for (const auto &o : out)
              {
                growth.tried(o.node);
                ++n_solves;
                if (o.reached)
                  {
                    growth.reached(o.node, o.p);
                    ++reached;
                    map.samples.push_back({{node_E(o.node),
                                            node_nu(o.node),
                                            angles[a],
                                            o.p[0],
                                            o.p[1],
                                            o.p[2],
                                            o.p[3],
                                            o.p[4],
                                            o.p[5],
                                            o.p[6],
                                            o.p[7]}});
                  }
              }
            return reached;
          };
          if (a == 0 && transversal && !extended)
            {
              // The thesis's initial map (ch. 4.6.2): the simplex inverse
              // of H on the transversal subspace gives every target it
              // covers a start, polished by an inverse solve.
              std::vector<std::pair<double, double>> targets;
              for (unsigned int n = 0; n < n_nodes; ++n)
                targets.push_back({node_E(n), node_nu(n)});
              RhombicStructure s = seed;
              s.alpha            = angles[0] * M_PI / 180;
              const auto starts  = transversal_initial_map(
                transversal_parameters, targets, s, setup, context);
              std::vector<Job> jobs;
              for (unsigned int n = 0; n < n_nodes; ++n)
                if (starts[n])
                  jobs.push_back({n, *starts[n]});
              AssertThrow(!jobs.empty(),
                          ExcMessage(
                            "build map: the image of the transversal subspace "
                            "contains none of the (E, nu) targets; move the "
                            "grid into its coverage (see the log) or sample "
                            "V more densely"));
              const unsigned int reached = take(solve(angles[0], jobs));
              context.print("map: angle " + sig(angles[0]) + ": " +
                            std::to_string(reached) + " of " +
                            std::to_string(jobs.size()) +
                            " starts from the transversal map reached");
              context.summary["transversal"]["targets_reached"] = reached;
            }
          else if (a == 0 && !extended)
            {
              // Seed: the nodes nearest the seed structure's isotropic fit,
              // a rank's worth at a time, until one is reached.
              RhombicStructure s          = seed;
              s.alpha                     = angles[0] * M_PI / 180;
              const Sample              r = evaluate(s, setup, comm);
              std::vector<unsigned int> order(n_nodes);
              for (unsigned int n = 0; n < n_nodes; ++n)
                order[n] = n;
              const double sE  = Es.size() > 1 ? Es.back() - Es.front() : 1.,
                           snu = nus.size() > 1 ? nus.back() - nus.front() : 1.;
              std::sort(order.begin(),
                        order.end(),
                        [&](const unsigned int m, const unsigned int n) {
                          const auto d = [&](const unsigned int k) {
                            return std::hypot(
                              (node_E(k) - r.fit.E / setup.base.E) / sE,
                              (node_nu(k) - r.fit.nu) / snu);
                          };
                          return d(m) < d(n);
                        });
              for (unsigned int start = 0;
                   start < std::min<unsigned int>(n_nodes, 3 * n_ranks) &&
                   growth.n_solved() == 0;
                   start += n_ranks)
                {
                  std::vector<Job> jobs;
                  for (unsigned int k = start;
                       k < std::min<unsigned int>(n_nodes, start + n_ranks);
                       ++k)
                    jobs.push_back({order[k], seed.p});
                  take(solve(angles[0], jobs));
                }
            }
          else
            {
              // Continue every node of the previous angle.
              std::vector<Job> jobs;
              for (unsigned int n = 0; n < n_nodes; ++n)
                if (previous_solved[n])
                  jobs.push_back({n, previous[n]});
              take(solve(angles[a], jobs));
            }
          // Grow outward from the solved nodes; failed nodes are tried
          // again as they gain solved neighbours.
          while (true)
            {
              const auto starts = growth.next_starts();
              if (starts.empty())
                break;
              std::vector<Job> jobs;
              for (const auto &[n, start] : starts)
                jobs.push_back({n, start});
              take(solve(angles[a], jobs));
              context.print("map: angle " + sig(angles[a]) + ": " +
                            std::to_string(growth.n_solved()) + " of " +
                            std::to_string(n_nodes) + " nodes reached");
            }
          const unsigned int n_solved = growth.n_solved();
          context.print("map: angle " + sig(angles[a]) +
                        " done: " + std::to_string(n_solved) + " of " +
                        std::to_string(n_nodes) + " (E, nu) nodes covered");
          // Memory in the log (not stdout: machine-dependent), to tell a
          // leak over the build from a single runaway solve.
          {
            Utilities::System::MemoryStats stats;
            Utilities::System::get_memory_stats(stats);
            context.log(
              "map: angle " + sig(angles[a]) +
              ": resident memory, largest rank " +
              std::to_string(Utilities::MPI::max(stats.VmRSS, comm) / 1024) +
              " MB");
          }
          map.covered.push_back(growth.solved());
          previous        = growth.structures();
          previous_solved = growth.solved();
          // Progress: what a resumed run continues from (written whole, then
          // renamed, so that a kill leaves the previous one). A failed write
          // costs only the resumability: logged, not thrown (on root alone
          // it would leave the other ranks waiting).
          if (context.is_root())
            try
              {
                MaterialMap done = map;
                done.angles.resize(done.covered.size());
                replace_file(progress, [&](const std::string &file) {
                  done.write(file);
                });
              }
            catch (const std::exception &e)
              {
                context.log("map: map_progress.json not written: " +
                            error_message(e));
              }
        }
      // From here on, every angle of the map (an extension's old ones too).
      angles = map.angles;
      AssertThrow(map.samples.size() >= 4,
                  ExcMessage("build map: only " +
                             std::to_string(map.samples.size()) +
                             " grid nodes were reached; widen the grid around "
                             "the seed structure's moduli or change the seed"));

      if (branch_tolerance > 0)
        if (const unsigned int n = map.drop_branch_jumps(branch_tolerance))
          context.print("map: dropped " + std::to_string(n) +
                        " samples on another branch than their neighbours "
                        "(Map/Branch tolerance)");

      // The splines over (E, nu, alpha).
      std::vector<std::vector<double>> x;
      for (const auto &s : map.samples)
        x.push_back({s[0], s[1], s[2]});
      const std::vector<double> lower = {Es.front(),
                                         nus.front(),
                                         angles.back()},
                                upper = {Es.back(), nus.back(), angles.front()};
      double worst_fit                = 0;
      for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
        {
          map.parameters[i] =
            TensorSpline(lower,
                         upper,
                         {static_cast<unsigned int>(controls[0]),
                          static_cast<unsigned int>(controls[1]),
                          static_cast<unsigned int>(controls[2])},
                         {log_E, false, false});
          std::vector<double> y;
          for (const auto &s : map.samples)
            y.push_back(s[3 + i]);
          map.parameters[i].fit(x, y, smoothing);
          for (unsigned int k = 0; k < x.size(); ++k)
            worst_fit =
              std::max(worst_fit,
                       std::abs(map.parameters[i].value(x[k]) - y[k]));
        }
      map.log_coverage    = log_coverage;
      map.coverage_pieces = coverage_pieces;
      map.fit_coverage_polygons(height_weight);
      // Written on root, failed on all ranks (a throw on root alone would
      // leave the others waiting). The progress file stays: a run resumed
      // with a writable Map/Map file fits the splines and checks them
      // again, without new inverse solves.
      std::string write_error;
      if (context.is_root())
        {
          std::string file = "Map/Map file = " + map_file;
          try
            {
              map.write(context.path(map_file));
              file = "map_parameters.png";
              map.write_parameter_surfaces(context.path(file), angles.front());
            }
          catch (const std::exception &e)
            {
              write_error = file + ": " + error_message(e);
              if (!refit && std::filesystem::exists(progress))
                write_error += " (the samples are kept in map_progress.json: "
                               "run again with Map/Resume = true, which "
                               "solves nothing new)";
            }
        }
      write_error = Utilities::MPI::broadcast(comm, write_error);
      AssertThrow(write_error.empty(), ExcMessage(write_error));
      context.print("map: " + std::to_string(map.samples.size()) +
                    " samples from " + std::to_string(n_solves) +
                    " inverse solves; splines with " +
                    std::to_string(8 * map.parameters[0].n_coefficients()) +
                    " coefficients; largest fit residual " + sig(worst_fit, 2));

      // Accuracy off the samples (Fig. 4.33): midpoints between covered
      // neighbours, queried and homogenized (an extension's new angles;
      // every angle of a refit).
      std::vector<std::array<double, 3>> checks;
      for (unsigned int a = 0; a < angles.size(); ++a)
        if (angles[a] <= first_new_angle + 1e-9)
          for (unsigned int n = 0; n < n_nodes; ++n)
            {
              const unsigned int j = n % nus.size();
              if (map.covered[a][n] && j + 1 < nus.size() &&
                  map.covered[a][n + 1] && n + nus.size() < n_nodes &&
                  map.covered[a][n + nus.size()] &&
                  map.covered[a][n + nus.size() + 1])
                checks.push_back(
                  {{log_E ? std::sqrt(node_E(n) * node_E(n + nus.size())) :
                            (node_E(n) + node_E(n + nus.size())) / 2,
                    (node_nu(n) + node_nu(n + 1)) / 2,
                    angles[a]}});
            }
      if (checks.size() > n_checks)
        {
          std::vector<std::array<double, 3>> every;
          for (unsigned int k = 0; k < n_checks; ++k)
            every.push_back(checks[k * checks.size() / n_checks]);
          checks = every;
        }
      const auto achieved = rank_strided<std::array<double, 3>>(
        comm, checks.size(), [&](const unsigned int k) {
          try
            {
              bool         inside;
              const Sample r = evaluate(
                map.query(checks[k][0], checks[k][1], checks[k][2], 0, inside),
                setup,
                MPI_COMM_SELF);
              return std::array<double, 3>{
                {r.fit.E / setup.base.E,
                 r.fit.nu,
                 std::max(r.anisotropy.a1, r.anisotropy.a2)}};
            }
          catch (const std::exception &)
            {
              return std::array<double, 3>{{0., 0., 1e300}};
            }
        });
      nlohmann::json accuracy = nlohmann::json::array();
      double         max_dE = 0, max_dnu = 0, sum_dE = 0, sum_dnu = 0;
      unsigned int   n_ok = 0;
      for (unsigned int k = 0; k < checks.size(); ++k)
        {
          const auto &r = achieved[k];
          if (r[2] > 1e299)
            continue;
          const double dE  = std::abs(r[0] / checks[k][0] - 1),
                       dnu = std::abs(r[1] - checks[k][1]);
          max_dE = std::max(max_dE, dE), max_dnu = std::max(max_dnu, dnu);
          sum_dE += dE, sum_dnu += dnu, ++n_ok;
          accuracy.push_back({{"E", checks[k][0]},
                              {"nu", checks[k][1]},
                              {"angle", checks[k][2]},
                              {"E_achieved", r[0]},
                              {"nu_achieved", r[1]},
                              {"anisotropy", r[2]}});
        }
      if (n_ok > 0)
        context.print("map accuracy at " + std::to_string(n_ok) +
                      " points between the samples: |E/E* - 1| mean " +
                      sig(sum_dE / n_ok, 2) + ", max " + sig(max_dE, 2) +
                      "; |nu - nu*| mean " + sig(sum_dnu / n_ok, 2) + ", max " +
                      sig(max_dnu, 2));

      nlohmann::json &S   = context.summary;
      S["map_file"]       = map_file;
      S["samples"]        = map.samples.size();
      S["inverse_solves"] = n_solves;
      S["coefficients"]   = 8 * map.parameters[0].n_coefficients();
      S["fit_residual"]   = worst_fit;
      for (unsigned int a = 0; a < angles.size(); ++a)
        S["covered"].push_back(
          {{"angle", angles[a]},
           {"nodes",
            std::count(map.covered[a].begin(), map.covered[a].end(), true)}});
      S["accuracy"] = {{"points", accuracy},
                       {"E_relative_error_max", max_dE},
                       {"nu_error_max", max_dnu}};
      if (context.is_root())
        {
          map.write_coverage_plot(context.path("map_coverage.png"));
          // Fig. 4.33: every check as a segment from its target (E*, nu*)
          // to what the map's structure gives.
          if (!accuracy.empty())
            {
              std::vector<PlotSeries> segments(1);
              segments[0].label = "target";
              segments[0].size  = 3;
              // The plot shows every segment whole (write_xy_plot clips at
              // its ranges).
              std::array<double, 2> nu_range = {{nus.front(), nus.back()}};
              double                E_top    = Es.back();
              for (const auto &p : accuracy)
                {
                  const double E           = p["E"].get<double>(),
                               nu          = p["nu"].get<double>(),
                               E_achieved  = p["E_achieved"].get<double>(),
                               nu_achieved = p["nu_achieved"].get<double>();
                  segments[0].points.push_back({{nu, E}});
                  PlotSeries s;
                  s.points = {{{nu, E}}, {{nu_achieved, E_achieved}}};
                  s.line   = true;
                  s.color  = {{200, 30, 30}};
                  segments.push_back(s);
                  nu_range[0] = std::min(nu_range[0], nu_achieved);
                  nu_range[1] = std::max(nu_range[1], nu_achieved);
                  E_top       = std::max(E_top, E_achieved);
                }
              segments[1].label   = "what the map gives";
              const double margin = (nu_range[1] - nu_range[0]) / 10;
              write_xy_plot(context.path("map_accuracy.png"),
                            segments,
                            "Map accuracy off the samples",
                            "Poisson's ratio ν",
                            "E / E_b",
                            {{nu_range[0] - margin, nu_range[1] + margin}},
                            {{0, 1.1 * E_top}});
            }
        }
      // The build is complete: a later run with Resume starts afresh (the
      // progress file goes once the map is in place).
      if (!refit)
        {
          context.remove_on_commit("map_progress.json");
          context.remove_on_commit("map_progress.json.tmp");
        }
    }



    MaterialMap
    read_map(ParameterHandler &prm, const std::string &prm_directory)
    {
      prm.enter_subsection("Map");
      const std::string file = prm.get("Map file");
      prm.leave_subsection();
      return MaterialMap::read(path_relative_to(prm_directory, file));
    }



    void
    query_mode(ParameterHandler  &prm,
               const std::string &prm_directory,
               const Setup       &setup,
               RunContext        &context)
    {
      prm.enter_subsection("Query");
      const double E     = prm.get_double("Young's modulus");
      const double nu    = prm.get_double("Poisson's ratio");
      const double angle = prm.get_double("Angle");
      prm.leave_subsection();
      const MaterialMap map = read_map(prm, prm_directory);

      bool             inside = false;
      RhombicStructure s      = map.query(E, nu, angle, setup.base.nu, inside);
      // The evaluation cost of the map (the splines and the clamp).
      {
        Timer        timer;
        bool         dummy;
        unsigned int n = 0;
        for (; n < 1000; ++n)
          map.query(E, nu, angle, setup.base.nu, dummy);
        context.log("query: " + sig(1e6 * timer.wall_time() / n, 3) +
                    " microseconds per evaluation");
      }
      std::string p;
      for (const double v : s.p)
        p += (p.empty() ? "" : ", ") + sig(v, 4);
      context.print("query: E/E_b = " + sig(E) + ", nu = " + sig(nu) +
                    ", alpha = " + sig(angle) + " degrees -> p = " + p);
      if (!inside)
        {
          std::string          nearest = "the map covers nothing at this angle";
          const CoverageRegion region  = map.coverage(angle, setup.base.nu);
          context.summary["nearest_covered_point"] = nullptr;
          if (!region.empty())
            {
              const auto q = region.closest_point({{E, nu}});
              nearest =
                "the nearest covered point is (E/E_b, nu) = (" + sig(q[0], 3) +
                ", " + sig(q[1], 3) + ")" +
                (region.logarithmic() ? ", nearest in (log E, nu)" : "");
              context.summary["nearest_covered_point"] = q;
            }
          context.print("query: the point lies outside the map's coverage "
                        "D(alpha) (" +
                        nearest + "); the structure is an extrapolation");
        }
      const CellModel model(s, setup, context.communicator());
      const Sample   &r  = model.sample();
      const double    dE = r.fit.E / setup.base.E / E - 1, dnu = r.fit.nu - nu;
      context.print(
        "query: the structure gives E/E_b = " + sig(r.fit.E / setup.base.E) +
        " (" + sig(100 * dE, 2) + "%), nu = " + sig(r.fit.nu) + " (" +
        sig(dnu, 2) + "), a1 = " + sig(r.anisotropy.a1, 2) +
        ", a2 = " + sig(r.anisotropy.a2, 2));
      nlohmann::json &S = context.summary;
      S["query"] = {{"E_over_Eb", E}, {"nu", nu}, {"angle_degrees", angle}};
      S["inside_coverage"]  = inside;
      S["E_relative_error"] = dE;
      S["nu_error"]         = dnu;
      write_cell_results(context, s, model, setup);
    }
  } // namespace rhombic
} // namespace forma
