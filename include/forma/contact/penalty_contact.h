#ifndef forma_contact_penalty_contact_h
#define forma_contact_penalty_contact_h

#include <deal.II/base/quadrature.h>
#include <deal.II/base/table.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/fe_collection.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/hp/q_collection.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/contact/contact_parameters.h>

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <vector>

namespace dealii
{
  template <int dim>
  class FunctionParser;
}

namespace forma
{
  /**
   * Smoothed penalty contact and friction as a form of the discrete problem
   * h(u, q) = 0 (thesis eqs. 2.9-2.13): per contact point the traction
   *   t(j, n) = h_eta(j . n) / alpha (n + mu N_eta'(j - (j . n) n))
   * with j = u (RD) or j = u^- - u^+ (DD, n = n^- the outer normal of the
   * side with the lower material id), added as  int t . [w] ds  to the
   * residual. The friction term uses the total tangential displacement of
   * the static problem (eq. 2.12). Derivatives in j and n come from
   * forward AD of t, so the Jacobian (eq. 2.26 terms), the adjoint products
   * p^T d_x h theta on the shape field (eqs. 2.27 S_C..S_SF, in the
   * transport form that is exact for the discrete problem) and the
   * potential (frictionless) use one definition of t.
   *
   * DD sides must be conforming: every quadrature point of a face finds a
   * coincident one on its partner (checked at setup).
   */
  template <int dim>
  class PenaltyContact
  {
  public:
    using Vector_t = dealii::TrilinosWrappers::MPI::Vector;

    PenaltyContact(const ContactParameters &parameters);
    ~PenaltyContact();

    /// Find the contact faces and pair the DD sides, on the mesh as read.
    /// Throws with a message if a boundary id is missing or a side has no
    /// partner. Every rank must hold all cells (shared triangulation).
    void
    setup(const dealii::DoFHandler<dim>            &dof_handler,
          const dealii::hp::MappingCollection<dim> &mapping,
          const dealii::hp::QCollection<dim - 1>   &face_quadrature);

    /// Whether any rank has contact faces (the same on every rank).
    bool
    active() const
    {
      return any_faces;
    }

    /// Whether the Jacobian is unsymmetric (friction).
    bool
    has_friction() const
    {
      return parameters.has_friction();
    }

    /// Add the couplings of paired DD cells to a sparsity pattern.
    void
    add_couplings(const dealii::AffineConstraints<double>   &constraints,
                  dealii::TrilinosWrappers::SparsityPattern &pattern) const;

    /**
     * Add the contact residual (and Jacobian, transposed if asked) of the
     * locally owned contact faces at the state `u` (ghosted); `raw` gets the
     * residual without constraints. Returns the local part of the penalty
     * potential int H_eta(j . n) / alpha ds (meaningful without friction).
     * `evaluated` is false where the adaptive rule could not pair the
     * points of a DD face (a state too distorted: take a shorter step).
     */
    double
    assemble(const dealii::hp::MappingCollection<dim> &mapping,
             const Vector_t                           &u,
             const dealii::AffineConstraints<double>  &constraints,
             const bool                                transpose,
             dealii::TrilinosWrappers::SparseMatrix   *matrix,
             Vector_t                                 &residual,
             Vector_t                                 *raw,
             bool                                     &evaluated) const;

    /**
     * Add p^T (d h / d x) theta_a for every shape DoF a of the vector Q1/P1
     * shape field (the adjoint product of the shape derivative) at the
     * state `u` and adjoint `p` (both ghosted) to `gradient`.
     */
    void
    add_shape_products(
      const dealii::hp::MappingCollection<dim> &mapping,
      const Vector_t                           &u,
      const Vector_t                           &p,
      const dealii::DoFHandler<dim>            &shape_dof_handler,
      const dealii::AffineConstraints<double>  &shape_constraints,
      Vector_t                                 &gradient) const;

    /**
     * Per contact boundary: the force the contact exerts on the body (RD)
     * or on the side with the lower material id (DD), the largest
     * penetration j . n, the measure of the active set (h_eta > 0) and the
     * largest tangential slip there. Collective.
     */
    nlohmann::json
    statistics(const dealii::hp::MappingCollection<dim> &mapping,
               const Vector_t                           &u,
               const MPI_Comm                            comm) const;

    /// The obstacle's initial distance (Contact/Rigid gaps) of RD boundary
    /// `id` at the boundary point x; 0 for boundaries without a gap.
    double
    initial_gap(const dealii::types::boundary_id id,
                const dealii::Point<dim>        &x) const;

    /// The contact traction t (force per area on the obstacle; the body
    /// gets -t) of RD boundary `id` at the point x with displacement u and
    /// outer normal n: sigma n + t = 0 holds there for the exact solution.
    dealii::Tensor<1, dim>
    rigid_traction(const dealii::types::boundary_id id,
                   const dealii::Point<dim>        &x,
                   const dealii::Tensor<1, dim>    &u,
                   const dealii::Tensor<1, dim>    &n) const;

