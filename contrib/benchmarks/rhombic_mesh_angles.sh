#!/usr/bin/env bash
# The quad-to-rhombic meshes of the four two-scale examples (disk, bar,
# pliers, ghost): smallest and mean fitted angle alpha and rhombic error
# after optimization, (a) as the examples ran before (target cap 60
# degrees, no floor), (b) with a larger target cap (Minimum angle 66-80),
# (c) with the angle floor at the thesis's minimum angles (Fig. 4.34:
# pliers 57.4, ghost 64.5, disk 66.0, bar 67.2), and (d) on Gmsh's other
# quad algorithms. Builds rhombic_mesh_angles.cc in build/ (a target
# outside 'all'); writes contrib/benchmarks/results/rhombic_mesh_angles.csv.
# About 1 minute.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
make -C "$root/build" rhombic_mesh_angles > /dev/null
run="$root/build/bin/rhombic_mesh_angles"
meshes="$root/parameter_files/rhombic/meshes"
out="$root/contrib/benchmarks/results/rhombic_mesh_angles.csv"
{
  echo "shape,size,gmsh_algorithm,recombination,cap_degrees,floor_degrees,quads,alpha_min_in,alpha_mean_in,error_mean_in,error_max_in,alpha_min,alpha_mean,error_mean,error_max,smallest_corner,seconds"
  for shape in "disk 0.25 66" "bar 0.25 67.5" "pliers 0.2 57.5" "ghost 0.15 65"; do
    set -- $shape
    for cap in 60 66 70 75 80; do
      echo "$1,$2,6,1,$cap,0,$("$run" "$meshes/$1.geo" "$2" "$cap" 0)"
    done
    echo "$1,$2,6,1,60,$3,$("$run" "$meshes/$1.geo" "$2" 60 "$3")"
    # Gmsh 4.8's Frontal-Delaunay for quads (8) crashes on these
    # geometries; Delaunay (5), Packing of parallelograms (9), and Blossom
    # full-quad recombination (3).
    for ar in "5 1" "9 1" "6 3"; do
      set -- $shape $ar
      echo "$1,$2,$4,$5,60,0,$("$run" "$meshes/$1.geo" "$2" 60 0 "$4" "$5")"
    done
  done
} | tee "$out"
