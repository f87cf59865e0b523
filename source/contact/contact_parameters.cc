#include <deal.II/base/exceptions.h>

#include <forma/base/records.h>
#include <forma/contact/contact_parameters.h>

namespace forma
{
  using namespace dealii;

  void
  ContactParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    const std::string keys =
      " Keys: alpha (1/alpha is the penalty, force per length^3), eta "
      "(smoothing width of h_eta, a length), mu (Coulomb friction "
      "coefficient, 0: frictionless), eta_n (smoothing width of the "
      "friction norm N_eta, a length); defaults alpha=1e-4, eta=1e-4, mu=0, "
      "eta_n=1e-4.";
    prm.declare_entry(
      "Rigid-deformable",
      "",
      Patterns::Anything(),
      "Boundaries pressed against a rigid obstacle that keeps their initial "
      "shape (thesis eq. 2.5, 2.9): 'id : key=value, ... ; id : ...'." +
        keys);
    prm.declare_entry(
      "Rigid gaps",
      "",
      Patterns::Anything(),
      "Rigid obstacles that do not follow a boundary's initial shape: "
      "'id : expression ; ...', the obstacle's distance from the boundary "
      "point (x, y, z) along the boundary's outer normal (penetration j . n "
      "- gap), e.g. 'y + 1' for the plane y = -1 below a body resting on "
      "it at one point (Hertz contact). Every id must be a Rigid-deformable "
      "one; ids not named have gap 0. Shape designs are not available with "
      "a gap.");
    prm.declare_entry(
      "Deformable-deformable",
      "",
      Patterns::Anything(),
      "Interfaces between parts (boundary ids given by Mesh/Separate "
      "interfaces) whose two sides are in contact (thesis eq. 2.6, 2.10): "
      "'id : key=value, ... ; id : ...'." +
        keys);
    prm.declare_entry(
      "Quadrature",
      "gauss",
      Patterns::Selection("gauss|adaptive"),
      "Quadrature on contact faces. gauss: the elements' Gauss rule. "
      "adaptive (thesis ch. 2.9.4): split each face (in 2 or 4, "
      "recursively) where the branch of h_eta or N_eta changes between "
      "sample points, a Gauss rule in every piece: accurate where the "
      "contact state changes inside a face, at a higher cost.");
    prm.declare_entry("Adaptive depth",
                      "5",
                      Patterns::Integer(0, 12),
                      "Adaptive quadrature: largest number of splits.");
    prm.declare_entry("Adaptive Gauss points",
                      "4",
                      Patterns::Integer(1, 12),
                      "Adaptive quadrature: Gauss points per direction in "
                      "every piece.");
    prm.declare_entry("Adaptive samples",
                      "6",
                      Patterns::Integer(2, 20),
                      "Adaptive quadrature: sample points per direction "
                      "that decide whether a piece is split.");
    prm.leave_subsection();
  }



  void
  ContactParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact");
    rigid_deformable      = prm.get("Rigid-deformable");
    deformable_deformable = prm.get("Deformable-deformable");
    rigid_gaps_text       = prm.get("Rigid gaps");
    quadrature            = prm.get("Quadrature");
    adaptive_depth        = prm.get_integer("Adaptive depth");
    gauss_points          = prm.get_integer("Adaptive Gauss points");
    samples               = prm.get_integer("Adaptive samples");
    prm.leave_subsection();

    auto read = [](const std::string &text, const std::string &entry) {
      std::map<types::boundary_id, ContactLaw> laws;
      for (const auto &r : parse_records(text, 1, entry))
        {
          const std::string where =
            entry + ", boundary id " + std::to_string(r.id);
          AssertThrow(r.id != any_id,
                      ExcMessage("'" + entry +
                                 "': give a boundary id, not '*'."));
          AssertThrow(!laws.count(r.id),
                      ExcMessage("'" + where + "' is given twice."));
          ContactLaw law;
          for (const auto &[key, value] : parse_key_values(r.fields[0], entry))
            {
              if (key == "alpha")
                law.alpha = value;
              else if (key == "eta")
                law.eta = value;
              else if (key == "mu")
                law.mu = value;
              else if (key == "eta_n")
                law.eta_n = value;
              else
                AssertThrow(false,
                            ExcMessage("'" + where + "': unknown key '" + key +
                                       "' (known: alpha, eta, mu, eta_n)."));
            }
          AssertThrow(law.alpha > 0 && law.eta > 0 && law.eta_n > 0 &&
                        law.mu >= 0,
                      ExcMessage("'" + where +
                                 "': need alpha > 0, eta > 0, eta_n > 0 and "
                                 "mu >= 0."));
          laws[r.id] = law;
        }
      return laws;
    };
    rigid      = read(rigid_deformable, "Contact/Rigid-deformable");
    deformable = read(deformable_deformable, "Contact/Deformable-deformable");
    rigid_gaps.clear();
    for (const auto &r :
         parse_records(rigid_gaps_text, 1, "Contact/Rigid gaps"))
      {
        AssertThrow(r.id != any_id,
                    ExcMessage("'Contact/Rigid gaps': give a boundary id, "
                               "not '*'."));
        const std::string where =
          "Contact/Rigid gaps, boundary id " + std::to_string(r.id);
        AssertThrow(rigid.count(r.id),
                    ExcMessage("'" + where +
                               "': not a boundary of Contact/"
                               "Rigid-deformable."));
        AssertThrow(!rigid_gaps.count(r.id),
                    ExcMessage("'" + where + "' is given twice."));
        rigid_gaps[r.id] = r.fields[0];
      }
    for (const auto &[id, law] : rigid)
      AssertThrow(!deformable.count(id),
                  ExcMessage("Contact: boundary id " + std::to_string(id) +
                             " is both rigid-deformable and "
                             "deformable-deformable."));
  }



  bool
  ContactParameters::has_friction() const
  {
    for (const auto *m : {&rigid, &deformable})
      for (const auto &[id, law] : *m)
        if (law.mu > 0)
          return true;
    return false;
  }
} // namespace forma
