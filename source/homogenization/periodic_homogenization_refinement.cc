// PeriodicHomogenization::refine(): adaptive refinement of a regular grid's
// cell problems by the stress jumps of their solutions, periodicity kept.

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/grid_refinement.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_refinement.h>

#include "periodic_homogenization_impl.h"

#include <cmath>

namespace forma
{
  namespace
  {
    /// sigma n at the face points of `values`, strain A + eps(w).
    template <int dim>
    void
    tractions(const FEValuesBase<dim>             &values,
              const TrilinosWrappers::MPI::Vector &w,
              const SymmetricTensor<2, dim>       &A,
              const SymmetricTensor<4, dim>       &C,
              const std::vector<Tensor<1, dim>>   &normals,
              std::vector<Tensor<1, dim>>         &t)
    {
      const FEValuesExtractors::Vector     disp(0);
      std::vector<SymmetricTensor<2, dim>> eps(values.n_quadrature_points);
      values[disp].get_function_symmetric_gradients(w, eps);
      t.resize(eps.size());
      for (unsigned int q = 0; q < eps.size(); ++q)
        t[q] = (C * (A + eps[q])) * normals[q];
    }
  } // namespace



  template <int dim>
  Vector<float>
  PeriodicHomogenization<dim>::Impl::stress_jump_indicators(
    const MaterialFunction &material) const
  {
    const QGauss<dim - 1> rule(fe->degree + 1);
    const auto            flags =
      update_gradients | update_normal_vectors | update_JxW_values;
    FEFaceValues<dim>    here(*mapping, *fe, rule, flags);
    FESubfaceValues<dim> here_sub(*mapping, *fe, rule, flags);
    FEFaceValues<dim>    there(*mapping, *fe, rule, update_gradients);
    FESubfaceValues<dim> there_sub(*mapping, *fe, rule, update_gradients);

    double scale = 0; // |C| of the stiffest cell
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        scale =
          std::max(scale, material(cell->center(), cell->material_id()).norm());
    scale = Utilities::MPI::max(scale, comm);

    // The jump over one face, seen from `cell`: both sides' values at the
    // same points (aligned grid cells: the neighbor's face is opposite).
    std::vector<Tensor<1, dim>> t_here, t_there;
    auto                        jump = [&](const FEValuesBase<dim>       &a,
                    const FEValuesBase<dim>       &b,
                    const SymmetricTensor<4, dim> &Ca,
                    const SymmetricTensor<4, dim> &Cb) {
      double integral = 0;
      for (unsigned int c = 0; c < nv; ++c)
        {
          const auto A = test_strain<dim>(c);
          tractions(a, fluctuation[c], A, Ca, a.get_normal_vectors(), t_here);
          tractions(b, fluctuation[c], A, Cb, a.get_normal_vectors(), t_there);
          for (unsigned int q = 0; q < t_here.size(); ++q)
            integral += (t_here[q] - t_there[q]).norm_square() * a.JxW(q);
        }
      return integral;
    };

    Vector<float> eta(tria->n_active_cells());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto C   = material(cell->center(), cell->material_id());
          double     sum = 0;
          for (const unsigned int f : cell->face_indices())
            {
              const bool periodic = cell->has_periodic_neighbor(f);
              if (cell->at_boundary(f) && !periodic)
                continue; // a hole's boundary: none on grids
              const auto other =
                periodic ? cell->periodic_neighbor(f) : cell->neighbor(f);
              const unsigned int g = GeometryInfo<dim>::opposite_face[f];
              const double       h = cell->face(f)->diameter();
              if (other->is_active() &&
                  other->level() == cell->level()) // same size
                {
                  here.reinit(cell, f);
                  there.reinit(other, g);
                  sum +=
                    h * jump(here,
                             there,
                             C,
                             material(other->center(), other->material_id()));
                }
              else if (other->is_active()) // coarser: a part of its face
                {
                  const unsigned int sub =
                    periodic ?
                      cell->periodic_neighbor_of_coarser_periodic_neighbor(f)
                        .second :
                      cell->neighbor_of_coarser_neighbor(f).second;
                  here.reinit(cell, f);
                  there_sub.reinit(other, g, sub);
                  sum +=
                    h * jump(here,
                             there_sub,
                             C,
                             material(other->center(), other->material_id()));
                }
              else // finer: each child on a part of this face
                for (unsigned int sub = 0;
                     sub < GeometryInfo<dim>::max_children_per_face;
                     ++sub)
                  {
                    const auto child =
                      periodic ?
                        cell->periodic_neighbor_child_on_subface(f, sub) :
                        cell->neighbor_child_on_subface(f, sub);
                    here_sub.reinit(cell, f, sub);
                    there.reinit(child, g);
                    sum +=
                      0.5 * h *
                      jump(here_sub,
                           there,
                           C,
                           material(child->center(), child->material_id()));
                  }
            }
          // Half of each face to each side.
          eta[cell->active_cell_index()] =
            std::sqrt(0.5 * sum) / (scale > 0 ? scale : 1.);
        }
    return eta;
  }



  template <int dim>
  unsigned int
  PeriodicHomogenization<dim>::refine(const MaterialFunction &material,
                                      const double            fraction)
  {
    Impl &m = *impl;
    auto *mesh =
      dynamic_cast<parallel::distributed::Triangulation<dim> *>(m.tria.get());
    AssertThrow(!m.grid && mesh != nullptr && !m.lattice.inversion,
                ExcMessage("homogenization: adaptive refinement needs a "
                           "regular grid solved on its mesh (not Solver = "
                           "multigrid) without the inversion symmetry"));
    AssertThrow(fraction > 0 && fraction <= 1,
                ExcMessage("homogenization: the refined fraction must be in "
                           "(0, 1]"));
    AssertThrow(m.fluctuation.size() == Impl::nv,
                ExcMessage("homogenization: refine() needs a homogenize() "
                           "first"));
    const Vector<float> eta = m.stress_jump_indicators(material);
    parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
      *mesh, eta, fraction, 0);
    const auto before = mesh->n_global_active_cells();
    mesh->execute_coarsening_and_refinement();
    const unsigned int refined = (mesh->n_global_active_cells() - before) /
                                 (GeometryInfo<dim>::max_children_per_cell - 1);

    m.congruent_cells = false;
    m.refined         = true;
    m.fluctuation.clear();
    m.cell_tensors.clear();
    m.dof_handler.distribute_dofs(*m.fe);
    m.owned = m.dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(m.dof_handler, m.relevant);
    m.make_constraints(m.box_size);
    m.solver_parameters = m.requested_solver;
    m.setup_system();
    return refined;
  }

  template Vector<float>
  PeriodicHomogenization<2>::Impl::stress_jump_indicators(
    const MaterialFunction &) const;
  template Vector<float>
  PeriodicHomogenization<3>::Impl::stress_jump_indicators(
    const MaterialFunction &) const;
  template unsigned int
  PeriodicHomogenization<2>::refine(const MaterialFunction &, const double);
  template unsigned int
  PeriodicHomogenization<3>::refine(const MaterialFunction &, const double);
} // namespace forma
