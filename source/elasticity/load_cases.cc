#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/base/records.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/simulator.h>

#include <algorithm>
#include <cstdint>

namespace forma
{
  template <int dim>
  LoadCases<dim>::LoadCases(const ElasticityParameters &parameters,
                            const MPI_Comm              comm)
  {
    std::vector<std::string> tractions = {parameters.traction};
    if (!dealii::Utilities::trim(parameters.load_cases).empty())
      tractions = split_top_level(parameters.load_cases, '|');
    for (const auto &t : tractions)
      {
        ElasticityParameters p = parameters;
        p.traction             = dealii::Utilities::trim(t);
        cases.push_back(std::make_unique<ElasticitySimulator<dim>>(p, comm));
      }
  }

  template <int dim>
  LoadCases<dim>::~LoadCases() = default;

  template <int dim>
  unsigned int
  LoadCases<dim>::n_cases() const
  {
    return cases.size();
  }

  template <int dim>
  ElasticitySimulator<dim> &
  LoadCases<dim>::operator[](const unsigned int k)
  {
    return *cases[k];
  }

  template <int dim>
  void
  LoadCases<dim>::prepare(RunContext *context)
  {
    for (unsigned int k = 0; k < cases.size(); ++k)
      {
        cases[k]->prepare(k == 0 ? context : nullptr);
        AssertThrow(cases[k]->design_layout().size() ==
                      cases[0]->design_layout().size(),
                    dealii::ExcMessage(
                      "Boundary conditions/Load cases: case " +
                      std::to_string(k + 1) +
                      " has another design space than case 1 (the 'loads' "
                      "design block has one entry per traction record: give "
                      "every case the same number of records)."));
      }
  }

  template <int dim>
  void
  LoadCases<dim>::set_objective(const ObjectiveParameters &parameters)
  {
    objectives.clear();
    for (unsigned int k = 0; k < cases.size(); ++k)
      {
        objectives.push_back(
          std::make_shared<const Objective<dim>>(parameters, k > 0));
        cases[k]->set_objective(objectives.back());
      }
  }

  template <int dim>
  bool
  LoadCases<dim>::ramp_objective_weights(const double progress)
  {
    bool ramps = false;
    for (const auto &J : objectives)
      for (const auto &t : J->terms())
        {
          t->ramp_weight(progress);
          ramps = ramps || t->first_weight != t->last_weight;
        }
    return ramps;
  }

  template <int dim>
  std::vector<std::pair<std::string, double>>
  LoadCases<dim>::ramped_weights() const
  {
    std::vector<std::pair<std::string, double>> weights;
    if (!objectives.empty())
      for (const auto &t : objectives[0]->terms())
        if (t->first_weight != t->last_weight)
          weights.emplace_back(t->name, t->weight);
    return weights;
  }

  template <int dim>
  const DesignLayout &
  LoadCases<dim>::design_layout() const
  {
    return cases[0]->design_layout();
  }

  template <int dim>
  const std::vector<double> &
  LoadCases<dim>::design() const
  {
    return cases[0]->design();
  }

  template <int dim>
  void
  LoadCases<dim>::set_design(const std::vector<double> &q)
  {
    for (auto &c : cases)
      c->set_design(q);
  }

  template <int dim>
  void
  LoadCases<dim>::freeze_time_steps(const bool freeze)
  {
    for (auto &c : cases)
      c->freeze_time_steps(freeze);
  }



  template <int dim>
  bool
  LoadCases<dim>::adaptive_time_steps() const
  {
    return cases[0]->adaptive_time_steps();
  }



  template <int dim>
  void
  LoadCases<dim>::solve_design()
  {
    for (unsigned int k = 0; k < cases.size(); ++k)
      try
        {
          cases[k]->solve_design();
        }
      catch (const std::exception &e)
        {
          if (cases.size() == 1)
            throw;
          AssertThrow(false,
                      dealii::ExcMessage("load case " + std::to_string(k + 1) +
                                         ": " + error_message(e)));
        }
  }

  template <int dim>
  double
  LoadCases<dim>::objective() const
  {
    double J = 0;
    for (const auto &c : cases)
      J += c->objective();
    return J;
  }

