#!/usr/bin/env bash
# The cluster recipes of docs/cluster.md, run for real (CTest, label "cluster"):
#
#   1. the single-process run of tests/cluster/cluster.yaml (one worker, no journal);
#   2. a single-node Slurm brought up here (munged with a generated key,
#      slurmctld and slurmd on 127.0.0.1, free ports, everything under a fresh
#      temporary folder), docs/cluster/study-array.sbatch submitted as the
#      docs say in N = 3 array tasks, one task requeued mid-way (scontrol
#      requeue: it must resume from its journal), the merge as the dependent
#      job of the docs; the merged CSV must equal the single run byte for byte;
#   3. docs/cluster/study-parallel.sh in 3 shards, 2 at a time, shard 2
#      stopped mid-way (SIGTERM), the same command rerun: it must resume shard
#      2 from its journal and leave the finished shard 1 alone; the same byte
#      comparison.
#
# Needs root (slurmd and munged run as root here) and Debian's slurm-wlm,
# munge and parallel (sh .ci/install-deps): otherwise exit 77 (CTest: skipped).
# Every daemon is started here, in the foreground under `timeout` (so none
# outlives the test even if it is killed hard), and stopped by its pid on exit,
# whatever the outcome; any other process still using the temporary folder
# (a job, a shard) is killed by its pid. Every wait is bounded.
# Env: EA_SOURCE_DIR, EA_BINARY (set by CTest), EA_KEEP=1 keeps the folder.
set -euo pipefail

SRC=${EA_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}
EA_BIN=${EA_BINARY:-$SRC/build/elasticarm}
SPEC=$SRC/tests/cluster/cluster.yaml
NAME=cluster # the spec's file name without .yaml: the stem of the outputs
N=3
LIMIT=600 # [s] the whole test; the daemons die 60 s after it at the latest

skip() {
  echo "SKIP: $*"
  exit 77
}
[ "$(id -u)" -eq 0 ] || skip "needs root (slurmd, slurmctld and munged run as root here)"
for c in munged munge unmunge slurmctld slurmd sbatch squeue scontrol scancel sinfo parallel; do
  command -v "$c" >/dev/null 2>&1 ||
    skip "'$c' not found (sh .ci/install-deps installs Debian's slurm-wlm, munge and parallel)"
done
[ -x "$EA_BIN" ] || {
  echo "no elasticarm binary at $EA_BIN (set EA_BINARY)"
  exit 1
}

T0=$SECONDS
T=$(mktemp -d /tmp/ea-slurm.XXXXXX)
chmod 755 "$T" # munged wants its socket's folders searchable by all
daemons=()     # pids of the `timeout` wrapping each daemon, in start order
jobs_=()       # the Slurm jobs submitted here
note() { printf '[%3d s] %s\n' $((SECONDS - T0)) "$*"; }

