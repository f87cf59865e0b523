#!/bin/bash
# Regenerate the plots in doc/ that the shipped examples draw, and their
# data files (doc/data/<picture>.plot.csv or .plot.csv.gz, redrawn by
# contrib/plot/redraw.py):
#   bash contrib/doc/regenerate_plots.sh            # about 25 minutes, 2 cores
#   WORK=<dir> REUSE=1 bash contrib/doc/regenerate_plots.sh   # continue in <dir>
# The maps' coverage and parameter surfaces are redrawn from the committed
# maps (contrib/rhombic/*.json), without their hours of inverse solves.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$root/build/bin
work=${WORK:-$(mktemp -d)}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$root/doc/data"

# run <app> <app directory> <prm> [mpirun ranks]: output into $work/<prm>/
# (REUSE=1: keep a run that has finished before, e.g. after an interruption).
run() {
  if [ -n "${REUSE:-}" ] && [ -f "$work/$3/summary.json" ]; then
    echo "== $3 (kept)"
    return
  fi
  local launcher=""
  [ "${4:-1}" -gt 1 ] && launcher="mpirun -np $4"
  echo "== $3"
  (cd "$root/parameter_files/$2" &&
     $launcher "$bin/$1" "$3.prm" --set "Output directory=$work/$3" > "$work/$3.log" 2>&1)
}

# keep <run> <plot stem> <doc picture name>: the PNG and its CSV into doc/
# A CSV over 1 MB is gzipped; one still over 1 MB (fine-scale meshes of 10^5
# triangles, 120 x 120 parameter grids) stays out of the repository: the run
# that writes it is the command above it.
keep() {
  cp "$work/$1/$2.png" "$root/doc/$3.png"
  local csv=$work/$1/$2.plot.csv data=$root/doc/data/$3.plot.csv
  rm -f "$data" "$data.gz"
  [ -f "$csv" ] || return 0
  if [ "$(stat -c %s "$csv")" -le 1000000 ]; then
    cp "$csv" "$data"
  else
    gzip -9 -n -c "$csv" > "$data.gz"
    if [ "$(stat -c %s "$data.gz")" -gt 1000000 ]; then
      rm "$data.gz"
      echo "   $3: data not kept ($(stat -c %s "$csv") bytes); rerun to get it"
    fi
  fi
}

run forma-laminate laminate coverage_limit 2
keep coverage_limit coverage laminate_coverage_limit
run forma-laminate laminate coverage_intermediate 2
keep coverage_intermediate coverage laminate_coverage_intermediate
run forma-laminate laminate coverage_bimaterial 2
keep coverage_bimaterial coverage laminate_coverage_bimaterial
run forma-laminate laminate coverage_by_beams 2
keep coverage_by_beams coverage_by_beams laminate_coverage_by_beams
keep coverage_by_beams coverage laminate_coverage_beams_samples
run forma-laminate laminate coverage_phi1 2
keep coverage_phi1 coverage laminate_coverage_phi1
run forma-rhombic rhombic coverage_square 2
keep coverage_square coverage rhombic_coverage_square
run forma-rhombic rhombic twist_study 2
keep twist_study compound_cell rhombic_twist_study
run forma-rhombic rhombic disk_design 2
keep disk_design rhombic_mesh rhombic_disk_mesh
keep disk_design material_E rhombic_disk_E
keep disk_design geometry rhombic_disk_geometry
keep disk_design fine_scale_family rhombic_disk_fine_scale
keep disk_design cut_grid_geometry rhombic_disk_cut_grid_geometry
keep disk_design fine_scale_cut_grid rhombic_disk_cut_grid_fine_scale
run forma-rhombic rhombic ghost_design 2
keep ghost_design fine_scale_family rhombic_ghost_fine_scale
keep ghost_design material_E rhombic_ghost_E
make -C "$root/build" map_plots > /dev/null
mkdir -p "$work/maps"
"$bin/map_plots" "$root/contrib/rhombic/map.json" "$work/maps/shipped" 90 60
"$bin/map_plots" "$root/contrib/rhombic/map_full.json" "$work/maps/full" 90
"$bin/map_plots" "$root/contrib/rhombic/map_wide.json" "$work/maps/wide" \
  --coverage=90,80,70,60 90 60
keep maps shipped_coverage rhombic_map_coverage
keep maps shipped_parameters_90 rhombic_map_parameters_90
keep maps shipped_parameters_60 rhombic_map_parameters_60
keep maps full_parameters_90 rhombic_map_full_parameters_90
keep maps wide_coverage rhombic_map_wide_coverage
keep maps wide_parameters_90 rhombic_map_wide_parameters_90
keep maps wide_parameters_60 rhombic_map_wide_parameters_60
echo "plots in $root/doc, data in $root/doc/data (runs in $work)"
