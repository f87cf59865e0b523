// Mode = optimize: what ends an L-BFGS run of thesis Algorithm 1 short of
// the end: a hold of the vertices that block the line search, an element
// removal, a remesh or a refinement, each followed by a fresh run.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>

#include <forma/elasticity/element_removal.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/simulator.h>

#include "optimize_job_impl.h"

#include <algorithm>

namespace forma
{
  namespace internal
  {
    // The guard blocked the line search in the last window: hold the cells
    // that blocked it and go on with the rest. False: nothing new to hold.
    template <int dim>
    bool
    OptimizeJob<dim>::hold_blocked()
    {
      const std::size_t      last = result.history.size() - 1;
      std::set<unsigned int> fresh;
      for (const auto &[k, entries] : blocked)
        if (k + stage_settings.decrease_window >= last)
          for (const unsigned int i : entries)
            if (!held.count(i))
              fresh.insert(i);
      blocked.clear();
      if (fresh.empty())
        return false;
      held.insert(fresh.begin(), fresh.end());
      ++n_holds;
      ensure(result.design);
      context.print(at_iteration(last) + "holding " +
                    std::to_string(fresh.size()) + " more shape entries (" +
                    std::to_string(held.size()) +
                    " in all) where the mesh-quality guard blocked the line "
                    "search; going on with the rest");
      holds.push_back({{"iteration", last}, {"entries", held.size()}});
      stage_settings.decrease_window_start = last;
      restart("held");
      return true;
    }



    // The ESO-like step (thesis ch. 2.7.1): drop the low-stress cells of
    // the converged shape, remesh with the holes and optimize on, the
    // volume bound holding the volume left. False: the run ends.
    template <int dim>
    bool
    OptimizeJob<dim>::remove_elements()
    {
      removal_done = true;
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  at   = at_iteration(last);
      const std::string  stem = "optimization.mesh_" + std::to_string(last);
      std::string        line;
      const unsigned int n_before = simulator.n_remeshes();
      try
        {
          dealii::Timer remesh_timer;
          const auto    removed =
            select_low_stress_cells(simulator[0].triangulation(),
                                    simulator.cell_mean_stress(),
                                    settings.element_removal,
                                    settings.element_removal_boundary,
                                    simulator[0].holding_boundaries());
          if (std::find(removed.begin(), removed.end(), true) == removed.end())
            {
              context.print(at + "element removal: no cell below " +
                            sig(settings.element_removal, 3) +
                            " of the largest stress");
              return false;
            }
          line = simulator.remesh_without(directory + "/" + stem,
                                          removed,
                                          settings.element_removal_boundary);
          remesh_seconds += remesh_timer.wall_time();
          solve_on_new_mesh();
        }
      catch (const std::exception &e)
        {
          // The shape-optimized design stands, on its mesh.
          if (!roll_back(n_before))
            throw;
          line =
            "element removal failed, keeping the design: " + error_message(e);
          context.print(at + line);
          remeshes.push_back({{"iteration", last},
                              {"description", line},
                              {"element_removal", false}});
          return false;
        }
      mesh = stem;
      context.print(at + line);
      const double volume = simulator.state_statistics()["volume"];
      simulator.cap_volume_bounds();
      context.print("  volume bounds lowered to the volume left, " +
                    sig(volume, 5));
      remeshes.push_back({{"iteration", last},
                          {"description", line},
                          {"element_removal", true},
                          {"volume", volume}});
      begin_outer_iteration(last);
      // The stage with the holes gets its own iteration budget.
      iteration_cap    = last + settings.max_iterations;
      remeshed_quality = simulator.mesh_quality();
      restart("remeshed");
      return true;
    }



