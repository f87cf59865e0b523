// Refinement of a design between optimization iterations (issue 46, item
// 4): quad/hex meshes refine in place, and the design moves with them. The
// shape field is bi/trilinear, so its positions interpolated at the new
// vertices are the same shape; a refined cell's children take its entries
// per cell. A refinement is recorded by the CellIds it refined, which
// name the same cells on any number of ranks (resume).

#include <deal.II/distributed/solution_transfer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/grid/cell_id.h>

#include <forma/base/on_root.h>
#include <forma/base/replace_file.h>

#include "simulator_impl.h"

#include <algorithm>
#include <fstream>

namespace forma
{
  namespace
  {
    template <int dim>
    parallel::distributed::Triangulation<dim> &
    refinable_mesh(Triangulation<dim> &tria)
    {
      auto *mesh =
        dynamic_cast<parallel::distributed::Triangulation<dim> *>(&tria);
      AssertThrow(mesh != nullptr,
                  ExcMessage("refining a design: only quad/hex meshes "
                             "refine in place (this one is simplicial or a "
                             "shared mesh of separated interfaces)."));
      return *mesh;
    }

    std::vector<std::string>
    gathered(const std::vector<std::string> &local, const MPI_Comm comm)
    {
      std::vector<std::string> all;
      for (const auto &part : Utilities::MPI::all_gather(comm, local))
        all.insert(all.end(), part.begin(), part.end());
      std::sort(all.begin(), all.end());
      return all;
    }
  } // namespace



