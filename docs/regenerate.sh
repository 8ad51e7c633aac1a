#!/bin/sh
# Regenerates the numbers published in README.md and docs/ and checks them.
#
#   sh docs/regenerate.sh            check: rerun the commands, exit 1 if a
#                                    published number differs from the fresh one
#                                    in the digits it is published with
#   sh docs/regenerate.sh --print    the fresh table: file, text as it should
#                                    read, the command that produced it
#   sh docs/regenerate.sh --write    rewrite the published numbers in place, and
#                                    the figures (docs/figures/make.sh)
#   --figures                        (with check or --print) redraw the figures
#                                    too: `git diff docs/figures` shows changes
#   --no-figures                     (with --write) leave the figures alone
#
# Run from anywhere after building (B=build by default; B=other-build to use
# another). Every command's output goes to out/regen/ (NAME.cmd holds the
# command, NAME.out / NAME.err its output). Only deterministic numbers are
# checked: timings and jitter depend on the machine, so the bench tables'
# time columns and the times quoted in the text are matched as "any number"
# ({*} below) or not at all (their outputs stay in out/regen/); bench_stream
# (jitter only) is not run. About 4.5 minutes on 2 cores.
#
# Each check is `pub SOURCE FILE 'TEMPLATE' VALUE...`: TEMPLATE is the
# published text on one line of FILE, with {} where a checked number stands
# (in order, VALUE... formatted with the published digits) and {*} for a
# number that is not checked. The template must match exactly one line.
# shellcheck disable=SC2046,SC2016 # number lists are split on purpose; templates hold backquotes
set -eu
cd "$(dirname "$0")/.."
B=${B:-build}
EA=$B/elasticarm
R=out/regen
mode=check
figures=0
nofig=0
for a in "$@"; do
  case $a in
  --check) mode=check ;;
  --print) mode=print ;;
  --write) mode=write figures=1 ;;
  --figures) figures=1 ;;
  --no-figures) nofig=1 ;;
  -h | --help)
    awk 'NR > 1 && /^# shellcheck/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"
    exit 0
    ;;
  *)
    echo "regenerate.sh: unknown option '$a' (--check, --print, --write, --figures, --no-figures)" >&2
    exit 2
    ;;
  esac
done
for x in "$EA" "$B/bench/bench_statics" "$B/bench/bench_fe" "$B/bench/bench_plan" "$B/tests/test_statics" \
  "$B/tests/test_plan" "$B/tests/test_fe" "$B/tests/test_stream" "$B/tests/test_refine_robust" \
  "$B/tests/test_plan_rest" "$B/tests/test_plan_vib" "$B/tests/test_plan_limits" "$B/tests/test_rom" \
  "$B/tests/test_rom_modes" "$B/tests/test_plan_hess" "$B/tests/test_plan_sweep" "$B/bench/bench_calib" \
  "$B/tests/test_calib_e2e" "$B/tests/test_rest_sweep" "$B/bench/bench_rest" "$B/tests/test_romnl"; do
  [ -x "$x" ] || {
    echo "regenerate.sh: $x not built (cmake -S . -B build && cmake --build build -j2)" >&2
    exit 2
  }
done
mkdir -p "$R"
export EA_CACHE_DIR="${EA_CACHE_DIR:-$R/cache}"
unset EA_ARM_FILE

# run NAME COMMAND...: stdout to $R/NAME.out, stderr to $R/NAME.err.
run() {
  name=$1
  shift
  echo "$*" >"$R/$name.cmd"
  rc=0
  "$@" >"$R/$name.out" 2>"$R/$name.err" || rc=$?
  if [ $rc -ne 0 ] && [ $rc -ne 77 ]; then # 77: a test that skipped a part (no pty)
    echo "regenerate.sh: failed ($rc): $*" >&2
    tail -20 "$R/$name.err" >&2
    exit 1
  fi
}
# jnum FILE KEY: a top-level number of a pretty-printed JSON file.
jnum() {
  awk -v k="\"$2\":" '$1 == k { v = $2; sub(/,$/, "", v); print v; exit }' "$1"
}
# calc 'printf-format' 'awk expression'
calc() { awk "BEGIN { printf \"$1\", $2 }"; }
# sci 'printf-format' 'awk expression': calc with a short exponent (2.0e-4)
sci() { calc "$1" "$2" | sed 's/e\([-+]\)0*\([0-9]\)/e\1\2/'; }

echo "== running the commands (outputs in $R/)"
# The README's main job and its FE transient.
run plan "$EA" plan problems/examples/paper-line.yaml -o "$R/paper-line.csv"
run simulate "$EA" simulate "$R/paper-line.csv" --json -o "$R/paper-line-sim.csv"
# Fig. 5, and the same sweep for other hand inertias I_L (README, FE model).
run fig5 "$EA" frequencies --sweep --csv "$R/fig5.csv"
for il in 0 4.0e-4 8.0e-4 1.2e-3 2.0e-3; do
  sed "s/^\( *Izz_kg_m2:\) *[-+.0-9e]*/\1 $il/" data/elasticarm.yaml >"$R/arm-IL-$il.yaml"
  grep -q "Izz_kg_m2: $il " "$R/arm-IL-$il.yaml" || {
    echo "regenerate.sh: could not set Izz_kg_m2 in $R/arm-IL-$il.yaml" >&2
    exit 1
  }
  run "fig5-IL-$il" "$EA" frequencies --sweep --arm "$R/arm-IL-$il.yaml" --csv "$R/fig5-IL-$il.csv"
done
# Statics accuracy: the work-precision table (errors; times vary) and tests.
run bench_statics "$B/bench/bench_statics" 1
run test_statics "$B/tests/test_statics"
run test_plan "$B/tests/test_plan"
run test_stream "$B/tests/test_stream"
# README.md: arriving at rest (each plan's FE transient by plan --verify), robust rest.
run plan-zv "$EA" plan problems/examples/paper-line.yaml --shape zv --verify -o "$R/paper-line-zv.csv"
run plan-rest "$EA" plan problems/examples/paper-line-rest.yaml --verify -o "$R/paper-line-rest.csv"
run plan-refined "$EA" plan problems/examples/paper-line-rest.yaml --refine --verify \
  -o "$R/paper-line-refined.csv"
run test_refine_robust env EA_SOURCE_DIR=. "$B/tests/test_refine_robust"
# docs/planner.md: plans that arrive at rest judged by the FE transient (~40 s).
run test_plan_rest env EA_SOURCE_DIR=. "$B/tests/test_plan_rest"
# docs/planner.md: the at-rest plan's knots, grid and replanning (bench_dyn, ~50 s).
run bench_dyn "$B/bench/bench_dyn"
# docs/planner.md: the random sweep of verified at-rest plans (~80 s).
run test_rest_sweep env EA_SOURCE_DIR=. "$B/tests/test_rest_sweep"
# docs/planner.md: time per verified at-rest plan (bench_rest, ~1 min).
run bench_rest "$B/bench/bench_rest" 20 7
# docs/planner.md: the same by the nonlinear reduced model (refine.by; ~1 min each).
run bench_rest_model_only "$B/bench/bench_rest" 20 7 model_only
run bench_rest_model "$B/bench/bench_rest" 20 7 model
# docs/fe.md, docs/planner.md: the nonlinear reduced model against the FE (~40 s).
run test_romnl env EA_SOURCE_DIR=. "$B/tests/test_romnl"
# docs/planner.md: the dynamics rows' Hessian against its reference (~1 s).
run test_plan_hess env EA_SOURCE_DIR=. "$B/tests/test_plan_hess"
# docs/planner.md: 200 random tasks, free and line paths (~15 s).
run test_plan_sweep env EA_SOURCE_DIR=. "$B/tests/test_plan_sweep"
# docs/fe.md: the reduced model's accuracy (~2 s).
run test_rom env EA_SOURCE_DIR=. EA_BINARY="$EA" "$B/tests/test_rom"
# docs/planner.md: the shoulder-limited line against its time-optimal reference (~6 s).
run test_plan_limits env EA_SOURCE_DIR=. EA_BINARY="$EA" "$B/tests/test_plan_limits"
# docs/planner.md: the frequency-weighted surrogate against the FE transient (~5 s).
run test_plan_vib env EA_SOURCE_DIR=. EA_BINARY="$EA" "$B/tests/test_plan_vib"
# README.md: the planner's iteration counts (bench_plan, ~70 s; times vary).
run bench_plan "$B/bench/bench_plan"
# docs/planner.md: the paper line with many knots (~35 s in all).
for n in 1000 2000 3000 4000; do
  run "plan-knots-$n" "$EA" plan problems/examples/paper-line.yaml --knots "$n" -o "$R/paper-line-k$n.csv"
done
# docs/fe.md: the FE tests and the mesh convergence table (times vary).
run test_fe "$B/tests/test_fe"
run bench_fe "$B/bench/bench_fe"
# docs/streaming.md: the smooth plan streamed to the controller simulator,
# which simulates what it accepted; the trajectory file simulated alike.
run plan-smooth "$EA" plan problems/examples/paper-line-smooth.yaml -o "$R/paper-line-smooth.csv"
run simulate-smooth "$EA" simulate "$R/paper-line-smooth.csv" --scheme energy --settle 1 --json \
  -o "$R/paper-line-smooth-sim.csv"
rm -f "$R/ctrl.port"
echo "$EA controller-sim --port-file $R/ctrl.port --log $R/ctrl-log.csv --simulate $R/ctrl-tip.csv --json" \
  >"$R/controller-sim.cmd"
"$EA" controller-sim --port-file "$R/ctrl.port" --log "$R/ctrl-log.csv" \
  --simulate "$R/ctrl-tip.csv" --json >"$R/controller-sim.out" 2>"$R/controller-sim.err" &
ctrl=$!
i=0
while [ ! -s "$R/ctrl.port" ] && [ $i -lt 100 ]; do
  sleep 0.1
  i=$((i + 1))
done
[ -s "$R/ctrl.port" ] || {
  echo "regenerate.sh: controller-sim did not start" >&2
  kill "$ctrl" 2>/dev/null
  exit 1
}
run stream "$EA" stream "$R/paper-line-smooth.csv" --to "tcp://127.0.0.1:$(cat "$R/ctrl.port")"
wait "$ctrl" || {
  echo "regenerate.sh: controller-sim failed" >&2
  cat "$R/controller-sim.err" >&2
  exit 1
}
run stream-line "$EA" stream "$R/paper-line.csv" --to "file:$R/paper-line.frames"
# docs/studies.md: the design study, and min_time of the paper line for two payloads.
run study-design "$EA" study problems/examples/studies/design.yaml -o "$R/design.csv" --threads 1 \
  --no-checkpoint --quiet
run study-line "$EA" study payload --payload-factors 0,0.25 --metrics min_time \
  --task problems/examples/paper-line.yaml -o "$R/study-line.csv" --threads 1 --no-checkpoint --quiet
run study-rest "$EA" study problems/examples/studies/payload-rest.yaml -o "$R/payload-rest.csv" \
  --no-checkpoint --quiet
# docs/calibration.md: the example identification experiment.
run calib-experiment "$EA" calibrate-experiment problems/examples/calibration/experiment.yaml \
  -o "$R/calib-experiment.csv" --json
# docs/calibration.md: the bench table (~45 s) and the end-to-end test (~80 s; it writes its
# files in the working folder: $R/e2e).
run bench_calib "$B/bench/bench_calib"
mkdir -p "$R/e2e"
run test_calib_e2e sh -c 'cd "$1" && EA_SOURCE_DIR="$2" EA_BINARY="$3" "$4"' sh "$R/e2e" "$PWD" \
  "$(cd "$(dirname "$EA")" && pwd)/$(basename "$EA")" "$(cd "$B/tests" && pwd)/test_calib_e2e"
if [ $figures = 1 ] && [ $nofig = 0 ]; then
  echo "== figures (docs/figures/make.sh)"
  B="$EA" sh docs/figures/make.sh
fi

