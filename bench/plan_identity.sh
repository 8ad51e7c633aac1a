#!/bin/sh
# Plans every example task (problems/examples/*.yaml, with the CLI) and a fixed random sweep
# (bench/plan_identity.c) with the build in BUILD and writes every trajectory, JSON summary
# and solve record into OUT, the run ids, wall times and source paths masked; two such
# folders of two builds compare with `diff -r` (identical plans: no output).
# usage: sh bench/plan_identity.sh BUILD OUT [PAIRS]
set -eu
B=$(cd "$1" && pwd)
OUT=$2
PAIRS=${3:-40}
SRC=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$OUT"
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
LINK=$(sed -e 's/^.* -o bench_plan *//' "$B/bench/CMakeFiles/bench_plan.dir/link.txt")
(cd "$B/bench" && eval cc -O2 -I"$SRC/planner/include" -I"$SRC/problems/include" \
  -I"$SRC/model/include" -I"$B/include" "$SRC/bench/plan_identity.c" -o "$OUT/plan_identity" $LINK)
for t in "$SRC"/problems/examples/*.yaml; do
  n=$(basename "$t" .yaml)
  "$B/elasticarm" plan "$t" -o "$OUT/$n.csv" --summary "$OUT/$n.json" --quiet \
    >"$OUT/$n.stdout" 2>"$OUT/$n.stderr" || echo "exit $?" >>"$OUT/$n.stdout"
done
# the FE-in-the-loop refinement of the at-rest examples
for n in paper-line-rest paper-line-robust; do
  "$B/elasticarm" plan "$SRC/problems/examples/$n.yaml" -o "$OUT/$n-refined.csv" --refine --quiet \
    >"$OUT/$n-refined.stdout" 2>"$OUT/$n-refined.stderr" || echo "exit $?" >>"$OUT/$n-refined.stdout"
done
"$OUT/plan_identity" "$OUT" "$PAIRS"
rm -f "$OUT/plan_identity" "$OUT"/*.lock
# mask: run ids, wall times, the stderr's timing words
for f in "$OUT"/*.csv "$OUT"/*.json; do
  [ -f "$f" ] || continue
  sed -i -E -e 's/^# run_id: .*/# run_id: X/' -e 's/("run_id": )"[^"]*"/\1"X"/' \
    -e 's/"predicted_time_to_rest_s"/"PREDICTED_REST"/' \
    -e 's/("([a-z_]*_)?time(_[a-z_]+)?_s"|"elapsed_s"|"initial_guess"|"statics_jacobians"|"solve"|"rest"): [-0-9.e+]+/\1: T/' \
    -e 's/"PREDICTED_REST"/"predicted_time_to_rest_s"/' "$f"
done
sed -i -E -e 's/[0-9.]+ (ms|s)\b/T \1/g' "$OUT"/*.stderr "$OUT"/*.stdout
sed -i -E -e "/\"message\"/s/, [0-9.]+ s;/, T s;/" "$OUT"/*.json