    // Remesh the design (mesh quality, or the next outer iteration); if that
    // fails, go on without remeshing.
    template <int dim>
    void
    OptimizeJob<dim>::remesh_and_restart()
    {
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  next = "optimization.mesh_" + std::to_string(last);
      std::string        line;
      const unsigned int n_before = simulator.n_remeshes();
      try
        {
          dealii::Timer remesh_timer;
          line = simulator.remesh(directory + "/" + next);
          remesh_seconds += remesh_timer.wall_time();
          solve_on_new_mesh();
          mesh             = next;
          remeshed_quality = simulator.mesh_quality();
          begin_outer_iteration(last);
        }
      catch (const std::exception &e)
        {
          // Gmsh, the quality check, the reference run of a target
          // objective or the solve on the new mesh failed: go on with the
          // design on the mesh it was found on, without remeshing.
          if (!roll_back(n_before))
            throw;
          line = "remeshing failed, continuing on the current mesh: " +
                 error_message(e);
          remesh_allowed = false;
          outer_possible = false;
        }
      context.print(at_iteration(last) + line);
      remeshes.push_back({{"iteration", last}, {"description", line}});
      restart("remeshed");
    }



    // A new mesh (remeshed, refined, with holes) after iteration `last`:
    // the next outer iteration. J jumps where the new mesh resolves the
    // stress differently, so the decrease window restarts; the new DoFs
    // release held vertices.
    template <int dim>
    void
    OptimizeJob<dim>::begin_outer_iteration(const std::size_t last)
    {
      held.clear(), blocked.clear(), n_holds = 0;
      stage_settings.decrease_window_start = last;
      outer_last_J.push_back(result.history.back());
      outer_start = last, ++n_outer;
      outer_starts.push_back(outer_start);
    }



    // The next outer iteration on the mesh refined for the current design
    // (Outer step = refine); the design is carried over.
    template <int dim>
    void
    OptimizeJob<dim>::refine_and_restart()
    {
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  next = "optimization.mesh_" + std::to_string(last);
      dealii::Timer      refine_timer;
      std::string        line;
      const unsigned int refinements = simulator[0].n_refinements();
      const double       before      = simulator.objective();
      try
        {
          line = simulator.refine_design(directory + "/" + next);
        }
      catch (const std::exception &e)
        {
          // Refused before the mesh changed: on without outer steps.
          if (simulator[0].n_refinements() != refinements)
            throw;
          solved.clear(); // an indicator may have solved other states
          line =
            "not refined, continuing on the current mesh: " + error_message(e);
          context.print(at_iteration(last) + line);
          remeshes.push_back({{"iteration", last}, {"description", line}});
          outer_possible = false;
          restart("refined");
          return;
        }
      remesh_seconds += refine_timer.wall_time();
      solve_on_new_mesh();
      mesh = next;
      begin_outer_iteration(last);
      context.print(at_iteration(last) + line);
      // J of the same design before and after: the discretization error
      // the refinement removed.
      remeshes.push_back({{"iteration", last},
                          {"description", line},
                          {"refinement", true},
                          {"n_dofs", simulator[0].n_dofs()},
                          {"objective_before", before},
                          {"objective_after", simulator.objective()}});
      restart("refined");
    }



    // After a failed remesh: back to the mesh (and design) the design was
    // found on. False if a new mesh was kept already and cannot be undone.
    template <int dim>
    bool
    OptimizeJob<dim>::roll_back(const unsigned int n_before)
    {
      solved.clear();
      return simulator.undo_remesh() || simulator.n_remeshes() == n_before;
    }



    // A new mesh is kept only once the design solves on it; otherwise the
    // caller undoes the remesh (roll_back()).
    template <int dim>
    void
    OptimizeJob<dim>::solve_on_new_mesh()
    {
      solved.clear();
      ensure(simulator.design());
      simulator.commit_remesh();
    }



    // The next L-BFGS run continues the history so far; `kind` marks its
    // first entry in the summary's history.
    template <int dim>
    void
    OptimizeJob<dim>::restart(const std::string &kind)
    {
      history_so_far        = result.history;
      stage_settings.resume = false;
      restart_kind          = kind;
    }



    template class OptimizeJob<2>;
    template class OptimizeJob<3>;
  } // namespace internal
} // namespace forma