# wait_for WHAT SECONDS COMMAND...: polls COMMAND every 0.2 s
wait_for() {
  local what=$1 end=$((SECONDS + $2))
  shift 2
  until "$@"; do
    if [ $SECONDS -ge $end ]; then
      note "timed out waiting for $what"
      return 1
    fi
    sleep 0.2
  done
}
alive() { kill -0 "$1" 2>/dev/null; }
dead() { ! alive "$1"; }
# Processes other than this shell with their working folder or an open file
# under the temporary folder: the jobs' slurmstepd and studies, GNU parallel.
procs_in_tmp() {
  find /proc/[0-9]*/cwd /proc/[0-9]*/fd -maxdepth 1 -lname "$T*" 2>/dev/null |
    sed -n 's|^/proc/\([0-9]*\)/.*|\1|p' | sort -u | grep -vx "$$" || true
}
# stop PID: TERM to a daemon's `timeout` (it passes the signal on), KILL after 15 s
stop() {
  local t=$1 d
  d=$(cat "/proc/$t/task/$t/children" 2>/dev/null || true)
  kill -TERM "$t" 2>/dev/null || return 0
  if ! wait_for "pid $t to exit" 15 dead "$t"; then
    # shellcheck disable=SC2086 # d: the pids of its children
    kill -KILL $d "$t" 2>/dev/null || true
  fi
  wait "$t" 2>/dev/null || true
}
no_jobs() { [ -z "$(squeue -h -o %i -j "$(
  IFS=,
  echo "${jobs_[*]}"
)" 2>/dev/null)" ]; }
cleanup() {
  local rc=$? i p
  set +e
  trap - EXIT INT TERM
  [ -n "${watchdog:-}" ] && kill "$watchdog" 2>/dev/null && wait "$watchdog" 2>/dev/null
  cd /
  if [ ${#jobs_[@]} -gt 0 ] && [ ${#daemons[@]} -ge 3 ]; then
    scancel "${jobs_[@]}" 2>/dev/null
    wait_for "the jobs to end" 45 no_jobs
  fi
  for ((i = ${#daemons[@]} - 1; i >= 0; i--)); do stop "${daemons[i]}"; done
  for p in $(procs_in_tmp); do
    note "killing pid $p, left in $T: $(tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null)"
    kill -KILL "$p" 2>/dev/null
  done
  if [ $rc -ne 0 ]; then
    # the daemons' logs (their stderr only if they wrote no log), the jobs'
    for f in "$T"/log/*.out "$T"/log/*.log "$T"/work/*.out "$T"/pwork/*.log; do
      [ -s "$f" ] || continue
      case $f in *.out) [ -s "${f%.out}.log" ] && continue ;; esac
      echo "---- $f (last 30 lines)"
      tail -n 30 "$f"
    done
  fi
  if [ -n "${EA_KEEP:-}" ]; then note "kept $T"; else rm -rf "$T"; fi
  note "exit $rc"
  exit $rc
}
trap cleanup EXIT
trap 'note "interrupted"; exit 1' INT TERM
# A test that overruns its time is stopped by itself, with its clean-up.
(
  trap 'kill "$s" 2>/dev/null; exit 0' TERM
  sleep $LIMIT &
  s=$!
  wait "$s" && kill -TERM $$
) </dev/null >/dev/null 2>&1 &
watchdog=$!
mkdir -p "$T/log" "$T/munge" "$T/state" "$T/spool" "$T/work" "$T/pwork"

# --- 1. The single-process run (one worker, in this process), beside the set-up.
note "single-process run: $EA_BIN study $SPEC --threads 1"
"$EA_BIN" study "$SPEC" --threads 1 --no-checkpoint --quiet -o "$T/single.csv" &
single=$!

# --- 2. A single-node Slurm.
# Two free TCP ports below the ephemeral range, chosen now (listening sockets
# from /proc/net/tcp{,6}).
listening() {
  local _ addr st
  cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | while read -r _ addr _ st _; do
    [ "$st" = 0A ] && echo $((16#${addr##*:}))
  done
  return 0
}
free_port() {
  local used p i
  used=$(listening)
  for i in $(seq 200); do
    p=$((20000 + RANDOM % 12000))
    [ "$p" != "${1:-}" ] && ! grep -qx "$p" <<<"$used" && echo "$p" && return 0
  done
  return 1
}
ctld_port=$(free_port)
slurmd_port=$(free_port "$ctld_port")
host=$(hostname -s)
note "Slurm $(slurmd -V | awk '{ print $2 }') in $T: node $host, ports $ctld_port (slurmctld) and $slurmd_port (slurmd)"

dd if=/dev/urandom of="$T/munge/key" bs=1024 count=1 status=none
chmod 400 "$T/munge/key"
# MUNGE as root: --force, since its socket's parent folders (/tmp) are
# writable by others.
timeout -k 5 $((LIMIT + 60)) munged -F --force --key-file="$T/munge/key" \
  --socket="$T/munge/socket" --pid-file="$T/munge/pid" --seed-file="$T/munge/seed" \
  --log-file="$T/log/munged.log" >"$T/log/munged.out" 2>&1 &
daemons+=($!)
munge_ok() { munge -n -S "$T/munge/socket" 2>/dev/null | unmunge -S "$T/munge/socket" >/dev/null 2>&1; }
wait_for "munged" 20 munge_ok

# No cgroups: process tracking by /proc, no task binding, no accounting.
# cred_expire=10 (default 120 s): a requeued job waits that long before it
# may start again; sched_interval=1 (default 60 s): it starts then.
cat >"$T/slurm.conf" <<EOF
ClusterName=elasticarm-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/socket,cred_expire=10
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
ReturnToService=2
MailProg=/bin/true
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$T/slurm.conf
timeout -k 5 $((LIMIT + 60)) slurmctld -D -f "$SLURM_CONF" >"$T/log/slurmctld.out" 2>&1 &
daemons+=($!)
ctld_up() { scontrol ping 2>/dev/null | grep -q 'is UP'; }
wait_for "slurmctld" 30 ctld_up
timeout -k 5 $((LIMIT + 60)) slurmd -D -f "$SLURM_CONF" >"$T/log/slurmd.out" 2>&1 &
daemons+=($!)
node_idle() { [ "$(sinfo -h -n "$host" -o %t 2>/dev/null)" = idle ]; }
wait_for "slurmd (node $host idle)" 30 node_idle
note "Slurm up: $(sinfo -h -o '%P %a %D %t %C')"

wait "$single"
note "single-process run done: $(wc -l <"$T/single.csv") lines"

# The recipe, as docs/cluster.md gives it (with the binary from EA).
cd "$T/work"
export EA=$EA_BIN
jid=$(sbatch --parsable --array=1-$N --cpus-per-task=1 --time=10 \
  "$SRC/docs/cluster/study-array.sbatch" "$SPEC" $N)
jobs_+=("$jid")
mjid=$(sbatch --parsable --dependency=afterok:"$jid" --wrap \
  "$EA study merge results/$NAME.csv results/$NAME.shard*-of-$N.csv --spec $SPEC")
jobs_+=("$mjid")
note "submitted array job $jid (tasks 1-$N) and merge job $mjid (afterok:$jid)"

# Requeue task 2 once its journal holds 2 cases.
journal=results/$NAME.shard2-of-$N.csv.journal
cases_in() { grep -c '^#case ' "$1" 2>/dev/null || true; }
two_cases() { [ "$(cases_in "$journal")" -ge 2 ]; }
wait_for "task 2's journal to hold 2 cases" 120 two_cases
scontrol requeue "${jid}_2"
at=$(cases_in "$journal")
note "requeued task ${jid}_2 with $at case(s) in its journal"

wait_for "the array and the merge to end" 300 no_jobs
note "jobs done"
fail=0
check() {
  if "$@"; then return 0; fi
  note "FAILED: $*"
  fail=1
}
field() { scontrol show job "$1" | tr ' ' '\n' | sed -n "s/^$2=//p" | head -n 1; }
for k in $(seq 1 $N); do
  check [ "$(field "${jid}_$k" JobState)" = COMPLETED ]
  check [ "$(field "${jid}_$k" ExitCode)" = 0:0 ]
done
check [ "$(field "$mjid" JobState)" = COMPLETED ]
check [ "$(field "${jid}_2" Restarts)" = 1 ]
jnum() { sed -n "s/^ *\"$2\": \([0-9]*\),*$/\1/p" "$1"; }
skipped=$(jnum "results/$NAME.shard2-of-$N.json" cases_skipped_from_checkpoint)
note "task 2 after its restart: $skipped case(s) from the journal, $(jnum "results/$NAME.shard2-of-$N.json" cases_computed) computed"
check [ "${skipped:-0}" -ge "$at" ]
check grep -q 'interrupted' "slurm-${jid}_2.out"
check [ ! -e "$journal" ]
check cmp "results/$NAME.csv" "$T/single.csv"
[ $fail -eq 0 ] || exit 1
note "Slurm: the merged CSV equals the single run's ($(wc -c <"results/$NAME.csv") bytes)"

# --- 3. GNU parallel: study-parallel.sh, 3 shards 2 at a time; shard 2
# stopped mid-way (SIGTERM to its study, as a preemption would), then the same
# command again: it must resume shard 2 from its journal, run shard 3 and
# leave the finished shard 1 alone.
cd "$T/pwork"
recipe() { THREADS=1 JOBS=2 sh "$SRC/docs/cluster/study-parallel.sh" "$SPEC" $N; }
ea_exe=$(readlink -f "$EA_BIN")
# shard_pid K: the elasticarm process computing shard K here
shard_pid() {
  local p
  for p in $(procs_in_tmp); do
    [ "$(readlink -f "/proc/$p/exe" 2>/dev/null)" = "$ea_exe" ] &&
      [ "$(readlink "/proc/$p/cwd")" = "$T/pwork" ] &&
      tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null | grep -q -- "--shard $1/$N " && echo "$p"
  done
  return 0
}
recipe >"$T/pwork/first.log" 2>&1 &
prun=$!
journal=results/$NAME.shard2-of-$N.csv.journal
wait_for "shard 2's journal to hold 2 cases" 120 two_cases
p2=$(shard_pid 2)
[ -n "$p2" ] || {
  note "no process computing shard 2"
  exit 1
}
kill -TERM "$p2"
at=$(cases_in "$journal")
note "stopped shard 2 (pid $p2) with $at case(s) in its journal"
wait_for "the first run of study-parallel.sh to end" 120 dead "$prun"
prc=0
wait "$prun" || prc=$?
note "first run: exit $prc; $(cd results && echo *)"
check [ $prc -ne 0 ]
check [ ! -e "results/$NAME.csv" ]
check [ -f "results/$NAME.shard1-of-$N.csv" ]
stamp1=$(stat -c '%i %Y' "results/$NAME.shard1-of-$N.csv" 2>/dev/null || true)
recipe >"$T/pwork/second.log" 2>&1 || check false "second run of study-parallel.sh"
skipped=$(jnum "results/$NAME.shard2-of-$N.json" cases_skipped_from_checkpoint)
note "second run: shard 2 took $skipped case(s) from its journal"
check [ "${skipped:-0}" -ge "$at" ]
check [ "$(stat -c '%i %Y' "results/$NAME.shard1-of-$N.csv")" = "$stamp1" ]
check cmp "results/$NAME.csv" "$T/single.csv"
[ $fail -eq 0 ] || exit 1
note "GNU parallel: the merged CSV equals the single run's"
note "passed"
