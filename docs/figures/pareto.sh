#!/bin/sh
# Duration against residual vibration (docs/planner.md, "Duration against residual
# vibration"): the paper line (0.3, -0.2) -> (0.6, -0.2) m at payload factors 0 and 0.25, and
# (0.3, -0.2) -> (0.5, -0.2) m at 0.5, planned
#   - quasi-static in minimum time (qs_min_time),
#   - min_vibration at a fixed duration of 1.5, 2 and 3 s (min_vibration; parameter: duration),
#   - quasi-static in minimum time, then ZV-shaped (plan --shape zv),
#   - in minimum time with the reduced dynamic model (dynamics: {modes: 2, residual_m: R}),
#     R = 0 (at rest) and 1, 2, 5, 10 mm (dynamics; parameter: R);
# every point measured by `plan --verify`: the FE transient of the written plan (12 elements,
# generalized-alpha, dt 1 ms, 3 s after the motion, the arm's damping). Writes the points to
# out/pareto.csv and the figure to docs/figures/pareto.png (log residual).
# Run from the repository root after building: sh docs/figures/pareto.sh
set -eu
B=${B:-build/elasticarm}
O=${O:-out/pareto}
CSV=${CSV:-out/pareto.csv}
PNG=${PNG:-docs/figures/pareto.png}
ARM=${ARM:-$(pwd)/data/elasticarm.yaml}
mkdir -p "$O" "$(dirname "$CSV")" "$(dirname "$PNG")"

# The value of "key" in a JSON summary (one key per line): the last occurrence.
val() { sed -n "s/^ *\"$1\": \([^,]*\),\{0,1\}$/\1/p" "$2" | tail -n 1; }

# task NAME PAYLOAD GOAL_X BODY: a task file in $O.
task() {
  printf 'name: %s\narm_file: %s\npayload_factor: %s\nstart:\n  tip: [0.3, -0.2]\ngoal:\n  tip: [%s, -0.2]\npath: line\nknots: 100\n%s\n' \
    "$1" "$ARM" "$2" "$3" "$4" > "$O/$1.yaml"
}

# point PAYLOAD METHOD PARAMETER TASK NAME [plan options]: plan $O/TASK.yaml --verify into
# $O/NAME.csv and .json, one CSV row.
point() {
  g=$1 method=$2 par=$3 tk=$4 name=$5
  shift 5
  if "$B" plan "$O/$tk.yaml" -o "$O/$name.csv" --summary "$O/$name.json" --verify --quiet "$@" \
      2> "$O/$name.err"; then
    printf '%s,%s,%s,%s,%s,%s,%s,%s\n' "$g" "$method" "$par" \
      "$(val motion_duration_s "$O/$name.json")" "$(val measured_residual_peak_m "$O/$name.json")" \
      "$(val measured_residual_rms_m "$O/$name.json")" "$(val predicted_residual_m "$O/$name.json")" \
      EA_OK >> "$CSV.tmp"
  else
    st=$(val status "$O/$name.json" 2> /dev/null | head -n 1)
    printf '%s,%s,%s,nan,nan,nan,nan,%s\n' "$g" "$method" "$par" "${st:-failed}" >> "$CSV.tmp"
    echo "pareto: $name: $(tail -n 1 "$O/$name.err")" >&2
  fi
}

echo "payload_factor,method,parameter,duration_s,fe_residual_peak_m,fe_residual_rms_m,predicted_residual_m,status" > "$CSV.tmp"
for g in 0 0.25 0.5; do
  gx=0.6
  [ "$g" = 0.5 ] && gx=0.5
  task "qs-$g" "$g" "$gx" "objective: min_time"
  point "$g" qs_min_time "" "qs-$g" "qs-$g"
  point "$g" zv_shaped "" "qs-$g" "zv-$g" --shape zv
  for d in 1.5 2 3; do
    task "mv$d-$g" "$g" "$gx" "objective: {type: min_vibration, duration_s: $d}"
    point "$g" min_vibration "$d" "mv$d-$g" "mv$d-$g"
  done
  for r in 0 0.001 0.002 0.005 0.01; do
    task "dyn$r-$g" "$g" "$gx" "objective: min_time
