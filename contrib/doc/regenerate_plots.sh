#!/bin/bash
# Regenerate the plots in doc/ that the shipped examples draw, and their
# data files (doc/data/<picture>.csv or .csv.gz, redrawn by
# contrib/plot/redraw.py):
#   bash contrib/doc/regenerate_plots.sh            # about 25 minutes, 2 cores
# The material-map plots (rhombic_map_*.png) come from `build map`, hours
# of inverse solves: rebuild a map (doc/rhombic.md) and copy its
# map_coverage.png and map_parameters.png by hand.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=$root/build/bin
work=${WORK:-$(mktemp -d)}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$root/doc/data"

# run <app> <app directory> <prm> [mpirun ranks]: output into $work/<prm>/
run() {
  local launcher=""
  [ "${4:-1}" -gt 1 ] && launcher="mpirun -np $4"
  echo "== $3"
  (cd "$root/parameter_files/$2" &&
     $launcher "$bin/$1" "$3.prm" --set "Output directory=$work/$3" > "$work/$3.log" 2>&1)
}

# keep <run> <plot stem> <doc picture name>: the PNG and its CSV into doc/
# (a CSV over 1 MB gzipped: fine-scale meshes have 10^5 triangles).
keep() {
  cp "$work/$1/$2.png" "$root/doc/$3.png"
  local csv=$work/$1/$2.csv
  rm -f "$root/doc/data/$3.csv" "$root/doc/data/$3.csv.gz"
  if [ -f "$csv" ]; then
    if [ "$(stat -c %s "$csv")" -gt 1000000 ]; then
      gzip -9 -n -c "$csv" > "$root/doc/data/$3.csv.gz"
    else
      cp "$csv" "$root/doc/data/$3.csv"
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
echo "plots in $root/doc, data in $root/doc/data (runs in $work)"