  template <int dim>
  std::vector<std::pair<std::string, double>>
  LoadCases<dim>::objective_terms() const
  {
    std::vector<std::pair<std::string, double>> terms;
    for (const auto &c : cases)
      for (const auto &[name, value] : c->objective_terms())
        {
          const auto it =
            std::find_if(terms.begin(), terms.end(), [&](const auto &t) {
              return t.first == name;
            });
          if (it == terms.end())
            terms.emplace_back(name, value);
          else
            it->second += value;
        }
    return terms;
  }

  template <int dim>
  double
  LoadCases<dim>::gradient(std::vector<double> &dJ) const
  {
    double J = cases[0]->gradient(dJ);
    for (unsigned int k = 1; k < cases.size(); ++k)
      {
        std::vector<double> g;
        J += cases[k]->gradient(g);
        for (unsigned int i = 0; i < dJ.size(); ++i)
          dJ[i] += g[i];
      }
    return J;
  }

  template <int dim>
  void
  LoadCases<dim>::write_state(const unsigned int index, RunContext &context)
  {
    cases[0]->write_state(index, context);
  }

  template <int dim>
  nlohmann::json
  LoadCases<dim>::state_statistics() const
  {
    nlohmann::json s = cases[0]->state_statistics();
    if (cases.size() == 1)
      return s;
    nlohmann::json per_case = nlohmann::json::array({s});
    for (unsigned int k = 1; k < cases.size(); ++k)
      {
        const auto t = cases[k]->state_statistics();
        for (const char *key : {"max_stress", "max_von_mises_stress"})
          s[key] = std::max(double(s[key]), double(t[key]));
        per_case.push_back(t);
      }
    s["load_cases"] = per_case;
    return s;
  }

  template <int dim>
  nlohmann::json
  LoadCases<dim>::adjoint_statistics() const
  {
    nlohmann::json s = cases[0]->adjoint_statistics();
    if (cases.size() > 1)
      {
        // Every case solves and differentiates: counts, times and stored
        // states add up.
        const char *const sums[] = {"forward_solves",
                                    "gradients",
                                    "forward_seconds",
                                    "adjoint_seconds",
                                    "adjoint_solve_seconds",
                                    "derivative_products_seconds",
                                    "stored_state_bytes"};
        for (unsigned int k = 1; k < cases.size(); ++k)
          {
            const nlohmann::json a = cases[k]->adjoint_statistics();
            for (const char *key : sums)
              if (s[key].is_number_integer())
                s[key] =
                  s[key].get<std::int64_t>() + a[key].get<std::int64_t>();
              else
                s[key] = double(s[key]) + double(a[key]);
          }
        s["seconds_per_forward_solve"] =
          double(s["forward_seconds"]) /
          std::max(1., double(s["forward_solves"]));
        s["seconds_per_gradient"] =
          double(s["adjoint_seconds"]) / std::max(1., double(s["gradients"]));
        s["load_cases"] = cases.size();
      }
    return s;
  }

  template <int dim>
  double
  LoadCases<dim>::max_shape_offset() const
  {
    return cases[0]->max_shape_offset();
  }

  template <int dim>
  double
  LoadCases<dim>::cell_size() const
  {
    return cases[0]->cell_size();
  }

  template <int dim>
  double
  LoadCases<dim>::mesh_quality() const
  {
    return cases[0]->mesh_quality();
  }

  template <int dim>
  std::vector<unsigned int>
  LoadCases<dim>::degenerate_shape_entries(const double threshold) const
  {
    return cases[0]->degenerate_shape_entries(threshold);
  }

  template <int dim>
  bool
  LoadCases<dim>::remesh_improves(std::string &reason)
  {
    return cases[0]->remesh_improves(reason);
  }

  template <int dim>
  void
  LoadCases<dim>::cap_volume_bounds()
  {
    for (auto &c : cases)
      c->cap_volume_bounds();
  }

