// A material map's plots redrawn from its JSON without rebuilding it: the
// coverage (Fig. 4.14) and the parameter surfaces (Fig. 4.17) at the given
// angles:
//   map_plots <map.json> <output stem> [--coverage=a,b,...] <angle>...
// writes <stem>_coverage.png (all construction angles, or those listed)
// and <stem>_parameters_<angle>.png, each with its .plot.csv. Built and
// run by contrib/doc/regenerate_plots.sh.
#include <forma/rhombic/material_map.h>

#include <exception>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

int
main(int argc, char **argv)
{
  if (argc < 3)
    {
      std::cerr << "usage: " << argv[0]
                << " <map.json> <output stem> [angle in degrees]...\n";
      return 2;
    }
  try
    {
      const std::string   stem  = argv[2];
      const auto          map   = forma::rhombic::MaterialMap::read(argv[1]);
      int                 first = 3;
      std::vector<double> only;
      const std::string   flag = "--coverage=";
      if (argc > 3 && std::string(argv[3]).rfind(flag, 0) == 0)
        {
          std::istringstream list(std::string(argv[3]).substr(flag.size()));
          for (std::string a; std::getline(list, a, ',');)
            only.push_back(std::stod(a));
          first = 4;
        }
      map.write_coverage_plot(stem + "_coverage.png", only);
      for (int i = first; i < argc; ++i)
        map.write_parameter_surfaces(stem + "_parameters_" + argv[i] + ".png",
                                     std::stod(argv[i]));
    }
  catch (const std::exception &e)
    {
      std::cerr << "error: " << e.what() << '\n';
      return 1;
    }
  return 0;
}