# ---------------------------------------------------------------- checks
FAILS=$R/fails.txt
: >"$FAILS"
: >"$R/table.txt"
# pub SOURCE FILE TEMPLATE VALUE...
pub() {
  src=$1 file=$2 tmpl=$3
  shift 3
  vals=""
  sep=$(printf '\034')
  for v in "$@"; do vals="$vals$v$sep"; done
  EA_T=$tmpl EA_V=$vals EA_S=$src EA_F=$file EA_TABLE=$R/table.txt awk -v mode="$mode" -f - "$file" \
    >"$R/rewrite.tmp" 2>>"$FAILS" <<'AWK'
function esc(s) { gsub(/[][\\^$.|()*+?{}]/, "\\\\&", s); return s }
BEGIN {
  NUM = "[-+]?[0-9]+(,[0-9][0-9][0-9])*(\\.[0-9]+)?([eE][-+]?[0-9]+)?"
  t = ENVIRON["EA_T"]; nv = split(ENVIRON["EA_V"], V, "\034") - 1
  k = 0; lit = ""
  while (length(t) > 0) {
    if (substr(t, 1, 2) == "{}") { L[k] = lit; lit = ""; P[++k] = "v"; t = substr(t, 3) }
    else if (substr(t, 1, 3) == "{*}") { L[k] = lit; lit = ""; P[++k] = "*"; t = substr(t, 4) }
    else { lit = lit substr(t, 1, 1); t = substr(t, 2) }
  }
  L[k] = lit
  re = esc(L[0]); for (j = 1; j <= k; j++) re = re NUM esc(L[j])
  n = 0
}
{ line[NR] = $0; if (match($0, re)) { n++; at = NR; s0 = RSTART; len = RLENGTH } }
END {
  where = ENVIRON["EA_F"]
  if (n != 1) {
    printf "%s: the text '%s' is on %d lines, not one: update docs/regenerate.sh\n", \
      where, ENVIRON["EA_T"], n > "/dev/stderr"
    for (i = 1; i <= NR; i++) print line[i]
    exit
  }
  m = substr(line[at], s0, len); pos = length(L[0]) + 1; out = L[0]; vi = 0; bad = ""
  for (j = 1; j <= k; j++) {
    match(substr(m, pos), "^" NUM); pubv = substr(m, pos, RLENGTH); pos += RLENGTH
    if (substr(m, pos, length(L[j])) != L[j]) {
      printf "%s:%d: cannot read the numbers of '%s'\n", where, at, ENVIRON["EA_T"] > "/dev/stderr"
      for (i = 1; i <= NR; i++) print line[i]
      exit
    }
    pos += length(L[j])
    if (P[j] == "v") {
      fresh = V[++vi]
      if (pubv != fresh) bad = bad sprintf(" %s -> %s", pubv, fresh)
      out = out fresh L[j]
    } else out = out pubv L[j]
  }
  if (vi != nv) printf "%s: '%s' has %d {} but %d values\n", where, ENVIRON["EA_T"], vi, nv > "/dev/stderr"
  if (bad != "")
    printf "%s:%d: published%s (%s; from: %s)\n", where, at, bad, out, ENVIRON["EA_S"] > "/dev/stderr"
  printf "%s: %s\n    <- %s\n", where, out, ENVIRON["EA_S"] >> ENVIRON["EA_TABLE"]
  for (i = 1; i <= NR; i++) print (i == at ? substr(line[i], 1, s0 - 1) out substr(line[i], s0 + len) : line[i])
}
AWK
  if [ $mode = write ] && ! cmp -s "$R/rewrite.tmp" "$file"; then
    cat "$R/rewrite.tmp" >"$file"
  fi
}