  template <int dim>
  std::vector<double>
  LoadCases<dim>::cell_mean_stress() const
  {
    auto stress = cases[0]->cell_mean_stress();
    for (unsigned int k = 1; k < cases.size(); ++k)
      {
        const auto other = cases[k]->cell_mean_stress();
        for (unsigned int c = 0; c < stress.size(); ++c)
          stress[c] = std::max(stress[c], other[c]);
      }
    return stress;
  }

  template <int dim>
  std::string
  LoadCases<dim>::remesh_without(const std::string         &file_stem,
                                 const std::vector<bool>   &removed,
                                 dealii::types::boundary_id open_id)
  {
    AssertThrow(!file_stem.empty(), dealii::ExcInternalError());
    const std::string line =
      cases[0]->remesh_without(file_stem, removed, open_id);
    for (unsigned int k = 1; k < cases.size(); ++k)
      cases[k]->load_remeshed(file_stem);
    return line;
  }

  template <int dim>
  std::string
  LoadCases<dim>::remesh(const std::string &file_stem)
  {
    AssertThrow(cases.size() == 1 || !file_stem.empty(),
                dealii::ExcInternalError());
    const std::string line = cases[0]->remesh(file_stem);
    for (unsigned int k = 1; k < cases.size(); ++k)
      cases[k]->load_remeshed(file_stem);
    return line;
  }

  template <int dim>
  void
  LoadCases<dim>::load_remeshed(const std::string &file_stem)
  {
    for (auto &c : cases)
      c->load_remeshed(file_stem);
  }

  template <int dim>
  bool
  LoadCases<dim>::undo_remesh()
  {
    bool undone = false;
    for (auto &c : cases)
      undone = c->undo_remesh() || undone;
    return undone;
  }

  template <int dim>
  void
  LoadCases<dim>::commit_remesh()
  {
    for (auto &c : cases)
      c->commit_remesh();
  }

  template <int dim>
  std::vector<double>
  LoadCases<dim>::material_offsets() const
  {
    return cases[0]->material_offsets();
  }

  template <int dim>
  std::vector<double>
  LoadCases<dim>::design_scales(const std::vector<double> &q0) const
  {
    return cases[0]->design_scales(q0);
  }

  template <int dim>
  void
  LoadCases<dim>::design_bounds(const std::vector<double> &q0,
                                const double               shape_bound,
                                std::vector<double>       &lower,
                                std::vector<double>       &upper) const
  {
    cases[0]->design_bounds(q0, shape_bound, lower, upper);
  }

  template <int dim>
  unsigned int
  LoadCases<dim>::n_remeshes() const
  {
    return cases[0]->n_remeshes();
  }

  template <int dim>
  std::string
  LoadCases<dim>::refine_design(const std::string &file_stem)
  {
    // Each case's indicators over their sum: no case's units decide.
    for (const auto &c : cases)
      AssertThrow(c->triangulation().n_global_active_cells() ==
                    cases[0]->triangulation().n_global_active_cells(),
                  dealii::ExcMessage(
                    "refining a design: the load cases' meshes differ "
                    "(Finite element/Adaptive cycles adapted each to its "
                    "own loads)."));
    dealii::Vector<float> sum;
    for (auto &c : cases)
      {
        const auto   eta = c->refinement_indicators();
        const double total =
          dealii::Utilities::MPI::sum(static_cast<double>(eta.l1_norm()),
                                      c->triangulation().get_communicator());
        if (sum.size() == 0)
          sum.reinit(eta.size());
        if (total > 0)
          sum.add(static_cast<float>(1. / total), eta);
      }
    const auto        cells = cases[0]->cells_to_refine(sum);
    const std::string line  = cases[0]->refine_design(cells, file_stem);
    for (unsigned int k = 1; k < cases.size(); ++k)
      cases[k]->refine_design(cells, "");
    return line;
  }

  template <int dim>
  void
  LoadCases<dim>::load_refinement(const std::string &file_stem)
  {
    for (auto &c : cases)
      c->load_refinement(file_stem);
  }

  template <int dim>
  void
  LoadCases<dim>::guard_cell_corners(const bool on)
  {
    for (auto &c : cases)
      c->guard_cell_corners(on);
  }

  template class LoadCases<2>;
  template class LoadCases<3>;
} // namespace forma
