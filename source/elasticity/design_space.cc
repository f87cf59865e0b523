// The design space of the elasticity simulator: its blocks (one registered
// parameterization each, adjoint/parameterization.h), the starting design,
// applying a design to the physical parameters and chaining their
// sensitivities back to the design.

#include <deal.II/base/utilities.h>
#include <deal.II/numerics/vector_tools.h>

#include <forma/base/records.h>

#include "simulator_impl.h"

#include <limits>

namespace forma
{
  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::build_design_layout()
  {
    design_bodies.clear();
    for (const auto &id : Utilities::split_string_list(p.design.bodies, ','))
      {
        const auto m = static_cast<types::material_id>(std::stoi(id));
        AssertThrow(all_ids.count(m),
                    ExcMessage("Design/Bodies: the mesh has no material id " +
                               id + "."));
        design_bodies.push_back(m);
      }
    if (design_bodies.empty())
      design_bodies.assign(all_ids.begin(), all_ids.end());

    physical.clear_wanted();
    extension.reset();
    if (p.design.boundary_shape)
      extension = std::make_unique<HarmonicExtension<dim>>(shape_dof_handler,
                                                           shape_constraints,
                                                           mesh_mapping[0],
                                                           comm);
    if (ipc_contact)
      {
        if (problem_friction.empty()) // not a remeshed design's
          problem_friction = ipc_contact->friction_values();
        friction->value = ipc_contact->friction_values();
      }
    const DesignContext<dim> context{p.design,
                                     physical,
                                     *tria,
                                     comm,
                                     p.problem == "transient",
                                     bodies,
                                     design_bodies,
                                     extension.get(),
                                     [this]() { return shape_start(); }};

    // Blocks in the registry's order; the starting design is the problem
    // as given (the mesh moved by the shape perturbation, the materials of
    // Material/Bodies, unit load scales, no offsets).
    layout.blocks.clear();
    parameterizations.clear();
    design.clear();
    for (const auto *entry :
         ParameterizationRegistry<dim>::instance().entries())
      if (p.design.has(entry->name))
        {
          auto               block = entry->create(context);
          const unsigned int size  = block->size();
          layout.blocks.push_back({entry->name,
                                   layout.size(),
                                   size,
                                   block->lives_on_mesh(),
                                   block->summary(),
                                   block->entries_per_cell()});
          const auto q0 = block->initial();
          design.insert(design.end(), q0.begin(), q0.end());
          parameterizations.push_back(std::move(block));
        }
    if (carried_shape.empty()) // a refined design keeps its values
      apply_start_values();
  }



  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::Impl::shape_start() const
  {
    if (!carried_shape.empty()) // a refined design's shape
      return carried_shape;
    std::vector<double> start(shape_dof_handler.n_dofs(), 0.);
    // A remeshed mesh is the current shape: nothing to perturb.
    if (p.design.shape_perturbation.empty() || remeshed)
      return start;
    Vector_t delta(shape_owned, comm);
    VectorTools::interpolate(
      reference_mapping[0],
      shape_dof_handler,
      *make_function<dim>(split_top_level(p.design.shape_perturbation, ','),
                          std::vector<bool>(dim, true),
                          constants,
                          "Design/Shape perturbation"),
      delta);
    shape_constraints.set_zero(delta);
    for (const auto i : shape_owned)
      start[i] = delta(i);
    Utilities::MPI::sum(start, comm, start);
    return start;
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::apply_start_values()
  {
    // Design/Start: other starting values (recoveries).
    for (const auto &record : split_top_level(p.design.start, ';'))
      {
        if (record.empty())
          continue;
        const auto colon = record.find(':');
        AssertThrow(colon != std::string::npos,
                    ExcMessage("Design/Start: '" + record +
                               "' is not 'block : values'."));
        const std::string  name = Utilities::trim(record.substr(0, colon));
        const DesignBlock *b    = layout.find(name);
        const bool         settable =
          b && parameterizations[b - layout.blocks.data()]->has_start_values();
        AssertThrow(settable,
                    ExcMessage("Design/Start: '" + name +
                               "' is not in Design/Parameters" +
                               (b ? std::string(" (a shape starts at Design/"
                                                "Shape perturbation).") :
                                    std::string("."))));
        const auto values = parse_numbers(record.substr(colon + 1),
                                          "Design/Start (" + name + ")",
                                          -std::numeric_limits<double>::max(),
                                          std::numeric_limits<double>::max());
        AssertThrow(values.size() == b->size,
                    ExcMessage("Design/Start: '" + name + "' has " +
                               std::to_string(b->size) + " entries, got " +
                               std::to_string(values.size()) + "."));
        std::copy(values.begin(), values.end(), design.begin() + b->offset);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::carry_design(const DesignLayout &old_layout,
                                               const std::vector<double> &old,
                                               const std::string &change,
                                               const bool         cells_carried)
  {
    // Shape blocks (and, after a refinement, blocks per cell) start where
    // build_design_layout() put them; the others keep their entries.
    for (unsigned int k = 0; k < layout.blocks.size(); ++k)
      {
        const auto &b     = layout.blocks[k];
        const auto &block = *parameterizations[k];
        if (block.restarts_on_remesh() || (cells_carried && b.per_cell > 0))
          continue;
        const auto *o = old_layout.find(b.name);
        AssertThrow(!block.lives_on_mesh() && o && o->size == b.size,
                    ExcMessage(change + ": the design block '" + b.name +
                               "' lives on the mesh; only shape, per-body " +
                               (cells_carried ? "and global blocks and blocks "
                                                "per cell survive it." :
                                                "and global blocks survive "
                                                "it.")));
        std::copy(old.begin() + o->offset,
                  old.begin() + o->offset + o->size,
                  design.begin() + b.offset);
      }
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::apply_design(const std::vector<double> &q)
  {
    AssertThrow(q.size() == layout.size(),
                ExcMessage("the design vector has " + std::to_string(q.size()) +
                           " entries; the design space has " +
                           std::to_string(layout.size()) + "."));
    design = q;
    reset_physical_parameters("");
    for (unsigned int k = 0; k < parameterizations.size(); ++k)
      parameterizations[k]->apply(q.data() + layout.blocks[k].offset);
    if (friction && friction->wanted)
      ipc_contact->set_friction_values(friction->value);
    if (!shape_field->wanted)
      return;

    // The shape: fixed vertices do not move, hanging ones follow.
    Vector_t x(shape_field->offset);
    shape_constraints.set_zero(x);
    shape_constraints.distribute(x);
    Vector_t X(shape_owned, comm);
    X = shape_reference;
    x += X;
    shape_ghost = x;

    // A shape that inverts or flattens a cell has no meaning: say so
    // instead of solving.
    Point<dim>   where;
    const double worst  = min_scaled_jacobian(&where);
    const double global = Utilities::MPI::min(worst, comm);
    AssertThrow(global >= p.design.min_scaled_jacobian,
                ExcMessage(
                  "the design " +
                  std::string(global <= 0 ? "inverts" : "degenerates") +
                  " a cell (scaled Jacobian " + fmt(global, 3) +
                  " < Design/Min scaled Jacobian = " +
                  fmt(p.design.min_scaled_jacobian, 3) + ")" +
                  (worst == global ? " near " + fmt(Tensor<1, dim>(where)) +
                                       " of the mesh as read" :
                                     std::string()) +
                  "."));
    update_ipc_geometry("the design");
  }



  template <int dim>
  void
  ElasticitySimulator<dim>::Impl::chain_to_design(std::vector<double> &dJ) const
  {
    dJ.assign(layout.size(), 0.);
    for (unsigned int k = 0; k < parameterizations.size(); ++k)
      {
        const unsigned int offset = layout.blocks[k].offset;
        parameterizations[k]->chain(design.data() + offset, dJ.data() + offset);
      }
    Utilities::MPI::sum(dJ, comm, dJ);
  }



  // ---------------------------------------------------------------- facade

  template <int dim>
  const DesignLayout &
  ElasticitySimulator<dim>::design_layout() const
  {
    return impl->layout;
  }

  template <int dim>
  const std::vector<double> &
  ElasticitySimulator<dim>::design() const
  {
    return impl->design;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::set_design(const std::vector<double> &q)
  {
    impl->apply_design(q);
  }

  template <int dim>
  std::vector<double>
  ElasticitySimulator<dim>::design_scales(const std::vector<double> &q0) const
  {
    std::vector<double> scales(q0.size(), 1.);
    const double        length = cell_size();
    for (unsigned int k = 0; k < impl->parameterizations.size(); ++k)
      {
        const unsigned int offset = impl->layout.blocks[k].offset;
        impl->parameterizations[k]->scales(q0.data() + offset,
                                           length,
                                           scales.data() + offset);
      }
    return scales;
  }

  template <int dim>
  void
  ElasticitySimulator<dim>::design_bounds(const std::vector<double> &q0,
                                          const double         shape_bound,
                                          std::vector<double> &lower,
                                          std::vector<double> &upper) const
  {
    const std::vector<double> center = material_offsets();
    lower.assign(q0.size(), 0.);
    upper.assign(q0.size(), 0.);
    for (unsigned int k = 0; k < impl->parameterizations.size(); ++k)
      {
        const unsigned int offset = impl->layout.blocks[k].offset;
        impl->parameterizations[k]->bounds(q0.data() + offset,
                                           center.data() + offset,
                                           shape_bound,
                                           lower.data() + offset,
                                           upper.data() + offset);
      }
  }

  template const DesignLayout &
  ElasticitySimulator<2>::design_layout() const;
  template const DesignLayout &
  ElasticitySimulator<3>::design_layout() const;
  template const std::vector<double> &
  ElasticitySimulator<2>::design() const;
  template const std::vector<double> &
  ElasticitySimulator<3>::design() const;
  template void
  ElasticitySimulator<2>::set_design(const std::vector<double> &);
  template void
  ElasticitySimulator<3>::set_design(const std::vector<double> &);
  template std::vector<double>
  ElasticitySimulator<2>::design_scales(const std::vector<double> &) const;
  template std::vector<double>
  ElasticitySimulator<3>::design_scales(const std::vector<double> &) const;
  template void
  ElasticitySimulator<2>::design_bounds(const std::vector<double> &,
                                        const double,
                                        std::vector<double> &,
                                        std::vector<double> &) const;
  template void
  ElasticitySimulator<3>::design_bounds(const std::vector<double> &,
                                        const double,
                                        std::vector<double> &,
                                        std::vector<double> &) const;
  template class ElasticitySimulator<2>::Impl;
  template class ElasticitySimulator<3>::Impl;
} // namespace forma