# block NAME FILE OUT FIRST LAST [MORE]: the fenced block after the line
# `<!-- regen: NAME -->` in FILE is the lines of OUT from the first one starting with FIRST
# through the next one starting with LAST and MORE lines after it. Compared with the time columns masked (mask_times: the five time
# columns of a bench_plan row, the per-iteration time, the update time); --write puts in
# the fresh lines, times included.
mask_times() {
  awk '{
    n = split($0, a, " ")
    if (n >= 10 && a[n] ~ /^[0-9.]+$/ && a[n - 6] ~ /^[0-9]+$/ && a[n - 7] ~ /^[0-9]+$/)
      for (i = n - 5; i < n; i++) a[i] = "*"
    if ($0 ~ /\(per iteration\)/) a[1] = "*"
    if ($0 ~ /\(ea_planner_update [0-9.]+ ms[;)]/) a[2] = "*"
    o = a[1]; for (i = 2; i <= n; i++) o = o " " a[i]; print o }'
}
block() {
  name=$1 file=$2 out=$3 first=$4 last=$5 more=${6:-0}
  awk -v f="$first" -v l="$last" -v m="$more" 'k == 0 && index($0, f) == 1 { k = 1 }
    k == 2 && m-- <= 0 { exit } k >= 1 { print } k == 1 && index($0, l) == 1 { k = 2; if (m == 0) exit }' \
    "$out" >"$R/block.fresh"
  awk -v tag="<!-- regen: $name -->" 'st == 2 && /^```/ { exit } st == 2 { print } st == 1 { st = 2 } $0 == tag { st = 1 }' \
    "$file" >"$R/block.pub"
  if [ ! -s "$R/block.fresh" ] || [ ! -s "$R/block.pub" ]; then
    echo "$file: block '$name' or its lines in $out ('$first' .. '$last') not found: update docs/regenerate.sh" >>"$FAILS"
    return
  fi
  mask_times <"$R/block.fresh" >"$R/block.fresh.m"
  mask_times <"$R/block.pub" >"$R/block.pub.m"
  if ! cmp -s "$R/block.fresh.m" "$R/block.pub.m"; then
    echo "$file: block '$name' differs from $out outside the time columns:" >>"$FAILS"
    diff "$R/block.pub.m" "$R/block.fresh.m" | head -6 | sed 's/^/    /' >>"$FAILS"
  fi
  printf '%s: block %s (%s lines)\n    <- %s\n' "$file" "$name" "$(wc -l <"$R/block.fresh")" "${out#"$R"/}" >>"$R/table.txt"
  if [ $mode = write ]; then
    awk -v tag="<!-- regen: $name -->" -v fresh="$R/block.fresh" '
      st == 2 && /^```/ { while ((getline x < fresh) > 0) print x; st = 3 }
      st == 2 { next }
      { print }
      st == 1 { st = 2 }
      $0 == tag { st = 1 }' "$file" >"$R/rewrite.tmp"
    cmp -s "$R/rewrite.tmp" "$file" || cat "$R/rewrite.tmp" >"$file"
  fi
}

# --- README.md: the main job (plan) and its FE transient (simulate)
dur=$(jnum "$R/paper-line.json" duration_s)
track=$(jnum "$R/simulate.out" max_tracking_error_m)
rms=$(jnum "$R/simulate.out" residual_vibration_rms_m)
pub "plan paper-line.yaml (duration_s)" README.md 'the minimum-time plan, {} s on' "$(calc %.2f "$dur")"
pub "simulate (max_tracking_error_m, residual_vibration_rms_m)" README.md \
  'up to {} mm off the quasi-static path and vibrating {} mm rms' \
  "$(calc %.0f "$track*1e3")" "$(calc %.0f "$rms*1e3")"
pub "plan paper-line.yaml (duration_s)" README.md '(100 knots, minimum time, {} s)' "$(calc %.5f "$dur")"
# test_plan's checks of that plan: the knots re-solved cold, the closed form.
resolve=$(awk '/^PASS: paper line: plan vs cold re-solve/ { sub(/.*abs err /, ""); print $1 + 0 }' "$R/test_plan.out")
closed=$(awk '/^PASS: paper line: duration vs closed form/ { sub(/.*rel err /, ""); print $1 + 0 }' "$R/test_plan.out")
topp=$(awk '/^PASS: min time vs time-optimal path/ { sub(/.*rel err /, ""); print $1 + 0 }' "$R/test_plan.out")
pub "tests/test_plan (paper line: plan vs cold re-solve)" README.md 're-solved independently agrees to {};' \
  "$(sci %.0e "$resolve")"
pub "tests/test_plan (paper line: duration vs closed form)" README.md \
  'of the nominal speed and acceleration limits, D/v + v/a, to {} relative' "$(sci %.1e "$closed")"
pub "tests/test_plan (min time vs time-optimal path parameterisation)" README.md \
  'within {} relative of, and not below, an independent' "$(sci %.1e "$topp")"

# --- README.md: arriving at rest (the table and the robust paragraph)
qpk=$(jnum "$R/simulate.out" residual_vibration_peak_m)
pub "plan paper-line.yaml; simulate (residual_vibration_peak_m)" README.md \
  '| quasi-static, minimum time (`paper-line.yaml`) | {} s | {} mm |' "$(calc %.4f "$dur")" \
  "$(calc %.2f "$qpk*1e3")"
for c in zv:'the same, ZV-shaped (`plan --shape zv`)':%.3f rest:'at rest in the model (`paper-line-rest.yaml`)':%.3f \
  refined:'the same with `--refine` (FE in the loop)':%.4f; do
  name=${c%%:*} rest=${c#*:} label=${rest%:*} fmt=${rest##*:}
  f=$R/paper-line-$name.json
  pub "plan $name --verify (duration_s, measured_residual_peak_m)" README.md "| $label | {} s | {} mm |" \
    "$(calc %.4f "$(jnum "$f" duration_s)")" "$(calc "$fmt" "$(jnum "$f" measured_residual_peak_m)*1e3")"
done
# test_refine_robust: 'robust refined plan  T s: nominal X mm, light, soft X mm, ...'
rob() { awk -v w="$1" 'index($0, "  " w " ") == 1 && / s: /' "$R/test_refine_robust.out"; }
# the largest corner residual (every "X mm" after the nominal's), to the published 3 digits
rmax() { echo "$1" | awk '{ m = 0; c = 0; for (i = 2; i <= NF; i++) if ($i ~ /^mm,?$/ && c++) m = ($(i - 1) + 0 > m) ? $(i - 1) + 0 : m; printf "%.3f", m }'; }
rr=$(rob "robust refined plan")
nr=$(rob "non-robust at-rest plan (2 modes)")
pub "tests/test_refine_robust (robust refined plan)" README.md \
  'EI +-5 %, five models in the transcription, refined against five FE transients): {} s,' \
  "$(echo "$rr" | awk '{ for (i = 1; i <= NF; i++) if ($i == "s:") print $(i - 1) }')"
pub "tests/test_refine_robust (corners: max of the four)" README.md \
  'FE residual at the four corner arms at most {} mm (the non-robust at-rest plan: up to' "$(rmax "$rr")"
pub "tests/test_refine_robust (non-robust plan's corners: max)" README.md '{} mm there).' "$(rmax "$nr")"

# --- docs/planner.md: arriving at rest (tests/test_plan_rest's lines)
# field N (1-based, blank-separated, trailing ',;()x%' dropped) of the line starting with P
tf() { awk -v p="$1" -v n="$2" 'index($0, p) == 1 { v = $n; gsub(/[,;()x%]/, "", v); print v; exit }' \
  "$R/test_plan_rest.out"; }
for g in 0.00:'paper line, payload 0' 0.25:'paper line, payload factor 0.25' \
  0.50:'line to (0.5, -0.2), payload factor 0.5'; do
  p="payload factor ${g%%:*}:" label=${g#*:}
  pub "tests/test_plan_rest ($p)" docs/planner.md "| $label | {} s, {} mm | {} s ({} x), {} mm |" \
    "$(calc %.4f "$(tf "$p" 5)")" "$(calc %.2f "$(tf "$p" 9)")" "$(calc %.3f "$(tf "$p" 26)")" \
    "$(calc %.2f "$(tf "$p" 29)")" "$(calc %.2f "$(tf "$p" 36)")"
done
pub "tests/test_plan_rest (paper-line.yaml: path and knot transcriptions)" docs/planner.md \
  'line gives {} s against {} s with knots' "$(tf "paper-line.yaml: knots" 10)" \
  "$(tf "paper-line.yaml: knots" 3)"
share() { calc %.1f "$(tf "payload factor $1:" 38)"; }
pub "tests/test_plan_rest (FE residual share of the quasi-static)" docs/planner.md \
  'What is left is what the model misses ({} %, {} % and {} % of the quasi-static residual:' \
  "$(share 0.00)" "$(share 0.25)" "$(share 0.50)"
pub "tests/test_plan_rest (pick-place-3d)" docs/planner.md '| pick-place-3d | {} s, {} mm | {} s, {} mm |' \
  "$(calc %.3f "$(tf "pick-place-3d.yaml: quasi-static" 3)")" "$(calc %.2f "$(tf "pick-place-3d.yaml: quasi-static" 7)")" \
  "$(calc %.3f "$(tf "pick-place-3d.yaml: quasi-static" 11)")" "$(calc %.3f "$(tf "pick-place-3d.yaml: quasi-static" 15)")"
pub "tests/test_plan_rest (polyline-effort)" docs/planner.md \
  '| polyline-effort (3 s, min effort) | 3 s, {} mm | 3 s, {} mm |' \
  "$(calc %.2f "$(tf "polyline-effort.yaml: quasi-static" 7)")" "$(calc %.2f "$(tf "polyline-effort.yaml: quasi-static" 15)")"
pub "tests/test_plan_rest (residual_m 5 mm)" docs/planner.md '{} mm in the FE against {} mm predicted.' \
  "$(calc %.2f "$(tf 'residual_m 5 mm:' 17)")" "$(calc %.2f "$(tf 'residual_m 5 mm:' 10)")"
# the limits table: durations against their references
set -- $(awk '/^shoulder-limited line: plan / { print $4, $8 }' "$R/test_plan_limits.out")
pub "tests/test_plan_limits (shoulder-limited line)" docs/planner.md \
  '| line (0.25, -0.45) -> (0.6, -0.3), payload factor 0.25 | {} s | {} s time-optimal path parameterisation with theta0 from the statics ({} %) |' \
  "$(calc %.6f "$1")" "$(calc %.6f "$2")" "$(calc %+.3f "($1/$2-1)*100")"
set -- $(awk '/^PASS: min time vs time-optimal path/ { print $9, $11 }' "$R/test_plan.out")
pub "tests/test_plan (TOPP task)" docs/planner.md \
  '| TOPP task of tests/test_plan.c (alpha limited too) | {} s | {} s ({} %) |' \
  "$(calc %.5f "$1")" "$(calc %.5f "$2")" "$(calc %+.3f "($1/$2-1)*100")"
cf2=$(awk '/^PASS: paper line: duration vs closed form/ { sub(/.*want /, ""); print $1 }' "$R/test_plan.out")
pub "plan paper-line.yaml; tests/test_plan (closed form)" docs/planner.md \
  '| paper line (problems/examples/paper-line.yaml) | {} s | {} s closed form D/v + v/a ({} %) |' \
  "$(calc %.5f "$dur")" "$(calc %.6f "$cf2")" "$(calc %+.3f "($dur/$cf2-1)*100")"
th0=$(awk '/^paper line: [0-9]+ samples/ { for (i = 1; i <= NF; i++) if ($i == "statics" && $(i - 1) == "vs") { print $(i + 1); exit } }' "$R/test_plan.out")
pub "tests/test_plan (theta0 cubic vs statics at 1 kHz)" docs/planner.md \
  'agrees with the statics at the interpolated (L_c, alpha) to {} rad on' "$(sci %.1e "$th0")"
gap() { awk -v c="$1 knots" 'index($0, c) == 1 { getline; sub(/.* = /, ""); print $1 + 0; exit }' "$R/bench_plan.out"; }
pub "bench/bench_plan (scaling with the knot count: t_f / (D/v + v/a) - 1)" docs/planner.md \
  'interval at each acceleration switch, O(h): {}, {}, {}, {},' \
  "$(sci %.1e "$(gap 25)")" "$(sci %.1e "$(gap 50)")" "$(sci %.1e "$(gap 100)")" "$(sci %.1e "$(gap 200)")"
pub "bench/bench_plan (scaling with the knot count: t_f / (D/v + v/a) - 1)" docs/planner.md \
  '{} at 25, 50, 100, 200, 400 knots on the paper line (bench_plan).' "$(sci %.1e "$(gap 400)")"
# the surrogate's table: FE residual peaks of the 3 s paper line by objective
set -- $(awk '/^residual vibration peak \(FE transient, 3 s after a 3 s paper line\)/ {
  for (i = 1; i <= NF; i++) if ($i == "mm," || $i == "mm") v = v " " $(i - 1); print v }' "$R/test_plan_vib.out")
pub "tests/test_plan_vib (min_effort)" docs/planner.md '| min_effort | {} mm |' "$1"
pub "tests/test_plan_vib (min_jerk)" docs/planner.md '| min_jerk | {} mm |' "$2"
pub "tests/test_plan_vib (min_vibration)" docs/planner.md '| min_vibration | {} mm ({} % of min_effort) |' \
  "$3" "$(calc %.0f "$3/$1*100")"
pub "tests/test_plan_rest (min_vibration on the model)" docs/planner.md \
  '`min_vibration` on the model at 3 s: {} mm' "$(calc %.3f "$(tf '3 s paper line' 20)")"
pub "tests/test_plan_rest (surrogate, min_effort)" docs/planner.md \
  '(the f1-weighted surrogate: {} mm; minimum effort: {} mm).' \
  "$(calc %.2f "$(tf '3 s paper line' 10)")" "$(calc %.2f "$(tf '3 s paper line' 13)")"

# --- README.md: Fig. 5 (first row of the CSV: L_c = 0.254 m, last: 0.635 m)
# fig5 CSV -> "f1_short f1_long f2_short f2_long f3_short f3_long" [Hz]
ends() { awk -F, 'NR == 2 { a = $2 " " $3 " " $4 } NR > 2 { b = $2 " " $3 " " $4 } END { print a, b }' "$1"; }
set -- $(ends "$R/fig5.csv")
pub "frequencies --sweep --csv" README.md '| f1, as the cable shortens | {} -> {} Hz, **{} %** | +55 % |' \
  "$(calc %.3f "$4")" "$(calc %.3f "$1")" "$(calc %+.1f "($1/$4-1)*100")"
pub "frequencies --sweep --csv" README.md '| f2, as the cable lengthens | {} -> {} Hz, **{} %** | +38 % |' \
  "$(calc %.2f "$2")" "$(calc %.2f "$5")" "$(calc %+.1f "($5/$2-1)*100")"
pub "frequencies --sweep --csv" README.md '| f3, as the cable lengthens | {} -> {} Hz, **{} %** | +12 % |' \
  "$(calc %.2f "$3")" "$(calc %.2f "$6")" "$(calc %+.1f "($6/$3-1)*100")"
pub "frequencies --sweep --csv" docs/cli-fe.md '101 lengths): f1 {} -> {} Hz, **{} %**' \
  "$(calc %.4f "$4")" "$(calc %.4f "$1")" "$(calc %+.1f "($1/$4-1)*100")"
pub "frequencies --sweep --csv" docs/cli-fe.md 'as the cable shortens (paper 55 %); f2 {} -> {} Hz, **{} %**, f3 {} ->' \
  "$(calc %.4f "$2")" "$(calc %.4f "$5")" "$(calc %+.1f "($5/$2-1)*100")" "$(calc %.3f "$3")"
pub "frequencies --sweep --csv" docs/cli-fe.md '{} Hz, **{} %** as it lengthens (paper 38 % and 12 %' \
  "$(calc %.3f "$6")" "$(calc %+.1f "($6/$3-1)*100")"
f1min=1e9 f1max=-1e9
for il in 0 4.0e-4 8.0e-4 1.2e-3 2.0e-3; do
  set -- $(ends "$R/fig5-IL-$il.csv")
  f1=$(calc %.1f "($1/$4-1)*100")
  f3=$(calc %.0f "($6/$3-1)*100")
  label=$il
  [ "$il" = 4.0e-4 ] && label="4.0e-4 (Table 2)"
  [ "$il" = 1.2e-3 ] && f3_12=$f3
  pub "frequencies --sweep --arm (I_L = $il) --csv" README.md "| $label | {} % | {} % | {} % |" \
    "$(calc %+.1f "($1/$4-1)*100")" "$(calc %+.1f "($5/$2-1)*100")" "$(calc %+.1f "($6/$3-1)*100")"
  f1min=$(calc %.1f "($f1 < $f1min) ? $f1 : $f1min")
  f1max=$(calc %.1f "($f1 > $f1max) ? $f1 : $f1max")
done
pub "frequencies --sweep --arm (I_L sweep)" README.md 'is insensitive ({}-{} %)' "$f1min" "$f1max"
pub "frequencies --sweep --arm (I_L = 1.2e-3)" README.md "Table 2's, at which f3 rises {} %" "$f3_12"

# --- README.md: statics accuracy (bench_statics: errors checked, times not)
row() { # row INTEGRATOR STEPS -> "it tip T theta0" as printed by the bench
  awk -F' *[|] *' -v a="$1" -v b="$2" '$2 == a && $3 == b { print $5, $6, $7, $8 }' "$R/bench_statics.out"
}
bench() { # bench 'README row template' INTEGRATOR STEPS
  set -- "$1" $(row "$2" "$3")
  pub "bench/bench_statics (errors; times vary)" README.md "$1" "$2" \
    "$(calc %.1e "$3")" "$(calc %.1e "$4")" "$(calc %.1e "$5")"
}
bench '| rk8pd-fixed | 8 steps | {*} | {} | {} | {} | {} |' rk8pd-fixed "8 steps"
bench '| **rk8pd-fixed (default)** | **12 steps** | **{*}** | {} | **{}** | **{}** | **{}** |' \
  rk8pd-fixed "12 steps"
bench '| rk8pd-fixed | 16 steps | {*} | {} | {} | {} | {} |' rk8pd-fixed "16 steps"
bench '| rk4-fixed | 200 steps | {*} | {} | {} | {} | {} |' rk4-fixed "200 steps"
bench '| rk8pd-adaptive | tol 1e-9 | {*} | {} | {} | {} | {} |' rk8pd-adaptive "tol 1e-09"
bench '| rkf45-adaptive | tol 1e-9 | {*} | {} | {} | {} | {} |' rkf45-adaptive "tol 1e-09"
green=$(awk '/Greenhill critical length/ { sub(/.*rel err /, ""); print $1 + 0 }' "$R/test_statics.out")
pub "tests/test_statics (Greenhill)" README.md '({} relative), sensitivities' "$(sci %.1e "$green")"

# --- docs/streaming.md: the stream and the controller simulator
sent=$(awk '/setpoints .* at 1000 Hz/ { print $2 }' "$R/stream.out")
acked=$(awk '/setpoints .* at 1000 Hz/ { sub(/.*acknowledged /, ""); print $1 + 0 }' "$R/stream.out")
pub "stream paper-line-smooth.csv (TCP, controller-sim)" docs/streaming.md \
  '  setpoints {} at 1000 Hz, frames sent {} (stop ramp 0), acknowledged {}, late {*}' \
  "$sent" "$sent" "$acked"
c_rows=$(jnum "$R/controller-sim.out" sim_tip_rows)
c_rms=$(jnum "$R/controller-sim.out" residual_vibration_rms_m)
c_peak=$(jnum "$R/controller-sim.out" residual_vibration_peak_m)
s_rms=$(jnum "$R/simulate-smooth.out" residual_vibration_rms_m)
s_peak=$(jnum "$R/simulate-smooth.out" residual_vibration_peak_m)
pub "controller-sim --simulate (sim_tip_rows)" docs/streaming.md '(3 s, {} setpoints): tip history of {} rows;' \
  "$sent" "$c_rows"
pub "controller-sim --simulate (residual_vibration_*)" docs/streaming.md 'residual vibration rms {} mm, peak {} mm,' \
  "$(calc %.4f "$c_rms*1e3")" "$(calc %.4f "$c_peak*1e3")"
pub "simulate --scheme energy --settle 1 (residual_vibration_*)" docs/streaming.md \
  'the trajectory file ({} / {} mm;' "$(calc %.4f "$s_rms*1e3")" "$(calc %.4f "$s_peak*1e3")"
tipd() { # distance [um] of final_static_tip_m (the JSON's array line) from (0.6, -0.2)
  awk -v k="\"$2\":" '$1 == k { gsub(/[][,]/, " "); printf "%.1f", sqrt(($2 - 0.6)^2 + ($3 + 0.2)^2) * 1e6; exit }' "$1"
}
pub "controller-sim / simulate (final static tip - planned end)" docs/streaming.md \
  '{} / {} um from the planned end' \
  "$(tipd "$R/controller-sim.out" sim_final_static_tip_m)" "$(tipd "$R/simulate-smooth.out" final_static_tip_m)"
line_sp=$(awk '/setpoints .* at 1000 Hz/ { print $2 }' "$R/stream-line.out")
pub "plan paper-line.yaml; stream --to file:" docs/streaming.md '`problems/examples/paper-line.yaml` plan ({} s)' \
  "$(calc %.3f "$dur")"
pub "stream paper-line.csv --to file: (setpoints)" docs/streaming.md 'streams at 1 kHz as planned ({} setpoints' "$line_sp"

# --- docs/studies.md: min_time in a study; the design study's table and areas
# study CSV -> the value of METRIC for payload factor G and EI E (case order)
sval() {
  awk -F, -v m="$2" -v g="$3" -v e="$4" '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["metric"] == m && $c["payload_factor"] + 0 == g + 0 && (e == "" || $c["EI_Nm2"] + 0 == e + 0) {
      print $c["value"]; exit }' "$1"
}
l0=$(sval "$R/study-line.csv" min_time_duration 0 "")
l1=$(sval "$R/study-line.csv" min_time_duration 0.25 "")
cf=$(awk '/^PASS: paper line: duration vs closed form/ { sub(/.*want /, ""); print $1 + 0 }' "$R/test_plan.out")
[ "$(calc %.4f "$l0")" = "$(calc %.4f "$l1")" ] || echo "docs/studies.md: the paper line's min_time differs between payloads 0 and 0.25 ($l0, $l1 s)" >>"$FAILS"
pub "study payload --metrics min_time --task paper-line.yaml; test_plan (closed form)" docs/studies.md \
  'same {} s, {} % above' "$(calc %.4f "$l0")" "$(calc %.3f "($l0/$cf-1)*100")"
pub "tests/test_plan (closed form D/v + v/a)" docs/studies.md '{} s (`tests/test_plan`' "$(calc %.4f "$cf")"
for g in 0 0.25 0.5; do
  pub "study design.yaml (min_time_duration)" docs/studies.md "| $g | {} s | {} s | {} s |" \
    "$(calc %.4f "$(sval "$R/design.csv" min_time_duration $g 0.6)")" \
    "$(calc %.4f "$(sval "$R/design.csv" min_time_duration $g 0.705)")" \
    "$(calc %.4f "$(sval "$R/design.csv" min_time_duration $g 0.8)")"
done
pub "study design.yaml (area, payload factor 0)" docs/studies.md 'area {} to {} m^2 at payload factor 0,' \
  "$(calc %.4f "$(sval "$R/design.csv" area 0 0.6)")" "$(calc %.4f "$(sval "$R/design.csv" area 0 0.8)")"
pub "study design.yaml (area, payload factor 0.5)" docs/studies.md '{} to {} m^2 at 0.5.' \
  "$(calc %.4f "$(sval "$R/design.csv" area 0.5 0.6)")" "$(calc %.4f "$(sval "$R/design.csv" area 0.5 0.8)")"
# the payload-rest table: durations in s (5 digits), residual peaks in mm, the ratio
for g in 0 0.25 0.5; do
  pr() { sval "$R/payload-rest.csv" "$1" $g ""; }
  pub "study payload-rest.yaml" docs/studies.md "| $g | {} s | {} mm | {} s | {} | {} mm |" \
    "$(calc %.5f "$(pr qs_min_time_s)")" "$(calc %.2f "$(pr qs_fe_residual_peak_m)*1000")" \
    "$(calc %.5f "$(pr at_rest_duration_s)")" "$(calc %.3f "$(pr at_rest_time_ratio)")" \
    "$(calc %.3f "$(pr at_rest_fe_residual_peak_m)*1000")"
done
prv() { sval "$R/payload-rest.csv" "$1" "$2" ""; }
pub "study payload-rest.yaml" docs/studies.md 'vibration it leaves grows with it from {} to {} mm; arriving at rest costs' \
  "$(calc %.0f "$(prv qs_fe_residual_peak_m 0)*1000")" "$(calc %.0f "$(prv qs_fe_residual_peak_m 0.5)*1000")"
pub "study payload-rest.yaml" docs/studies.md '{} % more time at payload 0 and {} % at 0.5, and leaves {} % to {} % of that' \
  "$(calc %.0f "($(prv at_rest_time_ratio 0)-1)*100")" "$(calc %.0f "($(prv at_rest_time_ratio 0.5)-1)*100")" \
  "$(calc %.1f "$(prv at_rest_fe_residual_peak_m 0)/$(prv qs_fe_residual_peak_m 0)*100")" \
  "$(calc %.1f "$(prv at_rest_fe_residual_peak_m 0.5)/$(prv qs_fe_residual_peak_m 0.5)*100")"

# --- docs/planner.md: polylines over the knot count (bench_plan: the value column of the
# rows named CASE, at 30 / 60 / 100 / 200 / 400 knots)
poly() { awk -v c="$1" 'index($0, c) == 1 { print $(NF - 1) }' "$R/bench_plan.out"; }
set -- $(poly "polyline min time")
pub "bench/bench_plan (polylines over the knot count)" docs/planner.md \
  '(0.3, -0.2) through (0.45, -0.12) to (0.6, -0.25) takes {} / {} / {} /' "$1" "$2" "$3"
pub "bench/bench_plan (polylines over the knot count)" docs/planner.md \
  '{} / {} s: +{} % from the default 100 knots to 400, still rising. The' \
  "$4" "$5" "$(calc %.1f "($5 / $3 - 1) * 100")"
set -- $(poly "polyline-effort")
pub "bench/bench_plan (polylines over the knot count)" docs/planner.md \
  "polyline-effort example's objective is {} / {} / {} / {} / {}" "$@"
pub "bench/bench_plan (polylines over the knot count)" docs/planner.md \
  '(within {} % from 60 knots on). The path holds at the knots only, and a corner in actuator' \
  "$(printf '%s\n' "$2" "$3" "$4" "$5" | awk 'NR == 1 || $1 > M { M = $1 } NR == 1 || $1 < m { m = $1 } END { printf "%.1f", (M / m - 1) * 100 }')"

# --- docs/planner.md: bench_plan's tables of the paper line (times masked)
block bench_plan docs/planner-measurements.md "$R/bench_plan.out" "paper line, 100 knots" "2000 knots" 1

# --- README.md: bench_plan's iteration counts (column "iters" of the row named CASE;
# the N-th such row with a second argument)
iters() {
  awk -v c="$1" -v n="${2:-1}" 'index($0, c) == 1 && substr($0, length(c) + 1, 1) ~ /[ ]/ && ++k == n {
    for (i = 1; i <= NF; i++) if ($i ~ /^[0-9]+$/ && $(i + 1) ~ /^[0-9]+$/ && $(i + 2) ~ /^[0-9]+$/) { print $(i + 2); exit } }' \
    "$R/bench_plan.out"
}
pub "bench/bench_plan (cold, partial Hessian (default))" README.md 'in {*}-{*} ms with {} iterations of its own interior point,' \
  "$(iters "cold, partial Hessian (default)")"
pub "bench/bench_plan (warm (previous solution); same task from a plan file)" README.md \
  'task takes {} iterations (a KKT test of the previous solution, {*} ms), and replanning from a previous plan file {} iterations' \
  "$(iters "warm (previous solution)")" "$(iters "same task")"
for c in "goal moved 1 mm" "goal moved 5 mm" "goal moved 20 mm" "start moved 5 mm" "payload +5 %" \
  "cable speed limit -10 %"; do
  bc=$c
  [ "$c" = "payload +5 %" ] && bc="payload +5 % (factor 0.2 -> 0.21)"
  # the Newton's steps where its point was taken, else what it did ("gave up", "not tried")
  nw=$(awk -v c="$bc: replan" 'index($0, c) == 1 { f = 1; next }
    f { sub(/.*active-set Newton: /, ""); sub(/ steps.*/, ""); sub(/, (Ipopt|the own interior point).*/, ""); print; exit }' \
    "$R/bench_plan.out")
  case $nw in
  *[!0-9]*)
    pub "bench/bench_plan (replanning a live planner)" README.md "| $c | $nw | {} | {} |" \
      "$(iters "$bc: replan")" "$(iters "$bc: cold")"
    ;;
  *)
    pub "bench/bench_plan (replanning a live planner)" README.md "| $c | {} | {} | {} |" \
      "$nw" "$(iters "$bc: replan")" "$(iters "$bc: cold")"
    ;;
  esac
done
pub "bench/bench_plan (Hessian modes)" docs/planner.md 'statics curvature left out | {} it, {*}-{*} ms / {*}-{*} ms |' \
  "$(iters "cold, partial Hessian (default)")"
pub "bench/bench_plan (Hessian modes)" docs/planner.md 'closed form of L_c cos/sin alpha | {} it, {*}-{*} ms / {*}-{*} ms |' \
  "$(iters "cold, exact Hessian")"
pub "bench/bench_plan (Hessian modes)" docs/planner.md "Ipopt's L-BFGS | {} it, {*}-{*} ms / {*}-{*} ms;" \
  "$(iters "cold, limited-memory Hessian")"
pub "bench/bench_plan (scaling with the knot count)" README.md \
  'the knot count: {} / {} / {} / {} / {} iterations,' "$(iters "25 knots")" "$(iters "50 knots")" \
  "$(iters "100 knots")" "$(iters "200 knots")" "$(iters "400 knots")"

# --- docs/planner.md: knot counts
kd() { calc %.5f "$(jnum "$R/paper-line-k$1.json" duration_s)"; }
ki() { jnum "$R/paper-line-k$1.json" iterations; }
pub "plan paper-line.yaml --knots 1000 (duration_s, iterations)" docs/planner.md \
  '`elasticarm plan --knots N`: 1000 knots {} s in {} iterations, 2000' "$(kd 1000)" "$(ki 1000)"
pub "plan paper-line.yaml --knots 2000, 3000, 4000 (duration_s, iterations)" docs/planner.md \
  'knots {} s ({}), 3000 ({}), 4000 ({}) iterations; the closed form is' \
  "$(kd 2000)" "$(ki 2000)" "$(ki 3000)" "$(ki 4000)"

pub "plan paper-line.yaml (iterations)" docs/planner.md 'the cold solve needs {} iterations (the own interior point;' \
  "$(jnum "$R/paper-line.json" iterations)"

# --- README.md: the FE model's checks (tests/test_fe)
tang=$(awk '/max\|K_fd - K\| \/ max\|K\| = / { sub(/.*max\|K\| = /, ""); v = $1 + 0; if (v > m) m = v } END { print m }' "$R/test_fe.out")
drift=$(awk '/^energy: E0 = .* ratio / { sub(/.* ratio /, ""); print $1 + 0; exit }' "$R/test_fe.out")
zeta=$(awk '/mode 1: measured zeta / { sub(/.*measured zeta /, ""); print $1; exit }' "$R/test_fe.out")
fosc=$(awk '/^zero crossings .* eigen-solver/ { sub(/.*Hz \(/, ""); print $1; exit }' "$R/test_fe.out")
pub "tests/test_fe (analytic tangent vs central differences, largest)" README.md \
  '(checked against central differences to {}),' "$(sci %.0e "$tang")"
pub "tests/test_fe (energy scheme drift / oscillation energy)" README.md 'the discrete gradient; drift {} of the' \
  "$(sci %.1e "$drift")"
pub "tests/test_fe (mode 1 release, measured zeta)" README.md '(requested 0.02, measured {}).' "$zeta"
pub "tests/test_fe (free oscillation vs eigen-solver)" README.md "first frequency ({} %)." "$fosc"

# --- docs/cli-fe.md: simulate on the paper-line plan (the README's run)
pub "simulate paper-line.csv (residual_vibration_rms_m)" docs/cli-fe.md \
  'motion) runs in {*} s ({*}x faster than real time); residual vibration rms {} mm, peak' \
  "$(calc %.1f "$rms*1e3")"
pub "simulate paper-line.csv (residual_vibration_peak_m, max_tracking_error_m, static_offset_start_m)" \
  docs/cli-fe.md '{} mm; max tracking error {} mm; static offset at the start {} um. At the default dt' \
  "$(calc %.1f "$(jnum "$R/simulate.out" residual_vibration_peak_m)*1e3")" "$(calc %.1f "$track*1e3")" \
  "$(calc %.1f "$(jnum "$R/simulate.out" static_offset_start_m)*1e6")"

# --- docs/planner.md: bench_rest (times vary; the evaluations and the loop's residual do not,
# except where a refinement stops at its wall-time cap: the worst columns of the random lines)
sw=$(grep '^sweep: ' "$R/test_rest_sweep.out")
swn() { echo "$sw" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_rest_sweep" docs/planner.md \
  "the {} that the planner accepts end within 1 mm (worst {} mm). One is refused with exit 3:" \
  "$(swn 'sweep: \([0-9]*\) planned')" "$(calc %.3f "$(swn 'worst \([0-9.]*\) mm')")"
pub "tests/test_rest_sweep" docs/planner.md \
  "seeded, payload factor 0..0.5, 2 modes, default settings; the FE at dt 0.5 ms, 3 s): {} of" \
  "$(swn '(\([0-9]*\) within 1 mm')"
du=$(grep '^durations: ' "$R/test_rest_sweep.out")
dun() { echo "$du" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_rest_sweep (durations)" docs/planner.md \
  "quasi-static minimum in the median (p90 {}, worst {}, over the {} plans that keep their" \
  "$(dun 'p90 \([0-9.]*\),')" "$(dun 'worst \([0-9.]*\)')" "$(dun 'minimum, \([0-9]*\) plans')"
pub "tests/test_rest_sweep (durations)" docs/planner.md \
  "Arriving at rest costs time: the checked at-rest plans take {} times the" \
  "$(dun 'median \([0-9.]*\),')"
db=$(grep '^durations, bound 5 mm: ' "$R/test_rest_sweep.out")
dbn() { echo "$db" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_rest_sweep (durations, bound 5 mm)" docs/planner.md \
  "Allowed 5 mm (below; the sweep's first 20 lines), the median is {} (worst" \
  "$(dbn 'median \([0-9.]*\),')"
pub "tests/test_rest_sweep (durations, bound 5 mm)" docs/planner.md \
  "{}): on these lines the quasi-static plan rings with tens of millimetres, so a 5 mm" \
  "$(dbn 'worst \([0-9.]*\)')"
bw=$(grep '^bound 5 mm: ' "$R/test_rest_sweep.out")
bwn() { echo "$bw" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_rest_sweep (bound 5 mm)" docs/planner.md \
  "the model's 5 mm plan leaves more than 5 mm in the FE on {} of the {} lines the planner" \
  "$(bwn '; \([0-9]*\) over it')" "$(bwn 'bound 5 mm: \([0-9]*\) planned')"
pub "tests/test_rest_sweep (bound 5 mm)" docs/planner.md \
  "{} of the {} end within 5 mm by the FE at dt 0.5 ms (worst {} mm); the vertical line" \
  "$(bwn '(\([0-9]*\) within 5 mm')" "$(bwn 'bound 5 mm: \([0-9]*\) planned')" \
  "$(calc %.3f "$(bwn 'worst \([0-9.]*\) mm;')")"
brow() { awk -F'|' -v n="$1" 'index($2, " " n " ") == 1 { print $3, $9, $10, $11; exit }' "$R/bench_rest.out"; }
set -- $(brow "paper line")
pub "bench/bench_rest (paper line)" docs/planner.md \
  "| paper line (paper-line-rest.yaml) | {} | {*} / {*} / {*} | {*} / {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {} / {} | {} / {} | {} |" \
  "$1" "$2" "$4" "$(calc %.4f "$5")" "$(calc %.4f "$7")" "$8"
set -- $(brow "random straight lines")
pub "bench/bench_rest (random straight lines)" docs/planner.md \
  "| random straight lines | {} | {*} / {*} / {*} | {*} / {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {} / {*} | {} / {*} | {*} |" \
  "$1" "$2" "$(calc %.4f "$5")"
set -- $(brow "the same, residual_m 5 mm")
pub "bench/bench_rest (residual_m 5 mm)" docs/planner.md \
  "| the same, residual_m 5 mm | {} | {*} / {*} / {*} | {*} / {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {} / {*} | {} / {*} | {*} |" \
  "$1" "$2" "$(calc %.4f "$5")"

# --- docs/planner.md: bench_rest by the nonlinear reduced model (plans, evaluations and the
# paper line's residual are deterministic, times are not; on the random lines the worst line's
# loop stops at its time cap, so only the medians there, and the median of the residuals where
# the model's loops stopped is not checked: a loop stops at its first residual under 0.05 mm,
# and a line near that edge takes one evaluation more or less when the plans differ in their
# last bits (tables built in the process or read from the cache): 0.0064 or 0.0074 mm)
for by in model_only model; do
  c="paper line (paper-line-rest.yaml)"
  set -- $(awk -F'|' -v n=" $c, by $by " 'index($2, n) == 1 { print $3, $10, $11, $12; exit }' \
    "$R/bench_rest_$by.out")
  pub "bench/bench_rest $by ($c)" docs/planner.md \
    "| $c, by $by | {} | {*} / {*} / {*} | {*} / {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {} / {} | {} / {} | {} |" \
    "$1" "$2" "$4" "$(calc %.4f "$5")" "$(calc %.4f "$7")" "$8"
  for c in "random straight lines" "the same, residual_m 5 mm"; do
    set -- $(awk -F'|' -v n=" $c, by $by " 'index($2, n) == 1 { print $3, $10, $11; exit }' \
      "$R/bench_rest_$by.out")
    pub "bench/bench_rest $by ($c)" docs/planner.md \
      "| $c, by $by | {} | {*} / {*} / {*} | {*} / {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {*} / {*} | {} / {*} | {*} / {*} | {*} |" \
      "$1" "$2"
  done
done
# --- docs/fe.md, docs/planner.md: tests/test_romnl
rn=$(grep ' lines measured, ' "$R/test_romnl.out")
rnn() { echo "$rn" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_romnl (5 mm plans)" docs/fe.md \
  "  refused by a limit): the predicted residual is within {} % of the FE's on every line; the" \
  "$(rnn 'worst nonlinear error \([0-9.]*\) %')"
pub "tests/test_romnl (5 mm plans)" docs/fe.md \
  "  linear model is off by up to {} times on the same lines:" \
  "$(rnn 'up to \([0-9.]*\) times')"
for ln in "the diagonal" "line 1" "line 2" "line 4" "line 7" "line 8"; do
  set -- $(awk -F'|' -v n=" $ln " '$2 == n { print $3, $4, $5, $6, $7, $8; exit }' "$R/test_romnl.out")
  pub "tests/test_romnl (5 mm plans, $ln)" docs/fe.md "| $ln | {} | {} | {} | {} | {*} | {} |" \
    "$1" "$2" "$3" "$4" "$6"
done
rl=$(grep '^at rest by the model alone, lines: ' "$R/test_romnl.out")
rln() { echo "$rl" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_romnl (at rest, lines)" docs/fe.md \
  "  diagonal and 20 seeded random lines all end within 1 mm by the FE (worst {} mm)." \
  "$(calc %.3f "$(rln 'worst \([0-9.]*\) mm')")"
pub "tests/test_romnl (at rest, lines)" docs/planner.md \
  "diagonal and 20 seeded random straight lines all end within 1 mm (worst {} mm); the paper" \
  "$(calc %.3f "$(rln 'worst \([0-9.]*\) mm')")"
rp=$(grep '^at rest by the model alone, polylines: ' "$R/test_romnl.out")
rpn() { echo "$rp" | sed -n "s/.*$1.*/\1/p"; }
pub "tests/test_romnl (at rest, polylines)" docs/fe.md \
  "- Polylines (two via points, motions of 2.7-6.2 s) are harder: {} of {} end within 1 mm by the" \
  "$(rpn ', \([0-9]*\) within 1 mm')" "$(rpn 'polylines: \([0-9]*\) planned')"

# --- docs/planner.md: bench_dyn (section 1: knots; 3: grid; 4: replanning)
dyn() { awk -v k="$1" -v t="$2" '$1 == k && $2 == t { print $3, $7, $8, $10; exit }' "$R/bench_dyn.out"; }
for k in 25 50 100 200 400; do
  itp=$(dyn $k path | awk '{ print $1 }')
  set -- $(dyn $k knots)
  label=$k
  [ $k = 100 ] && label="100 (default)"
  ch=$(sci %.1e "$3")
  [ $k = 400 ] && ch=$(calc %.0f "$3")
  ip='{}'
  pub "bench/bench_dyn (at-rest paper line, $k knots)" docs/planner-measurements.md "| $label | {} / $ip | {} | {} | {} |" \
    "$1" ${itp:+"$itp"} "$(calc %.6f "$2")" "$ch" "$(calc %.4f "$4")"
done
hw=$(awk '/worst entry/ && !/kinematic/ && !/path layout/ { v = $0; sub(/.*worst entry /, "", v); sub(/ .*/, "", v); if (v + 0 > m) m = v + 0 }
  END { print m }' "$R/test_plan_hess.out")
pub "tests/test_plan_hess (worst Hessian entry of a dynamics row, both tasks)" docs/planner.md \
  "exact gradient over all its variables, modal states included: within {} of the row's largest" \
  "$(sci %.1e "$hw")"
hp=$(awk '/path layout [0-9]+ variables/ { v = $0; sub(/.*worst entry /, "", v); sub(/ .*/, "", v); print v; exit }' "$R/test_plan_hess.out")
pub "tests/test_plan_hess (the path transcription's Lagrangian Hessian with dynamics)" docs/planner.md \
  "its Hessian row's largest reference entry: {} (stated 1e-7;" "$(sci %.1e "$hp")"
hk=$(awk '/path-layout defects/ { v = $0; sub(/.*knot layout.s: /, "", v); sub(/ .*/, "", v); print v; exit }' "$R/test_plan_hess.out")
pub "tests/test_plan_hess (the path layout's kept defect values against the knot layout's)" docs/planner.md \
  "rule: within {} of each row's largest entry (stated 1e-12)." "$(sci %.1e "$hk")"
# sw KIND: planned, infeasible, failures, iterations of the sweep's KIND paths, then the
# worst relative excess and the re-solves of the limits line after it, then the Ipopt solves
# repeated for a row left out of its problem
sw() {
  awk -v k="$1" 'index($0, "sweep of 200 (" k " paths)") { f = 1; n = split($0, w, /[ ;(),:]+/)
      for (i = 1; i <= n; i++) { if (w[i + 1] == "planned") p = w[i]; if (w[i + 1] == "reported") r = w[i]
        if (w[i + 1] == "failures") fl = w[i]; if (w[i + 1] == "iterations" && w[i + 2] == "in") it = w[i]
        if (w[i + 1] == "Ipopt" && w[i + 2] == "solves") rs = w[i] }; next }
    f && /every limit re-checked/ { x = $0; sub(/.*excess /, "", x); sub(/ .*/, "", x)
      y = $0; sub(/ plans re-solved.*/, "", y); sub(/.* /, "", y); f = 2
      if (k == "free") { print p, r, fl, it, x, y, rs; exit }; next }
    f == 2 && index($0, "sweep (" k " paths): ") { n = split($0, w, /[ ;(),:]+/)
      for (i = 1; i <= n; i++) { if (w[i + 1] == "cold" && w[i + 2] == "plans") a = w[i]
        if (w[i + 1] == "by" && w[i + 2] == "Ipopt" && w[i + 3] == "after") b = w[i]
        if (w[i] == "difference") d = w[i + 1] }
      print p, r, fl, it, x, y, rs, a, b, d; exit }' \
    "$R/test_plan_sweep.out"
}
set -- $(sw free) $(sw line)
pub "tests/test_plan_sweep (free paths)" docs/planner.md \
  '3-D, payload factor 0..0.5), free paths: {} planned, {} reported infeasible (20 goals' "$1" "$2"
pub "tests/test_plan_sweep (free paths)" docs/planner.md \
  'beyond the edge on purpose), {} failures, slowest plan {*} s,' "$3"
pub "tests/test_plan_sweep (free paths)" docs/planner.md \
  '{} iterations in all, {} Ipopt solves repeated for a row left out of its problem; every plan'"'"'s file' \
  "$4" "$7"
pub "tests/test_plan_sweep (free paths)" docs/planner.md \
  're-checked at 1 kHz: worst relative excess {} (tolerance 0); plans re-solved for a' "$(sci %.1e "$5")"
pub "tests/test_plan_sweep (free and line paths)" docs/planner.md \
  'limit between the knots: {}. The same 200 pairs on line paths: {} planned, {} reported' "$6" "$8" "$9"
pub "tests/test_plan_sweep (line paths)" docs/planner.md \
  'infeasible, {} failures, {} iterations in all ({} Ipopt solves repeated), worst relative' \
  "${10}" "${11}" "${14}"
pub "tests/test_plan_sweep (line paths)" docs/planner.md \
  'excess {}; {} plans by the own interior point and {} by Ipopt after it, their durations' \
  "$(sci %.1e "${12}")" "${15}" "${16}"
pub "tests/test_plan_sweep (line paths, own interior point)" docs/planner.md \
  'within {} of Ipopt'"'"'s plans of the same tasks (`solver.nlp: ipopt`).' "$(sci %.1e "${17}")"
# the line sweep's replans: replans, by the Newton, by the own interior point, by Ipopt,
# failures, worst duration vs Ipopt's cold plans
rps=$(awk '/replan sweep \(/ { n = split($0, w, /[ ;(),:]+/)
    for (i = 1; i <= n; i++) { if (w[i + 1] == "replans") a = w[i]
      if (w[i + 1] == "by" && w[i + 3] == "active-set") b = w[i]
      if (w[i + 1] == "by" && w[i + 3] == "own") f = w[i]
      if (w[i + 1] == "by" && w[i + 2] == "Ipopt") c = w[i]; if (w[i + 1] == "failures") d = w[i]
      if (w[i] == "plan" && w[i - 1] == "cold" && w[i - 2] == "Ipopt'"'"'s") e = w[i + 1] }
    print a, b, f, c, d, e; exit }' \
  "$R/test_plan_sweep.out")
set -- $rps
pub "tests/test_plan_sweep (line replans)" docs/planner.md \
  'up to 5 mm and 0.01 rad: {} replans, {} by the active-set Newton, {} by the own interior' \
  "$1" "$2" "$3"
pub "tests/test_plan_sweep (line replans)" docs/planner.md \
  'point after it, {} by Ipopt, {} failures, durations as Ipopt'"'"'s cold plans'"'"' within {}, every' \
  "$4" "$5" "$(sci %.1e "$6")"
set -- $(dyn 100 knots) $(dyn 400 knots)
pub "bench/bench_dyn (100 vs 400 knots)" docs/planner-measurements.md \
  'The default 100 knots gives the duration to {} % and the residual to {} mm. The' \
  "$(calc %.2f "$3*100")" "$(calc %.3f "$8-$4")"
set -- $(dyn 100 path)
pub "bench/bench_dyn (iterations of the at-rest paper line, the default path transcription)" docs/planner.md \
  '{} iterations of the own interior point, KKT systems by KLU then; with Ipopt 19 iterations and' "$1"
grid() { awk -v g="$1" '$1 == g { print $2, $3, $4, $5, $7, $8; exit }' "$R/bench_dyn.out"; }
set -- $(grid default) $(grid x1/2)
pub "bench/bench_dyn (the table's grid at the cell centres)" docs/planner-measurements.md \
  "table's default grid ({} x {} here) interpolates omega within {}, B within {} and" \
  "${1%x*}" "${1#*x}" "$(sci %.1e "$2")" "$(sci %.1e "$3")"
pub "bench/bench_dyn (the table's grid at the cell centres)" docs/planner-measurements.md \
  'the tip vectors within {} (relative, at the cell centres against the model computed' "$(sci %.1e "$4")"
pub "bench/bench_dyn (grid halved)" docs/planner-measurements.md \
  'there); halving the spacing moves the duration by {} relative and the FE residual by' \
  "$(sci %.0e "($5-${11})/$5")"
pub "bench/bench_dyn (grid halved)" docs/planner-measurements.md '{} mm. The table is built in {*} s and loaded from the cache in {*} ms.' \
  "$(calc %.3f "$6-${12}")"
set -- $(awk '$1 == "warm" || $1 == "cold" { print $2 }' "$R/bench_dyn.out")
pub "bench/bench_dyn (replanning after a 5 mm goal move)" docs/planner.md \
  're-plans after a 5 mm goal move in {} iterations (cold: {}), from the cold guess by the' "$1" "$2"
# the FE cable tension of the at-rest paper line (plan --verify) against the planned minimum
pub "plan paper-line-rest.yaml --verify (verify.measured_tension_min_N)" docs/planner.md \
  '{} N after the motion against the planned minimum of {} N' \
  "$(calc %.2f "$(jnum "$R/paper-line-rest.json" measured_tension_min_N)")" \
  "$(calc %.2f "$(jnum "$R/paper-line-rest.json" min_tension_margin_N)+0.05")"

# --- docs/fe.md: the reduced model (tests/test_rom's lines)
set -- $(awk '/^difference step halved:/ { print $6 + 0, $8 + 0 }' "$R/test_rom.out")
pub "tests/test_rom (difference step)" docs/fe.md 'halving the difference step moves B by {} and C by' \
  "$(sci %.1e "$1")"
pub "tests/test_rom (difference step)" docs/fe.md '{} of their largest entries; a 12 x 12 table' "$(sci %.1e "$2")"
set -- $(awk '/^table 12 x 12 over/ { sub(/.*cell centres: /, ""); gsub(/,/, ""); print $2, $4, $6, $8, $10 }' "$R/test_rom.out")
pub "tests/test_rom (table vs direct)" docs/fe.md \
  'centres: omega^2 {}, B {}, C {}, tip {}, tension {}. What it predicts' \
  "$(sci %.1e "$1")" "$(sci %.1e "$2")" "$(sci %.1e "$3")" "$(sci %.1e "$4")" "$(sci %.1e "$5")"
romr() { awk -v c="$1" 'index($0, c) == 1 { sub(/.*residual peak /, ""); print $1; sub(/.*FE transient /, ""); print $1; exit }' "$R/test_rom.out"; }
set -- $(romr "paper line, min time:") $(romr "paper line, min_vibration 3 s:") $(romr "1 cm cable cycloid")
pub "tests/test_rom (model vs FE)" docs/fe.md 'transient: the minimum-time paper line {} mm vs {} mm, the min_vibration paper line' \
  "$(calc %.2f "$1")" "$(calc %.2f "$2")"
pub "tests/test_rom (model vs FE)" docs/fe.md '{} vs {} mm, a 1 cm cable-length cycloid (linear regime) {} vs {} mm.' \
  "$(calc %.3f "$3")" "$(calc %.3f "$4")" "$(calc %.4f "$5")" "$(calc %.4f "$6")"

# --- docs/fe.md: the test count and the mesh convergence table
nfe=$(awk '/^test_fe: [0-9]+ checks, 0 failed/ { print $2 }' "$R/test_fe.out")
pub "tests/test_fe (checks)" docs/fe.md 'Tests (`build/tests/test_fe`, {} checks pass):' "$nfe"
for lc in 0.254 0.400 0.635; do
  for ne in 6 8 10 12 16; do
    set -- $(awk -F' *[|] *' -v a="$lc" -v b="$ne" '/^## Mesh convergence/ { s = 1 } /^## Assembly/ { s = 0 }
      s && $2 == a && $3 == b { print $4, $5, $6, $7, $8, $9; exit }' "$R/bench_fe.out")
    pub "bench/bench_fe (mesh convergence)" docs/fe.md "| $lc | $ne | {} | {} | {} | {} | {} | {} |" "$@"
  done
done

# --- README.md's C example is docs/example_api.c from its first #include on
# (the file is the one compiled and run by the tests example_api and install).
readme_c() { awk '/^## The C API/ { s = 1 } s && /^```c$/ { p = 1; next } p && /^```$/ { exit } p' README.md; }
sed -n '/^#include/,$p' docs/example_api.c >"$R/example_api.body.c"
readme_c >"$R/readme_example.c"
if ! cmp -s "$R/example_api.body.c" "$R/readme_example.c"; then
  if [ $mode = write ]; then
    awk -v body="$R/example_api.body.c" '
      /^## The C API/ { s = 1 }
      s == 1 && /^```c$/ { print; while ((getline l < body) > 0) print l; skip = 1; s = 2; next }
      skip && /^```$/ { skip = 0 }
      !skip { print }' README.md >"$R/rewrite.tmp"
    cat "$R/rewrite.tmp" >README.md
  fi
  echo "README.md: the C example differs from docs/example_api.c (diff $R/readme_example.c $R/example_api.body.c)" >>"$FAILS"
fi
echo "README.md: C example    <- docs/example_api.c (built and run by ctest -R 'example_api|install')" >>"$R/table.txt"

# --- the streamer's round trip (tests/test_stream): README.md, docs/streaming.md
rt() { # rt FIELD: the number after FIELD on the round-trip line, as printed
  awk -v f="$1" '/^round trip max errors:/ { sub(".*" f " ", ""); print $1; exit }' "$R/test_stream.out"
}
rt_cable=$(awk '/^round trip max errors:/ { sub(/.*rad \(/, ""); print $1 + 0; exit }' "$R/test_stream.out")
pub "tests/test_stream (round trip)" README.md 'reproduces the actuator trajectory to {} m of' "$(sci %.0e "$rt_cable")"
# (the digits the test prints, exponents shortened: rounding them again could
# round a printed ...5 the wrong way)
short() { echo "$1" | sed 's/e\([-+]\)0*\([0-9]\)/e\1\2/'; }
pub "tests/test_stream (round trip)" docs/streaming.md '(max errors {} rad of spool = {} m of' \
  "$(short "$(rt spool)")" "$(sci %.0e "$rt_cable")"
pub "tests/test_stream (round trip)" docs/streaming.md 'cable, {} rad of shoulder with its estimated accelerations, {} rad' \
  "$(short "$(rt shoulder)")" "$(short "$(rt base)")"

# ==== reduced-model accuracy and the choice of K (tests/test_rom, tests/test_plan_rest) ====
# One block for: docs/fe.md's independent modal-forcing check, docs/planner.md's tables of the
# model's prediction against the FE transient (plans not at rest in the model), of K = 1..4
# modes, and of the time to rest at 2 % damping.
# the modal forcing against FE static states differenced in test_rom (max over its two lines)
set -- $(awk '/^modal forcing vs FE static states/ { s = $0; sub(/.*rad\): B /, "", s); sub(/ \(modes.*/, "", s)
  gsub(/,/, "", s); split(s, a, " ")
  m[1] = mx(m[1], a[1], a[2]); m[2] = mx(m[2], a[6], a[7]); m[3] = mx(m[3], a[3], a[4]); m[4] = mx(m[4], a[8], a[9]) }
  function mx(x, y, z) { x += 0; y += 0; z += 0; return x > y ? (x > z ? x : z) : (y > z ? y : z) }
  END { print m[1], m[2], m[3], m[4] }' "$R/test_rom.out")
pub "tests/test_rom (modal forcing vs FE differences)" docs/fe.md \
  'agrees within {} (B) and {} (C) for modes 1 and 2, {} and {} for modes 3 and 4' \
  "$(sci %.1e "$1")" "$(sci %.1e "$2")" "$(sci %.1e "$3")" "$(sci %.1e "$4")"
# the tables of docs/planner.md "Arriving at rest" from tests/test_plan_rest and the new
# tests/test_rom_modes (K = 1..4, ~25 s)
run test_rom_modes env EA_SOURCE_DIR=. "$B/tests/test_rom_modes"
# rx OUT SED-SCRIPT: the numbers a sed s///p script picks from the first matching line of OUT
rx() { sed -n "$2" "$R/$1" | head -1; }
N='\([-0-9.e+]*\)'
# the payload-0.5 deflection table
set -- $(rx test_plan_rest.out "s/^payload factor 0.50, at rest: largest modal tip deflection $N mm, FE residual $N mm, residual \/ deflection^2 $N 1\/m.*/\1 \2 \3/p") \
  $(rx test_plan_rest.out "s/^payload factor 0.50: .* at rest $N s (x $N,.*/\1 \2/p")
pub "tests/test_plan_rest (payload 0.5, deflection)" docs/planner.md \
  '| {} mm (unbounded) | {} s ({} x) | {} mm | {} 1/m |' "$1" "$4" "$5" "$2" "$3"
for d in 0.015:15 0.010:10; do
  set -- $(rx test_plan_rest.out "s/^payload factor 0.50, at rest, max_tip_deviation_m ${d%%:*}: $N s (x $N), largest modal tip deflection $N mm, FE residual $N mm, residual \/ deflection^2 $N 1\/m.*/\1 \2 \3 \4 \5/p")
  pub "tests/test_plan_rest (payload 0.5, max_tip_deviation_m ${d%%:*})" docs/planner.md \
    "| {} mm (bound ${d%%:*} m) | {} s ({} x) | {} mm | {} 1/m |" "$3" "$1" "$2" "$4" "$5"
done
# the refined plans and the time to rest at 2 % damping
for g in 0.00:'paper line, payload 0' 0.25:'paper line, payload factor 0.25' \
  0.50:'line to (0.5, -0.2), payload factor 0.5'; do
  p=${g%%:*} label=${g#*:}
  set -- $(rx test_plan_rest.out "s/^payload factor $p refined: $N s (x $N, $N evaluations), FE residual $N mm.*/\1 \2 \3 \4/p")
  pub "tests/test_plan_rest (payload factor $p refined)" docs/planner.md \
    "| $label | {} s ({} x), {} | {} mm |" "$1" "$2" "$3" "$4"
  set -- $(rx test_plan_rest.out "s/^time to rest within 1 mm at 2 % damping, payload factor $p: quasi-static $N s, at rest $N s, refined $N s after the motion; residual peak at 2 % damping $N, $N, $N mm.*/\1 \2 \3 \4 \5 \6/p")
  pub "tests/test_plan_rest (time to rest, payload factor $p)" docs/planner-measurements.md \
    "| $label | {} s ({} mm) | {} s ({} mm) | {} s ({} mm) |" "$1" "$4" "$2" "$5" "$3" "$6"
done
# the model against the FE: the rows, the factor and the miss
for w in 'payload factor 0.00: quasi-static plan' 'payload factor 0.00: residual_m 1 mm' \
  'payload factor 0.00: residual_m 5 mm' 'payload factor 0.25: quasi-static plan' \
  'payload factor 0.25: residual_m 1 mm' 'payload factor 0.25: residual_m 5 mm' \
  'payload factor 0.50: quasi-static plan' 'payload factor 0.50: residual_m 1 mm' \
  'payload factor 0.50: residual_m 5 mm' 'pick-place-3d.yaml: quasi-static plan' \
  'polyline-effort.yaml: quasi-static plan'; do
  set -- $(rx test_plan_rest.out "s/^model vs FE: $w: predicted $N mm, FE $N mm, FE \/ predicted $N, |FE - predicted| $N mm = $N x .*/\1 \2 \3 \5/p")
  case $w in
  payload*0.50*) label="line to (0.5, -0.2), $w" ;;
  payload*) label="paper line, $w" ;;
  *) label=$w ;;
  esac
  pub "tests/test_plan_rest (model vs FE)" docs/planner-measurements.md "| $label | {} mm | {} mm | {} | {} |" \
    "$1" "$2" "$3" "$4"
done
set -- $(rx test_plan_rest.out "s/^model vs FE on .* within a factor $N (worst.*<= $N x the same.*/\1 \2/p")
pub "tests/test_plan_rest (model vs FE: factor)" docs/planner-measurements.md \
  '(measured {}); on every plan |FE - predicted| is at most 1.25 x what the model misses at' "$1"
pub "tests/test_plan_rest (model vs FE: miss)" docs/planner-measurements.md 'rest on the same task (measured {} x). A ratio is no measure for small predicted residuals:' "$2"
# Choosing K: the K table (test_rom_modes) and the other examples' predictions
for g in 0.00:0 0.25:0.25 0.50:0.5; do
  for K in 1 2 3 4; do
    set -- $(rx test_rom_modes.out "s/^modes $K, payload factor ${g%%:*}: at rest $N s ($N iterations), FE residual $N mm; quasi-static plan predicted $N mm, FE $N mm.*/\1 \2 \3 \4 \5/p")
    pub "tests/test_rom_modes (modes $K, payload factor ${g%%:*})" docs/planner-measurements.md \
      "| ${g#*:} | $K | {} s | {} | {} mm | {} mm ({} mm) |" "$1" "$2" "$3" "$(calc %.3f "$4")" "$(calc %.3f "$5")"
  done
done
for ex in pick-place-3d polyline-effort; do
  set -- $(rx test_rom_modes.out "s/^$ex.yaml, quasi-static plan: FE $N mm; predicted with modes 1..4 $N, $N, $N, $N mm.*/\1 \2 \3 \4 \5/p")
  eval "ex_${ex%%-*}=\"\$(calc %.3f \"\$2\"), \$(calc %.3f \"\$3\"), \$(calc %.3f \"\$4\"), \$(calc %.3f \"\$5\") mm (FE \$(calc %.3f \"\$1\") mm)\""
done
set -- $ex_pick
pub "tests/test_rom_modes (pick-place-3d)" docs/planner-measurements.md 'polyline-effort predicted with K = 1..4: {}, {}, {}, {} mm (FE {} mm) and' \
  "${1%,}" "${2%,}" "${3%,}" "$4" "$7"
set -- $ex_polyline
pub "tests/test_rom_modes (polyline-effort)" docs/planner-measurements.md '{}, {}, {}, {} mm (FE {} mm). The default K = 2: the second mode lowers the' \
  "${1%,}" "${2%,}" "${3%,}" "$4" "$7"
# the sentences derived from the K table
kfe() { rx test_rom_modes.out "s/^modes $1, payload factor $2: at rest .* FE residual $N mm;.*/\1/p"; }
pub "tests/test_rom_modes (K = 3, 4 at payload 0.5)" docs/planner.md '(K = 3 and 4 leave {} and {} mm, "Choosing K" in docs/planner-measurements.md), nor the knots' \
  "$(calc %.2f "$(kfe 3 0.50)")" "$(calc %.2f "$(kfe 4 0.50)")"
pub "tests/test_rom_modes (K = 1 - K = 2, at rest)" docs/planner-measurements.md 'at-rest FE residual (by {}, {} and {} mm) for' \
  "$(calc %.3f "$(kfe 1 0.00) - $(kfe 2 0.00)")" "$(calc %.3f "$(kfe 1 0.25) - $(kfe 2 0.25)")" \
  "$(calc %.3f "$(kfe 1 0.50) - $(kfe 2 0.50)")"
# ==== end of the block

# ---------------------------------------------------------------- FE transient accuracy
# docs/fe.md: the CLI fast move of tests/test_cli_fe at dt 1 ms and 0.25 ms, both schemes
# (the test writes its files in its working directory: run it in $R).
absp() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
[ -x "$B/tests/test_cli_fe" ] || {
  echo "regenerate.sh: $B/tests/test_cli_fe not built" >&2
  exit 2
}
run test_cli_fe sh -c 'cd "$0" && exec "$@"' "$R" env EA_SOURCE_DIR="$PWD" EA_BINARY="$(absp "$EA")" \
  "$(absp "$B/tests/test_cli_fe")"
# default (genalpha 0.9, 1 ms), genalpha 0.7, genalpha 1, energy 1 ms, energy 0.25 ms, genalpha 0.25 ms [m]
set -- $(awk '/^fast move residual rms \[m\]:/ { for (i = 1; i <= NF; i++) if ($i ~ /^0\.[0-9][0-9][0-9][0-9][0-9][0-9]+,?$/) {
  v = $i; sub(/,$/, "", v); printf "%s ", v } exit }' "$R/test_cli_fe.out")
[ $# -eq 6 ] || echo "docs/fe.md: tests/test_cli_fe printed no 'fast move residual rms' line" >>"$FAILS"
if [ $# -eq 6 ]; then
  pub "tests/test_cli_fe (fast move, genalpha 1 ms)" docs/fe.md \
    '- CLI fast move (test_cli_fe, dt = 1 ms): residual rms {} mm (rho_inf 0.7 and 1 agree to' \
    "$(calc %.4f "$1*1e3")"
  pub "tests/test_cli_fe (fast move: rho_inf 1 / 0.7 - 1; energy scheme 1 and 0.25 ms; genalpha 0.25 ms)" \
    docs/fe.md '  {}); energy scheme {} mm at 1 ms and {} mm at 0.25 ms; generalized-alpha at' \
    "$(sci %.1e "($3>$2)?$3/$2-1:$2/$3-1")" "$(calc %.4f "$4*1e3")" "$(calc %.4f "$5*1e3")"
  pub "tests/test_cli_fe (fast move: genalpha 0.25 ms; genalpha 1 ms vs 0.25 ms)" docs/fe.md \
    '  0.25 ms {} mm. At 1 ms both schemes carry the same time-step error: {} (genalpha)' \
    "$(calc %.4f "$6*1e3")" "$(sci %.1e "($1>$6)?$1/$6-1:1-$1/$6")"
  pub "tests/test_cli_fe (fast move: energy 1 ms vs 0.25 ms)" docs/fe.md \
    '  and {} (energy) of the rms from dt 1 ms to 0.25 ms.' "$(sci %.1e "($4>$5)?$4/$5-1:1-$4/$5")"
fi

# docs/cli-fe.md: the transient's work-precision table (bench/bench_sim, one run, ~30 s):
# every row's steps, Newton iterations, residual peak and errors (wall time and real-time
# factor as {*}), and the sentences quoting its errors at the default dt.
[ -x "$B/bench/bench_sim" ] || {
  echo "regenerate.sh: $B/bench/bench_sim not built" >&2
  exit 2
}
run bench_sim "$B/bench/bench_sim" 1
# each row as "TEMPLATE<TAB>VALUES": case, scheme and dt stay literal (a row that did not
# converge: dt is its one value)
tab=$(printf '\t')
awk -F' [|] ' '/^[|] [a-z]/ && $1 != "| case" {
    sub(/^[|] /, "", $1)
    if ($4 == "did not converge")
      printf "| %s | %s | {} | did not converge | | | | | | |\t%s\n", $1, $2, $3
    else if ($2 == "energy (ref)")
      printf "| %s | %s | %s | {} | {} | {*} | {*} | {} | | |\t%s %s %s\n", $1, $2, $3, $4, $5, $8
    else {
      rest = $10; sub(/^[^|]*/, "", rest); herr = $10; sub(/ [|].*/, "", herr)
      printf "| %s | %s | %s | {} | {} | {*} | {*} | {} | {} | {} %s\t%s %s %s %s %s\n", $1, $2, $3,
        rest, $4, $5, $8, $9, herr }
  }' "$R/bench_sim.out" >"$R/bench_sim.rows"
[ -s "$R/bench_sim.rows" ] || echo "docs/cli-fe.md: no rows in $R/bench_sim.out" >>"$FAILS"
while IFS="$tab" read -r t v; do
  # shellcheck disable=SC2086 # $v: the row's values, split on purpose
  pub "bench/bench_sim (work-precision; times vary)" docs/cli-fe.md "$t" $v
done <"$R/bench_sim.rows"
# bse CASE SCHEME DT: the rel. error column of that row (exponent as published: 7.2e-5)
bse() { awk -F' [|] ' -v c="$1" -v s="$2" -v d="$3" '$1 == "| " c && $2 == s && $3 == d { print $9; exit }' \
  "$R/bench_sim.out" | sed 's/e\([-+]\)0*\([0-9]\)/e\1\2/'; }
# worst SCHEME [EXCLUDED CASE]: the largest rel. error at dt 1 ms over the cases
worst() { awk -F' [|] ' -v s="$1" -v x="| ${2:-none}" '$2 == s && $3 == "1" && $1 != x && $9 + 0 > m { m = $9 + 0; w = $9 }
  END { print w }' "$R/bench_sim.out" | sed 's/e\([-+]\)0*\([0-9]\)/e\1\2/'; }
pub "bench/bench_sim (rel. error at dt 1 ms: worst case, genalpha)" docs/cli-fe.md \
  '(1 ms) the residual peak is within {} of the dt -> 0 limit with genalpha and within' "$(worst genalpha)"
pub "bench/bench_sim (rel. error at dt 1 ms: worst case, energy)" docs/cli-fe.md \
  '{} with the energy scheme on the four cases below (the energy scheme'"'"'s worst case,' "$(worst energy)"
pub "bench/bench_sim (rel. error at dt 1 ms: energy, the other cases)" docs/cli-fe.md \
  'polyline-effort, is above 1e-4; on the other three it is within {}).' "$(worst energy polyline-effort)"
pub "bench/bench_sim (polyline-effort, genalpha at 4, 2, 1 ms)" docs/cli-fe.md \
  "Errors fall at least at second order down to 1 ms (genalpha's peak error falls {} -> {} -> {} on" \
  "$(bse polyline-effort genalpha 4)" "$(bse polyline-effort genalpha 2)" "$(bse polyline-effort genalpha 1)"
pub "bench/bench_sim (polyline-effort, energy at 4, 2, 1 ms)" docs/cli-fe.md \
  "polyline-effort, the energy scheme's {} -> {} -> {}); below about 2e-5 of the" \
  "$(bse polyline-effort energy 4)" "$(bse polyline-effort energy 2)" "$(bse polyline-effort energy 1)"

# --- docs/statics.md: the Fig. 3 region's metrics and the reach within the arm's limits;
# docs/cluster.md: the case counts of the per-case cost table (its times are not checked).
# Self-contained: runs its own commands (~10 s). `workspace` prints one row per payload
# factor (gamma area max_reach x_max y_min, 10 digits) and where each extremum lies.
run workspace-nolimits "$EA" workspace --no-limits
run workspace-limits "$EA" workspace
run workspace-72 "$EA" workspace --payload-factors 0 --alpha-min-deg -72 --csv -
wsrow() { awk -v g="$2" '$1 == g && NF == 5 { print $2, $3, $4, $5; exit }' "$R/$1.out"; }
# wsat FILE GAMMA METRIC: the cable angle [deg] the extremum lies at, as printed
wsat() {
  awk -v g="gamma $2:" -v m="$3" 'index($0, g) == 1 { s = 1 } s && $0 ~ ("^ *(" g " )?" m " at alpha ") {
    sub(".* " m " at alpha ", ""); print $1; exit }' "$R/$1.out"
}
for g in 0 0.1 0.25 0.5; do
  set -- $(wsrow workspace-nolimits $g)
  at=$(wsat workspace-nolimits $g x_max)
  [ "$(wsat workspace-nolimits $g max_reach)" = -60 ] && [ "$(wsat workspace-nolimits $g y_min)" = -60 ] ||
    echo "docs/statics.md: Fig. 3 (gamma $g): max_reach or y_min no longer at the range start, -60 deg" >>"$FAILS"
  if [ $g = 0 ]; then
    pub "workspace --no-limits (gamma 0)" docs/statics.md '| 0 | {} | {} | {} (alpha {} deg) | {} |' \
      "$1" "$2" "$3" "$at" "$4"
  else
    pub "workspace --no-limits (gamma $g)" docs/statics.md "| $g | {} | {} | {} ({} deg) | {} |" \
      "$1" "$2" "$3" "$at" "$4"
  fi
done
for g in 0 0.1; do
  [ "$(wsrow workspace-limits $g)" = "$(wsrow workspace-nolimits $g)" ] ||
    echo "docs/statics.md: within the arm's limits gamma $g is no longer the Fig. 3 region" >>"$FAILS"
done
set -- $(wsrow workspace-limits 0.25) $(wsrow workspace-limits 0.5)
pub "workspace (area, gamma 0.25 and 0.5)" docs/statics.md 'area {} m^2 (gamma 0.25) and {} m^2 (gamma 0.5), reach' \
  "$1" "$5"
pub "workspace (max_reach, gamma 0.5)" docs/statics.md '{} m for gamma 0.5 (on the torque limit); gamma 0 and 0.1 are' \
  "$6"
grep -q '^gamma 0.5: max_reach at alpha .*, shoulder torque limit' "$R/workspace-limits.out" ||
  echo "docs/statics.md: gamma 0.5's reach within the limits is no longer on the torque limit" >>"$FAILS"
th72=$(awk -F, '$2 == "outer" { print $8; exit }' "$R/workspace-72.out")
pub "workspace --payload-factors 0 --alpha-min-deg -72 --csv (first outer point, theta0_rad)" docs/statics.md \
  '{} rad, below the -30 deg limit (the first outer point of' "$(calc %.4f "$th72")"
tq=$(awk '$1 == "torque_max_Nm:" { print $2 + 0; exit }' data/elasticarm.yaml)
pub "data/elasticarm.yaml (actuators: shoulder torque_max_Nm)" docs/statics.md \
  '(`elasticarm workspace`) the shoulder torque limit ({} N m, an assumed value' "$tq"
run case-costs env EA="$EA" sh docs/cluster/case-costs.sh
awk -F' [|] ' 'index($0, "| `") == 1 { sub(/^[|] /, "", $1); print $1 "\034" $2 "\034" $3 }' \
  "$R/case-costs.out" >"$R/case-costs.rows"
[ "$(wc -l <"$R/case-costs.rows")" -eq 5 ] ||
  echo "docs/cluster.md: docs/cluster/case-costs.sh printed $(wc -l <"$R/case-costs.rows") metric rows, not 5" >>"$FAILS"
while IFS=$(printf '\034') read -r label cases failed; do
  pub "docs/cluster/case-costs.sh (cases, failed; times not checked)" docs/cluster.md \
    "  | $label | {} | {} | {*} ms |" "$cases" "$failed"
done <"$R/case-costs.rows"
# .ci/Containerfile runs the README's two "Set up and run" commands, verbatim.
# --- docs/calibration.md: the example experiment's duration
ce=$R/calib-experiment.out
pub "calibrate-experiment calib-experiment.yaml (f1_min_Hz)" docs/calibration.md \
  'arm, which has no measured damping, so zeta 0.02 is assumed; f1 from {} to' \
  "$(calc %.3f "$(jnum "$ce" f1_min_Hz)")"
pub "calibrate-experiment calib-experiment.yaml (f1_max_Hz, hold_s, duration_s)" docs/calibration.md \
  '{} Hz) holds each configuration {} s and takes {} s' "$(calc %.3f "$(jnum "$ce" f1_max_Hz)")" \
  "$(calc %.2f "$(jnum "$ce" hold_s)")" "$(calc %.2f "$(jnum "$ce" duration_s)")"
pub "calibrate-experiment calib-experiment.yaml (move_time_s)" docs/calibration.md \
  'in all, of which {} s are moves; every streamer check' "$(calc %.2f "$(jnum "$ce" move_time_s)")"
pub "calibrate-experiment calib-experiment.yaml (setpoints)" docs/calibration.md \
  'passes at 1 kHz ({} setpoints). `docs/regenerate.sh` reruns it.' "$(jnum "$ce" setpoints)"

# --- docs/calibration.md: the bench table (bench_calib: every column but the fit time)
cb=$R/bench_calib.out
for rn in "8 0.5" "18 0.5" "34 0.5" "8 1" "18 1" "34 1" "8 2" "18 2" "34 2"; do
  set -- $rn
  vals=$(awk -F' [|] ' -v r="| $1" -v x="$2" '$1 == r && $2 == x { sub(/ [|]$/, "", $11); print $4, $5, $6, $7, $8, $9, $10, $11; exit }' "$cb")
  pub "bench/bench_calib (times not checked)" docs/calibration.md \
    "| $1 | $2 | {*} | {} | {} | {} | {} | {} | {} | {} | {} |" $vals
done
# --- docs/calibration.md: end to end (test_calib_e2e)
ce2=$R/test_calib_e2e.out
e2r() { awk -v l="$1:" -v w="$2" '$1 == l { for (i = 1; i <= NF; i++) if ($i == "mm," || $i == "mm") { if (++c == w) print $(i - 1) } }' "$ce2"; }
e2c() { awk -v k="$1" '$1 == "calibrated:" { for (i = 1; i <= NF; i++) if ($i == k) { v = $(i + 1); sub(/,$/, "", v); print v } }' "$ce2"; }
pub "tests/test_calib_e2e (experiment)" docs/calibration.md \
  'third, which the static rows average; {} s in all) planned on the paper'"'"'s arm; the' \
  "$(calc %.2f "$(awk '$1 == "experiment:" { print $2; exit }' "$ce2")")"
pub "tests/test_calib_e2e (calibrated EI, hand mass)" docs/calibration.md \
  'carry no stretch to fit EA_c to) gives EI off by {} %, the hand mass by {} %, the' \
  "$(calc %.3f "$(e2c EI)")" "$(calc %.3f "$(e2c m_hand)")"
pub "tests/test_calib_e2e (damping ratio)" docs/calibration.md \
  'damping ratio {} +- {}, and names I_L as not identifiable (with 5 % damping on mode 1' \
  $(awk '$1 == "zeta_1" { printf "%.4f %.2g\n", $3, $4; exit }' "$ce2")
pub "tests/test_calib_e2e (paper line)" docs/calibration.md \
  '| paper line (0.3, -0.2) -> (0.6, -0.2), no payload | {} mm | {} mm |' \
  "$(calc %.2f "$(e2r paper 1)")" "$(calc %.2f "$(e2r paper 2)")"
pub "tests/test_calib_e2e (line a)" docs/calibration.md \
  '| (0.68, -0.05) -> (0.54, -0.55), payload factor 0.15 | {} mm | {} mm |' \
  "$(calc %.1f "$(e2r line_a 1)")" "$(calc %.2f "$(e2r line_a 2)")"
pub "tests/test_calib_e2e (line b)" docs/calibration.md \
  '| (0.23, -0.37) -> (0.56, 0.00), payload factor 0.08 | {} mm | {} mm |' \
  "$(calc %.1f "$(e2r line_b 1)")" "$(calc %.2f "$(e2r line_b 2)")"

awk '/^## Set up and run/ { s = 1 } s && /^sh \.ci\/install-deps( --runtime)? && / { print } /^## Install|^## The C API/ { s = 0 }' \
  README.md >"$R/readme-setup.txt"
[ "$(wc -l <"$R/readme-setup.txt")" -eq 2 ] ||
  echo "README.md: 'Set up and run' no longer holds two 'sh .ci/install-deps [--runtime] && ...' commands" >>"$FAILS"
while IFS= read -r c; do
  grep -qF -- "$c" .ci/Containerfile ||
    echo ".ci/Containerfile: does not run the README's command '$c'" >>"$FAILS"
done <"$R/readme-setup.txt"

# ---------------------------------------------------------------- verdict
rm -f "$R/rewrite.tmp"
nfail=$(grep -c . "$FAILS" || true)
case $mode in
write)
  echo "== rewritten: $nfail published numbers (or the C example) updated (git diff README.md docs/)"
  cat "$FAILS"
  ;;
print)
  cat "$R/table.txt"
  [ "$nfail" -eq 0 ] || { echo "== differing from the published text:"; cat "$FAILS"; }
  ;;
check)
  if [ "$nfail" -gt 0 ]; then
    cat "$FAILS"
    echo "== $nfail published numbers (or the C example) differ from the regenerated ones (--write to update)"
    exit 1
  fi
  echo "== every checked number in README.md and docs/ matches its command"
  ;;
esac
