#!/usr/bin/env bash
# Install forma into a scratch prefix, build doc/examples/my_app against it
# with find_package(forma), and run it: a simulation, Taylor tests of its own
# form, parameterization and objective term in 2D and 3D, the same loaded as
# a plugin by the installed forma-transient-ipc, and a short optimization.
set -euo pipefail
src=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$src/doc/examples/my_app" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/build" -j2 > "$work/build.log"
cd "$work"

# problem DIM MODE OUTPUT: a cantilever on an elastic foundation.
problem() {
  local dim=$1 mode=$2 out=$3 mesh="8, 2 : 0, 0 : 4, 1 : true"
  local dirichlet="0 : xy : 0, 0" traction="1 : 0, -1"
  if [ "$dim" = 3 ]; then
    mesh="4, 1, 1 : 0, 0, 0 : 4, 1, 1 : true"
    dirichlet="0 : xyz : 0, 0, 0"; traction="1 : 0, -1, 0"
  fi
  cat <<PRM
set Dimension = $dim
set Output directory = $out
set Mode = $mode
subsection Mesh
  set Generator = subdivided_hyper_rectangle
  set Generator arguments = $mesh
end
subsection Finite element
  set Degree = 2
end
subsection Material
  set Model = neo-hookean
  set Bodies = * : E = 100, nu = 0.3
end
subsection Boundary conditions
  set Dirichlet = $dirichlet
  set Traction = $traction
end
subsection Loads
  set Additional forms = elastic foundation : k=5
end
subsection Design
  set Parameters = shape, material, foundation stiffness
  set Fixed boundaries = 0, 1
end
subsection Objective
  set Terms = squared displacement ; volume bound : bound=3.9
end
subsection Optimization
  set Max iterations = 4
end
PRM
}

problem 2 simulate simulate > simulate.prm
./build/my_app simulate.prm > simulate.log
grep -q '"status": "ok"' simulate/summary.json
for dim in 2 3; do
  problem $dim "verify gradient" gradient_$dim > gradient_$dim.prm
  ./build/my_app gradient_$dim.prm > gradient_$dim.log
  grep -q '"passed": true' gradient_$dim/summary.json
  grep "min rate" gradient_$dim.log
done
# The same pieces as a plugin of the installed forma-transient-ipc.
{ echo "set Additional shared libraries = build/libmy_plugin.so"
  problem 2 "verify gradient" plugin; } > plugin.prm
lib=$(dirname "$(find prefix -name 'libforma.so' | head -n 1)")
LD_LIBRARY_PATH="$work/$lib" ./prefix/bin/forma-transient-ipc plugin.prm > plugin.log
grep -q '"passed": true' plugin/summary.json
grep "min rate" plugin.log
problem 2 optimize optimize > optimize.prm
./build/my_app optimize.prm > optimize.log
python3 - <<'EOPY'
import json
s = json.load(open("optimize/summary.json"))
assert s["final_objective"] < s["initial_objective"], s
print("optimize: J %.4g -> %.4g" % (s["initial_objective"], s["final_objective"]))
EOPY
echo "installed forma: external application built and ran"
