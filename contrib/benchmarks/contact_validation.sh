#!/bin/bash
# Accuracy of the smoothed penalty contact model (thesis ch. 2.6, Figs.
# 2.7-2.8) on a box (2 x 1, E = 1, nu = 0.3, plane strain, P2) pressed by
# p = 0.01 onto a rigid floor, against closed forms:
#  alpha: frictionless, eta = 1e-12: the floor offset is alpha p, so the
#         relative error of the top displacement against the alpha -> 0 limit
#         u0 = -(1 - nu^2) p is alpha / (1 - nu^2) (first order in alpha);
#  eta:   alpha = 1e-6 (alpha p = 1e-8): the offset is alpha p where
#         alpha p >= eta, else 2 sqrt(alpha p eta) - eta (quadratic branch);
#  eta_n: friction mu = 0.5, tangential load 0.1 p (after the normal one),
#         no other support: the block sticks; its slip (bottom center) is set
#         by the regularization, proportional to eta_n;
#  mu:    the same block for mu from 0.09 to 0.16: no equilibrium below the
#         load ratio 0.1 (clear error), then the slip falls with mu.
# Writes results/contact_validation.csv and prints it.
#   contrib/benchmarks/contact_validation.sh [build/bin/forma-contact-assembly]
set -e
. "$(dirname "$0")/contact_setup.sh" contact_validation "$@"
echo "study,parameter,measured,predicted,newton_iterations_last_step" > "$out"
cd "$work"

box() { # dirichlet tangential_load contact_law -> summary in out/
  cat > run.prm <<EOT
set Dimension = 2
set Output directory = out
subsection Mesh
  set Generator = subdivided_hyper_rectangle
  set Generator arguments = 8, 4 : 0, 0 : 2, 1 : true
end
subsection Finite element
  set Degree = 2
end
subsection Material
  set Bodies = * : E = 1, nu = 0.3
end
subsection Boundary conditions
  set Dirichlet = $1
  set Traction = 3 : $2, -0.01 * min(1, 2 * t)
end
subsection Time
  set Load steps = 4
end
subsection Contact
  set Rigid-deformable = 2 : $3
end
subsection Output
  set Write vtu = false
  set Points = 2, 1 ; 1, 0
end
EOT
  "$app" run.prm > run.log 2>&1
}

report() { # study parameter predicted: reads out/summary.json
  python3 - "$@" >> "$out" <<'EOPY'
import json, sys
study, parameter, predicted = sys.argv[1], float(sys.argv[2]), sys.argv[3]
s = json.load(open("out/summary.json"))
steps = s["steps"]
its = steps[-1]["newton_iterations"]
top, bottom = steps[-1]["point_displacements"]
if study in ("alpha", "eta"):
    u0 = -(1 - 0.3**2) * 0.01
    measured = abs(top[1] - u0) / abs(u0)
else:
    measured = bottom[0]  # slip of the bottom center
print("%s,%.4g,%.6g,%s,%d" % (study, parameter, measured, predicted, its))
EOPY
  tail -1 "$out"
}

for k in 0 2 4 6 8 10; do
  a=$(python3 -c "print(1e-7 * 2**$k)")
  box "0 : x : 0" 0 "alpha=$a, eta=1e-12"
  report alpha "$a" "$(python3 -c "print('%.6g' % ($a / (1 - 0.3**2)))")"
done
for e in 1e-9 1e-8 1e-7 1e-6 1e-5 1e-4; do
  box "0 : x : 0" 0 "alpha=1e-6, eta=$e"
  report eta "$e" "$(python3 -c "
import math
ap, e = 1e-8, $e
g = ap if ap >= e else 2 * math.sqrt(ap * e) - e
print('%.6g' % (abs(g) / ((1 - 0.3**2) * 0.01)))")"
done
# Press first, then push sideways: a sliding start has no tangential
# stiffness to begin Newton with.
tangential="if(t < 0.5, 0, 0.001 * (2 * t - 1))"
for en in 1e-6 1e-5 1e-4 1e-3; do
  box "" "$tangential" "alpha=1e-4, eta=1e-6, mu=0.5, eta_n=$en"
  report eta_n "$en" "~eta_n"
done
for mu in 0.09 0.11 0.12 0.13 0.14 0.16; do
  if box "" "$tangential" "alpha=1e-4, eta=1e-6, mu=$mu, eta_n=1e-4"; then
    report mu "$mu" "-"
  else
    echo "mu,$mu,no equilibrium,-,-" >> "$out"
    tail -1 "$out"
  fi
done
