#ifndef forma_ipc_ipc_contact_h
#define forma_ipc_ipc_contact_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/ipc/ccd.h>
#include <forma/ipc/collision_mesh.h>
#include <forma/ipc/ipc_parameters.h>

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace forma
{
  namespace ipc
  {
    /**
     * Incremental potential contact as a form of the discrete problem
     * (thesis ch. 3.6-3.7, Li et al. 2020): the potential
     *   E(u) = kappa sum_k A_k b(d_k(x + u))
     *        + sum_k mu_k N_k f_0(|T_k^T Gamma_k (u - u^{i-1})|)
     * over the primitive pairs k of the collision mesh (and the static
     * planes) closer than dhat, with lagged normal forces N_k, tangent
     * bases T_k and closest-point weights Gamma_k for friction. Its
     * gradient is added to the residual, its Hessian, with every pair's
     * block projected to positive semi-definite, to the Jacobian, and its
     * value to the Newton line search's merit; continuous collision
     * detection caps every Newton step so that no pair ever touches.
     *
     * Candidate pairs come from a sort-and-sweep broad phase over boxes of
     * the primitives swept along the step and grown by dhat; each candidate
     * is classified (point-point, point-edge, ... ) at every evaluation.
     * Candidates couple vertices anywhere in the mesh: the Jacobian's
     * sparsity pattern grows with them (update_candidates() says when).
     * Work is split over MPI ranks by candidate; every rank holds the
     * collision mesh and the displacements of its vertices.
     */
    template <int dim>
    class IpcContact
    {
    public:
      using Vector_t = dealii::TrilinosWrappers::MPI::Vector;

      explicit IpcContact(const IpcParameters &parameters);
      ~IpcContact();

      /**
       * Build the collision mesh at the current shape (`mapping`), fix dhat
       * and check the rest state: throws with the place if boundary
       * primitives intersect or touch, or a body starts on the wrong side
       * of a plane. With the shape field's DoF handler, the collision mesh
       * also knows how its rest positions follow the shape (for shape
       * derivatives); `where` names the geometry in error messages. The
       * couplings are those at rest: rebuild the Jacobian's pattern.
       * Collective.
       */
      void
      setup(const dealii::DoFHandler<dim, dim>            &dof_handler,
            const dealii::hp::MappingCollection<dim, dim> &mapping,
            const dealii::IndexSet                        &owned,
            const MPI_Comm                                 comm,
            const dealii::DoFHandler<dim, dim> *shape_dof_handler = nullptr,
            const std::string                  &where = "the mesh as read");

      /**
       * Differentiable mode (gradients and optimization, thesis ch. 3.7):
       * dhat and kappa keep the values they have (or get at the first
       * solve) for every later setup() and step, instead of following the
       * shape and the adaptive stiffness rule, so that the discrete
       * problem is one smooth function of the design.
       */
      void
      freeze();

      /**
       * @name Friction coefficients as parameters (thesis ch. 3.7: one per
       * pair of bodies)
       * Sources, in order: IPC/Friction coefficient, each Friction pairs
       * record, each obstacle (plane, then mesh) with its own coefficient.
       */
      //@{
      const std::vector<std::string> &
      friction_names() const
      {
        return source_names;
      }
      const std::vector<double> &
      friction_values() const
      {
        return source_values;
      }
      /// Set them (>= 0); pairs with a zero coefficient are then kept (their
      /// force is zero, their derivative is not).
      void
      set_friction_values(const std::vector<double> &values);
      /// Whether any pair can have friction.
      bool
      has_friction() const;
      //@}

      const CollisionMesh<dim> &
      mesh() const;

      /// DoFs every rank must be able to read and write (collision mesh).
      const dealii::IndexSet &
      collision_dofs() const;

      double
      barrier_distance() const
      {
        return dhat;
      }

      double
      barrier_stiffness() const
      {
        return kappa;
      }

      /**
       * The automatic barrier stiffness: kappa_min makes a pair's barrier
       * as stiff as an average DoF of the rest of the system (mean diagonal
       * `mean_diagonal` of its Jacobian) half-way into dhat; kappa starts
       * there and may grow to 1e4 kappa_min.
       */
      void
      set_stiffness_scale(const double mean_diagonal);

      /**
       * Collect the candidate pairs for the states u + s du, s in [0, 1]
       * (for the state u alone if `du` is null). Returns (on every rank)
       * whether the Jacobian's sparsity pattern misses couplings of the
       * candidates; then rebuild it with add_couplings(). Collective.
       */
      bool
      update_candidates(const Vector_t &u, const Vector_t *du);

      /// Add the couplings of the candidates and friction pairs handled by
      /// this rank.
      void
      add_couplings(const dealii::AffineConstraints<double>   &constraints,
                    dealii::TrilinosWrappers::SparsityPattern &pattern) const;

      /// The largest fraction in (0, 1] of the step du from u that no
      /// candidate pair crosses (additive CCD, stopping where a distance
      /// falls to `gap` times its start; 0: IPC/CCD gap). Collective.
      double
      max_step(const Vector_t &u, const Vector_t &du, const double gap = 0);

      /**
       * Throw with the place if at state u boundary primitives touch or
       * cross, or a boundary point is on or behind a plane (`where` names
       * the state in the message); at `rest`, also if primitives of one
       * body are closer than dhat. Collective.
       */
      void
      check_state(const Vector_t &u, const std::string &where, const bool rest);

      /**
       * Add the potential's gradient to `residual` (and `raw`, without
       * constraints) and its projected Hessian to `matrix` (if given) at
       * state u. Returns this rank's part of the potential; `admissible` is
       * set to false if a pair touches or crosses (d <= 0).
       */
      double
      assemble(const Vector_t                          &u,
               const dealii::AffineConstraints<double> &constraints,
               dealii::TrilinosWrappers::SparseMatrix  *matrix,
               Vector_t                                &residual,
               Vector_t                                *raw,
               bool                                    &admissible,
               const bool                               project = true);

      /// Derivatives of p^T (h^c + h^f) with respect to parameters.
      struct AdjointProducts
      {
        std::vector<Vec>    rest;     ///< per collision vertex position
        std::vector<double> friction; ///< per friction source
      };

      /**
       * The adjoint products of the contact and friction forces at state u
       * (after update_candidates(u) and, with friction, update_friction()):
       * adds to `out` the derivatives of p^T h with respect to the rest
       * positions of the collision vertices (thesis B^c and eq. 3.27,
       * including the area weights and the edge-edge mollifier's rest
       * threshold) and to the friction coefficients, for this rank's
       * pairs; adds (dh/du_lagged + dh/du_start)^T p (eq. 3.29) to
       * `lagged` if given. The matching A^c is the unprojected Hessian of
       * assemble(..., false). Collective.
       */
      void
      adjoint_products(const Vector_t                          &u,
                       const Vector_t                          &p,
                       const dealii::AffineConstraints<double> &constraints,
                       Vector_t                                *lagged,
                       AdjointProducts                         &out);

      /**
       * @name The resultant of the barrier forces (a contact force objective)
       * R = -sum over the collision vertices of the bodies `bodies` (material
       * ids; empty: all, where pairs between bodies cancel and R is the
       * obstacles' push) of grad E, at state u after update_candidates(u).
       */
      //@{
      /// R (collective).
      dealii::Tensor<1, dim>
      barrier_resultant(const Vector_t                             &u,
                        const std::set<dealii::types::material_id> &bodies);
      /// For an objective J(R), given dJ/dR: adds dJ/du (the barrier Hessian
      /// times -dJ/dR on the bodies' DoFs) to `dJ_du` through `constraints`
      /// (collective) and dJ/d rest positions of the collision vertices (this
      /// rank's pairs) to `rest`.
      void
      barrier_resultant_products(
        const Vector_t                             &u,
        const dealii::Tensor<1, dim>               &dJ_dR,
        const std::set<dealii::types::material_id> &bodies,
        const dealii::AffineConstraints<double>    &constraints,
        Vector_t                                   &dJ_du,
        std::vector<Vec>                           &rest);
      //@}
      /**
       * Lagged friction: normal forces, tangent bases and closest points of
       * the pairs active at `u_lagged`; slip is measured from `u_start`
       * (the previous step), smoothed below `eta` (eq. 3.26). Collective.
       */
      void
      update_friction(const Vector_t &u_lagged,
                      const Vector_t &u_start,
                      const double    eta);

      /// After an accepted Newton step at the state of the last assemble():
      /// the adaptive stiffness update of IPC. Returns whether kappa grew.
      bool
      update_stiffness();

      /// Smallest distance over the candidates and the number of pairs
      /// within dhat at the last assemble() (over all ranks).
      std::pair<double, unsigned int>
      last_state(const MPI_Comm comm) const;

      /// Force the obstacles exert on the bodies (barrier and friction) at
      /// the last assemble(). Collective.
      dealii::Tensor<1, dim>
      obstacle_reaction(const MPI_Comm comm) const;

      /// Accumulated wall times: broad phase, CCD, assembly (this rank).
      nlohmann::json
      timings() const;

    private:
      struct Candidate
      {
        PairKind                    kind;
        std::array<unsigned int, 4> vertex;
        unsigned int                plane = 0;
      };
      struct FrictionPair
      {
        Candidate                   candidate;  ///< classified at u_lagged
        unsigned int                source = 0; ///< friction coefficient
        unsigned int                n      = 0;
        std::array<unsigned int, 4> vertex{};
        std::array<double, 4>       weight{}; ///< slip = sum weight_i du_i
        std::array<Vec, dim - 1>    tangent;
        double                      mu_n     = 0;     ///< mu times normal force
        bool                        obstacle = false; ///< against a plane
      };

      /// A candidate classified at positions X: distance formula, distance
      /// (signed against a plane), area weight A_k (half the vertex area
      /// for a point against a primitive: both sides of a contact are
      /// sampled; the vertex area against a plane; an eighth of the four
      /// vertex areas for an edge pair) and the edge-edge mollifier value
      /// (1 where it does not act) with its threshold.
      struct PairGeometry
      {
        DistanceStencil stencil;
        double          distance  = 0;
        double          weight    = 0;
        double          mollifier = 1;
        double          eps_x     = 0;
        /// weight = sum of coefficient * vertex_area over these terms.
        std::vector<std::pair<unsigned int, double>> weight_terms;
      };
      PairGeometry
      pair_geometry(const Candidate &c, const std::array<Vec, 4> &X) const;

      /// Positions rest + u of every collision vertex; u imported into
      /// `values` first.
      std::vector<Vec>
      positions(const Vector_t &u);
      std::vector<Vec>
      displacements(const Vector_t &u);
      /// Call f(candidate, geometry, moving slots, e) for this rank's pairs
      /// within dhat at positions x, e = kappa A_k b(d_k) m_k as nested AD
      /// over the moving coordinates (and the mollifier threshold).
      template <typename F>
      void
      for_each_barrier_pair(const std::vector<Vec> &x, const F &f) const;
      /// Add the derivatives of p^T grad E (p per vertex in `pv`) with
      /// respect to the rest positions to `rest` (through x = rest + u) and
      /// `area` (vertex area weights); if `hessian_p`, add H p there.
      void
      barrier_products(const std::vector<Vec>                  &x,
                       const std::vector<Vec>                  &pv,
                       std::vector<Vec>                        &rest,
                       std::vector<double>                     &area,
                       const dealii::AffineConstraints<double> *constraints,
                       Vector_t *hessian_p) const;
      /// Add s d eps_x / d rest (edge-edge mollifier threshold) to `rest`.
      void
      add_threshold_gradient(const Candidate  &c,
                             const double      s,
                             std::vector<Vec> &rest) const;
      /// Fill `candidates` for the segment u + s du (or the state u).
      void
      collect_candidates(const Vector_t &u, const Vector_t *du);
      std::array<Vec, 4>
      pair_positions(const Candidate &c, const std::vector<Vec> &x) const;
      /// The DoFs of a list of vertices (obstacle vertices have none).
      void
      local_dofs(const unsigned int                           *vertex,
                 const unsigned int                            n,
                 std::vector<dealii::types::global_dof_index> &dofs) const;
      /// Friction source of a pair classified as `s`.
      unsigned int
      friction_source(const Candidate &c, const DistanceStencil &s) const;
      /// The moving vertices (slots) the barrier of a pair depends on;
      /// returns whether an obstacle takes part.
      bool
      barrier_variables(const Candidate           &c,
                        const PairGeometry        &pg,
                        std::vector<unsigned int> &used) const;
      /// Pairs this rank evaluates.
      bool
      mine(const unsigned int k) const
      {
        return k % n_ranks == rank;
      }

      const IpcParameters                 parameters;
      std::unique_ptr<CollisionMesh<dim>> collision_mesh;
      MPI_Comm                            comm;
      unsigned int                        rank = 0, n_ranks = 1;
      Vector_t                            values; ///< ghosted on the mesh
      double                              dhat = 0, kappa = 0;
      double                              kappa_min = 0, kappa_max = 0;
      bool                                automatic_kappa = true;
      std::vector<Candidate>              candidates;
      std::set<std::pair<unsigned int, unsigned int>> couplings;
      std::vector<FrictionPair>                       friction;
      std::vector<Vec> friction_start;  ///< displacements at the step start
      std::vector<Vec> friction_lagged; ///< positions friction is lagged at
      std::vector<std::string> source_names;
      std::vector<double>      source_values;
      std::map<
        std::pair<dealii::types::material_id, dealii::types::material_id>,
        unsigned int>
                       pair_source;
      std::vector<int> plane_source, mesh_source; ///< -1: default
      bool             frozen = false, keep_zero_friction = false;
      double           friction_eta = 1;
      double           min_distance = 0, previous_min_distance = 0;
      unsigned int     n_active = 0;
      Vec              obstacle_force;
      double           broad_seconds = 0, ccd_seconds = 0, assemble_seconds = 0;
    };
  } // namespace ipc
} // namespace forma

#endif
