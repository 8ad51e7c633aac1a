#!/bin/sh
# Sizes a cluster run of an elasticarm study from a measurement (docs/cluster.md):
#
#   sh docs/cluster/study-size.sh SPEC.yaml [TARGET_MINUTES [PROBE_SHARDS [THREADS]]]
#
# runs shard 1/PROBE_SHARDS (default 20) of the study on one thread, reads the
# number of cases and the time it took from its JSON summary, and prints how
# many shards N give tasks of about TARGET_MINUTES (default 30) of computing,
# with the Slurm and GNU parallel lines to run them. A study with min_time
# gets 1 thread per task (its plans are serialised: more threads do not make
# them faster); otherwise THREADS (default 4) per task. EA=... overrides the
# command (e.g. EA="apptainer exec elasticarm.sif elasticarm").
set -eu
[ $# -ge 1 ] || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
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
if grep -q '"min_time_duration"' "$tmp/probe.json"; then threads=1; fi
name=$(basename "$spec" .yaml)
awk -v total="$total" -v n0="$done_" -v t="$secs" -v target="$target" -v th="$threads" \
  -v spec="$spec" -v name="$name" 'BEGIN {
  if (n0 < 1) { print "the probe shard had no case: use fewer probe shards"; exit 1 }
  pc = t / n0; cpu = pc * total
  n = int(cpu / (target * 60 * th)) + 1; if (n > total) n = total
  printf "probe: %d of %d cases in %.3f s on 1 thread: %.4f s per case, %.1f CPU-minutes in all\n",
    n0, total, t, pc, cpu / 60
  printf "plan: N = %d shards of ~%d cases, %d thread(s) each, ~%.1f min per task\n",
    n, (total + n - 1) / n, th, cpu / n / th / 60
  printf "\nSlurm (docs/cluster/study-array.sbatch; time limit: twice the estimate):\n"
  printf "  sbatch --array=1-%d --cpus-per-task=%d --time=%d docs/cluster/study-array.sbatch %s %d\n",
    n, th, 2 * (cpu / n / th / 60) + 5, spec, n
  printf "then: elasticarm study merge results/%s.csv results/%s.shard*-of-%d.csv --spec %s --cases %d\n",
    name, name, n, spec, total
  printf "\nGNU parallel (docs/cluster/study-parallel.sh):\n"
  printf "  THREADS=%d JOBS=<tasks per machine> sh docs/cluster/study-parallel.sh %s %d\n", th, spec, n
}'
