#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/plot.h>
#include <forma/base/rank_strided.h>
#include <forma/base/records.h>
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
#include <memory>
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



      /// What a map build reads from its parameter file (the Map section
      /// and the inverse solves' limits), parsed and checked once.
      struct BuildSettings
      {
        /// sampling_settings(): what a resumed build must share.
        nlohmann::json         sampling;
        OptimizationParameters op;
        /// The (E, nu) grid ascending, the angles descending.
        std::vector<double> Es, nus, angles, controls;
        /// An extension with no new angle: the splines refitted only.
        bool                     refit     = false;
        double                   smoothing = 0, branch_tolerance = 0;
        bool                     log_E = false, log_coverage = false;
        std::string              map_file;
        unsigned int             n_checks = 0, coverage_pieces = 0;
        double                   height_weight = 0;
        bool                     resume        = false;
        bool                     transversal   = false;
        TransversalMapParameters transversal_parameters;
        /// Initial map = file: the map's path (else empty).
        std::string initial_map_file;
      };



      /// The Map section's entries; the checks that need no map.
      BuildSettings
      read_build_settings(ParameterHandler  &prm,
                          const std::string &prm_directory)
      {
        BuildSettings b;
        b.sampling = sampling_settings(prm);
        prm.enter_subsection("Inverse");
        b.op.max_iterations = prm.get_integer("Max iterations");
        prm.leave_subsection();
        b.op.relative_decrease  = 1e-5;
        b.op.decrease_window    = 3;
        b.op.gradient_tolerance = 1e-6;
        b.op.print_iterations   = false;
        b.op.checkpoint         = false;

        prm.enter_subsection("Map");
        b.Es = parse_values(prm.get("Young's moduli"), "Map/Young's moduli");
        b.nus =
          parse_values(prm.get("Poisson's ratios"), "Map/Poisson's ratios");
        b.refit = prm.get("Initial map") == "file" &&
                  Utilities::trim(prm.get("Angles")).empty();
        if (!b.refit)
          b.angles = parse_values(prm.get("Angles"), "Map/Angles");
        b.controls         = parse_values(prm.get("Spline control points"),
                                  "Map/Spline control points");
        b.smoothing        = prm.get_double("Smoothing");
        b.log_E            = prm.get("Young's modulus axis") == "logarithmic";
        b.branch_tolerance = prm.get_double("Branch tolerance");
        b.map_file         = prm.get("Map file");
        b.n_checks         = prm.get_integer("Accuracy checks");
        b.height_weight    = prm.get_double("Coverage height weight");
        b.log_coverage     = prm.get("Coverage axis") == "automatic" ?
                               b.log_E :
                               prm.get("Coverage axis") == "logarithmic";
        b.coverage_pieces  = prm.get_integer("Coverage pieces");
        b.transversal      = prm.get("Initial map") == "transversal";
        b.resume           = prm.get_bool("Resume");
        if (prm.get("Initial map") == "file")
          {
            const std::string file = prm.get("Initial map file");
            AssertThrow(!file.empty(),
                        ExcMessage("Map/Initial map = file needs Map/Initial "
                                   "map file"));
            b.initial_map_file = path_relative_to(prm_directory, file);
          }
        if (b.transversal)
          {
            auto &t = b.transversal_parameters;
            t.fixed =
              TransversalMapParameters::parse_fixed(prm.get("Fixed parameters"),
                                                    "Map/Fixed parameters");
            t.ranges =
              TransversalMapParameters::parse_ranges(prm.get("Sampling ranges"),
                                                     "Map/Sampling ranges");
            t.subspace_samples = prm.get_integer("Subspace samples");
            t.grid_samples     = prm.get_integer("Transversal grid samples");
          }
        prm.leave_subsection();
        return b;
      }



      /// The checks of read_build_settings() that follow the initial
      /// map's note, in the order users have seen them.
      void
      check_build_settings(BuildSettings &b, const Setup &setup)
      {
        AssertThrow(b.controls.size() == 3 &&
                      std::all_of(b.controls.begin(),
                                  b.controls.end(),
                                  [](const double c) {
                                    return c >= 4 && c == std::floor(c);
                                  }),
                    ExcMessage("Map/Spline control points: three integers "
                               ">= 4 (along E, nu, alpha)"));
        check_target_grid(b.Es, b.nus, "Map");
        AssertThrow(setup.material.poisson == 0,
                    ExcMessage("build map: the map is built for a base with "
                               "Poisson's ratio 0 (other bases follow by the "
                               "CLM transform when it is queried)"));
        // Ascending grids (descending angles), no repeated values.
        std::sort(b.Es.begin(), b.Es.end());
        std::sort(b.nus.begin(), b.nus.end());
        std::sort(b.angles.begin(), b.angles.end(), std::greater<double>());
        for (const auto *list : {&b.Es, &b.nus, &b.angles})
          AssertThrow(std::adjacent_find(list->begin(), list->end()) ==
                        list->end(),
                      ExcMessage("Map: the Young's moduli, Poisson's ratios "
                                 "and angles must not repeat a value"));
      }



      /// Initial map = file: the map being extended to smaller angles.
      std::optional<MaterialMap>
      read_initial_map(const BuildSettings &b, const RunContext &context)
      {
        if (b.initial_map_file.empty())
          return std::nullopt;
        auto map = MaterialMap::read(b.initial_map_file);
        if (map.parameters[0].is_logarithmic(0) != b.log_E)
          context.print(std::string("map: note: the splines are fitted ") +
                        (b.log_E ? "uniform in log E" : "uniform in E") +
                        " (Map/Young's modulus axis), the initial map's " +
                        "were not");
        return map;
      }



      /**
       * Map/Resume: the progress file at `progress` holds every angle done
       * so far (an extension's kept ones too) and stands for the initial
       * map; the angles it holds leave b.angles. Root reads it for all
       * ranks, so that they take the same branches. Empty if there is
       * nothing to resume.
       */
      std::optional<MaterialMap>
      read_progress(BuildSettings     &b,
                    const std::string &progress,
                    const RunContext  &context)
      {
        const MPI_Comm comm = context.communicator();
        std::string    text;
        if (b.resume && !b.refit && context.is_root() &&
            std::filesystem::exists(progress))
          {
            std::ifstream in(progress);
            text.assign(std::istreambuf_iterator<char>(in), {});
          }
        text = Utilities::MPI::broadcast(comm, text);
        if (b.resume && !b.refit && text.empty())
          context.print(
            "map: Map/Resume: no map_progress.json, starting afresh");
        if (text.empty())
          return std::nullopt;
        std::istringstream in(text);
        auto               map = MaterialMap::read(in, progress, false);
        AssertThrow(!map.angles.empty(),
                    ExcMessage("Map/Resume: " + progress + " holds no angle"));
        // Samples of other settings would be continued as if they were
        // this build's.
        std::string changed;
        for (const auto &[name, value] : b.sampling.items())
          if (map.build_settings.contains(name) &&
              map.build_settings[name] != value)
            changed += "\n  " + name + " = " + map.build_settings[name].dump() +
                       " (now " + value.dump() + ")";
        AssertThrow(changed.empty(),
                    ExcMessage("Map/Resume: " + progress +
                               " was built with other settings:" + changed +
                               "\nRestore them, or remove the file to "
                               "start afresh."));
        const double last   = map.angles.back();
        auto        &angles = b.angles;
        angles.erase(std::remove_if(angles.begin(),
                                    angles.end(),
                                    [&](const double a) {
                                      return a >= last - 1e-9;
                                    }),
                     angles.end());
        context.print("map: resuming from map_progress.json: " +
                      std::to_string(map.samples.size()) +
                      " samples at angles " + sig(map.angles.front()) +
                      " ... " + sig(last) + "; " +
                      std::to_string(angles.size()) + " angles left");
        return map;
      }



      /**
       * Check that the map being continued fits this build (grid,
       * blending), and drop its trailing angles that cover nothing (where
       * an earlier build gave up) and those at or below the first new
       * angle, with their samples: the extension redoes them from the last
       * angle kept.
       */
      void
      trim_initial_map(MaterialMap         &map,
                       const BuildSettings &b,
                       const Setup         &setup)
      {
        const auto same = [](const std::vector<double> &x,
                             const std::vector<double> &y) {
          return x.size() == y.size() &&
                 std::equal(x.begin(),
                            x.end(),
                            y.begin(),
                            [](const double u, const double v) {
                              return std::abs(u - v) < 1e-9;
                            });
        };
        AssertThrow(same(map.E, b.Es) && same(map.nu, b.nus),
                    ExcMessage("Map/Initial map file: its (E, nu) grid "
                               "differs from Map/Young's moduli and "
                               "Poisson's ratios; an extension keeps the "
                               "grid"));
        AssertThrow(std::abs(map.blending - setup.blending) < 1e-12,
                    ExcMessage("Map/Initial map file: built with blending " +
                               sig(map.blending) + ", Structure/Blending is " +
                               sig(setup.blending)));
        while (
          !map.covered.empty() &&
          (std::none_of(map.covered.back().begin(),
                        map.covered.back().end(),
                        [](const bool c) { return c; }) ||
           (!b.angles.empty() && map.angles.back() <= b.angles.front() + 1e-9)))
          {
            const double dropped = map.angles.back();
            map.covered.pop_back();
            map.angles.pop_back();
            map.samples.erase(std::remove_if(map.samples.begin(),
                                             map.samples.end(),
                                             [&](const auto &sample) {
                                               return std::abs(sample[2] -
                                                               dropped) < 1e-9;
                                             }),
                              map.samples.end());
          }
        AssertThrow(!map.angles.empty(),
                    ExcMessage("Map/Initial map file: the map covers no "
                               "node at an angle above the first of "
                               "Map/Angles, nothing to continue from"));
      }



      /**
       * The continuation over the angles (see build_map_mode()): the map
       * under construction, each node's structure at the last angle done,
       * and the inverse solves that grow it.
       */
      class Continuation
      {
      public:
        Continuation(const BuildSettings    &b,
                     const RhombicStructure &seed,
                     const InverseProblem   &base,
                     const Setup            &setup,
                     RunContext             &context);

        /// Continue from the last angle of `initial` (an extension or a
        /// resumed build), keeping its angles and samples.
        void
        continue_from(const MaterialMap &initial);

        /// Reach the grid's nodes at b.angles[a], from the previous angle's
        /// structures (at the first angle, from the transversal map or the
        /// seed), growing outward; then write the progress file.
        void
        add_angle(const unsigned int a,
                  const bool         first,
                  const std::string &progress);

        MaterialMap  map;
        unsigned int n_solves = 0;

      private:
        unsigned int
        n_nodes() const
        {
          return b.Es.size() * b.nus.size();
        }

        double
        node_E(const unsigned int n) const
        {
          return b.Es[n / b.nus.size()];
        }

        double
        node_nu(const unsigned int n) const
        {
          return b.nus[n % b.nus.size()];
        }

        /// Whether the inverse problem treats a structure and its mirror
        /// image alike (the swapped parameters both free or both fixed at
        /// one value, with the same bounds): only then can a sample be
        /// mirrored.
        bool
        mirror_symmetric() const;

        /// One inverse solve (on this rank alone).
        Outcome
        solve(const double angle, const Job &job) const;

        /// Solve jobs at one angle, shared among the ranks; the reached
        /// ones become samples. Returns how many were reached.
        unsigned int
        take(const double angle, const std::vector<Job> &jobs);

        /// First angle, Initial map = transversal.
        void
        start_from_transversal_map(const double angle);

        /// First angle: the nodes nearest the seed structure's isotropic
        /// fit, a rank's worth at a time, until one is reached.
        void
        start_from_seed(const double angle);

        void
        write_progress(const std::string &progress) const;

        const BuildSettings    &b;
        const RhombicStructure &seed;
        const InverseProblem   &base;
        const Setup            &setup;
        RunContext             &context;
        const bool              mirror;
        /// Each node's structure at the last angle done, and whether it
        /// was reached there.
        std::vector<Parameters> previous;
        std::vector<bool>       previous_solved;
        /// The angle being built.
        std::unique_ptr<GridGrowth> growth;
      };



      Continuation::Continuation(const BuildSettings    &b,
                                 const RhombicStructure &seed,
                                 const InverseProblem   &base,
                                 const Setup            &setup,
                                 RunContext             &context)
        : b(b)
        , seed(seed)
        , base(base)
        , setup(setup)
        , context(context)
        , mirror(mirror_symmetric())
        , previous(n_nodes())
        , previous_solved(n_nodes(), false)
      {
        map.E              = b.Es;
        map.nu             = b.nus;
        map.blending       = setup.blending;
        map.build_settings = b.sampling;
      }



      bool
      Continuation::mirror_symmetric() const
      {
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
      }



      void
      Continuation::continue_from(const MaterialMap &initial)
      {
        map.angles  = initial.angles;
        map.covered = initial.covered;
        map.samples = initial.samples;
        for (const auto &s : initial.samples)
          if (std::abs(s[2] - initial.angles.back()) < 1e-9)
            for (unsigned int n = 0; n < n_nodes(); ++n)
              if (std::abs(node_E(n) - s[0]) < 1e-9 &&
                  std::abs(node_nu(n) - s[1]) < 1e-9)
                {
                  previous_solved[n] = true;
                  std::copy(s.begin() + 3, s.end(), previous[n].begin());
                }
        const auto n_from =
          std::count(previous_solved.begin(), previous_solved.end(), true);
        AssertThrow(n_from > 0,
                    ExcMessage("Map/Initial map file: no samples at " +
                               sig(initial.angles.back()) +
                               " degrees to continue from (a map "
                               "written without its samples?)"));
        context.print("map: extending a map of " +
                      std::to_string(map.samples.size()) +
                      " samples at angles " + sig(map.angles.front()) +
                      " ... " + sig(initial.angles.back()) + " from " +
                      std::to_string(n_from) + " nodes");
      }



      Outcome
      Continuation::solve(const double angle, const Job &job) const
      {
        Outcome o;
        o.node                 = job.node;
        InverseProblem problem = base;
        problem.target_E       = node_E(o.node);
        problem.target_nu      = node_nu(o.node);
        problem.target =
          IsotropicModuli::from_young_poisson(problem.target_E * setup.base.E,
                                              problem.target_nu)
            .tensor();
        problem.start      = job.start;
        RhombicStructure s = seed;
        s.alpha            = angle * M_PI / 180;
        s.p                = job.start;
        // Within the bounds InverseProblem sets (node 2 kept inside its
        // triangle when both of its offsets vary).
        const auto &ranges = base.bounds;
        const bool  offsets_free =
          std::count_if(base.free.begin(),
                        base.free.end(),
                        [](const unsigned int i) { return i < 2; }) == 2;
        for (unsigned int i = 0; i < s.p.size(); ++i)
          s.p[i] =
            std::clamp(s.p[i],
                       ranges[i][0],
                       i < 2 && offsets_free ? std::min(ranges[i][1], 0.49) :
                                               ranges[i][1]);
        try
          {
            const auto r =
              problem.solve(s, setup, MPI_COMM_SELF, b.op, context);
            o.reached = r.reached;
            o.p       = r.structure.p;
            // On the square cell a structure and its mirror image have the
            // same moduli: a solve may land on either. Samples keep p3 <=
            // p4, so that neighbours lie on one branch (the wide map's
            // growth otherwise crossed to the mirror branch between two
            // rows of E, a jump of up to 0.46 in six parameters that the
            // branch test cannot see along a whole row).
            if (mirror && std::abs(angle - 90) < 1e-9 && o.p[2] > o.p[3])
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
      }



      unsigned int
      Continuation::take(const double angle, const std::vector<Job> &jobs)
      {
        const auto   out     = rank_strided<Outcome>(context.communicator(),
                                               jobs.size(),
                                               [&](const unsigned int k) {
                                                 return solve(angle, jobs[k]);
                                               });
        unsigned int reached = 0;
        for (const auto &o : out)
          {
            growth->tried(o.node);
            ++n_solves;
            if (o.reached)
              {
                growth->reached(o.node, o.p);
                ++reached;
                map.samples.push_back({{node_E(o.node),
                                        node_nu(o.node),
                                        angle,
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
      }



      void
      Continuation::start_from_transversal_map(const double angle)
      {
        // The thesis's initial map (ch. 4.6.2): the simplex inverse of H on
        // the transversal subspace gives every target it covers a start,
        // polished by an inverse solve.
        std::vector<std::pair<double, double>> targets;
        for (unsigned int n = 0; n < n_nodes(); ++n)
          targets.push_back({node_E(n), node_nu(n)});
        RhombicStructure s = seed;
        s.alpha            = angle * M_PI / 180;
        const auto starts  = transversal_initial_map(
          b.transversal_parameters, targets, s, setup, context);
        std::vector<Job> jobs;
        for (unsigned int n = 0; n < n_nodes(); ++n)
          if (starts[n])
            jobs.push_back({n, *starts[n]});
        AssertThrow(!jobs.empty(),
                    ExcMessage(
                      "build map: the image of the transversal subspace "
                      "contains none of the (E, nu) targets; move the "
                      "grid into its coverage (see the log) or sample "
                      "V more densely"));
        const unsigned int reached = take(angle, jobs);
        context.print("map: angle " + sig(angle) + ": " +
                      std::to_string(reached) + " of " +
                      std::to_string(jobs.size()) +
                      " starts from the transversal map reached");
        context.summary["transversal"]["targets_reached"] = reached;
      }



      void
      Continuation::start_from_seed(const double angle)
      {
        RhombicStructure s = seed;
        s.alpha            = angle * M_PI / 180;
        const Sample r     = evaluate(s, setup, context.communicator());
        std::vector<unsigned int> order(n_nodes());
        for (unsigned int n = 0; n < n_nodes(); ++n)
          order[n] = n;
        const double sE  = b.Es.size() > 1 ? b.Es.back() - b.Es.front() : 1.,
                     snu = b.nus.size() > 1 ? b.nus.back() - b.nus.front() : 1.;
        const auto distance = [&](const unsigned int k) {
          return std::hypot((node_E(k) - r.fit.E / setup.base.E) / sE,
                            (node_nu(k) - r.fit.nu) / snu);
        };
        std::sort(order.begin(),
                  order.end(),
                  [&](const unsigned int m, const unsigned int n) {
                    return distance(m) < distance(n);
                  });
        const unsigned int n_ranks =
          Utilities::MPI::n_mpi_processes(context.communicator());
        for (unsigned int start = 0;
             start < std::min<unsigned int>(n_nodes(), 3 * n_ranks) &&
             growth->n_solved() == 0;
             start += n_ranks)
          {
            std::vector<Job> jobs;
            for (unsigned int k = start;
                 k < std::min<unsigned int>(n_nodes(), start + n_ranks);
                 ++k)
              jobs.push_back({order[k], seed.p});
            take(angle, jobs);
          }
      }



      void
      Continuation::add_angle(const unsigned int a,
                              const bool         first,
                              const std::string &progress)
      {
        const double angle = b.angles[a];
        growth = std::make_unique<GridGrowth>(b.Es.size(), b.nus.size());
        if (first && b.transversal)
          start_from_transversal_map(angle);
        else if (first)
          start_from_seed(angle);
        else
          {
            // Continue every node of the previous angle.
            std::vector<Job> jobs;
            for (unsigned int n = 0; n < n_nodes(); ++n)
              if (previous_solved[n])
                jobs.push_back({n, previous[n]});
            take(angle, jobs);
          }
        // Grow outward from the solved nodes; failed nodes are tried again
        // as they gain solved neighbours.
        for (auto starts = growth->next_starts(); !starts.empty();
             starts      = growth->next_starts())
          {
                 std::vector<Job> jobs;
                 for (const auto &[n, start] : starts)
              jobs.push_back({n, start});
            take(angle, jobs);
                 context.print("map: angle " + sig(angle) + ": " +
                          std::to_string(growth->n_solved()) + " of " +
                          std::to_string(n_nodes()) + " nodes reached");
          }
        context.print("map: angle " + sig(angle) +
                      " done: " + std::to_string(growth->n_solved()) + " of " +
                      std::to_string(n_nodes()) + " (E, nu) nodes covered");
        // Memory in the log (not stdout: machine-dependent), to tell a
        // leak over the build from a single runaway solve.
        Utilities::System::MemoryStats stats;
        Utilities::System::get_memory_stats(stats);
        context.log(
          "map: angle " + sig(angle) + ": resident memory, largest rank " +
          std::to_string(
            Utilities::MPI::max(stats.VmRSS, context.communicator()) / 1024) +
          " MB");
        map.covered.push_back(growth->solved());
        previous        = growth->structures();
        previous_solved = growth->solved();
        write_progress(progress);
      }



      void
      Continuation::write_progress(const std::string &progress) const
      {
        // What a resumed run continues from (written whole, then renamed,
        // so that a kill leaves the previous one). A failed write costs
        // only the resumability: logged, not thrown (on root alone it
        // would leave the other ranks waiting).
        if (context.is_root())
          try
            {
              MaterialMap done = map;
              done.angles.resize(done.covered.size());
              replace_file(progress,
                           [&](const std::string &file) { done.write(file); });
            }
          catch (const std::exception &e)
            {
              context.log("map: map_progress.json not written: " +
                          error_message(e));
            }
      }



      /// One tensor-product spline per parameter over (E, nu, alpha),
      /// fitted to the samples; returns the largest fit residual.
      double
      fit_splines(MaterialMap &map, const BuildSettings &b)
      {
        std::vector<std::vector<double>> x;
        for (const auto &s : map.samples)
          x.push_back({s[0], s[1], s[2]});
        const std::vector<double> lower = {b.Es.front(),
                                           b.nus.front(),
                                           map.angles.back()},
                                  upper = {b.Es.back(),
                                           b.nus.back(),
                                           map.angles.front()};
        double worst_fit                = 0;
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          {
            map.parameters[i] =
              TensorSpline(lower,
                           upper,
                           {static_cast<unsigned int>(b.controls[0]),
                            static_cast<unsigned int>(b.controls[1]),
                            static_cast<unsigned int>(b.controls[2])},
                           {b.log_E, false, false});
            std::vector<double> y;
            for (const auto &s : map.samples)
              y.push_back(s[3 + i]);
            map.parameters[i].fit(x, y, b.smoothing);
            for (unsigned int k = 0; k < x.size(); ++k)
              worst_fit =
                std::max(worst_fit,
                         std::abs(map.parameters[i].value(x[k]) - y[k]));
          }
        return worst_fit;
      }



      /**
       * The map file and map_parameters.png. Written on root, failed on
       * all ranks. The progress file stays: a run resumed with a writable
       * Map/Map file fits the splines and checks them again, without new
       * inverse solves.
       */
      void
      write_map(const MaterialMap   &map,
                const BuildSettings &b,
                const std::string   &progress,
                const RunContext    &context)
      {
        on_root_or_throw(context.communicator(), [&]() {
          std::string file = "Map/Map file = " + b.map_file;
          try
            {
              map.write(context.path(b.map_file));
              file = "map_parameters.png";
              map.write_parameter_surfaces(context.path(file),
                                           map.angles.front());
            }
          catch (const std::exception &e)
            {
              std::string error = file + ": " + error_message(e);
              if (!b.refit && std::filesystem::exists(progress))
                error += " (the samples are kept in map_progress.json: run "
                         "again with Map/Resume = true, which solves "
                         "nothing new)";
              AssertThrow(false, ExcMessage(error));
            }
        });
      }



      /**
       * Accuracy off the samples (Fig. 4.33): at most b.n_checks midpoints
       * between covered neighbours at the angles at or below
       * `first_new_angle` (an extension's new angles; every angle of a
       * refit), queried and homogenized. Returns, per point, the target
       * and what the map's structure gives; printed and in the summary.
       */
      nlohmann::json
      check_accuracy(const MaterialMap   &map,
                     const BuildSettings &b,
                     const double         first_new_angle,
                     const Setup         &setup,
                     RunContext          &context)
      {
        const unsigned int n_nu = b.nus.size(), n_nodes = b.Es.size() * n_nu;
        std::vector<std::array<double, 3>> checks;
        for (unsigned int a = 0; a < map.angles.size(); ++a)
          if (map.angles[a] <= first_new_angle + 1e-9)
            for (unsigned int n = 0; n < n_nodes; ++n)
              {
                const auto &c = map.covered[a];
                if (c[n] && n % n_nu + 1 < n_nu && c[n + 1] &&
                    n + n_nu < n_nodes && c[n + n_nu] && c[n + n_nu + 1])
                  {
                    const double E0 = b.Es[n / n_nu], E1 = b.Es[n / n_nu + 1];
                    checks.push_back(
                      {{b.log_E ? std::sqrt(E0 * E1) : (E0 + E1) / 2,
                        (b.nus[n % n_nu] + b.nus[n % n_nu + 1]) / 2,
                        map.angles[a]}});
                  }
              }
        if (checks.size() > b.n_checks)
          {
            std::vector<std::array<double, 3>> every;
            for (unsigned int k = 0; k < b.n_checks; ++k)
              every.push_back(checks[k * checks.size() / b.n_checks]);
            checks = every;
          }
        const auto achieved = rank_strided<std::array<double, 3>>(
          context.communicator(), checks.size(), [&](const unsigned int k) {
            try
              {
                bool         inside;
                const Sample r = evaluate(map.query(checks[k][0],
                                                    checks[k][1],
                                                    checks[k][2],
                                                    0,
                                                    inside),
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
        nlohmann::json points = nlohmann::json::array();
        double         max_dE = 0, max_dnu = 0, sum_dE = 0, sum_dnu = 0;
        for (unsigned int k = 0; k < checks.size(); ++k)
          {
            const auto &r = achieved[k];
            if (r[2] > 1e299)
              continue;
            const double dE  = std::abs(r[0] / checks[k][0] - 1),
                         dnu = std::abs(r[1] - checks[k][1]);
            max_dE = std::max(max_dE, dE), max_dnu = std::max(max_dnu, dnu);
            sum_dE += dE, sum_dnu += dnu;
            points.push_back({{"E", checks[k][0]},
                              {"nu", checks[k][1]},
                              {"angle", checks[k][2]},
                              {"E_achieved", r[0]},
                              {"nu_achieved", r[1]},
                              {"anisotropy", r[2]}});
          }
        if (const unsigned int n_ok = points.size(); n_ok > 0)
          context.print("map accuracy at " + std::to_string(n_ok) +
                        " points between the samples: |E/E* - 1| mean " +
                        sig(sum_dE / n_ok, 2) + ", max " + sig(max_dE, 2) +
                        "; |nu - nu*| mean " + sig(sum_dnu / n_ok, 2) +
                        ", max " + sig(max_dnu, 2));
        return {{"points", points},
                {"E_relative_error_max", max_dE},
                {"nu_error_max", max_dnu}};
      }



      /// Fig. 4.33: every accuracy check as a segment from its target
      /// (E*, nu*) to what the map's structure gives (the plot shows every
      /// segment whole: write_xy_plot clips at its ranges).
      void
      write_accuracy_plot(const std::string    &file,
                          const nlohmann::json &points,
                          const BuildSettings  &b)
      {
        std::vector<PlotSeries> segments(1);
        segments[0].label              = "target";
        segments[0].size               = 3;
        std::array<double, 2> nu_range = {{b.nus.front(), b.nus.back()}};
        double                E_top    = b.Es.back();
        for (const auto &p : points)
          {
            const double E = p["E"].get<double>(), nu = p["nu"].get<double>(),
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
        write_xy_plot(file,
                      segments,
                      "Map accuracy off the samples",
                      "Poisson's ratio ν",
                      "E / E_b",
                      {{nu_range[0] - margin, nu_range[1] + margin}},
                      {{0, 1.1 * E_top}});
      }



      /// The summary's entries of a finished build.
      void
      summarize(const MaterialMap    &map,
                const BuildSettings  &b,
                const unsigned int    n_solves,
                const double          worst_fit,
                const nlohmann::json &accuracy,
                nlohmann::json       &S)
      {
        S["map_file"]       = b.map_file;
        S["samples"]        = map.samples.size();
        S["inverse_solves"] = n_solves;
        S["coefficients"]   = 8 * map.parameters[0].n_coefficients();
        S["fit_residual"]   = worst_fit;
        for (unsigned int a = 0; a < map.angles.size(); ++a)
          S["covered"].push_back(
            {{"angle", map.angles[a]},
             {"nodes",
              std::count(map.covered[a].begin(), map.covered[a].end(), true)}});
        S["accuracy"] = accuracy;
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
      BuildSettings          b    = read_build_settings(prm, prm_directory);
      const RhombicStructure seed = read_structure(prm, setup);
      const InverseProblem   base =
        InverseProblem::read(prm, setup, seed, context.communicator());
      std::optional<MaterialMap> initial = read_initial_map(b, context);
      check_build_settings(b, setup);
      // The accuracy checks cover the angles this run was asked for (all of
      // a refit's), also when it resumes below some of them.
      const double      first_new_angle = b.angles.empty() ?
                                            std::numeric_limits<double>::infinity() :
                                            b.angles.front();
      const std::string progress = context.persistent_path("map_progress.json");
      if (auto resumed = read_progress(b, progress, context))
        initial = std::move(resumed);
      if (initial)
        trim_initial_map(*initial, b, setup);

      Continuation build(b, seed, base, setup, context);
      if (initial)
        build.continue_from(*initial);
      build.map.angles.insert(build.map.angles.end(),
                              b.angles.begin(),
                              b.angles.end());
      for (unsigned int a = 0; a < b.angles.size(); ++a)
        build.add_angle(a, a == 0 && !initial, progress);
      MaterialMap &map = build.map;
      AssertThrow(map.samples.size() >= 4,
                  ExcMessage("build map: only " +
                             std::to_string(map.samples.size()) +
                             " grid nodes were reached; widen the grid around "
                             "the seed structure's moduli or change the seed"));
      if (b.branch_tolerance > 0)
        if (const unsigned int n = map.drop_branch_jumps(b.branch_tolerance))
          context.print("map: dropped " + std::to_string(n) +
                        " samples on another branch than their neighbours "
                        "(Map/Branch tolerance)");

      const double worst_fit = fit_splines(map, b);
      map.log_coverage       = b.log_coverage;
      map.coverage_pieces    = b.coverage_pieces;
      map.fit_coverage_polygons(b.height_weight);
      write_map(map, b, progress, context);
      context.print("map: " + std::to_string(map.samples.size()) +
                    " samples from " + std::to_string(build.n_solves) +
                    " inverse solves; splines with " +
                    std::to_string(8 * map.parameters[0].n_coefficients()) +
                    " coefficients; largest fit residual " + sig(worst_fit, 2));

      const auto accuracy =
        check_accuracy(map, b, first_new_angle, setup, context);
      summarize(map, b, build.n_solves, worst_fit, accuracy, context.summary);
      if (context.is_root())
        {
          map.write_coverage_plot(context.path("map_coverage.png"));
          if (!accuracy["points"].empty())
            write_accuracy_plot(context.path("map_accuracy.png"),
                                accuracy["points"],
                                b);
        }
      // The build is complete: a later run with Resume starts afresh (the
      // progress file goes once the map is in place).
      if (!b.refit)
        {
          context.remove_on_commit("map_progress.json");
          context.remove_on_commit("map_progress.json.tmp");
        }
    }
  } // namespace rhombic
} // namespace forma
