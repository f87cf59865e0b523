// Pipe assemblies from graphs: ball connectors at the nodes, pipes along the
// edges, meshed by Gmsh's OpenCASCADE kernel.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/records.h>
#include <forma/ipc/distance.h>
#include <forma/mesh/pipe_graph.h>

#include "gmsh_session.h"
#include <gmsh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace
  {
    const std::string section = "Mesh/Pipe graph";

    /// One finite number (the shared list parser, which names `entry`).
    double
    number(const std::string &text, const std::string &entry)
    {
      const auto v = parse_values(text, section + "/" + entry);
      AssertThrow(v.size() == 1 && std::isfinite(v[0]),
                  ExcMessage(section + "/" + entry + ": '" + text +
                             "' is not one finite number."));
      return v[0];
    }

    unsigned int
    index(const std::string &text, const std::string &entry)
    {
      const double x = number(text, entry);
      AssertThrow(x >= 0 && x == std::floor(x) && x < 65535,
                  ExcMessage(section + "/" + entry + ": '" + text +
                             "' is not a non-negative integer."));
      return static_cast<unsigned int>(x);
    }

    /// `record` split at ':' into its body, an optional id and an optional
    /// material.
    struct Record
    {
      std::string  body;
      unsigned int id, material;
    };

    Record
    split_record(const std::string &record,
                 const unsigned int default_id,
                 const unsigned int default_material,
                 const std::string &entry)
    {
      const auto fields = split_top_level(record, ':');
      AssertThrow(fields.size() <= 3,
                  ExcMessage(section + "/" + entry + ": the record '" + record +
                             "' has more than two ':'."));
      Record r{fields[0],
               fields.size() >= 2 ? index(fields[1], entry) : default_id,
               fields.size() == 3 ? index(fields[2], entry) : default_material};
      AssertThrow(r.material > 0 && r.material < 255,
                  ExcMessage(section + "/" + entry + ": the material in '" +
                             record + "' must lie between 1 and 254."));
      return r;
    }

    std::vector<std::string>
    records(const std::string &text)
    {
      std::vector<std::string> result;
      for (const auto &r : split_top_level(text, ';'))
        if (!Utilities::trim(r).empty())
          result.push_back(Utilities::trim(r));
      return result;
    }

    /// Closest distance between segments [p0, p1] and [q0, q1] (IPC's
    /// classified distance).
    double
    segment_distance(const Point<3> &p0,
                     const Point<3> &p1,
                     const Point<3> &q0,
                     const Point<3> &q1)
    {
      return std::sqrt(
        ipc::classify_edge_edge(p0, p1, q0, q1).distance_squared);
    }

    /// Distance of x from the segment [a, b].
    double
    point_distance(const Point<3> &x, const Point<3> &a, const Point<3> &b)
    {
      return std::sqrt(ipc::classify_point_edge(x, a, b).distance_squared);
    }

    /// Coefficients n and constant f0 of a linear form such as
    /// '2*x + y - 0.5 z + 1': terms joined by + or -, each a finite number,
    /// a variable, or a number and a variable (with or without '*'); false
    /// if `text` is not one.
    bool
    linear_form(const std::string &text, Tensor<1, 3> &n, double &f0)
    {
      const char *c     = text.c_str();
      const auto  blank = [&]() {
        while (*c == ' ' || *c == '\t')
          ++c;
      };
      bool first = true;
      blank();
      if (*c == '\0')
        return false;
      while (*c != '\0')
        {
          double sign = 1;
          if (*c == '+' || *c == '-')
            sign = *c++ == '-' ? -1 : 1;
          else if (!first)
            return false; // two terms without an operator between
          blank();
          double     value = 1;
          char      *end   = nullptr;
          const bool digit = std::isdigit(*c) || *c == '.';
          if (digit)
            {
              value = std::strtod(c, &end);
              if (end == c || !std::isfinite(value))
                return false;
              c = end;
              blank();
              if (*c == '*')
                {
                  ++c;
                  blank();
                  if (*c != 'x' && *c != 'y' && *c != 'z')
                    return false;
                }
            }
          if (*c == 'x' || *c == 'y' || *c == 'z')
            n[*c++ - 'x'] += sign * value;
          else if (digit)
            f0 += sign * value;
          else
            return false;
          blank();
          first = false;
        }
      return std::isfinite(n[0] + n[1] + n[2] + f0);
    }

    /// 'a x + b y + c z >= d : id' (or <=) as a unit normal and offset.
    PipeGraph::Clip
    parse_clip(const std::string &record)
    {
      const std::string entry  = section + "/Clip planes";
      const auto        fields = split_top_level(record, ':');
      AssertThrow(fields.size() == 2,
                  ExcMessage(entry + ": the record '" + record +
                             "' must read '<linear form in x, y, z> >= value "
                             ": id' (or <=), e.g. 'x + y >= 1 : 7'."));
      const std::string  body = fields[0];
      const unsigned int id   = index(fields[1], "Clip planes");
      const auto         op   = body.find_first_of("<>");
      AssertThrow(op != std::string::npos && op + 1 < body.size() &&
                    body[op + 1] == '=',
                  ExcMessage(entry + ": the record '" + record +
                             "' must read '<linear form in x, y, z> >= value "
                             ": id' (or <=), e.g. 'x + y >= 1 : 7'."));
      Tensor<1, 3> n;
      double       f0 = 0;
      AssertThrow(linear_form(body.substr(0, op), n, f0),
                  ExcMessage(entry + ": '" +
                             Utilities::trim(body.substr(0, op)) + "' in '" +
                             record +
                             "' is not a linear form in x, y, z (such as "
                             "'x', '-z' or '2*x + y - 0.5 z')."));
      const double length = n.norm();
      AssertThrow(length > 0 && std::isfinite(length),
                  ExcMessage(entry + ": '" + record + "' names no direction."));
      const double    value = number(body.substr(op + 2), "Clip planes");
      const double    sign  = body[op] == '>' ? 1 : -1;
      PipeGraph::Clip c;
      c.normal      = sign * n / length;
      c.offset      = sign * (value - f0) / length;
      c.boundary_id = id;
      return c;
    }

    std::string
    edge_name(const PipeGraph::Edge &e)
    {
      return std::to_string(e.a) + "-" + std::to_string(e.b);
    }
  } // namespace



  void
  PipeGraph::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Pipe graph");
    prm.declare_entry(
      "Nodes",
      "",
      Patterns::Anything(),
      "Mesh/Source = pipe graph: the graph's nodes, each a ball connector "
      "unless listed in Free ends, numbered from 0: 'x, y, z ; x, y, z : id "
      "; x, y, z : id : material ; ...'. The optional id is the boundary id "
      "of the ball's free surface, or of a free end's flat face (default 1; "
      "0 leaves it untagged), e.g. for a load or a support; the ball's "
      "material id defaults to 1 (a free end has none).");
    prm.declare_entry(
      "Edges",
      "",
      Patterns::Anything(),
      "The graph's edges, each a pipe between two nodes whose ends sit in "
      "sockets of their balls (or end at a free end): '0-1 ; 1-2 : id ; 2-3 "
      ": id : material ; "
      "...'. The optional id is the boundary id of the pipe's free surface "
      "(default 2), the material id defaults to 2. The sockets are shared "
      "surfaces: Mesh/Separate interfaces = 1-2 : id cuts those between "
      "materials 1 and 2 open for contact, and a pipe of the ball's own "
      "material (or of a pair not separated) stays glued to it, e.g. an arm "
      "of a connector.");
    prm.declare_entry(
      "Free ends",
      "",
      Patterns::Anything(),
      "Nodes without a ball, e.g. '4, 5': the one pipe ending at such a node "
      "runs to it and ends in a flat face with the node's boundary id (a "
      "dowel's end to load or clamp, a hook's tip). A clip plane may cut "
      "it instead (a leg standing on a floor).");
    prm.declare_entry("Connector radius",
                      "0.5",
                      Patterns::Double(0),
                      "Radius of the ball connectors.");
    prm.declare_entry("Pipe radius",
                      "0.15",
                      Patterns::Double(0),
                      "Radius of the pipes.");
    prm.declare_entry("Socket depth",
                      "0.25",
                      Patterns::Double(0),
                      "How far a pipe reaches into a ball along its axis, "
                      "from the ball's surface: pipes end at Connector "
                      "radius - Socket depth from their balls' nodes. "
                      "Between "
                      "R - sqrt(R^2 - r^2) (the pipe's rim just inside the "
                      "ball) and R; deep sockets of pipes at small angles "
                      "meet, which is refused.");
    prm.declare_entry("Mesh size",
                      "0.1",
                      Patterns::Double(0),
                      "Target of the largest tetrahedron edge (Gmsh's size "
                      "field).");
    prm.declare_entry("Elements per circle",
                      "12",
                      Patterns::Integer(6, 64),
                      "Gmsh's curvature sizing: the target number of edges "
                      "per full turn of the balls' and pipes' curved "
                      "surfaces. Their flat facets lose about an inscribed "
                      "polygon's share of a pipe's section: 4.5% at 12, 17% "
                      "at 6.");
    prm.declare_entry(
      "Clip planes",
      "",
      Patterns::Anything(),
      "Planes cutting the assembly, each a linear inequality in x, y, z "
      "that keeps a side, and the boundary id of the cut faces: 'z >= -0.4 "
      ": 5 ; x >= 0 : 20 ; x + y + z <= 14 : 6'. A floor for rigid contact, "
      "a flat pad to load, or the mirror planes of a symmetric assembly "
      "(with a Dirichlet condition on the normal component).");
    prm.leave_subsection();
  }



  void
  PipeGraph::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Pipe graph");
    nodes.clear();
    for (const auto &r : records(prm.get("Nodes")))
      {
        const auto record = split_record(r, 1, 1, "Nodes");
        const auto xyz    = Utilities::split_string_list(record.body, ',');
        AssertThrow(xyz.size() == 3,
                    ExcMessage(section + "/Nodes: the record '" + r +
                               "' must read 'x, y, z' or 'x, y, z : id' or "
                               "'x, y, z : id : material'."));
        nodes.push_back({Point<3>(number(xyz[0], "Nodes"),
                                  number(xyz[1], "Nodes"),
                                  number(xyz[2], "Nodes")),
                         record.id,
                         record.material});
      }
    for (const auto &text :
         Utilities::split_string_list(prm.get("Free ends"), ','))
      {
        const unsigned int k = index(text, "Free ends");
        AssertThrow(k < nodes.size(),
                    ExcMessage(section + "/Free ends: there is no node " +
                               text + " among the " +
                               std::to_string(nodes.size()) + " Nodes."));
        nodes[k].free_end = true;
      }
    edges.clear();
    for (const auto &r : records(prm.get("Edges")))
      {
        const auto record = split_record(r, 2, 2, "Edges");
        const auto ab     = Utilities::split_string_list(record.body, '-');
        AssertThrow(ab.size() == 2,
                    ExcMessage(section + "/Edges: the record '" + r +
                               "' must read 'a-b', 'a-b : id' or 'a-b : id "
                               ": material'."));
        edges.push_back({index(ab[0], "Edges"),
                         index(ab[1], "Edges"),
                         record.id,
                         record.material});
      }
    clips.clear();
    for (const auto &r : records(prm.get("Clip planes")))
      clips.push_back(parse_clip(r));
    connector_radius    = prm.get_double("Connector radius");
    pipe_radius         = prm.get_double("Pipe radius");
    socket_depth        = prm.get_double("Socket depth");
    mesh_size           = prm.get_double("Mesh size");
    elements_per_circle = prm.get_integer("Elements per circle");
    prm.leave_subsection();
    check();
  }



  void
  PipeGraph::check() const
  {
    AssertThrow(nodes.size() >= 2 && !edges.empty(),
                ExcMessage(section + ": the graph needs at least two Nodes "
                                     "and one edge (Edges)."));
    check_sizes();
    check_balls();
    check_edges();
    check_pipes();
    check_sockets();
    for (const auto &c : clips)
      AssertThrow(c.boundary_id > 0,
                  ExcMessage(section + "/Clip planes: give the cut faces a "
                                       "boundary id above 0."));
  }



  void
  PipeGraph::check_sizes() const
  {
    const double R = connector_radius, r = pipe_radius;
    AssertThrow(R > 0 && r > 0 && mesh_size > 0 && r < R,
                ExcMessage(section + ": Connector radius, Pipe radius and "
                                     "Mesh size must be positive, the pipes "
                                     "thinner than the balls."));
    const double rim = std::sqrt(R * R - r * r);
    AssertThrow(socket_depth > R - rim && socket_depth < R,
                ExcMessage(section + ": Socket depth " + sig(socket_depth) +
                           " must lie between " + sig(R - rim) +
                           " (where the pipe's rim enters the ball) and the "
                           "Connector radius " +
                           sig(R) + "."));
  }



  void
  PipeGraph::check_edges() const
  {
    std::set<std::pair<unsigned int, unsigned int>> seen;
    for (const auto &e : edges)
      {
        AssertThrow(e.a < nodes.size() && e.b < nodes.size() && e.a != e.b,
                    ExcMessage(section + "/Edges: " + edge_name(e) +
                               " must join two different nodes of the " +
                               std::to_string(nodes.size()) + " given."));
        AssertThrow(seen.insert(std::minmax(e.a, e.b)).second,
                    ExcMessage(section + "/Edges: " + edge_name(e) +
                               " is given twice."));
        // A pipe to a free end leaves its ball (check_balls() spaces two).
        if (!nodes[e.a].free_end && !nodes[e.b].free_end)
          continue;
        const double length = nodes[e.a].x.distance(nodes[e.b].x);
        const double need   = (nodes[e.a].free_end ? 0 : connector_radius) +
                            (nodes[e.b].free_end ? 0 : connector_radius) +
                            0.1 * pipe_radius;
        AssertThrow(length >= need,
                    ExcMessage(section + "/Edges: " + edge_name(e) + " is " +
                               sig(length) + " long; its pipe needs at least " +
                               sig(need) + " to leave its balls."));
      }
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].free_end)
        {
          const auto degree =
            std::count_if(edges.begin(), edges.end(), [k](const Edge &e) {
              return e.a == k || e.b == k;
            });
          AssertThrow(degree == 1,
                      ExcMessage(section + "/Free ends: node " +
                                 std::to_string(k) + " has " +
                                 std::to_string(degree) +
                                 " edges; a free end needs exactly one."));
        }
  }



  void
  PipeGraph::check_balls() const
  {
    const double R = connector_radius, margin = 0.1 * pipe_radius;
    for (unsigned int i = 0; i < nodes.size(); ++i)
      for (unsigned int j = i + 1; j < nodes.size(); ++j)
        AssertThrow(nodes[i].free_end || nodes[j].free_end ||
                      nodes[i].x.distance(nodes[j].x) >= 2 * R + margin,
                    ExcMessage(section + ": the balls of nodes " +
                               std::to_string(i) + " and " + std::to_string(j) +
                               " overlap or touch (their centres are " +
                               sig(nodes[i].x.distance(nodes[j].x)) +
                               " apart, at least the diameter " + sig(2 * R) +
                               " and a tenth of the Pipe radius are "
                               "needed)."));
  }



  void
  PipeGraph::check_pipes() const
  {
    const double R = connector_radius, r = pipe_radius, margin = 0.1 * r;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      for (const auto &e : edges)
        if (e.a != k && e.b != k && !nodes[k].free_end)
          AssertThrow(point_distance(nodes[k].x, nodes[e.a].x, nodes[e.b].x) >=
                        R + r + margin,
                      ExcMessage(section + ": the pipe of edge " +
                                 edge_name(e) + " passes through the ball " +
                                 "of node " + std::to_string(k) + "."));
    for (unsigned int i = 0; i < edges.size(); ++i)
      for (unsigned int j = i + 1; j < edges.size(); ++j)
        {
          const auto &e = edges[i], &f = edges[j];
          if (e.a == f.a || e.a == f.b || e.b == f.a || e.b == f.b)
            continue; // check_sockets()
          const double d = segment_distance(nodes[e.a].x,
                                            nodes[e.b].x,
                                            nodes[f.a].x,
                                            nodes[f.b].x);
          AssertThrow(d >= 2 * r + margin,
                      ExcMessage(section + ": the pipes of edges " +
                                 edge_name(e) + " and " + edge_name(f) +
                                 " cross or touch (their axes come " + sig(d) +
                                 " close, at least the pipes' "
                                 "diameter " +
                                 sig(2 * r) +
                                 " and a tenth "
                                 "of their radius are needed)."));
        }
  }



  void
  PipeGraph::check_sockets() const
  {
    // Half-cylinders of radius r leaving one point at angle theta are apart
    // beyond r cot(theta / 2) from it (they lie on either side of the
    // bisector plane there). Two edges from one node in one direction
    // overlap (one may end at a free end, so check_pipes() cannot see it).
    const double r = pipe_radius, s = connector_radius - socket_depth;
    auto         direction = [&](const Edge &e, const unsigned int from) {
      const Tensor<1, 3> d = nodes[from == e.a ? e.b : e.a].x - nodes[from].x;
      return d / d.norm();
    };
    for (unsigned int i = 0; i < edges.size(); ++i)
      for (unsigned int j = i + 1; j < edges.size(); ++j)
        {
          const auto &e = edges[i], &f = edges[j];
          const int   k = e.a == f.a || e.a == f.b ?
                            e.a :
                            (e.b == f.a || e.b == f.b ? e.b : -1);
          if (k < 0)
            continue;
          const double c =
            std::clamp(direction(e, k) * direction(f, k), -1., 1.);
          const double half = 0.5 * std::acos(c);
          AssertThrow(half > 1e-6,
                      ExcMessage(section + ": the pipes of edges " +
                                 edge_name(e) + " and " + edge_name(f) +
                                 " leave node " + std::to_string(k) +
                                 " in the same direction."));
          const double need = r / std::tan(half) + 0.1 * r;
          AssertThrow(s >= need,
                      ExcMessage(
                        section + ": the sockets of edges " + edge_name(e) +
                        " and " + edge_name(f) + " meet inside the ball of " +
                        "node " + std::to_string(k) + " (" +
                        sig(2 * half * 180 / numbers::PI) +
                        " degrees apart): the pipes must end at least " +
                        sig(need) + " from the node, they end at " + sig(s) +
                        ". Lower Socket depth or the Pipe radius."));
        }
  }



  namespace
  {
    gmsh::vectorpair
    volumes(const std::vector<int> &tags)
    {
      gmsh::vectorpair v;
      for (const int t : tags)
        v.emplace_back(3, t);
      return v;
    }

    std::vector<int>
    tags_of(const gmsh::vectorpair &dim_tags)
    {
      std::vector<int> t;
      for (const auto &dt : dim_tags)
        if (dt.first == 3)
          t.push_back(dt.second);
      return t;
    }

    /// Throw what Gmsh logged during `what`, if anything: with
    /// General.AbortOnError off, its OpenCASCADE operations log their
    /// failures instead of throwing.
    void
    check_step(const std::string &what)
    {
      std::string last;
      gmsh::logger::getLastError(last);
      AssertThrow(last.empty(),
                  ExcMessage(section + ": Gmsh failed to " + what + ": " +
                             last));
    }

    /// The parts of the assembly: one list of OpenCASCADE volumes each, the
    /// balls first (none at a free end), then the pipes.
    struct Parts
    {
      std::vector<std::vector<int>> volumes;
      std::vector<unsigned int>     material, boundary_id;
    };

    Parts
    build_parts(const PipeGraph &g)
    {
      namespace occ   = gmsh::model::occ;
      const double s  = g.connector_radius - g.socket_depth;
      const auto   nn = g.nodes.size();
      Parts        parts;
      parts.volumes.resize(nn + g.edges.size());
      for (unsigned int i = 0; i < g.edges.size(); ++i)
        {
          const auto &na = g.nodes[g.edges[i].a], &nb = g.nodes[g.edges[i].b];
          const Tensor<1, 3> d = nb.x - na.x;
          const double       L = d.norm();
          const double   s_a = na.free_end ? 0 : s, s_b = nb.free_end ? 0 : s;
          const Point<3> p      = na.x + (s_a / L) * d;
          const double   f      = (L - s_a - s_b) / L;
          parts.volumes[nn + i] = {occ::addCylinder(
            p[0], p[1], p[2], f * d[0], f * d[1], f * d[2], g.pipe_radius)};
        }
      for (unsigned int k = 0; k < nn; ++k)
        {
          if (g.nodes[k].free_end)
            continue;
          const auto &x  = g.nodes[k].x;
          const int ball = occ::addSphere(x[0], x[1], x[2], g.connector_radius);
          std::vector<int> sockets;
          for (unsigned int i = 0; i < g.edges.size(); ++i)
            if (g.edges[i].a == k || g.edges[i].b == k)
              sockets.push_back(parts.volumes[nn + i][0]);
          gmsh::vectorpair              out;
          std::vector<gmsh::vectorpair> map;
          if (sockets.empty())
            parts.volumes[k] = {ball};
          else
            {
              occ::cut(
                {{3, ball}}, volumes(sockets), out, map, -1, true, false);
              parts.volumes[k] = tags_of(out);
            }
          check_step("cut the sockets of node " + std::to_string(k));
        }
      for (const auto &n : g.nodes)
        {
          parts.material.push_back(n.material);
          parts.boundary_id.push_back(n.boundary_id);
        }
      for (const auto &e : g.edges)
        {
          parts.material.push_back(e.material);
          parts.boundary_id.push_back(e.boundary_id);
        }
      return parts;
    }

    /// A solid box of size 2L x 2L x L on the kept side of `c`, its base on
    /// the plane.
    int
    half_space(const PipeGraph::Clip &c, const double L)
    {
      namespace occ = gmsh::model::occ;
      const int box = occ::addBox(-L, -L, 0, 2 * L, 2 * L, L);
      // Turn the z axis onto the normal, about z x n.
      const Tensor<1, 3> &n = c.normal;
      const Tensor<1, 3>  axis({-n[1], n[0], 0.});
      const double        angle = std::acos(std::clamp(n[2], -1., 1.));
      if (axis.norm() > 1e-12)
        occ::rotate({{3, box}}, 0, 0, 0, axis[0], axis[1], axis[2], angle);
      else if (n[2] < 0)
        occ::rotate({{3, box}}, 0, 0, 0, 1, 0, 0, numbers::PI);
      occ::translate({{3, box}},
                     c.offset * n[0],
                     c.offset * n[1],
                     c.offset * n[2]);
      return box;
    }

    /// Intersect every part with the half-spaces the clip planes keep.
    void
    clip(const PipeGraph &g, Parts &parts)
    {
      namespace occ = gmsh::model::occ;
      double L      = 0;
      for (const auto &n : g.nodes)
        L = std::max(L, n.x.norm());
      L = 4 * (L + 2 * g.connector_radius);
      for (const auto &c : g.clips)
        {
          // Beyond the assembly: it keeps all or nothing.
          AssertThrow(c.offset < L / 4,
                      ExcMessage(section +
                                 "/Clip planes: they leave nothing of "
                                 "the assembly."));
          if (c.offset <= -L / 4)
            continue;
          const int box = half_space(c, L);
          for (auto &v : parts.volumes)
            if (!v.empty())
              {
                gmsh::vectorpair              out;
                std::vector<gmsh::vectorpair> map;
                occ::intersect(
                  volumes(v), {{3, box}}, out, map, -1, true, false);
                v = tags_of(out);
              }
          occ::remove({{3, box}}, true);
          check_step("cut the assembly by a clip plane");
        }
    }

    /// Glue the parts (shared socket surfaces) and renumber their volumes.
    void
    fragment(Parts &parts)
    {
      gmsh::vectorpair          all;
      std::vector<unsigned int> owner;
      for (unsigned int p = 0; p < parts.volumes.size(); ++p)
        for (const int t : parts.volumes[p])
          {
            all.emplace_back(3, t);
            owner.push_back(p);
          }
      AssertThrow(!all.empty(),
                  ExcMessage(section + "/Clip planes: they leave nothing of "
                                       "the assembly."));
      gmsh::vectorpair              out;
      std::vector<gmsh::vectorpair> map;
      gmsh::model::occ::fragment(all, {}, out, map);
      check_step("glue the parts");
      AssertThrow(map.size() == all.size(),
                  ExcMessage(section + ": Gmsh failed to glue the parts."));
      for (auto &v : parts.volumes)
        v.clear();
      // A piece in two parts would be meshed twice: the checks of the graph
      // keep parts apart, so this is a kernel failure.
      std::set<int> seen;
      for (unsigned int i = 0; i < all.size(); ++i)
        for (const int t : tags_of(map[i]))
          {
            AssertThrow(seen.insert(t).second,
                        ExcMessage(section + ": two parts overlap after "
                                             "gluing (an OpenCASCADE "
                                             "failure)."));
            parts.volumes[owner[i]].push_back(t);
          }
    }

    /// The boundary id of a flat surface that lies in a clip plane or is a
    /// pipe's end at a free end, or `fallback`.
    unsigned int
    flat_face_id(const PipeGraph &g, const int surface, unsigned int fallback)
    {
      std::string type;
      gmsh::model::getType(2, surface, type);
      if (type != "Plane")
        return fallback;
      double x, y, z;
      gmsh::model::occ::getCenterOfMass(2, surface, x, y, z);
      const Point<3>      centre(x, y, z);
      std::vector<double> uv, normal;
      gmsh::model::getParametrization(2, surface, {x, y, z}, uv);
      gmsh::model::getNormal(surface, uv, normal);
      if (normal.size() != 3)
        return fallback;
      const double       tol = 1e-6 * g.connector_radius;
      const Tensor<1, 3> face_normal({normal[0], normal[1], normal[2]});
      for (const auto &c : g.clips)
        if (std::abs(c.normal * centre - c.offset) < tol &&
            std::abs(std::abs(c.normal * face_normal) - 1) < 1e-6)
          return c.boundary_id;
      // A free end's cap, whole or cut by a clip plane: in the plane through
      // the node normal to its pipe, within the pipe's radius.
      for (const auto &e : g.edges)
        for (const auto &[k, other] :
             {std::pair(e.a, e.b), std::pair(e.b, e.a)})
          if (g.nodes[k].free_end)
            {
              const Tensor<1, 3> axis = (g.nodes[other].x - g.nodes[k].x) /
                                        g.nodes[other].x.distance(g.nodes[k].x);
              const Tensor<1, 3> w = centre - g.nodes[k].x;
              if (std::abs(w * axis) < tol &&
                  std::abs(std::abs(face_normal * axis) - 1) < 1e-6 &&
                  w.norm() < g.pipe_radius)
                return g.nodes[k].boundary_id;
            }
      return fallback;
    }

    /// Physical groups: volumes by material, free surfaces by the ids of
    /// their part, clip plane or free end.
    void
    tag(const PipeGraph &g, const Parts &parts)
    {
      std::map<int, unsigned int>              part_of;
      std::map<unsigned int, std::vector<int>> by_material;
      for (unsigned int p = 0; p < parts.volumes.size(); ++p)
        for (const int t : parts.volumes[p])
          {
            part_of[t] = p;
            by_material[parts.material[p]].push_back(t);
          }
      for (const auto &[m, tags] : by_material)
        gmsh::model::addPhysicalGroup(3, tags, m);

      std::map<unsigned int, std::vector<int>> by_id;
      gmsh::vectorpair                         surfaces;
      gmsh::model::getEntities(surfaces, 2);
      for (const auto &[d, s] : surfaces)
        {
          std::vector<int> up, down;
          gmsh::model::getAdjacencies(2, s, up, down);
          if (up.size() != 1)
            continue; // a socket surface shared by a ball and a pipe
          const auto owner = part_of.find(up[0]);
          AssertThrow(owner != part_of.end(),
                      ExcMessage(section + ": Gmsh made a volume that belongs "
                                           "to no part."));
          const unsigned int id =
            flat_face_id(g, s, parts.boundary_id[owner->second]);
          if (id > 0)
            by_id[id].push_back(s);
        }
      for (const auto &[id, tags] : by_id)
        gmsh::model::addPhysicalGroup(2, tags, id);
    }
  } // namespace



  namespace
  {
    /// The mesh as Gmsh 2.2 text (call inside a Gmsh session).
    std::string
    mesh_text(const PipeGraph &g)
    {
      Parts parts = build_parts(g);
      clip(g, parts);
      fragment(parts);
      gmsh::model::occ::synchronize();
      tag(g, parts);
      check_step("tag the parts");
      gmsh::option::setNumber("Mesh.MeshSizeMax", g.mesh_size);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature",
                              g.elements_per_circle);
      gmsh::option::setNumber("Mesh.Optimize", 1);
      gmsh::option::setNumber("Mesh.OptimizeThreshold", 0.5);
      gmsh::model::mesh::generate(3);
      gmsh::model::mesh::optimize("Relocate3D");
      internal::gmsh_check_generated(3, section);
      return internal::gmsh_written_mesh();
    }
  } // namespace



  std::string
  pipe_graph_mesh(const PipeGraph &g, const MPI_Comm comm)
  {
    g.check();
    // Meshed once, on the root, so every rank reads the same cells.
    return on_root_or_throw(comm, [&]() {
      std::string text;
      internal::in_gmsh_session("forma-pipe-graph", section, [&]() {
        text = mesh_text(g);
      });
      return text;
    });
  }
} // namespace forma
