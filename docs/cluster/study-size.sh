#!/bin/sh
# Sizes a cluster run of an elasticarm study from a measurement (docs/cluster.md):
#
#   sh docs/cluster/study-size.sh SPEC.yaml [TARGET_MINUTES [PROBE_SHARDS [THREADS]]]
#
# runs shard 1/PROBE_SHARDS (default 20) of the study on one worker, reads the
# number of cases and the time it took from its JSON summary, and prints how
# many shards N give tasks of about TARGET_MINUTES (default 30) of computing
# on THREADS workers each (default 4), with the Slurm and GNU parallel lines
# to run them. Every study uses its workers: min_time and at_rest cases run in
# forked worker processes, the other metrics in threads (docs/studies.md:
# 1.9-2.0x on 2 workers), so the estimate divides by THREADS. EA=... overrides
# the command (e.g. EA="apptainer exec elasticarm.sif elasticarm").
set -eu
[ $# -ge 1 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
EA=${EA:-elasticarm}
spec=$1
target=${2:-30}
probe=${3:-20}
threads=${4:-4}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
# shellcheck disable=SC2086 # EA may be a command with arguments
$EA study "$spec" --shard "1/$probe" --threads 1 --no-checkpoint --quiet \
  -o "$tmp/probe.csv" --summary "$tmp/probe.json"
num() { awk -v k="\"$1\":" '$1 == k { v = $2; sub(/,$/, "", v); print v; exit }' "$tmp/probe.json"; }
total=$(num cases_total)
done_=$(num cases_computed)
secs=$(num time_s)
workers=threads
if grep -q '"name": "\(min_time_duration\|at_rest_\|qs_\)' "$tmp/probe.json"; then
  workers="forked processes: the study plans"
fi
name=$(basename "$spec" .yaml)
awk -v total="$total" -v n0="$done_" -v t="$secs" -v target="$target" -v th="$threads" \
  -v spec="$spec" -v name="$name" -v workers="$workers" 'BEGIN {
  if (n0 < 1) { print "the probe shard had no case: use fewer probe shards"; exit 1 }
  pc = t / n0; cpu = pc * total
  n = int(cpu / (target * 60 * th)) + 1; if (n > total) n = total
  printf "probe: %d of %d cases in %.3f s on 1 worker: %.4f s per case, %.1f CPU-minutes in all\n",
    n0, total, t, pc, cpu / 60
  printf "plan: N = %d shards of ~%d cases, %d worker(s) each (%s), ~%.1f min per task\n",
    n, (total + n - 1) / n, th, workers, cpu / n / th / 60
  printf "\nSlurm (docs/cluster/study-array.sbatch; time limit: twice the estimate):\n"
  printf "  sbatch --array=1-%d --cpus-per-task=%d --time=%d docs/cluster/study-array.sbatch %s %d\n",
    n, th, 2 * (cpu / n / th / 60) + 5, spec, n
  printf "then: elasticarm study merge results/%s.csv results/%s.shard*-of-%d.csv --spec %s --cases %d\n",
    name, name, n, spec, total
  printf "\nGNU parallel (docs/cluster/study-parallel.sh):\n"
  printf "  THREADS=%d JOBS=<tasks per machine> sh docs/cluster/study-parallel.sh %s %d\n", th, spec, n
}'
