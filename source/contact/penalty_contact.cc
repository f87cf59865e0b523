#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/base/records.h>
#include <forma/contact/adaptive_quadrature.h>
#include <forma/contact/penalty_contact.h>
#include <forma/contact/smoothing.h>

#include <Sacado.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <set>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /**
     * The reference points of `target` at the corners 0, e_1, ...,
     * e_{dim-1} of a face's reference face, the corners' physical points
     * given by `corner_values` (reinit on that face, so FEFaceValues's own
     * handling of face orientations is the one used). The reference face's
     * symmetries are affine, so where the corners coincide with vertices of
     * `target` (the face's own cell, or the partner on a conforming
     * interface) the point of face coordinates xi is
     * c_0 + sum_j xi_j (c_j - c_0). Empty if a corner has no coincident
     * vertex or the map is not affine.
     */
    template <int dim, typename Iterator>
    std::vector<Point<dim>>
    face_corners(const FEFaceValues<dim> &corner_values,
                 const Mapping<dim>      &mapping,
                 const Iterator          &target,
                 const double             tol)
    {
      const ReferenceCell     type = target->reference_cell();
      std::vector<Point<dim>> result;
      for (unsigned int v = 0; v < corner_values.n_quadrature_points; ++v)
        for (const unsigned int w : type.vertex_indices())
          {
            const Point<dim> x = type.template vertex<dim>(w);
            if (mapping.transform_unit_to_real_cell(target, x).distance(
                  corner_values.quadrature_point(v)) <= tol)
              {
                result.push_back(x);
                break;
              }
          }
      if (result.size() != corner_values.n_quadrature_points)
        return {};
      // A quadrilateral's fourth corner must follow from the other three.
      if (result.size() == 4 &&
          (result[3] - (result[1] + (result[2] - result[0]))).norm() > 1e-12)
        return {};
      result.resize(dim);
      return result;
    }



    /// The cell points of face points `q` for corners `c` (face_corners()).
    template <int dim>
    Quadrature<dim>
    cell_points(const std::vector<Point<dim>> &c, const Quadrature<dim - 1> &q)
    {
      std::vector<Point<dim>> x(q.size(), c[0]);
      for (unsigned int k = 0; k < q.size(); ++k)
        for (unsigned int j = 0; j + 1 < c.size(); ++j)
          x[k] += q.point(k)[j] * (c[j + 1] - c[0]);
      return Quadrature<dim>(x);
    }



    /// The face's normal scaled by its area element, from the cell's
    /// Jacobian J and the face's corners `c`: the cross product of the
    /// tangents J (c_j - c_0) (its sign is the corners' orientation).
    template <int dim>
    Tensor<1, dim>
    area_normal(const DerivativeForm<1, dim, dim> &J,
                const std::vector<Point<dim>>     &c)
    {
      std::array<Tensor<1, dim>, dim - 1> t;
      for (unsigned int j = 0; j + 1 < dim; ++j)
        t[j] = apply_transformation(J, c[j + 1] - c[0]);
      if constexpr (dim == 2)
        return cross_product_2d(t[0]);
      else
        return cross_product_3d(t[0], t[1]);
    }



    /// The contact traction at one point and its partial derivatives.
    template <int dim>
    struct PointResponse
    {
      Tensor<1, dim> t;
      Tensor<2, dim> dt_dj, dt_dn; ///< [k][m] = d t_k / d j_m, d n_m
      double         gap = 0;      ///< j . n - gap0 (penetration > 0)
      Tensor<1, dim> slip;         ///< tangential part of j
    };

    template <int dim>
    PointResponse<dim>
    respond(const ContactLaw     &law,
            const Tensor<1, dim> &j,
            const Tensor<1, dim> &n,
            const double          gap0)
    {
      using AD = Sacado::Fad::SFad<double, 2 * dim>;
      std::array<AD, dim> J, N, s;
      for (unsigned int d = 0; d < dim; ++d)
        {
          J[d] = AD(2 * dim, d, j[d]);
          N[d] = AD(2 * dim, dim + d, n[d]);
        }
      AD g = -gap0;
      for (unsigned int d = 0; d < dim; ++d)
        g += J[d] * N[d];
      const AD h  = contact::h_eta(g, law.eta) / law.alpha;
      AD       f  = 0.;
      AD       r2 = 0.;
      for (unsigned int d = 0; d < dim; ++d)
        {
          s[d] = J[d] - (g + gap0) * N[d];
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
  {
    for (const auto &[id, expression] : parameters.rigid_gaps)
      gaps[id] = make_function<dim>({expression},
                                    {true},
                                    {},
                                    "Contact/Rigid gaps, boundary id " +
                                      std::to_string(id));
  }



  template <int dim>
  PenaltyContact<dim>::~PenaltyContact() = default;



  template <int dim>
  double
  PenaltyContact<dim>::initial_gap(const types::boundary_id id,
                                   const Point<dim>        &x) const
  {
    const auto g = gaps.find(id);
    return g == gaps.end() ? 0. : g->second->value(x);
  }



  template <int dim>
  Tensor<1, dim>
  PenaltyContact<dim>::rigid_traction(const types::boundary_id id,
                                      const Point<dim>        &x,
                                      const Tensor<1, dim>    &u,
                                      const Tensor<1, dim>    &n) const
  {
    return respond(parameters.rigid.at(id), u, n, initial_gap(id, x)).t;
  }



  template <int dim>
  const ContactLaw &
  PenaltyContact<dim>::law(const Face &f) const
  {
    return f.deformable ? parameters.deformable.at(f.id) :
                          parameters.rigid.at(f.id);
  }



  template <int dim>
  struct PenaltyContact<dim>::GaussValues
  {
    GaussValues(const hp::MappingCollection<dim> &mapping,
                const hp::FECollection<dim>      &fe,
                const hp::QCollection<dim - 1>   &quadrature)
      : minus(mapping,
              fe,
              quadrature,
              update_values | update_JxW_values | update_normal_vectors |
                update_quadrature_points)
      , partner(mapping, fe, quadrature, update_values)
    {}
    hp::FEFaceValues<dim> minus, partner;
  };



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
    // Paired triangle faces meet in any of their orientations: their rule
    // must map onto itself under vertex permutations (Witherden-Vincent).
    if (dim == 3 &&
        !dof_handler.get_triangulation().all_reference_cells_are_hyper_cube())
      {
        quadrature = hp::QCollection<dim - 1>();
        for (unsigned int i = 0; i < fe->size(); ++i)
          quadrature.push_back(
            QWitherdenVincentSimplex<dim - 1>((*fe)[i].degree + 1));
      }
    if (parameters.empty())
      return;
    check_boundary_ids(dof_handler);
    pair_deformable_sides(collect_faces(dof_handler),
                          mapping,
                          dof_handler.get_communicator());
    set_face_frames(mapping);
    any_faces = Utilities::MPI::max(faces.empty() ? 0 : 1,
                                    dof_handler.get_communicator()) == 1;
  }



  template <int dim>
  void
  PenaltyContact<dim>::check_boundary_ids(
    const DoFHandler<dim> &dof_handler) const
  {
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
  }



  template <int dim>
  std::vector<typename PenaltyContact<dim>::Side>
  PenaltyContact<dim>::collect_faces(const DoFHandler<dim> &dof_handler)
  {
    // RD faces of owned cells; DD sides of every cell, paired later.
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
    return sides;
  }



  template <int dim>
  void
  PenaltyContact<dim>::pair_deformable_sides(
    std::vector<Side>                 sides,
    const hp::MappingCollection<dim> &mapping,
    const MPI_Comm                    comm)
  {
    // Sorted by face center, then paired by coincidence.
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
    // Checks of locally owned pairs fail on one rank only: collect the
    // message and throw on every rank after the loop.
    std::string failure;
    for (unsigned int a = 0; a < sides.size() && failure.empty(); ++a)
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
        if (m.cell->active_fe_index() != o.cell->active_fe_index())
          {
            failure = "Contact: the two sides of a deformable-deformable "
                      "interface need the same element degree.";
            break;
          }
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
            if (x[q].distance(y[best]) > 1e-8 * m.size)
              failure = "Contact: the quadrature points of two paired "
                        "deformable-deformable faces do not coincide "
                        "(non-matching interface).";
            face.permutation.push_back(best);
          }
        faces.push_back(face);
      }
    for (const auto &message : Utilities::MPI::all_gather(comm, failure))
      AssertThrow(message.empty(), ExcMessage(message));
  }



  template <int dim>
  void
  PenaltyContact<dim>::set_face_frames(
    const hp::MappingCollection<dim> &mapping)
  {
    // Face frames: the cells' reference points at the faces' corners,
    // with the sign that makes the corners' normal outward.
    std::map<std::pair<unsigned int, std::uint8_t>,
             std::unique_ptr<FEFaceValues<dim>>>
      corner_values;
    for (auto &face : faces)
      {
        const ReferenceCell type = face.cell->face(face.face)->reference_cell();
        auto &cv = corner_values[{face.cell->active_fe_index(), type}];
        if (!cv)
          {
            std::vector<Point<dim - 1>> corners(type.n_vertices());
            for (unsigned int v = 0; v < corners.size(); ++v)
              corners[v] = type.template vertex<dim - 1>(v);
            cv =
              std::make_unique<FEFaceValues<dim>>(mapping[0],
                                                  face.cell->get_fe(),
                                                  Quadrature<dim - 1>(corners),
                                                  update_quadrature_points |
                                                    update_normal_vectors |
                                                    update_jacobians);
          }
        cv->reinit(face.cell, face.face);
        const double tol = 1e-8 * face.cell->face(face.face)->diameter();
        face.corners     = face_corners(*cv, mapping[0], face.cell, tol);
        AssertThrow(!face.corners.empty(), ExcInternalError());
        face.orientation =
          area_normal(cv->jacobian(0), face.corners) * cv->normal_vector(0) <
              0 ?
            -1. :
            1.;
        if (face.deformable)
          face.partner_corners =
            face_corners(*cv, mapping[0], face.partner, tol);
      }
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
  void
  PenaltyContact<dim>::gather_dofs(const Face     &f,
                                   const Vector_t &u,
                                   FaceData       &d) const
  {
    const auto        &fe1 = f.cell->get_fe();
    const unsigned int n1  = fe1.n_dofs_per_cell();
    const unsigned int n2 =
      f.deformable ? f.partner->get_fe().n_dofs_per_cell() : 0;
    d.dofs.resize(n1);
    f.cell->get_dof_indices(d.dofs);
    if (f.deformable)
      {
        d.partner_dofs.resize(n2);
        f.partner->get_dof_indices(d.partner_dofs);
        d.dofs.insert(d.dofs.end(),
                      d.partner_dofs.begin(),
                      d.partner_dofs.end());
      }
    d.component.resize(n1 + n2);
    for (unsigned int i = 0; i < n1 + n2; ++i)
      d.component[i] = (i < n1 ? fe1 : f.partner->get_fe())
                         .system_to_component_index(i < n1 ? i : i - n1)
                         .first;
    d.values.resize(n1 + n2);
    for (unsigned int i = 0; i < n1 + n2; ++i)
      d.values[i] = u(d.dofs[i]);
    d.valid = true;
  }



  template <int dim>
  void
  PenaltyContact<dim>::gauss_values(const Face  &f,
                                    GaussValues &gauss,
                                    FaceData    &d) const
  {
    const unsigned int n1 = f.cell->get_fe().n_dofs_per_cell();
    const unsigned int n2 = d.dofs.size() - n1;
    d.quadrature          = quadrature[f.cell->active_fe_index()];
    gauss.minus.reinit(f.cell, f.face);
    const auto        &fv = gauss.minus.get_present_fe_values();
    const unsigned int nq = fv.n_quadrature_points;
    d.phi.reinit(n1 + n2, nq);
    for (unsigned int i = 0; i < n1; ++i)
      for (unsigned int k = 0; k < nq; ++k)
        d.phi[i][k] = fv.shape_value(i, k);
    d.normal = fv.get_normal_vectors();
    d.JxW    = fv.get_JxW_values();
    d.gap0.resize(nq);
    for (unsigned int k = 0; k < nq; ++k)
      d.gap0[k] = f.deformable ? 0. : initial_gap(f.id, fv.quadrature_point(k));
    if (f.deformable)
      {
        gauss.partner.reinit(f.partner, f.partner_face);
        const auto &pv = gauss.partner.get_present_fe_values();
        for (unsigned int i = 0; i < n2; ++i)
          for (unsigned int k = 0; k < nq; ++k)
            d.phi[n1 + i][k] = -pv.shape_value(i, f.permutation[k]);
      }
  }



  template <int dim>
  void
  PenaltyContact<dim>::values_at(const Face                       &f,
                                 const hp::MappingCollection<dim> &mapping,
                                 const Quadrature<dim - 1>        &q,
                                 FaceData                         &d) const
  {
    // Mapped into the cell by the face's corners: an FEFaceValues would be
    // built for every face and orientation.
    const auto        &fe1 = f.cell->get_fe();
    const unsigned int n1  = fe1.n_dofs_per_cell();
    FEValues<dim>      fv(mapping[0],
                     fe1,
                     cell_points(f.corners, q),
                     update_values | update_quadrature_points |
                       update_jacobians);
    fv.reinit(f.cell);
    const unsigned int nq = q.size();
    d.phi.reinit(d.dofs.size(), nq);
    for (unsigned int i = 0; i < n1; ++i)
      for (unsigned int k = 0; k < nq; ++k)
        d.phi[i][k] = fv.shape_value(i, k);
    d.normal.resize(nq);
    d.JxW.resize(nq);
    d.gap0.resize(nq);
    for (unsigned int k = 0; k < nq; ++k)
      {
        d.gap0[k] =
          f.deformable ? 0. : initial_gap(f.id, fv.quadrature_point(k));
        const Tensor<1, dim> a =
          f.orientation * area_normal(fv.jacobian(k), f.corners);
        d.normal[k] = a / a.norm();
        d.JxW[k]    = q.weight(k) * a.norm();
      }
    if (f.deformable)
      partner_values_at(f, mapping, q, fv.get_quadrature_points(), d);
  }



  template <int dim>
  void
  PenaltyContact<dim>::partner_values_at(
    const Face                       &f,
    const hp::MappingCollection<dim> &mapping,
    const Quadrature<dim - 1>        &q,
    const std::vector<Point<dim>>    &x,
    FaceData                         &d) const
  {
    const unsigned int nq = q.size();
    const unsigned int n1 = f.cell->get_fe().n_dofs_per_cell();
    const unsigned int n2 = d.dofs.size() - n1;
    // Affine in the face coordinates where the faces' corners coincide
    // (checked on the physical points, since the two copies' shape could
    // differ), else by inverse mapping.
    const auto                    &c = f.partner_corners;
    std::unique_ptr<FEValues<dim>> pv;
    bool                           paired = !c.empty();
    if (paired)
      {
        pv = std::make_unique<FEValues<dim>>(mapping[0],
                                             f.partner->get_fe(),
                                             cell_points(c, q),
                                             update_values |
                                               update_quadrature_points);
        pv->reinit(f.partner);
        const double tol = 1e-8 * f.cell->face(f.face)->diameter();
        for (unsigned int k = 0; k < nq && paired; ++k)
          paired = pv->quadrature_point(k).distance(x[k]) <= tol;
      }
    if (!paired)
      {
        std::vector<Point<dim>> unit(nq);
        mapping[0].transform_points_real_to_unit_cell(f.partner, x, unit);
        // A point the inverse mapping did not find (+inf) or outside the
        // partner: the interface is too distorted to pair points.
        for (auto &xi : unit)
          if (!std::isfinite(xi[0]) ||
              !f.partner->reference_cell().contains_point(xi, 1e-6))
            {
              d.valid = false;
              xi      = f.partner->reference_cell().template vertex<dim>(0);
            }
        pv = std::make_unique<FEValues<dim>>(mapping[0],
                                             f.partner->get_fe(),
                                             Quadrature<dim>(unit),
                                             update_values);
        pv->reinit(f.partner);
      }
    for (unsigned int i = 0; i < n2; ++i)
      for (unsigned int k = 0; k < nq; ++k)
        d.phi[n1 + i][k] = -pv->shape_value(i, k);
  }



  template <int dim>
  void
  PenaltyContact<dim>::evaluate(const Face                       &f,
                                const hp::MappingCollection<dim> &mapping,
                                const Vector_t                   &u,
                                GaussValues                      &gauss,
                                FaceData                         &d) const
  {
    gather_dofs(f, u, d);
    if (parameters.quadrature == "gauss")
      {
        // The elements' rule, with FE values made once per pass.
        gauss_values(f, gauss, d);
        return;
      }
    // Adaptive rule: refined where the state's contact regime changes.
    const ContactLaw &cl       = law(f);
    const bool        friction = cl.mu > 0;
    auto              regime   = [&](const std::vector<Point<dim - 1>> &x) {
      values_at(f, mapping, Quadrature<dim - 1>(x), d);
      std::vector<int> codes(x.size());
      for (unsigned int k = 0; k < x.size(); ++k)
        {
          const Tensor<1, dim> j     = d.jump(k);
          const double         jn    = j * d.normal[k];
          const double         gap   = jn - d.gap0[k];
          const double         slip2 = j * j - jn * jn;
          codes[k]                   = contact::contact_regime(
            gap, std::sqrt(std::max(slip2, 0.)), cl.eta, cl.eta_n, friction);
        }
      return codes;
    };
    const bool simplex =
      f.cell->face(f.face)->reference_cell().is_simplex() && dim == 3;
    d.quadrature =
      contact::adaptive_quadrature<dim - 1>(simplex,
                                            regime,
                                            parameters.gauss_points,
                                            parameters.adaptive_depth,
                                            parameters.samples);
    values_at(f, mapping, d.quadrature, d);
  }



  template <int dim>
  Tensor<1, dim>
  PenaltyContact<dim>::FaceData::jump(const unsigned int q) const
  {
    Tensor<1, dim> j;
    for (unsigned int i = 0; i < values.size(); ++i)
      j[component[i]] += values[i] * phi[i][q];
    return j;
  }



  template <int dim>
  double
  PenaltyContact<dim>::assemble(const hp::MappingCollection<dim> &mapping,
                                const Vector_t                   &u,
                                const AffineConstraints<double>  &constraints,
                                const bool                        transpose,
                                TrilinosWrappers::SparseMatrix   *matrix,
                                Vector_t                         &residual,
                                Vector_t                         *raw,
                                bool &evaluated) const
  {
    evaluated = true;
    FaceData               d;
    GaussValues            gauss(mapping, *fe, quadrature);
    FullMatrix<double>     local, transposed;
    dealii::Vector<double> local_residual;
    double                 potential = 0;
    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        evaluate(f, mapping, u, gauss, d);
        evaluated &= d.valid;
        const unsigned int n = d.dofs.size();
        local_residual.reinit(n);
        if (matrix)
          local.reinit(n, n);
        for (unsigned int q = 0; q < d.JxW.size(); ++q)
          {
            const auto   r   = respond(cl, d.jump(q), d.normal[q], d.gap0[q]);
            const double JxW = d.JxW[q];
            potential +=
              contact::h_eta_integral(r.gap, cl.eta) / cl.alpha * JxW;
            for (unsigned int i = 0; i < n; ++i)
              {
                const double vi = d.phi[i][q];
                if (vi == 0)
                  continue;
                const unsigned int ci = d.component[i];
                local_residual(i) += r.t[ci] * vi * JxW;
                if (matrix)
                  for (unsigned int k = 0; k < n; ++k)
                    local(i, k) +=
                      r.dt_dj[ci][d.component[k]] * vi * d.phi[k][q] * JxW;
              }
          }
        if (matrix && transpose)
          {
            transposed.reinit(n, n);
            transposed.copy_transposed(local);
            constraints.distribute_local_to_global(
              transposed, local_residual, d.dofs, *matrix, residual);
          }
        else if (matrix)
          constraints.distribute_local_to_global(
            local, local_residual, d.dofs, *matrix, residual);
        else
          constraints.distribute_local_to_global(local_residual,
                                                 d.dofs,
                                                 residual);
        if (raw)
          for (unsigned int i = 0; i < n; ++i)
            (*raw)(d.dofs[i]) += local_residual(i);
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
    const auto                          &shape_fe = shape_dof_handler.get_fe();
    const unsigned int                   ns       = shape_fe.n_dofs_per_cell();
    dealii::Vector<double>               local(ns);
    std::vector<types::global_dof_index> shape_dofs(ns);
    FaceData                             d;
    GaussValues                          gauss(mapping, *fe, quadrature);
    std::vector<double>                  adjoint;
    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        evaluate(f, mapping, u, gauss, d);
        // The adjoint's jump from the same shape values.
        adjoint.resize(d.dofs.size());
        for (unsigned int i = 0; i < d.dofs.size(); ++i)
          adjoint[i] = p(d.dofs[i]);
        const typename DoFHandler<dim>::active_cell_iterator shape_cell(
          &f.cell->get_triangulation(),
          f.cell->level(),
          f.cell->index(),
          &shape_dof_handler);
        FEValues<dim> sv(mapping[0],
                         shape_fe,
                         cell_points(f.corners, d.quadrature),
                         update_gradients);
        sv.reinit(shape_cell);
        shape_cell->get_dof_indices(shape_dofs);
        local = 0;
        for (unsigned int q = 0; q < d.JxW.size(); ++q)
          {
            Tensor<1, dim> r;
            for (unsigned int i = 0; i < d.dofs.size(); ++i)
              r[d.component[i]] += adjoint[i] * d.phi[i][q];
            const Tensor<1, dim> &nrm = d.normal[q];
            const auto            c   = respond(cl, d.jump(q), nrm, d.gap0[q]);
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
                  shape_fe.system_to_component_index(a).first;
                const Tensor<1, dim> &dN  = sv.shape_grad(a, q);
                const double          dNn = dN * nrm;
                local(a) += (-nrm[cmp] * (w * dN - wn * dNn) +
                             tr * (dN[cmp] - nrm[cmp] * dNn)) *
                            d.JxW[q];
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
      double area = 0, active = 0, penetration = -1e300, slip = 0, pressure = 0;
    };
    std::map<types::boundary_id, Sums> sums;
    for (const auto *m : {&parameters.rigid, &parameters.deformable})
      for (const auto &[id, law] : *m)
        sums[id];
    FaceData    d;
    GaussValues gauss(mapping, *fe, quadrature);
    for (const auto &f : faces)
      {
        const ContactLaw &cl = law(f);
        evaluate(f, mapping, u, gauss, d);
        Sums &s = sums[f.id];
        for (unsigned int q = 0; q < d.JxW.size(); ++q)
          {
            const auto r = respond(cl, d.jump(q), d.normal[q], d.gap0[q]);
            s.force -= r.t * d.JxW[q];
            s.area += d.JxW[q];
            s.penetration = std::max(s.penetration, r.gap);
            s.pressure    = std::max(s.pressure, r.t * d.normal[q]);
            if (r.gap > -cl.eta)
              {
                s.active += d.JxW[q];
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
        for (unsigned int c = 0; c < dim; ++c)
          force[c] = Utilities::MPI::sum(s.force[c], comm);
        e["force"]           = force;
        e["area"]            = Utilities::MPI::sum(s.area, comm);
        e["active_area"]     = Utilities::MPI::sum(s.active, comm);
        e["max_penetration"] = Utilities::MPI::max(s.penetration, comm);
        e["max_slip"]        = Utilities::MPI::max(s.slip, comm);
        e["max_pressure"]    = Utilities::MPI::max(s.pressure, comm);
        result.push_back(e);
      }
    return result;
  }

  template class PenaltyContact<2>;
  template class PenaltyContact<3>;
} // namespace forma