    /// Whether the problem has gaps (Contact/Rigid gaps).
    bool
    has_gaps() const
    {
      return !gaps.empty();
    }

    const ContactParameters parameters;

  private:
    struct Face
    {
      typename dealii::DoFHandler<dim>::active_cell_iterator cell, partner;
      unsigned int               face = 0, partner_face = 0;
      dealii::types::boundary_id id;
      bool                       deformable = false;
      /// Partner quadrature point of each point of `face`.
      std::vector<unsigned int> permutation;
      /// The reference points of `cell` and (DD) of `partner` at the
      /// face's corners xi = 0, e_1, ..., e_{dim-1}: face points are affine
      /// in xi on both sides (empty partner_corners: inverse mapping).
      std::vector<dealii::Point<dim>> corners, partner_corners;
      double orientation = 1; ///< makes the corners' normal outward
    };
    /// Values at the quadrature points of a contact face: signed shape
    /// values of both sides (partner negative), the nodal values of the
    /// state, weights and normals of the "-" side.
    struct FaceData
    {
      dealii::Quadrature<dim - 1>                  quadrature; ///< "-" face
      std::vector<dealii::types::global_dof_index> dofs, partner_dofs;
      std::vector<unsigned int>                    component;
      std::vector<double>                          values;
      dealii::Table<2, double> phi; ///< [dof][point], reused across faces
      std::vector<double>      JxW;
      std::vector<dealii::Tensor<1, dim>> normal;
      std::vector<double> gap0;         ///< the obstacle's initial gap (RD)
      bool                valid = true; ///< false: partner points not found

      /// u^- - u^+ (RD: u) at point q.
      dealii::Tensor<1, dim>
      jump(const unsigned int q) const;
    };

    /// FE face values of both sides for the Gauss rules, made once per pass.
    struct GaussValues;

    /// A boundary face of a DD interface, before pairing.
    struct Side
    {
      dealii::Point<dim>                                     center;
      typename dealii::DoFHandler<dim>::active_cell_iterator cell;
      unsigned int                                           face;
      double                                                 size;
    };

    /// Setup: every contact boundary id is on the mesh.
    void
    check_boundary_ids(const dealii::DoFHandler<dim> &dof_handler) const;

    /// Setup: the RD faces of owned cells into `faces`; the DD sides.
    std::vector<Side>
    collect_faces(const dealii::DoFHandler<dim> &dof_handler);

    /// Setup: pair coincident DD sides (throws on a side without partner
    /// or non-matching points) and add the "-" sides of owned cells.
    void
    pair_deformable_sides(std::vector<Side>                         sides,
                          const dealii::hp::MappingCollection<dim> &mapping,
                          const MPI_Comm                            comm);

    /// Setup: the faces' corner frames and outward orientation.
    void
    set_face_frames(const dealii::hp::MappingCollection<dim> &mapping);

    /// Face data of `f` at the state `u`: the Gauss rule of the element, or
    /// the adaptive rule for the state's contact regimes.
    void
    evaluate(const Face                               &f,
             const dealii::hp::MappingCollection<dim> &mapping,
             const Vector_t                           &u,
             GaussValues                              &gauss,
             FaceData                                 &d) const;

    /// evaluate(): the dofs of both sides, their components and values.
    void
    gather_dofs(const Face &f, const Vector_t &u, FaceData &d) const;

    /// evaluate() with the element's Gauss rule: FE face values of both
    /// sides (the partner's points by the face permutation).
    void
    gauss_values(const Face &f, GaussValues &gauss, FaceData &d) const;

    /// evaluate() at the reference face points `q` (the adaptive rule):
    /// the "-" side's values, normals and weights by the face's corners,
    /// the partner's at the same physical points.
    void
    values_at(const Face                               &f,
              const dealii::hp::MappingCollection<dim> &mapping,
              const dealii::Quadrature<dim - 1>        &q,
              FaceData                                 &d) const;

    /// values_at(): the partner's shape values at the "-" side's points
    /// `x` (affine where the faces' corners coincide, else by inverse
    /// mapping; d.valid is false where a point is not found).
    void
    partner_values_at(const Face                               &f,
                      const dealii::hp::MappingCollection<dim> &mapping,
                      const dealii::Quadrature<dim - 1>        &q,
                      const std::vector<dealii::Point<dim>>    &x,
                      FaceData                                 &d) const;

    std::map<dealii::types::boundary_id,
             std::unique_ptr<dealii::FunctionParser<dim>>>
                                         gaps;  ///< Contact/Rigid gaps
    std::vector<Face>                    faces; ///< of locally owned cells
    bool                                 any_faces = false;
    const dealii::hp::FECollection<dim> *fe        = nullptr;
    dealii::hp::QCollection<dim - 1>     quadrature;

    const ContactLaw &
    law(const Face &f) const;
  };
} // namespace forma

#endif