dynamics: {modes: 2, residual_m: $r}"
    point "$g" dynamics "$r" "dyn$r-$g" "dyn$r-$g"
  done
done
mv "$CSV.tmp" "$CSV"

# One data file per series (payload x method), in the CSV's order, for gnuplot.
for g in 0 0.25 0.5; do
  for m in qs_min_time zv_shaped min_vibration dynamics; do
    awk -F, -v g="$g" -v m="$m" 'NR > 1 && $1 == g && $2 == m && $8 == "EA_OK" {
      print $4, 1e3 * $5, ($3 == "" ? 0 : $3) }' "$CSV" > "$O/$m-$g.dat"
  done
  awk -F, -v g="$g" 'NR > 1 && $1 == g && $2 == "dynamics" && $3 == 0 && $8 == "EA_OK" {
    print $4, 1e3 * $5 }' "$CSV" > "$O/rest-$g.dat"
done

gnuplot <<EOF
set terminal pngcairo enhanced font 'Sans,11' size 1100,650
set output '$PNG.tmp.png'
set title 'Duration against residual vibration: paper line, FE transient of each written plan (plan --verify)'
set xlabel 'duration of the motion [s]'
set ylabel 'FE residual vibration peak, 3 s after the motion [mm]'
set logscale y
set format y '%g'
set grid xtics ytics mytics
set key outside right top vertical box opaque spacing 1.2
set xrange [0.8:3.2]
c0 = '#1f77b4'; c1 = '#ff7f0e'; c2 = '#2ca02c'
plot \
  keyentry w l lw 3 lc rgb c0 t 'payload factor 0', \
  keyentry w l lw 3 lc rgb c1 t 'payload factor 0.25', \
  keyentry w l lw 3 lc rgb c2 t 'payload factor 0.5 (goal x 0.5 m)', \
  keyentry w p pt 7 ps 1.6 lc rgb 'black' t 'quasi-static, minimum time', \
  keyentry w p pt 5 ps 1.6 lc rgb 'black' t 'the same, ZV-shaped (--shape zv)', \
  keyentry w lp pt 9 ps 1.6 dt 2 lc rgb 'black' t 'min\_vibration, 1.5 / 2 / 3 s', \
  keyentry w lp pt 6 ps 1.4 lc rgb 'black' t 'dynamics, residual\_m 10 / 5 / 2 / 1 mm', \
  keyentry w p pt 13 ps 1.8 lc rgb 'black' t 'dynamics, at rest (residual\_m 0)', \
  for [i=0:2] sprintf('$O/qs_min_time-%s.dat', word('0 0.25 0.5', i+1)) u 1:2 w p pt 7 ps 1.6 lc rgb word(c0.' '.c1.' '.c2, i+1) notitle, \
  for [i=0:2] sprintf('$O/zv_shaped-%s.dat', word('0 0.25 0.5', i+1)) u 1:2 w p pt 5 ps 1.6 lc rgb word(c0.' '.c1.' '.c2, i+1) notitle, \
  for [i=0:2] sprintf('$O/min_vibration-%s.dat', word('0 0.25 0.5', i+1)) u 1:2 w lp pt 9 ps 1.6 dt 2 lc rgb word(c0.' '.c1.' '.c2, i+1) notitle, \
  for [i=0:2] sprintf('$O/dynamics-%s.dat', word('0 0.25 0.5', i+1)) u 1:2 w lp pt 6 ps 1.4 lc rgb word(c0.' '.c1.' '.c2, i+1) notitle, \
  for [i=0:2] sprintf('$O/rest-%s.dat', word('0 0.25 0.5', i+1)) u 1:2 w p pt 13 ps 1.8 lc rgb word(c0.' '.c1.' '.c2, i+1) notitle
EOF
mv "$PNG.tmp.png" "$PNG"
echo "wrote $CSV, $PNG"
