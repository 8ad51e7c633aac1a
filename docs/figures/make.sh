#!/bin/sh
# Regenerates the figures shown in the README, one CLI command each.
# Run from the repository root after building: sh docs/figures/make.sh
set -eu
B=${B:-build/elasticarm}
D=docs/figures
$B workspace --figure $D/fig3-workspace.png > /dev/null                 # paper Fig. 3
$B path --figure $D/fig4-path.png > /dev/null                           # paper Fig. 4
$B frequencies --sweep --figure $D/fig5-frequencies.png > /dev/null     # paper Fig. 5
$B plan problems/examples/paper-line.yaml -o out/paper-line.csv --figure $D/paper-line-plan.png > /dev/null
$B torque-map --figure $D/torque-map.png --csv out/torque-map.csv > /dev/null
$B simulate out/paper-line.csv --figure $D/paper-line-simulated.png > /dev/null
# the README's Python example (docs/example_python.py), with the package of B's build
PYTHONPATH=$(dirname $B)/python /usr/bin/python3 docs/example_python.py $D/python-tip.png > /dev/null
B=$B sh $D/pareto.sh > /dev/null    # duration against FE residual (docs/planner.md), out/pareto.csv
echo "figures written to $D"
