#!/bin/sh
# Measures what one case of each study metric costs (docs/cluster.md, "Sizing"):
#
#   sh docs/cluster/case-costs.sh [PAYLOAD_FACTORS]
#
# runs `elasticarm study payload` once per metric on one worker, no journal,
# over the payload factors (default 0:0.1:0.5, 6 cases; the default arm file)
# and prints one Markdown table row per metric: the cases computed, those
# that failed, and the wall time per case (run.time_s / run.cases_computed of
# the JSON summary). Times depend on the machine; the case counts do not.
# EA=... overrides the command (e.g. EA="apptainer exec elasticarm.sif elasticarm").
# shellcheck disable=SC2016 # the table labels hold backquotes
set -eu
EA=${EA:-elasticarm}
factors=${1:-0:0.1:0.5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
num() { awk -v k="\"$2\":" '$1 == k { v = $2; sub(/,$/, "", v); print v; exit }' "$1"; }
# one LABEL NAME STUDY-OPTIONS...
one() {
  label=$1 name=$2
  shift 2
  # shellcheck disable=SC2086 # EA may be a command with arguments
  $EA study payload --payload-factors "$factors" "$@" --threads 1 --no-checkpoint --quiet \
    -o "$tmp/$name.csv" --summary "$tmp/$name.json"
  awk -v l="$label" -v n="$(num "$tmp/$name.json" cases_computed)" \
    -v f="$(num "$tmp/$name.json" failed_cases)" -v t="$(num "$tmp/$name.json" time_s)" \
    'BEGIN { printf "| %s | %d | %d | %.1f ms |\n", l, n, f, t / n * 1e3 }'
}
echo "| metric (options) | cases | failed | wall per case, 1 worker |"
echo "|---|---|---|---|"
one '`workspace` (within the arm'"'"'s limits)' workspace --metrics workspace
one '`frequencies` (`--config 0.4:-20,0.6:-40`, 3 modes)' frequencies --metrics frequencies \
  --config 0.4:-20,0.6:-40
one '`path` (`--path 0.3,-0.2,0.6,-0.2`)' path --metrics path --path 0.3,-0.2,0.6,-0.2
one '`min_time` (`--task problems/examples/studies/shoulder-swing.yaml`)' min_time \
  --metrics min_time --task problems/examples/studies/shoulder-swing.yaml
one '`at_rest` (`--task problems/examples/studies/line-to-0.5.yaml`: 2 plans, 2 FE transients)' at_rest \
  --metrics at_rest --task problems/examples/studies/line-to-0.5.yaml
