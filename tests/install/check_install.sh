#!/usr/bin/env bash
# Install forma into a scratch prefix, build doc/examples/my_app against it
# with find_package(forma), and run it on a small problem.
set -euo pipefail
src=$1; build=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$src/doc/examples/my_app" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/build" -j2 > "$work/build.log"
cat > "$work/run.prm" <<'PRM'
set Output directory = results
subsection Material
  set Bodies = * : E = 1, nu = 0
end
subsection Boundary conditions
  set Dirichlet = 0 : xy : 0, 0
  set Traction = 1 : 1, 0
end
PRM
cd "$work" && ./build/my_app run.prm
grep -q '"compliance"' results/summary.json
echo "installed forma: external application built and ran"
