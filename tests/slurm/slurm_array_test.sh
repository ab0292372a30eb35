#!/bin/bash
# Runs examples/slurm for real: a single-node Slurm (slurmctld, slurmd, munged) started here as
# root, without systemd, with its configuration and state in a temporary folder and every address 127.0.0.1.
# The job array runs the shards of a small study; one task is requeued (scontrol requeue) while it runs; the
# merge job runs after the array; the merged results and report must equal an unsharded local run.
# Exit 77 (ctest: skipped) without root or without Slurm and munge.
#   tests/slurm/slurm_array_test.sh KINCAL_BINARY SOURCE_DIR
set -u
kincal=$(realpath "$1")
source_dir=$(realpath "$2")
t_start=$(date +%s)

if [ "$(id -u)" -ne 0 ]; then
  echo "SKIPPED: needs root (it starts slurmctld, slurmd and munged)"
  exit 77
fi
for tool in slurmctld slurmd munged sbatch scontrol squeue sinfo; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIPPED: $tool not found (apt-get install slurm-wlm munge)"
    exit 77
  fi
done

tmp=$(mktemp -d /tmp/kincal-slurm.XXXXXX)
chmod 700 "$tmp"
pids=()
fail() {
  echo "FAILED: $*"
  for log in "$tmp"/slurmctld.log "$tmp"/slurmd.log "$tmp"/out/logs/*.log; do
    [ -f "$log" ] && { echo "---- $log (last 30 lines)"; tail -n 30 "$log"; }
  done
  exit 1
}
cleanup() {
  local status=$?
  if [ -f "$tmp/slurm.conf" ] && [ ${#pids[@]} -ge 2 ]; then
    scancel --full --quiet --user=root 2>/dev/null  # jobs first, so that no slurmstepd outlives the test
    for _ in $(seq 50); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.2; done
  fi
  for ((k = ${#pids[@]} - 1; k >= 0; --k)); do kill -TERM "${pids[k]}" 2>/dev/null; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null
  done
  rm -rf "$tmp"
  echo "slurm test took $(($(date +%s) - t_start)) s"
  exit $status
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# ---- munge: its own key and socket; munged refuses folders that root does not own ------------------------
mkdir -p "$tmp/munge"
chmod 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
munge_socket="$tmp/munge/munge.socket"
munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$munge_socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" \
  > "$tmp/munge/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$munge_socket" ] && break; sleep 0.1; done
[ -S "$munge_socket" ] || { cat "$tmp/munge/munged.out" "$tmp/munge/munged.log"; fail "munged did not start"; }

# ---- Slurm: one node, this machine, on 127.0.0.1 and two free ports ---------------------------------------
free_port() {
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
ctld_port=$(free_port)
slurmd_port=$(free_port)
[ "$ctld_port" != "$slurmd_port" ] || slurmd_port=$(free_port)
cpus=$(nproc)
mkdir -p "$tmp/state" "$tmp/spool" "$tmp/out"
cat > "$tmp/slurm.conf" <<CONF
ClusterName=kincaltest
SlurmctldHost=$(hostname -s)(127.0.0.1)
MailProg=/bin/true
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$munge_socket,cred_expire=5
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=2
KillWait=10
SlurmctldTimeout=30
SlurmdTimeout=30
MessageTimeout=10
NodeName=kincalnode NodeAddr=127.0.0.1 NodeHostname=kincalnode CPUs=$cpus State=UNKNOWN
PartitionName=kincal Nodes=kincalnode Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE:4
CONF
export SLURM_CONF="$tmp/slurm.conf"
slurmctld -D -c -f "$SLURM_CONF" > "$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N kincalnode > "$tmp/slurmd.out" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 100); do
  kill -0 "${pids[1]}" 2>/dev/null && kill -0 "${pids[2]}" 2>/dev/null || break  # a daemon died
  state=$(sinfo -h -o %t 2>/dev/null)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "$state" = idle ] || { cat "$tmp/slurmctld.out" "$tmp/slurmd.out"; fail "the node is not idle: '$state'"; }
echo "slurm up after $(($(date +%s) - t_start)) s"

# ---- a small study: 3 shards of 6 work items (a few seconds each) ---------------------------------------------------------------
cat > "$tmp/study.yaml" <<STUDY
name: slurm test
seed: 5
trials: 9
robots:
  nominal: $source_dir/examples/robots/seed_nominal.yaml
  truth: $source_dir/examples/robots/seed_identified.yaml
datasets:
  - name: random
    simulate: {protocol: random, poses: 60, noise: 10um}
estimators: [least_squares]
compensators: [jacobian]
validation:
  - {name: targets, random_targets: 6000}
STUDY
"$kincal" study "$tmp/study.yaml" --out "$tmp/local" --threads "$cpus" > "$tmp/local.out" 2>&1 || fail "local run"

out="$tmp/out"
submitted=$(cd "$tmp" && KINCAL="$kincal" "$source_dir/examples/slurm/submit.sh" "$tmp/study.yaml" "$out" 3 2>&1) ||
  fail "submit.sh: $submitted"
echo "$submitted"
array=$(sed -n 's/^array=\([0-9]*\) merge=\([0-9]*\)$/\1/p' <<< "$submitted")
merge=$(sed -n 's/^array=\([0-9]*\) merge=\([0-9]*\)$/\2/p' <<< "$submitted")
[ -n "$array" ] && [ -n "$merge" ] || fail "no job ids from submit.sh"

# Requeue task 2 once it has journaled a work item and is still running.
journal="$out/shard_2/study.journal"
records() { [ -f "$journal" ] && echo $(($(wc -l < "$journal") - 1)) || echo 0; }
for _ in $(seq 600); do
  [ "$(records)" -ge 1 ] && break
  sleep 0.05
done
task_state=$(squeue -h -j "${array}_2" -o %T 2>/dev/null)
done_before=$(records)
[ "$task_state" = RUNNING ] && [ "$done_before" -ge 1 ] && [ "$done_before" -lt 6 ] ||
  fail "task 2 not caught mid-run (state '$task_state', $done_before of 6 items journaled); make the study longer"
scontrol requeue "${array}_2" || fail "scontrol requeue"
echo "requeued task ${array}_2 with $done_before of 6 items journaled"

# Wait for the merge job (it runs after every task succeeded).
deadline=$(($(date +%s) + 150))
merge_state=""
while [ "$(date +%s)" -lt "$deadline" ]; do
  merge_state=$(scontrol show job "$merge" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
  case "$merge_state" in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) break ;; esac
  sleep 0.2
done
[ "$merge_state" = COMPLETED ] || fail "merge job state '$merge_state'"

grep -q "restart 1" "$out/logs/shard_2.log" || fail "task 2 did not run again after the requeue"
grep -q "resuming: [1-9]" "$out/logs/shard_2.log" || fail "task 2 did not resume from its journal"
for file in study.json results.csv parameters.csv convergence.csv iso9283.csv; do
  cmp -s "$tmp/local/$file" "$out/merged/$file" || fail "merged $file differs from the local run"
done
without_times() { sed '/^## Times/,/^## Files/{/^## Files/!d}' "$1"; }
[ "$(without_times "$tmp/local/report.md")" = "$(without_times "$out/merged/report.md")" ] ||
  fail "merged report.md differs from the local run"
echo "PASSED: merged results and report equal the local run (task 2 requeued after $done_before items)"
