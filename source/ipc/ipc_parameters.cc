#include <deal.II/base/utilities.h>

#include <forma/base/records.h>
#include <forma/ipc/ipc_parameters.h>

#include <cmath>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    void
    IpcParameters::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("IPC");
      prm.declare_entry("Enabled",
                        "false",
                        Patterns::Bool(),
                        "Incremental potential contact (Li et al. 2020, "
                        "thesis ch. 3.6-3.7): a log barrier keeps every pair "
                        "of boundary primitives (and the obstacles) apart, "
                        "continuous collision detection filters every Newton "
                        "step, so bodies never interpenetrate.");
      prm.declare_entry("Boundaries",
                        "",
                        Patterns::Anything(),
                        "Boundary ids whose faces form the collision mesh "
                        "(comma separated). Empty: the whole boundary.");
      prm.declare_entry("Barrier distance",
                        "0",
                        Patterns::Double(0),
                        "dhat: the barrier acts on pairs closer than this "
                        "(length). 0: Relative barrier distance times the "
                        "diagonal of the collision mesh's bounding box.");
      prm.declare_entry("Relative barrier distance",
                        "1e-3",
                        Patterns::Double(0),
                        "dhat as a fraction of the bounding box diagonal "
                        "(when Barrier distance = 0).");
      prm.declare_entry("Barrier stiffness",
                        "0",
                        Patterns::Double(0),
                        "kappa. 0: automatic (IPC's adaptive stiffness: "
                        "scaled to the elastic and inertial stiffness of the "
                        "mesh, balanced against the other forces where "
                        "contact starts, doubled while the closest distance "
                        "keeps shrinking below 0.03 dhat).");
      prm.declare_entry("Obstacles",
                        "",
                        Patterns::Anything(),
                        "Static obstacles, ';' between records: 'plane : "
                        "<point> : <normal> [: mu = <friction>]', e.g. "
                        "'plane : 0, 0 : 0, 1' (bodies stay on the side the "
                        "normal points to), or 'mesh : <file> [: mu = "
                        "<friction>]': a surface from a Gmsh .msh (its "
                        "elements of dimension dim - 1, or the boundary of "
                        "its cells), .stl (3D) or .obj file, relative to the "
                        ".prm file.");
      prm.declare_entry("Friction coefficient",
                        "0",
                        Patterns::Double(0),
                        "Coulomb coefficient of every contact pair not given "
                        "in Friction pairs (and of obstacles without mu).");
      prm.declare_entry("Friction pairs",
                        "",
                        Patterns::Anything(),
                        "Coefficients per pair of material ids, ';' between "
                        "records: '0-1 : 0.3 ; 1-1 : 0.1'.");
      prm.declare_entry("Friction velocity",
                        "1e-3",
                        Patterns::Double(0),
                        "eps_v: below this tangential speed friction is "
                        "smoothed (static friction by a stiff viscous law; "
                        "eta = eps_v dt in f_eta of eq. 3.26). Static "
                        "problems use dt = End time / Load steps.");
      prm.declare_entry("Friction iterations",
                        "1",
                        Patterns::Integer(1),
                        "Static problems: solves per load step, each with "
                        "the normal forces and tangent bases lagged from the "
                        "previous one (transient problems lag them from the "
                        "previous time step, thesis ch. 3.7).");
      prm.declare_entry("CCD gap",
                        "0.1",
                        Patterns::Double(0.01, 0.9),
                        "Additive CCD stops a step where a pair's distance "
                        "falls to this fraction of its distance at the step "
                        "start.");
      prm.declare_entry("Newton step tolerance",
                        "1e-5",
                        Patterns::Double(0),
                        "With IPC, Newton also stops when the largest "
                        "displacement change of a full Newton step is below "
                        "this times the bounding box diagonal (times the "
                        "time step for transient problems: a velocity; IPC's "
                        "default). The projected contact Hessians make "
                        "Newton's convergence linear near the solution, so "
                        "this criterion, not the residual, usually stops "
                        "contact steps.");
      prm.leave_subsection();
    }



    void
    IpcParameters::parse(ParameterHandler  &prm,
                         const unsigned int dim,
                         const std::string &prm_directory)
    {
      prm.enter_subsection("IPC");
      enabled = prm.get_bool("Enabled");
      boundaries.clear();
      for (const auto &s : Utilities::split_string_list(prm.get("Boundaries")))
        {
          const int id = Utilities::string_to_int(s);
          AssertThrow(id >= 0 && id < 256,
                      ExcMessage("IPC/Boundaries: '" + s +
                                 "' is not a boundary id."));
          boundaries.insert(id);
        }
      dhat                  = prm.get_double("Barrier distance");
      relative_dhat         = prm.get_double("Relative barrier distance");
      kappa                 = prm.get_double("Barrier stiffness");
      friction              = prm.get_double("Friction coefficient");
      friction_velocity     = prm.get_double("Friction velocity");
      friction_iterations   = prm.get_integer("Friction iterations");
      ccd_gap               = prm.get_double("CCD gap");
      newton_step_tolerance = prm.get_double("Newton step tolerance");
      AssertThrow(dhat > 0 || relative_dhat > 0,
                  ExcMessage("IPC: Barrier distance or Relative barrier "
                             "distance must be positive."));
      AssertThrow(friction_velocity > 0,
                  ExcMessage("IPC/Friction velocity must be positive."));

      planes.clear();
      meshes.clear();
      const std::string entry = "IPC/Obstacles";
      for (const auto &record : split_top_level(prm.get("Obstacles"), ';'))
        {
          if (Utilities::trim(record).empty())
            continue;
          const auto        fields = split_top_level(record, ':');
          const std::string type =
            fields.empty() ? "" : Utilities::trim(fields[0]);
          AssertThrow(type == "plane" || type == "mesh",
                      ExcMessage(entry + ": unknown obstacle type '" + type +
                                 "' in '" + record +
                                 "' (available: plane, mesh)."));
          const unsigned int n_geometry = type == "plane" ? 3 : 2;
          AssertThrow(fields.size() == n_geometry ||
                        fields.size() == n_geometry + 1,
                      ExcMessage(entry + ": '" + record + "' should read " +
                                 (type == "plane" ?
                                    "'plane : <point> : <normal> [: mu = "
                                    "<value>]'." :
                                    "'mesh : <file> [: mu = <value>]'.")));
          double friction = -1;
          if (fields.size() == n_geometry + 1)
            {
              const auto kv = parse_key_values(fields.back(), entry);
              AssertThrow(kv.size() == 1 && kv.count("mu") && kv.at("mu") >= 0,
                          ExcMessage(entry +
                                     ": expected 'mu = <value >= "
                                     "0>' in '" +
                                     record + "'."));
              friction = kv.at("mu");
            }
          if (type == "mesh")
            {
              MeshObstacle o;
              o.file = Utilities::trim(fields[1]);
              if (!o.file.empty() && o.file[0] != '/')
                o.file = prm_directory + "/" + o.file;
              o.friction = friction;
              meshes.push_back(o);
              continue;
            }
          Plane p;
          for (unsigned int k = 1; k <= 2; ++k)
            {
              const auto x = split_top_level(fields[k], ',');
              AssertThrow(x.size() == dim,
                          ExcMessage(entry + ": '" +
                                     Utilities::trim(fields[k]) + "' needs " +
                                     std::to_string(dim) + " coordinates."));
              for (unsigned int d = 0; d < dim; ++d)
                (k == 1 ? p.origin : p.normal)[d] =
                  Utilities::string_to_double(x[d]);
            }
          AssertThrow(p.normal.norm() > 0,
                      ExcMessage(entry + ": the normal of '" + record +
                                 "' is zero."));
          p.normal /= p.normal.norm();
          p.friction = friction;
          planes.push_back(p);
        }

      pair_friction.clear();
      for (const auto &record : split_top_level(prm.get("Friction pairs"), ';'))
        {
          if (Utilities::trim(record).empty())
            continue;
          const auto fields = split_top_level(record, ':');
          const auto ids    = fields.size() == 2 ?
                                Utilities::split_string_list(fields[0], '-') :
                                std::vector<std::string>();
          AssertThrow(ids.size() == 2,
                      ExcMessage("IPC/Friction pairs: '" + record +
                                 "' should read '<id>-<id> : <mu>'."));
          const int    a  = Utilities::string_to_int(ids[0]);
          const int    b  = Utilities::string_to_int(ids[1]);
          const double mu = Utilities::string_to_double(fields[1]);
          AssertThrow(a >= 0 && b >= 0 && mu >= 0,
                      ExcMessage("IPC/Friction pairs: '" + record +
                                 "' needs material ids and mu >= 0."));
          pair_friction[{std::min(a, b), std::max(a, b)}] = mu;
        }
      prm.leave_subsection();
    }



    bool
    IpcParameters::has_friction() const
    {
      if (friction > 0)
        return true;
      for (const auto &p : pair_friction)
        if (p.second > 0)
          return true;
      for (const auto &p : planes)
        if (p.friction > 0)
          return true;
      for (const auto &m : meshes)
        if (m.friction > 0)
          return true;
      return false;
    }
  } // namespace ipc
} // namespace forma
