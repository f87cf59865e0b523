#!/usr/bin/env bash
# Resource faults (issue 44 item 4): forma-laminate writing onto a full disk.
# Needs root (it mounts a 4 MB tmpfs); run from the repository root after a
# build:
#
#   bash contrib/fuzz/full_disk.sh
#
# Three runs into the same output directory on the small disk:
#   1. enough room: the results are written (exit 0);
#   2. room for the log but not the fields (a checked write fails): exit 1,
#      a clear error, the results of run 1 unchanged;
#   3. no room at all (only unchecked writes: the log, summary.json): the
#      commit sees the full disk, exit 1, the results of run 1 unchanged.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
app=$root/build/bin/forma-laminate
work=$(mktemp -d)
disk=$work/disk
mkdir -p "$disk"
mount -t tmpfs -o size=4m tmpfs "$disk"
trap 'umount "$disk"; rm -rf "$work"' EXIT
sed "s|^set Output directory.*|set Output directory = $disk/out|" \
  "$root/parameter_files/laminate/hexagon_homogenize.prm" > "$work/h.prm"
(cat "$work/h.prm"; printf 'subsection Output\n  set Write vtu = false\nend\n') > "$work/h2.prm"

run() { # name, prm, expected exit code
  set +e
  "$app" "$2" > "$work/$1.txt" 2>&1
  local code=$?
  set -e
  local sum
  sum=$(md5sum "$disk/out/summary.json" | cut -d' ' -f1)
  echo "$1: exit $code (expected $3); summary.json $sum; $(grep 'error:' "$work/$1.txt" || echo 'no error')"
  [ "$code" -eq "$3" ] || { echo "FAILED: $1"; exit 1; }
}
fill_to() { # leave about $1 bytes free
  local avail
  avail=$(df --output=avail -B1 "$disk" | tail -1)
  if [ "$avail" -gt "$1" ]; then
    dd if=/dev/zero of="$disk/filler.$RANDOM" bs=1024 count=$(( (avail - $1) / 1024 )) 2> /dev/null || true
  fi
}

run enough_room "$work/h.prm" 0
good=$(md5sum "$disk/out/summary.json")
fill_to 200000
run no_room_for_fields "$work/h.prm" 1
rm -rf "$disk/out/failed-run"
fill_to 0
dd if=/dev/zero of="$disk/filler.last" bs=1024 count=100000 2> /dev/null || true
run no_room_at_all "$work/h2.prm" 1
[ "$(md5sum "$disk/out/summary.json")" = "$good" ] || { echo "FAILED: the results of the first run changed"; exit 1; }
echo "the results of the first run are intact"
