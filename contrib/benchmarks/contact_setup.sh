# Sourced by the forma-contact-assembly benchmarks (after `set -e`):
#   . "$(dirname "$0")/contact_setup.sh" <name> "$@"
# Sets app (the benchmark's first argument, or
# build/bin/forma-contact-assembly), here (this directory), examples
# (parameter_files/contact_assembly), work (a temporary directory removed
# on exit) and out (results/<name>.csv).
app=$(realpath "${2:-build/bin/forma-contact-assembly}")
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
examples=$(cd "$here/../../parameter_files/contact_assembly" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$here/results/$1.csv"
mkdir -p "$here/results"
