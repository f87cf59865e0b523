#include <deal.II/base/exceptions.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/separate_interfaces.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace forma
{
  using namespace dealii;

  void
  MeshParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    prm.declare_entry("Source",
                      "generator",
                      Patterns::Selection("generator|file|pipe graph"),
                      "Build the coarse mesh with a deal.II GridGenerator "
                      "function, read it from a Gmsh .msh file, or make a 3D "
                      "pipe assembly of ball connectors and pipes from a "
                      "graph (subsection Pipe graph).");
    prm.declare_entry(
      "Generator",
      "hyper_cube",
      Patterns::Anything(),
      "Name of a deal.II GridGenerator function (e.g. "
      "hyper_rectangle, subdivided_hyper_rectangle, hyper_ball, "
      "hyper_shell, hyper_L, plate_with_a_hole).");
    prm.declare_entry("Generator arguments",
                      "0 : 1 : true",
                      Patterns::Anything(),
                      "Its arguments, ':' between arguments and ',' inside "
                      "points or lists, e.g. for subdivided_hyper_rectangle "
                      "'10, 1 : 0, 0 : 10, 1 : true' (colorize = true numbers "
                      "the faces x=min 0, x=max 1, y=min 2, y=max 3, z 4/5).");
    prm.declare_entry("File",
                      "",
                      Patterns::Anything(),
                      "Gmsh .msh file (relative to the parameter file). "
                      "Physical tags become material ids (cells) and boundary "
                      "ids (faces).");
    prm.declare_entry("Convert to simplices",
                      "false",
                      Patterns::Bool(),
                      "Split every quad/hex of the coarse mesh into triangles/"
                      "tetrahedra (P1/P2 elements are then used).");
    prm.declare_entry("Initial refinement",
                      "0",
                      Patterns::Integer(0, 12),
                      "Number of global refinements of the coarse mesh.");
    prm.declare_entry(
      "Separate interfaces",
      "",
      Patterns::Anything(),
      "Interfaces between parts (material ids) to cut open so the parts can "
      "separate and slide, e.g. for deformable-deformable contact: '1-2 : "
      "10 ; 2-3 : 11' duplicates the vertices shared by materials 1 and 2 "
      "and gives the faces on both sides boundary id 10.");
    PipeGraph::declare(prm);
    prm.leave_subsection();
  }



  void
  MeshParameters::parse(ParameterHandler &prm, const std::string &prm_directory)
  {
    prm.enter_subsection("Mesh");
    source              = prm.get("Source");
    generator           = prm.get("Generator");
    generator_arguments = prm.get("Generator arguments");
    file_as_given       = prm.get("File");
    file                = file_as_given.empty() ?
                            std::string() :
                            (std::filesystem::path(prm_directory) / file_as_given)
               .lexically_normal()
               .string();
    if (!file_as_given.empty() && file_as_given[0] == '/')
      file = file_as_given;
    convert_to_simplices = prm.get_bool("Convert to simplices");
    initial_refinement   = prm.get_integer("Initial refinement");
    separate_interfaces  = prm.get("Separate interfaces");
    if (source == "pipe graph")
      pipe_graph.parse(prm);
    prm.leave_subsection();
    parse_interface_cuts(separate_interfaces, "Mesh/Separate interfaces");
    AssertThrow(source != "file" || !file_as_given.empty(),
                ExcMessage("Mesh/Source = file but Mesh/File is empty."));
  }



  template <int dim>
  void
  check_mesh_validity(const Triangulation<dim> &tria, const std::string &where)
  {
    for (const auto &cell : tria.active_cell_iterators())
      {
        if (!cell->is_locally_owned() &&
            tria.locally_owned_subdomain() != numbers::invalid_subdomain_id)
          continue;
        const unsigned int nv    = cell->n_vertices();
        double             scale = 0;
        for (unsigned int v = 1; v < nv; ++v)
          scale = std::max(scale, cell->vertex(v).distance(cell->vertex(0)));
        const double tol = 1e-10 * std::pow(scale, dim);

        // Jacobian at each vertex from the edges leaving it: lexicographic
        // bit pattern for hypercubes, the affine map for simplices.
        std::vector<double> dets;
        if (cell->reference_cell().is_hyper_cube())
          for (unsigned int v = 0; v < nv; ++v)
            {
              Tensor<2, dim> J;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const Tensor<1, dim> e =
                    cell->vertex(v | (1u << d)) - cell->vertex(v & ~(1u << d));
                  for (unsigned int c = 0; c < dim; ++c)
                    J[c][d] = e[c];
                }
              dets.push_back(determinant(J));
            }
        else
          {
            Tensor<2, dim> J;
            for (unsigned int d = 0; d < dim; ++d)
              for (unsigned int c = 0; c < dim; ++c)
                J[c][d] = cell->vertex(d + 1)[c] - cell->vertex(0)[c];
            // deal.II simplices may be of either orientation; only a
            // degenerate one is invalid.
            dets.push_back(std::abs(determinant(J)));
          }
        for (unsigned int k = 0; k < dets.size(); ++k)
          if (!(dets[k] > tol))
            {
              std::ostringstream msg;
              msg << where << ": cell " << cell->index() << " (material id "
                  << cell->material_id() << ") is inverted or degenerate: its "
                  << "Jacobian determinant at vertex " << k << " is " << dets[k]
                  << ". Vertices:";
              for (unsigned int v = 0; v < nv; ++v)
                msg << " (" << cell->vertex(v) << ")";
              AssertThrow(false, ExcMessage(msg.str()));
            }
      }
  }



  template <int dim>
  void
  create_coarse_mesh(const MeshParameters &params,
                     Triangulation<dim>   &tria,
                     const MPI_Comm        comm)
  {
    std::string where;
    if (params.source == "generator")
      {
        where = "Mesh/Generator '" + params.generator + "'";
        try
          {
            GridGenerator::generate_from_name_and_arguments(
              tria, params.generator, params.generator_arguments);
          }
        catch (const std::exception &exc)
          {
            AssertThrow(false,
                        ExcMessage(where + " with arguments '" +
                                   params.generator_arguments +
                                   "' failed: " + error_message(exc)));
          }
      }
    else
      {
        std::unique_ptr<std::istream> in;
        if (params.source == "pipe graph")
          {
            where = "Mesh/Pipe graph";
            AssertThrow(dim == 3,
                        ExcMessage("Mesh/Source = pipe graph makes 3D "
                                   "assemblies: set Dimension = 3."));
            in = std::make_unique<std::istringstream>(
              pipe_graph_mesh(params.pipe_graph, comm));
          }
        else
          {
            where = "mesh file '" + params.file_as_given + "'";
            in    = std::make_unique<std::ifstream>(params.file);
            AssertThrow(in->good(),
                        ExcMessage("Mesh/File: cannot open '" +
                                   params.file_as_given +
                                   "' (looked relative to the parameter "
                                   "file's directory)."));
          }
        GridIn<dim> grid_in(tria);
        try
          {
            grid_in.read_msh(*in);
          }
        catch (const std::exception &exc)
          {
            AssertThrow(false,
                        ExcMessage(where +
                                   " could not be read as a Gmsh file: " +
                                   error_message(exc)));
          }
        AssertThrow(tria.n_active_cells() > 0,
                    ExcMessage(where + " contains no " + std::to_string(dim) +
                               "D cells."));
      }
    check_mesh_validity(tria, where);
    if (params.convert_to_simplices)
      {
        AssertThrow(tria.all_reference_cells_are_hyper_cube(),
                    ExcMessage(
                      "Mesh/Convert to simplices: the mesh already has "
                      "simplices."));
        // Refine the hexahedral mesh, then split: keeps the simplices as
        // shaped as the conversion makes them.
        tria.refine_global(params.initial_refinement);
        Triangulation<dim> flat, simplex_tria;
        GridGenerator::flatten_triangulation(tria, flat);
        GridGenerator::convert_hypercube_to_simplex_mesh(flat, simplex_tria);
        tria.clear();
        tria.copy_triangulation(simplex_tria);
      }
    separate_interfaces(tria,
                        parse_interface_cuts(params.separate_interfaces,
                                             "Mesh/Separate interfaces"),
                        where);
  }



  template <int dim>
  std::unique_ptr<parallel::TriangulationBase<dim>>
  create_distributed_mesh(const MeshParameters &params, const MPI_Comm comm)
  {
    Triangulation<dim> coarse;
    create_coarse_mesh(params, coarse, comm);

    AssertThrow(coarse.all_reference_cells_are_simplex() ||
                  coarse.all_reference_cells_are_hyper_cube(),
                ExcMessage("meshes mixing quads/hexes with simplices (or "
                           "wedges/pyramids) are not supported."));
    auto tria = make_parallel_triangulation<dim>(
      !coarse.all_reference_cells_are_hyper_cube(),
      !params.separate_interfaces.empty(),
      comm);
    tria->copy_triangulation(coarse);
    // A transfinite-interpolation manifold (plate_with_a_hole, say) refers
    // to the triangulation it was initialized with, which is `coarse`:
    // initialize a fresh one on the copy before anything is refined.
    for (const auto id : tria->get_manifold_ids())
      if (id != numbers::flat_manifold_id &&
          dynamic_cast<const TransfiniteInterpolationManifold<dim> *>(
            &tria->get_manifold(id)) != nullptr)
        {
          tria->reset_manifold(id); // not the stale copy while initializing
          TransfiniteInterpolationManifold<dim> tfi;
          tfi.initialize(*tria);
          tria->set_manifold(id, tfi);
        }
    if (!params.convert_to_simplices)
      tria->refine_global(params.initial_refinement);
    return tria;
  }

  template <int dim>
  std::unique_ptr<parallel::TriangulationBase<dim>>
  make_parallel_triangulation(const bool     simplex,
                              const bool     shared,
                              const MPI_Comm comm)
  {
    if (simplex || shared)
      return std::make_unique<parallel::shared::Triangulation<dim>>(comm);
    return std::make_unique<parallel::distributed::Triangulation<dim>>(
      comm, Triangulation<dim>::limit_level_difference_at_vertices);
  }

  template std::unique_ptr<parallel::TriangulationBase<2>>
  make_parallel_triangulation<2>(const bool, const bool, const MPI_Comm);
  template std::unique_ptr<parallel::TriangulationBase<3>>
  make_parallel_triangulation<3>(const bool, const bool, const MPI_Comm);
  template void
  create_coarse_mesh<2>(const MeshParameters &,
                        Triangulation<2> &,
                        const MPI_Comm);
  template void
  create_coarse_mesh<3>(const MeshParameters &,
                        Triangulation<3> &,
                        const MPI_Comm);
  template void
  check_mesh_validity<2>(const Triangulation<2> &, const std::string &);
  template void
  check_mesh_validity<3>(const Triangulation<3> &, const std::string &);
  template std::unique_ptr<parallel::TriangulationBase<2>>
  create_distributed_mesh<2>(const MeshParameters &, const MPI_Comm);
  template std::unique_ptr<parallel::TriangulationBase<3>>
  create_distributed_mesh<3>(const MeshParameters &, const MPI_Comm);
} // namespace forma
