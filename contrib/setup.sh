#!/usr/bin/env bash
# Install what forma needs (Debian packages), configure a Release build in
# build/, build with both cores, then optionally run the main example or the
# test suite.
#
#   bash contrib/setup.sh            install + build
#   bash contrib/setup.sh --run      ... and run the main example
#   bash contrib/setup.sh --test     ... and run the whole test suite
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
action=${1:-}
case "$action" in ""|--run|--test) ;; *) echo "usage: $0 [--run|--test]" >&2; exit 2;; esac

packages=(libdeal.ii-dev libgmsh-dev libsuitesparse-dev libopenblas0-serial numdiff cmake make g++ perl ccache nlohmann-json3-dev libeigen3-dev libcgal-dev libcairo2-dev libpng-dev libtiff-dev fonts-dejavu-core python3-matplotlib openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "forma: installing ${missing[*]}"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# OpenMPI refuses to start as root unless told it may (CI runs as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$root/build" -j2

case "$action" in
  --run)
    cd "$root"
    build/bin/forma-transient-ipc parameter_files/transient_ipc/swinging_strip.prm
    echo
    echo "Results: $root/results/swinging_strip/ (summary.json, solution.pvd for ParaView, log.txt)"
    ;;
  --test)
    cd "$root/build"
    ctest -j2 --output-on-failure
    ;;
esac
