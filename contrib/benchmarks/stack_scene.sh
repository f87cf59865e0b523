# The IPC scene of ipc_scaling.sh, direct_solvers.sh and ipc_gradient_cost.sh
# (sourced): two stacked Neo-Hookean blocks of P1 tetrahedra dropped on a
# floor plane.
#   stack_scene_prm MESH OUTPUT_DIR END_TIME LINEAR_SOLVER > FILE.prm
stack_scene_prm() {
  cat <<PRM
set Dimension        = 3
set Output directory = $2
subsection Mesh
  set Source               = file
  set File                 = $1
  set Convert to simplices = true
end
subsection Material
  set Model  = neo-hookean
  set Bodies = * : E = 1e5, nu = 0.3, density = 1000
end
subsection Loads
  set Gravity = 0, 0, -9.81
end
subsection Time
  set Problem   = transient
  set End time  = $3
  set Time step = 0.01
end
subsection Solver
  set Linear solver         = $4
  set Max Newton iterations = 100
end
subsection IPC
  set Enabled          = true
  set Barrier distance = 2e-3
  set Obstacles        = plane : 0, 0, 0 : 0, 0, 1
end
subsection Output
  set Write vtu = false
end
PRM
}
