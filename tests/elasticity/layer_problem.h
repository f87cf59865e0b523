// The manufactured solution the adaptivity tests share: u = (atan(50 (x + y
// - 1)), 0) on the unit square (a steep internal layer), lambda = 1.5, mu =
// 1, Dirichlet data and body force from the solution.

#ifndef forma_tests_elasticity_layer_problem_h
#define forma_tests_elasticity_layer_problem_h

#include <string>

const std::string layer_exact = "atan(50*(x + y - 1)), 0";

/// The problem as parameter text, `initial_refinement` times refined, with
/// `finite_element` the body of the Finite element subsection and `extra`
/// appended (further subsections).
inline std::string
layer_problem(const unsigned int initial_refinement,
              const std::string &finite_element,
              const std::string &extra = "")
{
  const std::string force =
    "250000*(lambda + 3*mu)*(x + y - 1)/(2500*(x + y - 1)^2 + 1)^2, "
    "250000*(lambda + mu)*(x + y - 1)/(2500*(x + y - 1)^2 + 1)^2";
  std::string dirichlet;
  for (unsigned int b = 0; b < 4; ++b)
    dirichlet +=
      std::to_string(b) + " : xy : " + layer_exact + (b < 3 ? " ; " : "");
  return "subsection Mesh\n set Generator = hyper_cube\n"
         " set Generator arguments = 0 : 1 : true\n"
         " set Initial refinement = " +
         std::to_string(initial_refinement) +
         "\nend\n"
         "subsection Finite element\n" +
         finite_element +
         "end\n"
         "subsection Material\n set Bodies = * : lambda = 1.5, mu = 1\nend\n"
         "subsection Boundary conditions\n set Dirichlet = " +
         dirichlet +
         "\n set Constants = lambda = 1.5, mu = 1\nend\n"
         "subsection Loads\n set Body force = " +
         force + "\nend\n" + extra;
}

#endif