  template <int dim>
  std::map<std::string, std::vector<double>>
  ElasticitySimulator<dim>::Impl::design_by_cell() const
  {
    std::map<std::string, std::vector<double>> by_cell;
    if (std::none_of(layout.blocks.begin(),
                     layout.blocks.end(),
                     [](const DesignBlock &b) { return b.per_cell > 0; }))
      return by_cell;
    // Every rank holds the whole design, but only its own cells' indices.
    std::vector<std::string> local;
    for (const auto &cell : tria->active_cell_iterators())
      if (cell->is_locally_owned())
        {
          std::ostringstream entry;
          entry << cell->id().to_string() << ' '
                << cell->global_active_cell_index();
          local.push_back(entry.str());
        }
    for (const auto &entry : gathered(local, comm))
      {
        std::istringstream in(entry);
        std::string        id;
        std::size_t        index = 0;
        in >> id >> index;
        auto &values = by_cell[id];
        for (unsigned int k = 0; k < layout.blocks.size(); ++k)
          if (const unsigned int n = layout.blocks[k].per_cell)
            for (unsigned int e = 0; e < n; ++e)
              values.push_back(design[layout.blocks[k].offset + n * index + e]);
      }
    return by_cell;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::set_design_by_cell(
    const std::map<std::string, std::vector<double>> &by_cell)
  {
    if (by_cell.empty()) // no block per cell
      return;
    std::vector<double> carried(design.size(), 0.);
    for (const auto &cell : tria->active_cell_iterators())
      if (cell->is_locally_owned())
        {
          // A refined cell's descendants take its entries.
          auto it = by_cell.find(cell->id().to_string());
          for (auto c = cell; it == by_cell.end() && c->level() > 0;)
            {
              c  = c->parent();
              it = by_cell.find(c->id().to_string());
            }
          AssertThrow(it != by_cell.end(), ExcInternalError());
          unsigned int e = 0;
          for (unsigned int k = 0; k < layout.blocks.size(); ++k)
            if (const unsigned int n = layout.blocks[k].per_cell)
              for (unsigned int j = 0; j < n; ++j, ++e)
                carried[layout.blocks[k].offset +
                        n * cell->global_active_cell_index() + j] =
                  it->second[e];
        }
    Utilities::MPI::sum(carried, comm, carried);
    for (unsigned int k = 0; k < layout.blocks.size(); ++k)
      if (layout.blocks[k].per_cell > 0)
        std::copy(carried.begin() + layout.blocks[k].offset,
                  carried.begin() + layout.blocks[k].offset +
                    layout.blocks[k].size,
                  design.begin() + layout.blocks[k].offset);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::check_refinable() const
  {
    refinable_mesh(*tria);
    AssertThrow(p.problem == "static" && !ipc_contact,
                ExcMessage("refining a design: static problems without IPC "
                           "only."));
    for (const auto &b : layout.blocks)
      AssertThrow(!b.on_mesh || b.per_cell > 0,
                  ExcMessage("refining a design: the design block '" + b.name +
                             "' lives on the mesh's DoFs and is not carried "
                             "over a refinement."));
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::refine_design_cells(
    const std::set<std::string> &cells)
  {
    check_refinable();
    auto &mesh = refinable_mesh(*tria);
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->is_locally_owned() && cells.count(cell->id().to_string()))
        cell->set_refine_flag();
    const auto old_layout = layout;
    const auto old_design = design;
    const auto by_cell    = design_by_cell();

    // The positions of the shape as solved and the material coordinates
    // move to the new vertices: the positions, not the offsets, because a
    // curved mesh puts its new vertices on its manifold.
    Vector_t x(shape_owned, shape_relevant, comm),
      material(shape_owned, shape_relevant, comm);
    x        = shape_ghost;
    material = material_positions;
    parallel::distributed::SolutionTransfer<dim, Vector_t> transfer(
      shape_dof_handler);
    transfer.prepare_for_coarsening_and_refinement(
      std::vector<const Vector_t *>{&x, &material});
    mesh.execute_coarsening_and_refinement();

    shape_dof_handler.distribute_dofs(*shape_fe);
    const IndexSet new_owned = shape_dof_handler.locally_owned_dofs();
    Vector_t       new_x(new_owned, comm), new_material(new_owned, comm);
    std::vector<Vector_t *> moved{&new_x, &new_material};
    transfer.interpolate(moved);
    if (!material_of_vertex.empty()) // a remeshed mesh's, by vertex
      rebuild_material_of_vertex(new_material);

    // setup_shape() numbers the shape DoFs as above.
    setup_mesh_dependents();
    carried_shape.assign(shape_dof_handler.n_dofs(), 0.);
    for (const auto i : new_owned)
      carried_shape[i] = new_x(i) - shape_reference(i);
    Utilities::MPI::sum(carried_shape, comm, carried_shape);
    build_design_layout(); // the shape block starts at carried_shape
    carried_shape.clear();
    carry_design(old_layout, old_design, "refining a design", true);
    set_design_by_cell(by_cell);
    apply_design(design);
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::rebuild_material_of_vertex(
    const Vector_t &material)
  {
    // setup_shape() looks up the vertices of the locally owned cells only.
    IndexSet relevant_shape;
    DoFTools::extract_locally_relevant_dofs(shape_dof_handler, relevant_shape);
    Vector_t X(shape_dof_handler.locally_owned_dofs(), relevant_shape, comm);
    X = material;
    material_of_vertex.clear();
    for (const auto &cell : shape_dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto v : cell->vertex_indices())
          {
            Point<dim> m;
            for (unsigned int d = 0; d < dim; ++d)
              m[d] = X(cell->vertex_dof_index(v, d));
            material_of_vertex.emplace_back(cell->vertex(v), m);
          }
    std::sort(material_of_vertex.begin(),
              material_of_vertex.end(),
              [](const auto &a, const auto &b) {
                return lexicographically_before(a.first, b.first);
              });
  }



  template <int dim>
  dealii::Vector<float>
  ElasticitySimulator<dim>::refinement_indicators()
  {
    auto &s = *impl;
    s.check_refinable();
    AssertThrow(!s.u_states.empty(),
                ExcMessage("refining a design: solve the design first."));
    s.set_step_state(0);
    if (s.p.error_indicator == "goal")
      {
        AssertThrow(s.goal, ExcInternalError());
        s.estimate_goal_error();
      }
    else
      s.kelly_indicators();
    return s.estimated_error;
  }



  template <int dim>
  std::vector<std::string>
  ElasticitySimulator<dim>::cells_to_refine(
    const dealii::Vector<float> &indicators)
  {
    auto &mesh = refinable_mesh(*impl->tria);
    impl->flag_cells(indicators, 0.);
    std::vector<std::string> local;
    for (const auto &cell : mesh.active_cell_iterators())
      if (cell->is_locally_owned() && cell->refine_flag_set())
        {
          local.push_back(cell->id().to_string());
          cell->clear_refine_flag();
        }
    return gathered(local, impl->comm);
  }



  template <int dim>
  std::string
  ElasticitySimulator<dim>::refine_design(const std::vector<std::string> &cells,
                                          const std::string &file_stem)
  {
    auto &s = *impl;
    s.check_refinable();
    {
      // The children would meet a fold at a corner: say so before anything
      // changes.
      const bool guarded = s.guard_corners;
      s.guard_corners    = true;
      const double worst = Utilities::MPI::min(s.min_scaled_jacobian(), s.comm);
      s.guard_corners    = guarded;
      AssertThrow(worst >= s.p.design.min_scaled_jacobian,
                  ExcMessage("refining a design: a cell of the shape folds "
                             "at a corner (scaled Jacobian " +
                             fmt(worst, 3) +
                             " < Design/Min scaled Jacobian), between its "
                             "quadrature points; its children would be "
                             "inverted."));
    }
    const auto n_before = s.tria->n_global_active_cells();
    const auto before   = s.dof_handler.n_dofs();
    auto       all      = s.refinements;
    all.push_back(cells);
    if (!file_stem.empty())
      on_root_or_throw(
        s.comm,
        [&]() {
          replace_file_text(file_stem + ".refinement.json",
                            nlohmann::json{{"refinements", all}}.dump());
        },
        "refining a design: cannot write '" + file_stem + ".refinement.json'");
    s.refinements = std::move(all); // from here on the mesh changes
    s.refine_design_cells(std::set<std::string>(cells.begin(), cells.end()));
    if (s.objective)
      set_objective(s.objective); // the reference run on the new mesh
    return "refined " + std::to_string(cells.size()) + " cells (" +
           s.p.error_indicator + " indicator): " + std::to_string(n_before) +
           " -> " + std::to_string(s.tria->n_global_active_cells()) +
           " cells, " + std::to_string(before) + " -> " +
           std::to_string(s.dof_handler.n_dofs()) + " DoFs";
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::load_refinement(const std::string &file_stem)
  {
    auto             &s    = *impl;
    const std::string file = file_stem + ".refinement.json";
    std::ifstream     in(file);
    AssertThrow(in,
                ExcMessage("cannot read the refined design '" + file + "'."));
    std::vector<std::vector<std::string>> all;
    try
      {
        all = nlohmann::json::parse(in)
                .at("refinements")
                .get<std::vector<std::vector<std::string>>>();
      }
    catch (const std::exception &e)
      {
        AssertThrow(false,
                    ExcMessage("the refined design '" + file +
                               "' is unreadable: " + e.what()));
      }
    AssertThrow(s.refinements.empty(),
                ExcMessage("load_refinement: the mesh is refined already."));
    for (const auto &cells : all)
      {
        // Every cell named must be an active cell of the mesh.
        const std::set<std::string> named(cells.begin(), cells.end());
        unsigned int                found = 0;
        for (const auto &cell : s.tria->active_cell_iterators())
          found +=
            cell->is_locally_owned() && named.count(cell->id().to_string());
        AssertThrow(Utilities::MPI::sum(found, s.comm) == named.size(),
                    ExcMessage("the refined design '" + file +
                               "' names cells that this mesh does not have "
                               "(was it written for another mesh?)."));
        s.refine_design_cells(named);
        s.refinements.push_back(cells);
      }
    if (s.objective)
      set_objective(s.objective);
  }



  template <int dim>
  unsigned int
  ElasticitySimulator<dim>::n_refinements() const
  {
    return impl->refinements.size();
  }



#define FORMA_INSTANTIATE(dim)                                                 \
  template void ElasticitySimulator<dim>::Impl::refine_design_cells(           \
    const std::set<std::string> &);                                            \
  template std::map<std::string, std::vector<double>>                          \
                ElasticitySimulator<dim>::Impl::design_by_cell() const;        \
  template void ElasticitySimulator<dim>::Impl::set_design_by_cell(            \
    const std::map<std::string, std::vector<double>> &);                       \
  template dealii::Vector<float>                                               \
  ElasticitySimulator<dim>::refinement_indicators();                           \
  template std::vector<std::string> ElasticitySimulator<dim>::cells_to_refine( \
    const dealii::Vector<float> &);                                            \
  template std::string ElasticitySimulator<dim>::refine_design(                \
    const std::vector<std::string> &, const std::string &);                    \
  template void ElasticitySimulator<dim>::load_refinement(                     \
    const std::string &);                                                      \
  template unsigned int ElasticitySimulator<dim>::n_refinements() const;

  FORMA_INSTANTIATE(2)
  FORMA_INSTANTIATE(3)
#undef FORMA_INSTANTIATE
} // namespace forma
