#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/rank_strided.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/rhombic/parameter_ranges.h>
#include <forma/rhombic/study.h>
#include <forma/rhombic/transversal_map.h>
#include <forma/rhombic/transversal_subspace.h>

#include <boost/serialization/array.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <optional>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      /// C1111, C2222, C1122, C1212 (relative to E_b), max(a1, a2), and 1
      /// if the sample was homogenized (0 if meshing or solving failed).
      using Moduli = std::array<double, 6>;

      std::array<double, 4>
      moduli(const SymmetricTensor<4, 2> &C, const double E_b)
      {
        return {{C[0][0][0][0] / E_b,
                 C[1][1][1][1] / E_b,
                 C[0][0][1][1] / E_b,
                 C[0][1][0][1] / E_b}};
      }

      /// Homogenize the structures, shared among the ranks.
      std::vector<Moduli>
      homogenize_all(const std::vector<RhombicStructure> &structures,
                     const Setup                         &setup,
                     RunContext                          &context)
      {
        const unsigned int n_ranks =
          Utilities::MPI::n_mpi_processes(context.communicator());
        return rank_strided<Moduli>(
          context.communicator(), structures.size(), [&](const unsigned int k) {
            Moduli m{};
            try
              {
                const Sample r = evaluate(structures[k], setup, MPI_COMM_SELF);
                const auto   c = moduli(r.C, setup.base.E);
                std::copy(c.begin(), c.end(), m.begin());
                m[4] = std::max(r.anisotropy.a1, r.anisotropy.a2);
                m[5] = 1;
              }
            catch (const std::exception &e)
              {
                context.log("transversal map: sample " + std::to_string(k) +
                            " failed: " + error_message(e));
              }
            // The log is the root's: it counts its own jobs, every n_ranks-th.
            if (k % n_ranks == 0 && (k / n_ranks + 1) % 50 == 0)
              context.log("transversal map: " + std::to_string(k + 1) + " of " +
                          std::to_string(structures.size()) +
                          " samples homogenized");
            return m;
          });
      }

      /// `n` values over [lo, hi], ends included.
      std::vector<double>
      spaced(const double lo, const double hi, const unsigned int n)
      {
        std::vector<double> v(n);
        for (unsigned int i = 0; i < n; ++i)
          v[i] = lo + (hi - lo) * i / (n - 1);
        return v;
      }

      /// All points of the tensor grid of `axes`, the last axis fastest.
      std::vector<std::vector<double>>
      grid_points(const std::vector<std::vector<double>> &axes)
      {
        std::vector<std::vector<double>> points{{}};
        for (const auto &axis : axes)
          {
            std::vector<std::vector<double>> next;
            for (const auto &p : points)
              for (const double v : axis)
                {
                  next.push_back(p);
                  next.back().push_back(v);
                }
            points = std::move(next);
          }
        return points;
      }
    } // namespace



    std::array<std::optional<double>, RhombicStructure::n_parameters>
    TransversalMapParameters::parse_fixed(const std::string &text,
                                          const std::string &entry)
    {
      std::array<std::optional<double>, RhombicStructure::n_parameters> fixed;
      const auto texts = parse_parameter_assignments(text, entry);
      for (unsigned int i = 0; i < texts.size(); ++i)
        if (texts[i])
          {
            const auto values = parse_values(*texts[i], entry);
            const auto name   = RhombicStructure::parameter_name(i);
            AssertThrow(values.size() == 1,
                        ExcMessage(entry + ": " + name + " needs one value"));
            const auto range = RhombicStructure::ranges()[i];
            AssertThrow(values[0] >= range[0] && values[0] <= range[1],
                        ExcMessage(entry + ": " + name + " = " +
                                   sig(values[0]) + " is outside its range [" +
                                   sig(range[0]) + ", " + sig(range[1]) + "]"));
            fixed[i] = values[0];
          }
      return fixed;
    }



    ParameterRanges
    TransversalMapParameters::parse_ranges(const std::string &text,
                                           const std::string &entry)
    {
      return parse_parameter_ranges(text,
                                    entry,
                                    RhombicStructure::ranges(),
                                    RhombicStructure::ranges());
    }



    namespace
    {
      using ParametersOrNone =
        std::optional<std::array<double, RhombicStructure::n_parameters>>;

      /**
       * transversal_initial_map()'s steps: H sampled on V' and the
       * subspace V fitted to it; H' sampled on a grid over V's coordinates
       * and inverted by simplices at the targets.
       */
      class TransversalMap
      {
      public:
        TransversalMap(const TransversalMapParameters               &parameters,
                       const std::vector<std::pair<double, double>> &targets,
                       const RhombicStructure                       &structure,
                       const Setup                                  &setup,
                       RunContext                                   &context);

        /// 1. The linear model of H on V' and the subspace V.
        TransversalSubspace
        fit_subspace();

        /// 2. H' on a grid over V's coordinates, inverted by simplices.
        SimplexInverse
        invert_on_grid(const TransversalSubspace &V);

        /// Every sample, for plots of H on V' and V.
        void
        write_samples(const std::string &file) const;

        /// Each target's parameters where H'(V) holds it.
        std::vector<ParametersOrNone>
        starts(const TransversalSubspace &V, const SimplexInverse &inverse);

        /// The summary's "transversal" record.
        nlohmann::json
        record(const TransversalSubspace &V,
               const SimplexInverse      &inverse) const;

      private:
        static constexpr unsigned int m = 4; ///< orthotropic moduli

        /// The structure with the free parameters x.
        RhombicStructure
        with(const std::vector<double> &x) const;

        /// "p1, p3, ..." of free parameters by their index in `free`.
        std::string
        names(const std::vector<unsigned int> &indices) const;

        /// The relative distance of moduli h from the nearest target's.
        double
        distance(const Moduli &h) const;

        const TransversalMapParameters               &parameters;
        const std::vector<std::pair<double, double>> &targets;
        const RhombicStructure                       &structure;
        const Setup                                  &setup;
        RunContext                                   &context;
        std::vector<unsigned int>                     free;
        std::vector<std::array<double, 4>>            target_moduli;
        /// Step 1: the samples on V' and their moduli; how many count.
        std::vector<RhombicStructure> subspace_structures;
        std::vector<Moduli>           sampled;
        unsigned int                  n_subspace_ok = 0;
        /// Step 2: the grid samples on V and their moduli; how many count.
        std::vector<RhombicStructure> grid_structures;
        std::vector<Moduli>           on_V;
        unsigned int                  n_grid_ok = 0;
        /// The targets' (E, nu) inside H'(V).
        std::vector<std::array<double, 2>> covered;
      };



      TransversalMap::TransversalMap(
        const TransversalMapParameters               &parameters,
        const std::vector<std::pair<double, double>> &targets,
        const RhombicStructure                       &structure,
        const Setup                                  &setup,
        RunContext                                   &context)
        : parameters(parameters)
        , targets(targets)
        , structure(structure)
        , setup(setup)
        , context(context)
      {
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          if (!parameters.fixed[i])
            free.push_back(i);
        AssertThrow(free.size() > m,
                    ExcMessage(
                      "Map/Fixed parameters: " + std::to_string(free.size()) +
                      " parameters left free; the transversal subspace "
                      "needs more than 4 (the orthotropic moduli)"));
        AssertThrow(parameters.subspace_samples >= 2 &&
                      parameters.grid_samples >= 2,
                    ExcMessage("Map: at least 2 subspace and grid samples per "
                               "parameter needed"));
        // Each sample is a homogenization (about 0.5 s): refuse runs of
        // weeks.
        const double n_samples =
          std::pow(parameters.subspace_samples, free.size()) +
          std::pow(parameters.grid_samples, m);
        AssertThrow(n_samples <= 1e6,
                    ExcMessage(
                      "Map: Subspace samples^" + std::to_string(free.size()) +
                      " + Transversal grid samples^4 = " + sig(n_samples, 3) +
                      " homogenizations; at most 1e6 (narrow the "
                      "Sampling ranges instead)"));
        for (const auto &[E, nu] : targets)
          target_moduli.push_back(moduli(
            IsotropicModuli::from_young_poisson(E * setup.base.E, nu).tensor(),
            setup.base.E));
      }



      RhombicStructure
      TransversalMap::with(const std::vector<double> &x) const
      {
        RhombicStructure s = structure;
        for (unsigned int i = 0; i < s.p.size(); ++i)
          if (parameters.fixed[i])
            s.p[i] = *parameters.fixed[i];
        for (unsigned int j = 0; j < free.size(); ++j)
          s.p[free[j]] = x[j];
        return s;
      }



      std::string
      TransversalMap::names(const std::vector<unsigned int> &indices) const
      {
        std::string s;
        for (const unsigned int j : indices)
          s +=
            (s.empty() ? "" : ", ") + RhombicStructure::parameter_name(free[j]);
        return s;
      }



      double
      TransversalMap::distance(const Moduli &h) const
      {
        double d = 1e300;
        for (const auto &q : target_moduli)
          {
            double e = 0, n = 0;
            for (unsigned int i = 0; i < m; ++i)
              e += std::pow(h[i] - q[i], 2), n += q[i] * q[i];
            d = std::min(d, std::sqrt(e / n));
          }
        return d;
      }



      TransversalSubspace
      TransversalMap::fit_subspace()
      {
        const auto               &ranges = parameters.ranges;
        std::vector<unsigned int> all_free(free.size());
        std::iota(all_free.begin(), all_free.end(), 0);
        std::vector<std::vector<double>> axes;
        for (const unsigned int i : free)
          axes.push_back(
            spaced(ranges[i][0], ranges[i][1], parameters.subspace_samples));
        std::vector<std::vector<double>> xs;
        for (const auto &x : grid_points(axes))
          {
            const auto s = with(x);
            if (s.p[0] + s.p[1] <= 0.98)
              subspace_structures.push_back(s), xs.push_back(x);
          }
        context.print(
          "transversal map: " + std::to_string(subspace_structures.size()) +
          " samples of H on V' (free: " + names(all_free) + ")");
        sampled = homogenize_all(subspace_structures, setup, context);
        std::vector<std::vector<double>>             x_ok, h_ok;
        std::vector<std::pair<double, unsigned int>> by_distance;
        for (unsigned int k = 0; k < sampled.size(); ++k)
          if (sampled[k][5] > 0)
            {
              by_distance.push_back({distance(sampled[k]), x_ok.size()});
              x_ok.push_back(xs[k]);
              h_ok.push_back({sampled[k].begin(), sampled[k].begin() + m});
            }
        n_subspace_ok = x_ok.size();
        AssertThrow(x_ok.size() > free.size() + 1,
                    ExcMessage("transversal map: only " +
                               std::to_string(x_ok.size()) + " of " +
                               std::to_string(sampled.size()) +
                               " samples on V' could be homogenized; see the "
                               "log"));
        // V passes through the mean of the tenth nearest to the targets, so
        // that its image is centred on them.
        std::sort(by_distance.begin(), by_distance.end());
        const unsigned int n_origin =
          std::max<unsigned int>(1, x_ok.size() / 10);
        std::vector<double> origin(free.size(), 0.);
        for (unsigned int k = 0; k < n_origin; ++k)
          for (unsigned int j = 0; j < free.size(); ++j)
            origin[j] += x_ok[by_distance[k].second][j] / n_origin;
        const TransversalSubspace V =
          fit_transversal_subspace(x_ok, h_ok, origin);
        std::string normal;
        for (const auto &w : V.normals)
          {
            std::string row;
            for (unsigned int j = 0; j < free.size(); ++j)
              row += (j > 0 ? ", " : "") + sig(w[j], 2);
            normal += (normal.empty() ? "(" : "; (") + row + ")";
          }
        std::string sv;
        for (const double s : V.singular_values)
          sv += (sv.empty() ? "" : ", ") + sig(s, 2);
        context.print("transversal map: " + std::to_string(x_ok.size()) +
                      " homogenized; linear model residual " +
                      sig(V.fit_residual, 2) + " (relative), singular values " +
                      sv + "; W = " + normal + " over (" + names(all_free) +
                      "); V: coordinates " + names(V.coordinates) +
                      ", dependent " + names(V.dependent));
        return V;
      }



      SimplexInverse
      TransversalMap::invert_on_grid(const TransversalSubspace &V)
      {
        const auto                      &ranges = parameters.ranges;
        std::vector<std::vector<double>> grid_axes;
        for (const unsigned int j : V.coordinates)
          grid_axes.push_back(spaced(ranges[free[j]][0],
                                     ranges[free[j]][1],
                                     parameters.grid_samples));
        const auto       grid = grid_points(grid_axes);
        std::vector<int> sample_of(grid.size(), -1);
        for (unsigned int k = 0; k < grid.size(); ++k)
          {
            const auto x      = V.point(grid[k]);
            bool       inside = true;
            for (const unsigned int j : V.dependent)
              inside = inside && x[j] >= ranges[free[j]][0] &&
                       x[j] <= ranges[free[j]][1];
            const auto s = with(x);
            if (inside && s.p[0] + s.p[1] <= 0.98)
              sample_of[k] = grid_structures.size(),
              grid_structures.push_back(s);
          }
        context.print(
          "transversal map: " + std::to_string(grid_structures.size()) +
          " of " + std::to_string(grid.size()) +
          " grid points on V inside the parameter box");
        on_V = homogenize_all(grid_structures, setup, context);
        std::vector<std::optional<std::vector<double>>> values(grid.size());
        for (unsigned int k = 0; k < grid.size(); ++k)
          if (sample_of[k] >= 0 && on_V[sample_of[k]][5] > 0)
            {
              values[k] = std::vector<double>(on_V[sample_of[k]].begin(),
                                              on_V[sample_of[k]].begin() + m);
              ++n_grid_ok;
            }
        return SimplexInverse(grid_axes, values);
      }



      void
      TransversalMap::write_samples(const std::string &file) const
      {
        std::ofstream csv(file);
        csv << "set";
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          csv << ',' << RhombicStructure::parameter_name(i);
        csv << ",C1111,C2222,C1122,C1212,anisotropy,homogenized\n";
        const auto rows = [&](const char                          *set,
                              const std::vector<RhombicStructure> &s,
                              const std::vector<Moduli>           &h) {
          for (unsigned int k = 0; k < s.size(); ++k)
            {
              csv << set;
              for (const double v : s[k].p)
                csv << ',' << v;
              for (const double v : h[k])
                csv << ',' << v;
              csv << '\n';
            }
        };
        rows("subspace", subspace_structures, sampled);
        rows("grid", grid_structures, on_V);
      }



      std::vector<ParametersOrNone>
      TransversalMap::starts(const TransversalSubspace &V,
                             const SimplexInverse      &inverse)
      {
        std::vector<ParametersOrNone> result(targets.size());
        for (unsigned int t = 0; t < targets.size(); ++t)
          {
            const auto &c = target_moduli[t];
            if (const auto y =
                  inverse.preimage(std::vector<double>(c.begin(), c.end())))
              {
                result[t] = with(V.point(*y)).p;
                covered.push_back({{targets[t].first, targets[t].second}});
              }
          }
        context.print(
          "transversal map: " + std::to_string(n_grid_ok) + " grid samples, " +
          std::to_string(inverse.n_kept()) + " simplices kept, " +
          std::to_string(inverse.n_flipped()) +
          " of the minority orientation dropped; " +
          std::to_string(covered.size()) + " of " +
          std::to_string(targets.size()) + " isotropic targets inside H'(V)" +
          (inverse.n_ambiguous() > 0 ?
             " (" + std::to_string(inverse.n_ambiguous()) +
               " inside several simplices)" :
             std::string()));
        return result;
      }



      nlohmann::json
      TransversalMap::record(const TransversalSubspace &V,
                             const SimplexInverse      &inverse) const
      {
        nlohmann::json record;
        for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
          if (parameters.fixed[i])
            record["fixed"][RhombicStructure::parameter_name(i)] =
              *parameters.fixed[i];
        for (const unsigned int i : free)
          record["free"].push_back(RhombicStructure::parameter_name(i));
        record["normals"]          = V.normals;
        record["origin"]           = V.origin;
        record["singular_values"]  = V.singular_values;
        record["fit_residual"]     = V.fit_residual;
        record["subspace_samples"] = n_subspace_ok;
        record["grid_samples"]     = n_grid_ok;
        record["simplices"]        = inverse.n_kept();
        record["flipped"]          = inverse.n_flipped();
        record["ambiguous"]        = inverse.n_ambiguous();
        record["targets_covered"]  = covered.size();
        record["covered"]          = covered;
        for (const unsigned int j : V.coordinates)
          record["coordinates"].push_back(
            RhombicStructure::parameter_name(free[j]));
        for (const unsigned int j : V.dependent)
          record["dependent"].push_back(
            RhombicStructure::parameter_name(free[j]));
        return record;
      }
    } // namespace



    std::vector<
      std::optional<std::array<double, RhombicStructure::n_parameters>>>
    transversal_initial_map(
      const TransversalMapParameters               &parameters,
      const std::vector<std::pair<double, double>> &targets,
      const RhombicStructure                       &structure,
      const Setup                                  &setup,
      RunContext                                   &context)
    {
      TransversalMap map(parameters, targets, structure, setup, context);
      const TransversalSubspace V       = map.fit_subspace();
      const SimplexInverse      inverse = map.invert_on_grid(V);
      if (context.is_root())
        map.write_samples(context.path("transversal_samples.csv"));
      const auto result              = map.starts(V, inverse);
      context.summary["transversal"] = map.record(V, inverse);
      return result;
    }
  } // namespace rhombic
} // namespace forma
