// A material map's plots redrawn from its JSON without rebuilding it: the
// coverage (Fig. 4.14) and the parameter surfaces (Fig. 4.17) at the given
// angles:
//   map_plots <map.json> <output stem> <angle in degrees>...
// writes <stem>_coverage.png and <stem>_parameters_<angle>.png, each with
// its .plot.csv. Built and run by contrib/doc/regenerate_plots.sh.
#include <forma/rhombic/material_map.h>

#include <exception>
#include <iostream>
#include <string>

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
      const std::string stem = argv[2];
      const auto        map  = forma::rhombic::MaterialMap::read(argv[1]);
      map.write_coverage_plot(stem + "_coverage.png");
      for (int i = 3; i < argc; ++i)
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
