#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/run_context.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/optimization/optimizer.h>
#include <forma/rhombic/inverse_problem.h>
#include <forma/rhombic/parameter_ranges.h>

#include <algorithm>
#include <map>
#include <memory>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    InverseProblem
    InverseProblem::read(ParameterHandler       &prm,
                         const Setup            &setup,
                         const RhombicStructure &structure,
                         const MPI_Comm          comm)
    {
      InverseProblem problem;
      prm.enter_subsection("Inverse");
      const std::string kind = prm.get("Target");
      problem.target_E       = prm.get_double("Target Young's modulus");
      problem.target_nu      = prm.get_double("Target Poisson's ratio");
      const std::string target_parameters = prm.get("Target parameters");
      problem.volume_weight               = prm.get_double("Volume weight");
      problem.proximity_weight            = prm.get_double("Proximity weight");
      problem.tolerance                   = prm.get_double("Tolerance");
      problem.bounds = parse_parameter_ranges(prm.get("Parameter bounds"),
                                              "Inverse/Parameter bounds",
                                              RhombicStructure::ranges(),
                                              RhombicStructure::limits());
      const auto names =
        Utilities::split_string_list(prm.get("Free parameters"));
      prm.leave_subsection();
      for (const auto &name : names)
        {
          const unsigned int i =
            RhombicStructure::parameter_index(name, "Inverse/Free parameters");
          if (std::find(problem.free.begin(), problem.free.end(), i) ==
              problem.free.end())
            problem.free.push_back(i);
        }
      AssertThrow(!problem.free.empty(),
                  ExcMessage("Inverse/Free parameters: none given"));
      std::sort(problem.free.begin(), problem.free.end());
      problem.start = structure.p;
      if (kind == "isotropic")
        {
          AssertThrow(problem.target_E > 0 && problem.target_E < 1,
                      ExcMessage("Inverse/Target Young's modulus (relative to "
                                 "the base's 2D modulus) must be in (0, 1)"));
          AssertThrow(problem.target_nu > -1 && problem.target_nu < 1,
                      ExcMessage("Inverse/Target Poisson's ratio must be in "
                                 "(-1, 1)"));
          problem.target =
            IsotropicModuli::from_young_poisson(problem.target_E * setup.base.E,
                                                problem.target_nu)
              .tensor();
        }
      else
        {
          // The C^H of a known structure on the same cell: a reachable,
          // generally anisotropic target (recovery tests).
          const auto p =
            parse_values(target_parameters, "Inverse/Target parameters");
          AssertThrow(p.size() == RhombicStructure::n_parameters,
                      ExcMessage("Inverse/Target parameters: " +
                                 std::to_string(p.size()) +
                                 " values given, the family has 8"));
          RhombicStructure t = structure;
          std::copy(p.begin(), p.end(), t.p.begin());
          t.check();
          problem.target_structure = t.p;
          const Sample r           = evaluate(t, setup, comm);
          problem.target           = r.C;
          problem.target_E         = r.fit.E / setup.base.E;
          problem.target_nu        = r.fit.nu;
        }
      return problem;
    }



    OptimizationParameters
    inverse_optimization_parameters(ParameterHandler &prm,
                                    const double      tolerance)
    {
      OptimizationParameters op;
      prm.enter_subsection("Inverse");
      op.max_iterations = prm.get_integer("Max iterations");
      prm.leave_subsection();
      op.value_target       = tolerance * tolerance;
      op.relative_decrease  = 1e-5;
      op.decrease_window    = 3;
      op.gradient_tolerance = 1e-6;
      return op;
    }



    RhombicStructure
    InverseProblem::with(const RhombicStructure    &s,
                         const std::vector<double> &z) const
    {
      RhombicStructure result = s;
      for (unsigned int k = 0; k < free.size(); ++k)
        result.p[free[k]] = z[k];
      return result;
    }



    std::vector<double>
    InverseProblem::free_values(const RhombicStructure &s) const
    {
      std::vector<double> z;
      for (const unsigned int i : free)
        z.push_back(s.p[i]);
      return z;
    }



    double
    InverseProblem::misfit(const Sample &r) const
    {
      return (r.C - target).norm() / target.norm();
    }



    double
    InverseProblem::objective(const CellModel     &model,
                              std::vector<double> *gradient) const
    {
      const Sample           &r  = model.sample();
      const RhombicStructure &s  = model.structure();
      const double            t2 = full_contraction(target, target);
      const auto              D  = r.C - target;
      double J = full_contraction(D, D) / t2 + volume_weight * r.phi;
      for (const unsigned int i : free)
        J += proximity_weight * (s.p[i] - start[i]) * (s.p[i] - start[i]);
      if (gradient)
        {
          const auto g = model.gradient();
          gradient->assign(free.size(), 0.);
          for (unsigned int k = 0; k < free.size(); ++k)
            {
              const unsigned int i = free[k];
              (*gradient)[k]       = 2 * full_contraction(D, g.C[i]) / t2 +
                               volume_weight * g.phi[i] +
                               2 * proximity_weight * (s.p[i] - start[i]);
            }
        }
      return J;
    }



    InverseSolution
    InverseProblem::solve(
      const RhombicStructure       &start,
      const Setup                  &setup,
      const MPI_Comm                comm,
      const OptimizationParameters &parameters,
      RunContext                   &context,
      const std::function<void(unsigned int, const CellModel &, double)>
        &accepted) const
    {
      // The material stays clear of the cell's corner, where node 4's joint
      // would join its image and change the topology (E jumps): a start
      // past that edge has node 4 moved back (and the proximity term then
      // measures from there), a step past it fails and is shortened.
      if (std::find(free.begin(), free.end(), 3u) != free.end())
        {
          RhombicStructure moved = start;
          if (moved.clear_corner(RhombicStructure::min_corner_clearance,
                                 bounds[3][0]))
            {
              context.log("inverse: the start's p4 moved from " +
                          sig(start.p[3], 6) + " to " + sig(moved.p[3], 6) +
                          " to keep node 4 clear of the cell's corner");
              InverseProblem from_moved = *this;
              from_moved.start          = moved.p;
              return from_moved.solve(
                moved, setup, comm, parameters, context, accepted);
            }
        }
      // One cell model (mesh + homogenization + gradient) per design: the
      // line search's value and the gradient at an accepted point share it.
      std::map<std::vector<double>, std::shared_ptr<CellModel>> cache;
      const auto model_at = [&](const std::vector<double> &z) {
        auto it = cache.find(z);
        if (it == cache.end())
          {
            const RhombicStructure s         = with(start, z);
            const double           clearance = s.corner_clearance();
            AssertThrow(clearance >= RhombicStructure::min_corner_clearance,
                        ExcMessage(
                          "inverse: the material " +
                          (clearance < 0 ?
                             std::string("covers the cell's corner") :
                             "is " + sig(clearance, 3) +
                               " from the cell's corner") +
                          ", where a joint (node 4's, or node 3's) joins its "
                          "image in the next cell; a clearance of " +
                          sig(RhombicStructure::min_corner_clearance) +
                          " is kept, and a start is moved back only by "
                          "lowering p4 when p4 is free"));
            if (cache.size() > 4)
              cache.clear();
            it = cache.emplace(z, std::make_shared<CellModel>(s, setup, comm))
                   .first;
          }
        return it->second;
      };
      const auto &ranges = bounds;
      DesignModel model;
      model.initial = free_values(start);
      for (const unsigned int i : free)
        {
          // Node 2 stays in its triangle: p1 + p2 <= 0.98.
          model.lower.push_back(ranges[i][0]);
          // With the partner fixed, its value sets the room left.
          const bool partner_free =
            i < 2 && std::find(free.begin(), free.end(), 1 - i) != free.end();
          model.upper.push_back(
            i >= 2       ? ranges[i][1] :
            partner_free ? std::min(ranges[i][1], 0.49) :
                           std::min(ranges[i][1], 0.98 - start.p[1 - i]));
          model.scale.push_back(0.1);
        }
      for (unsigned int k = 0; k < model.initial.size(); ++k)
        AssertThrow(model.initial[k] >= model.lower[k] - 1e-12 &&
                      model.initial[k] <= model.upper[k] + 1e-12,
                    ExcMessage("Inverse: the start's " +
                               RhombicStructure::parameter_name(free[k]) +
                               " = " + sig(model.initial[k]) +
                               " is outside its range [" + sig(model.lower[k]) +
                               ", " + sig(model.upper[k]) + "]"));
      model.value = [&](const std::vector<double> &z) {
        return objective(*model_at(z), nullptr);
      };
      model.gradient = [&](const std::vector<double> &z,
                           std::vector<double>       &g) {
        const auto   cell = model_at(z);
        Timer        timer;
        const double J = objective(*cell, &g);
        const auto  &r = cell->sample();
        context.log("seconds: mesh " + sig(r.seconds_mesh, 3) + ", set-up " +
                    sig(r.seconds_setup, 3) + ", solve " +
                    sig(r.seconds_solve, 3) + ", gradient " +
                    sig(timer.wall_time(), 3));
        return J;
      };
      model.accepted = [&](const unsigned int         k,
                           const std::vector<double> &z,
                           const double               J) {
        if (accepted)
          accepted(k, *model_at(z), J);
      };
      OptimizationParameters op = parameters;
      op.value_target           = tolerance * tolerance;
      const auto      result    = optimize(model, op, context);
      const auto      best      = model_at(result.design);
      InverseSolution solution;
      solution.structure   = best->structure();
      solution.sample      = best->sample();
      solution.misfit      = misfit(solution.sample);
      solution.reached     = solution.misfit <= tolerance;
      solution.iterations  = result.history.size() - 1;
      solution.stop_reason = result.stop_reason;
      solution.history     = result.history;
      return solution;
    }
  } // namespace rhombic
} // namespace forma
