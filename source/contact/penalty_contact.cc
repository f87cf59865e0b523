#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/base/records.h>
#include <forma/contact/penalty_contact.h>
#include <forma/contact/smoothing.h>

#include <Sacado.hpp>

#include <algorithm>
#include <array>
#include <set>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /// The contact traction at one point and its partial derivatives.
    template <int dim>
    struct PointResponse
    {
      Tensor<1, dim> t;
      Tensor<2, dim> dt_dj, dt_dn; ///< [k][m] = d t_k / d j_m, d n_m
      double         gap = 0;      ///< j . n (penetration where > 0)
      Tensor<1, dim> slip;         ///< tangential part of j
    };

    template <int dim>
    PointResponse<dim>
    respond(const ContactLaw     &law,
            const Tensor<1, dim> &j,
            const Tensor<1, dim> &n)
    {
      using AD = Sacado::Fad::SFad<double, 2 * dim>;
      std::array<AD, dim> J, N, s;
      for (unsigned int d = 0; d < dim; ++d)
        {
          J[d] = AD(2 * dim, d, j[d]);
          N[d] = AD(2 * dim, dim + d, n[d]);
        }
      AD g = 0.;
      for (unsigned int d = 0; d < dim; ++d)
        g += J[d] * N[d];
      const AD h  = contact::h_eta(g, law.eta) / law.alpha;
      AD       f  = 0.;
      AD       r2 = 0.;
      for (unsigned int d = 0; d < dim; ++d)
        {
          s[d] = J[d] - g * N[d];
          r2 += s[d] * s[d];
        }
      if (law.mu > 0)
        f = law.mu * contact::smoothed_norm_factor(r2, law.eta_n);

      PointResponse<dim> r;
      r.gap = g.val();
      for (unsigned int k = 0; k < dim; ++k)
        {
          const AD t = h * (N[k] + f * s[k]);
          r.t[k]     = t.val();
          r.slip[k]  = s[k].val();
          for (unsigned int m = 0; m < dim; ++m)
            {
              r.dt_dj[k][m] = t.dx(m);
              r.dt_dn[k][m] = t.dx(dim + m);
            }
        }
      return r;
    }
  } // namespace



  template <int dim>
  PenaltyContact<dim>::PenaltyContact(const ContactParameters &parameters)
    : parameters(parameters)
  {}



  template <int dim>
  const ContactLaw &
  PenaltyContact<dim>::law(const Face &f) const
  {
    return f.deformable ? parameters.deformable.at(f.id) :
                          parameters.rigid.at(f.id);
  }



  template <int dim>
  void
  PenaltyContact<dim>::setup(const DoFHandler<dim>            &dof_handler,
                             const hp::MappingCollection<dim> &mapping,
                             const hp::QCollection<dim - 1>   &face_quadrature)
  {
    faces.clear();
    any_faces  = false;
    fe         = &dof_handler.get_fe_collection();
    quadrature = face_quadrature;
    if (parameters.empty())
      return;
    std::set<types::boundary_id> mesh_ids;
    for (const auto b : dof_handler.get_triangulation().get_boundary_ids())
      mesh_ids.insert(b);
    for (const auto *m : {&parameters.rigid, &parameters.deformable})
      for (const auto &[id, law] : *m)
        AssertThrow(mesh_ids.count(id),
                    ExcMessage("Contact: the mesh has no boundary id " +
                               std::to_string(id) +
                               (m == &parameters.deformable ?
                                  " (DD interfaces get theirs from Mesh/"
                                  "Separate interfaces)." :
                                  ".")));

    // DD sides, sorted by face center, then paired by coincidence.
    struct Side
    {
      Point<dim>                                     center;
      typename DoFHandler<dim>::active_cell_iterator cell;
      unsigned int                                   face;
      double                                         size;
    };
    std::vector<Side> sides;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (cell->is_artificial())
          continue;
        for (const auto f : cell->face_indices())
          {
            if (!cell->face(f)->at_boundary())
              continue;
            const auto id = cell->face(f)->boundary_id();
            if (parameters.rigid.count(id) && cell->is_locally_owned())
              {
                Face face;
                face.cell = face.partner = cell;
                face.face = face.partner_face = f;
                face.id                       = id;
                faces.push_back(face);
              }
            else if (parameters.deformable.count(id))
              sides.push_back(
                {cell->face(f)->center(), cell, f, cell->face(f)->diameter()});
          }
      }
    std::sort(sides.begin(), sides.end(), [](const Side &a, const Side &b) {
      return a.center[0] < b.center[0];
    });
    std::vector<int> partner(sides.size(), -1);
    for (unsigned int a = 0; a < sides.size(); ++a)
      {
        const double tol = 1e-8 * sides[a].size;
        for (unsigned int b = a + 1;
             b < sides.size() && sides[b].center[0] <= sides[a].center[0] + tol;
             ++b)
          if (sides[a].center.distance(sides[b].center) <= tol &&
              sides[a].cell->face(sides[a].face)->boundary_id() ==
                sides[b].cell->face(sides[b].face)->boundary_id())
            {
              AssertThrow(partner[a] < 0 && partner[b] < 0,
                          ExcMessage("Contact: more than two coincident faces "
                                     "near " +
                                     sig(sides[a].center[0], 6) +
                                     "... on a deformable-deformable "
                                     "interface."));
              partner[a] = b;
              partner[b] = a;
            }
      }

    hp::FEFaceValues<dim> values(mapping,
                                 *fe,
                                 quadrature,
                                 update_quadrature_points);
    hp::FEFaceValues<dim> partner_values(mapping,
                                         *fe,
                                         quadrature,
                                         update_quadrature_points);
    for (unsigned int a = 0; a < sides.size(); ++a)
      {
        AssertThrow(
          partner[a] >= 0,
          ExcMessage(
            "Contact: the deformable-deformable face at (" +
            sig(sides[a].center[0], 6) + ", " + sig(sides[a].center[1], 6) +
            (dim == 3 ? ", " + sig(sides[a].center[dim - 1], 6) :
                        std::string()) +
            ") with boundary id " +
            std::to_string(sides[a].cell->face(sides[a].face)->boundary_id()) +
            " has no coincident face on the other part: the "
            "interface must be cut from a conforming mesh (Mesh/"
            "Separate interfaces)."));
        const Side &m = sides[a], &o = sides[partner[a]];
        // The side with the lower material id (then cell index) is "-".
        const bool minus =
          m.cell->material_id() != o.cell->material_id() ?
            m.cell->material_id() < o.cell->material_id() :
            m.cell->active_cell_index() < o.cell->active_cell_index();
        if (!minus || !m.cell->is_locally_owned())
          continue;
        AssertThrow(m.cell->active_fe_index() == o.cell->active_fe_index(),
                    ExcMessage("Contact: the two sides of a deformable-"
                               "deformable interface need the same element "
                               "degree."));
        Face face;
        face.cell         = m.cell;
        face.face         = m.face;
        face.partner      = o.cell;
        face.partner_face = o.face;
        face.id           = m.cell->face(m.face)->boundary_id();
        face.deformable   = true;
        values.reinit(m.cell, m.face);
        partner_values.reinit(o.cell, o.face);
        const auto &x = values.get_present_fe_values().get_quadrature_points();
        const auto &y =
          partner_values.get_present_fe_values().get_quadrature_points();
        for (unsigned int q = 0; q < x.size(); ++q)
          {
            unsigned int best = 0;
            for (unsigned int k = 1; k < y.size(); ++k)
              if (x[q].distance(y[k]) < x[q].distance(y[best]))
                best = k;
            AssertThrow(x[q].distance(y[best]) <= 1e-8 * m.size,
                        ExcMessage("Contact: the quadrature points of two "
                                   "paired deformable-deformable faces do not "
                                   "coincide (non-matching interface)."));
            face.permutation.push_back(best);
          }
        faces.push_back(face);
      }
    any_faces = Utilities::MPI::max(faces.empty() ? 0 : 1,
                                    dof_handler.get_communicator()) == 1;
  }



  template <int dim>
  void
  PenaltyContact<dim>::add_couplings(
    const AffineConstraints<double>   &constraints,
    TrilinosWrappers::SparsityPattern &pattern) const
  {
    std::vector<types::global_dof_index> a, b;
    for (const auto &f : faces)
      if (f.deformable)
        {
          a.resize(f.cell->get_fe().n_dofs_per_cell());
          b.resize(f.partner->get_fe().n_dofs_per_cell());
          f.cell->get_dof_indices(a);
          f.partner->get_dof_indices(b);
          a.insert(a.end(), b.begin(), b.end());
          constraints.add_entries_local_to_global(a, pattern, false);
        }
  }



  template <int dim>
  double
  PenaltyContact<dim>::assemble(const hp::MappingCollection<dim> &mapping,
                                const Vector_t                   &u,
                                const AffineConstraints<double>  &constraints,
                                const bool                        transpose,
                                TrilinosWrappers::SparseMatrix   *matrix,
                                Vector_t                         &residual,
                                Vector_t                         *raw) const
  {
    if (faces.empty())
      return 0.;
    const FEValuesExtractors::Vector     disp(0);
    hp::FEFaceValues<dim>                values(mapping,
                                 *fe,
                                 quadrature,
                                 update_values | update_JxW_values |
                                   update_normal_vectors);
    hp::FEFaceValues<dim>                partner_values(mapping,
                                         *fe,
                                         quadrature,
                                         update_values);
    std::vector<Tensor<1, dim>>          u_minus, u_plus;
    std::vector<types::global_dof_index> dofs, partner_dofs;
    FullMatrix<double>                   local, transposed;
    dealii::Vector<double>               local_residual;
    double                               potential = 0;

    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        values.reinit(f.cell, f.face);
        const auto        &fv = values.get_present_fe_values();
        const unsigned int n1 = fv.dofs_per_cell;
        dofs.resize(n1);
        f.cell->get_dof_indices(dofs);
        u_minus.resize(fv.n_quadrature_points);
        fv[disp].get_function_values(u, u_minus);
        const FEFaceValuesBase<dim> *pv = nullptr;
        unsigned int                 n2 = 0;
        if (f.deformable)
          {
            partner_values.reinit(f.partner, f.partner_face);
            pv = &partner_values.get_present_fe_values();
            n2 = pv->dofs_per_cell;
            partner_dofs.resize(n2);
            f.partner->get_dof_indices(partner_dofs);
            u_plus.resize(pv->n_quadrature_points);
            (*pv)[disp].get_function_values(u, u_plus);
            dofs.insert(dofs.end(), partner_dofs.begin(), partner_dofs.end());
          }
        const unsigned int n = n1 + n2;
        local_residual.reinit(n);
        if (matrix)
          local.reinit(n, n);

        // Shape function i: component, value at point q, sign (+1 on the
        // "-" side, -1 on its partner).
        auto shape = [&](const unsigned int i, const unsigned int q) {
          if (i < n1)
            return std::make_pair(
              fv.get_fe().system_to_component_index(i).first,
              fv.shape_value(i, q));
          const unsigned int k = i - n1;
          return std::make_pair(pv->get_fe().system_to_component_index(k).first,
                                -pv->shape_value(k, f.permutation[q]));
        };
        for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
          {
            Tensor<1, dim> j = u_minus[q];
            if (f.deformable)
              j -= u_plus[f.permutation[q]];
            const auto   r   = respond(cl, j, fv.normal_vector(q));
            const double JxW = fv.JxW(q);
            potential +=
              contact::h_eta_integral(r.gap, cl.eta) / cl.alpha * JxW;
            for (unsigned int i = 0; i < n; ++i)
              {
                const auto [ci, vi] = shape(i, q);
                if (vi == 0)
                  continue;
                local_residual(i) += r.t[ci] * vi * JxW;
                if (matrix)
                  for (unsigned int k = 0; k < n; ++k)
                    {
                      const auto [ck, vk] = shape(k, q);
                      local(i, k) += r.dt_dj[ci][ck] * vi * vk * JxW;
                    }
              }
          }
        if (matrix && transpose)
          {
            transposed.reinit(n, n);
            transposed.copy_transposed(local);
            constraints.distribute_local_to_global(
              transposed, local_residual, dofs, *matrix, residual);
          }
        else if (matrix)
          constraints.distribute_local_to_global(
            local, local_residual, dofs, *matrix, residual);
        else
          constraints.distribute_local_to_global(local_residual,
                                                 dofs,
                                                 residual);
        if (raw)
          for (unsigned int i = 0; i < n; ++i)
            (*raw)(dofs[i]) += local_residual(i);
      }
    return potential;
  }



  template <int dim>
  void
  PenaltyContact<dim>::add_shape_products(
    const hp::MappingCollection<dim> &mapping,
    const Vector_t                   &u,
    const Vector_t                   &p,
    const DoFHandler<dim>            &shape_dof_handler,
    const AffineConstraints<double>  &shape_constraints,
    Vector_t                         &gradient) const
  {
    if (faces.empty())
      return;
    const FEValuesExtractors::Vector     disp(0);
    hp::FEFaceValues<dim>                values(mapping,
                                 *fe,
                                 quadrature,
                                 update_values | update_JxW_values |
                                   update_normal_vectors);
    hp::FEFaceValues<dim>                partner_values(mapping,
                                         *fe,
                                         quadrature,
                                         update_values);
    const hp::FECollection<dim>          shape_fe(shape_dof_handler.get_fe());
    hp::FEFaceValues<dim>                shape_values(mapping,
                                       shape_fe,
                                       quadrature,
                                       update_gradients);
    const unsigned int                   ns = shape_fe[0].n_dofs_per_cell();
    dealii::Vector<double>               local(ns);
    std::vector<types::global_dof_index> shape_dofs(ns);
    std::vector<Tensor<1, dim>>          u_minus, u_plus, p_minus, p_plus;

    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        values.reinit(f.cell, f.face);
        const auto &fv = values.get_present_fe_values();
        const typename DoFHandler<dim>::active_cell_iterator shape_cell(
          &f.cell->get_triangulation(),
          f.cell->level(),
          f.cell->index(),
          &shape_dof_handler);
        shape_values.reinit(
          shape_cell, f.face, f.cell->active_fe_index(), 0, 0);
        const auto &sv = shape_values.get_present_fe_values();
        shape_cell->get_dof_indices(shape_dofs);
        const unsigned int nq = fv.n_quadrature_points;
        u_minus.resize(nq);
        p_minus.resize(nq);
        fv[disp].get_function_values(u, u_minus);
        fv[disp].get_function_values(p, p_minus);
        if (f.deformable)
          {
            partner_values.reinit(f.partner, f.partner_face);
            const auto &pv = partner_values.get_present_fe_values();
            u_plus.resize(nq);
            p_plus.resize(nq);
            pv[disp].get_function_values(u, u_plus);
            pv[disp].get_function_values(p, p_plus);
          }
        local = 0;
        for (unsigned int q = 0; q < nq; ++q)
          {
            Tensor<1, dim> j = u_minus[q], r = p_minus[q];
            if (f.deformable)
              {
                j -= u_plus[f.permutation[q]];
                r -= p_plus[f.permutation[q]];
              }
            const Tensor<1, dim> &nrm = fv.normal_vector(q);
            const auto            c   = respond(cl, j, nrm);
            // d(t . r ds) = (r^T dt/dn) dn ds + t . r div_S theta ds with
            // dn = -(I - n n^T) grad theta^T n (transported u, p).
            Tensor<1, dim> w;
            for (unsigned int k = 0; k < dim; ++k)
              for (unsigned int m = 0; m < dim; ++m)
                w[m] += r[k] * c.dt_dn[k][m];
            const double tr = c.t * r, wn = w * nrm;
            for (unsigned int a = 0; a < ns; ++a)
              {
                const unsigned int cmp =
                  shape_fe[0].system_to_component_index(a).first;
                const Tensor<1, dim> &dN  = sv.shape_grad(a, q);
                const double          dNn = dN * nrm;
                local(a) += (-nrm[cmp] * (w * dN - wn * dNn) +
                             tr * (dN[cmp] - nrm[cmp] * dNn)) *
                            fv.JxW(q);
              }
          }
        shape_constraints.distribute_local_to_global(local,
                                                     shape_dofs,
                                                     gradient);
      }
  }



  template <int dim>
  nlohmann::json
  PenaltyContact<dim>::statistics(const hp::MappingCollection<dim> &mapping,
                                  const Vector_t                   &u,
                                  const MPI_Comm                    comm) const
  {
    struct Sums
    {
      Tensor<1, dim> force;
      double         area = 0, active = 0, penetration = -1e300, slip = 0;
    };
    std::map<types::boundary_id, Sums> sums;
    for (const auto *m : {&parameters.rigid, &parameters.deformable})
      for (const auto &[id, law] : *m)
        sums[id];
    const FEValuesExtractors::Vector disp(0);
    hp::FEFaceValues<dim>            values(mapping,
                                 *fe,
                                 quadrature,
                                 update_values | update_JxW_values |
                                   update_normal_vectors);
    hp::FEFaceValues<dim>            partner_values(mapping,
                                         *fe,
                                         quadrature,
                                         update_values);
    std::vector<Tensor<1, dim>>      u_minus, u_plus;
    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        values.reinit(f.cell, f.face);
        const auto &fv = values.get_present_fe_values();
        u_minus.resize(fv.n_quadrature_points);
        fv[disp].get_function_values(u, u_minus);
        if (f.deformable)
          {
            partner_values.reinit(f.partner, f.partner_face);
            u_plus.resize(fv.n_quadrature_points);
            partner_values.get_present_fe_values()[disp].get_function_values(
              u, u_plus);
          }
        Sums &s = sums[f.id];
        for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
          {
            Tensor<1, dim> j = u_minus[q];
            if (f.deformable)
              j -= u_plus[f.permutation[q]];
            const auto r = respond(cl, j, fv.normal_vector(q));
            s.force -= r.t * fv.JxW(q);
            s.area += fv.JxW(q);
            s.penetration = std::max(s.penetration, r.gap);
            if (r.gap > -cl.eta)
              {
                s.active += fv.JxW(q);
                s.slip = std::max(s.slip, r.slip.norm());
              }
          }
      }
    nlohmann::json result = nlohmann::json::array();
    for (auto &[id, s] : sums)
      {
        nlohmann::json e;
        e["boundary"] = id;
        e["type"]     = parameters.rigid.count(id) ? "rigid-deformable" :
                                                     "deformable-deformable";
        std::vector<double> force(dim);
        for (unsigned int d = 0; d < dim; ++d)
          force[d] = Utilities::MPI::sum(s.force[d], comm);
        e["force"]           = force;
        e["area"]            = Utilities::MPI::sum(s.area, comm);
        e["active_area"]     = Utilities::MPI::sum(s.active, comm);
        e["max_penetration"] = Utilities::MPI::max(s.penetration, comm);
        e["max_slip"]        = Utilities::MPI::max(s.slip, comm);
        result.push_back(e);
      }
    return result;
  }

  template class PenaltyContact<2>;
  template class PenaltyContact<3>;
} // namespace forma
