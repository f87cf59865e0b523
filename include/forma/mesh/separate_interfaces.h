#ifndef forma_mesh_separate_interfaces_h
#define forma_mesh_separate_interfaces_h

#include <deal.II/base/types.h>

#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * An interface between two parts (material ids) of a conforming mesh that
   * is cut open, so the parts can separate and slide (thesis ch. 2.3.3,
   * Gamma_S): both sides become boundary faces with id `boundary`.
   */
  struct InterfaceCut
  {
    dealii::types::material_id first, second;
    dealii::types::boundary_id boundary;
  };

  /// Parse `1-2 : 10 ; 2-3 : 11` (`entry` names the parameter in errors).
  std::vector<InterfaceCut>
  parse_interface_cuts(const std::string &text, const std::string &entry);

  /**
   * Duplicate the vertices of the faces shared by cells of the materials of
   * a cut so the two sides no longer share any vertex: around every vertex,
   * the cells connected through uncut faces keep one copy. The coincident
   * copies have identical positions (the contact code pairs them by
   * position). Boundary ids of existing boundary faces are kept; manifold
   * ids are dropped (flat meshes). Throws if a cut names materials that
   * share no face. `tria` must be a coarse (level 0) serial mesh.
   */
  template <int dim>
  void
  separate_interfaces(dealii::Triangulation<dim, dim> &tria,
                      const std::vector<InterfaceCut> &cuts,
                      const std::string               &where);
} // namespace forma

#endif
