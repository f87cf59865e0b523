#!/usr/bin/env bash
# Rewrite doc/parameters/<app>.md from the code (`<app> --parameter-reference`)
# for the four applications; tests/transient_ipc/parameter_reference fails
# when these files are stale.
#
#   bash contrib/doc/update_parameter_reference.sh [build directory]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$root/build}
for app in forma-contact-assembly forma-transient-ipc forma-rhombic forma-laminate; do
  "$build/bin/$app" --parameter-reference > "$root/doc/parameters/$app.md.new"
  mv "$root/doc/parameters/$app.md.new" "$root/doc/parameters/$app.md"
done
