# Sourced by the forma-contact-assembly benchmarks (after `set -e`):
#   . "$(dirname "$0")/contact_setup.sh" <name> "$@"
# Sets app (the benchmark's first argument, or
# build/bin/forma-contact-assembly), here (this directory), examples
# (parameter_files/contact_assembly), work (a temporary directory removed
# on exit) and out (results/<name>.csv), and defines run_with_mesh.
app=$(realpath "${2:-build/bin/forma-contact-assembly}")
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
examples=$(cd "$here/../../parameter_files/contact_assembly" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$here/results/$1.csv"
mkdir -p "$here/results"

# Optimize example $1 (run from $examples) with the further arguments into
# $work/out (output in $work/log), and simulate its starting mesh into
# $work/mesh for the cell count (remeshing runs end on other meshes). A
# failed run leaves no summary.json, so it cannot report the last one.
run_with_mesh() {
  local name=$1
  shift
  rm -rf "$work/out" "$work/mesh"
  "$app" "$name.prm" --set "Output directory=$work/out" \
    --set "Output/Write vtu=false" "$@" > "$work/log" 2>&1 || true
  "$app" "$name.prm" --set "Output directory=$work/mesh" --set "Mode=simulate" \
    --set "Output/Write vtu=false" > "$work/mesh.log" 2>&1 || true
}
