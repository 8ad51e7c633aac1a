#!/bin/sh
# GNU parallel: the N shards of an elasticarm study on this machine or, with
# SSHLOGINFILE=hosts.txt, on several (a shared folder, elasticarm on each
# machine's PATH), then the merge (docs/cluster.md; N from study-size.sh):
#
#   [THREADS=T] [JOBS=J] [SSHLOGINFILE=hosts.txt] sh docs/cluster/study-parallel.sh SPEC.yaml N
#
# J shards run at once per machine (default: cores / T), each with T workers
# (default 1; threads, or forked processes for min_time and at_rest: every
# study scales with T). Rerun after an interruption, the same command runs
# only the shards that did not finish (GNU parallel's job log,
# results/NAME.of-N.joblog), each resuming from its journal; to start over
# (the spec changed), remove results/NAME.*.
set -eu
[ $# -eq 2 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
spec=$1
n=$2
EA=${EA:-elasticarm}
T=${THREADS:-1}
J=${JOBS:-$(($(nproc) / T > 0 ? $(nproc) / T : 1))}
name=$(basename "$spec" .yaml)
mkdir -p results
# --resume-failed: skip the shards the job log records as done
set -- --will-cite -j "$J" --halt soon,fail=1 --joblog "results/$name.of-$n.joblog" --resume-failed
[ -n "${SSHLOGINFILE:-}" ] && set -- "$@" --sshloginfile "$SSHLOGINFILE" --workdir "$PWD"
seq 1 "$n" | parallel "$@" \
  "$EA study '$spec' --shard {}/$n --threads $T -o 'results/$name.shard{}-of-$n.csv' --quiet"
# shellcheck disable=SC2086 # EA may be a command with arguments
$EA study merge "results/$name.csv" $(seq -f "results/$name.shard%g-of-$n.csv" 1 "$n") --spec "$spec"
