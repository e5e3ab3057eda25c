#!/usr/bin/env bash
# Issue 16, requirement 4: a real Slurm run. Starts a single-node Slurm cluster on localhost from the
# Debian packages (slurm-wlm, munge; no systemd: munged, slurmctld -D and slurmd -D as background
# children of this script, everything in one temporary folder, ports chosen free on 127.0.0.1),
# waits until the node is idle, submits `sbatch --array=1-4 --wait` of a job whose tasks run
# `shapespline sample ... --shard auto -o out-{shard:02d}-of-{count:02d}.EXT` (.f32 and welded .ply),
# merges each by its pattern and compares it byte for byte (cmp) with the unsharded job; then
# requeues array task 3 and checks that it says its shard is complete and leaves the files as they
# were (inode, mtime, SHA-256). The cluster is always torn down (trap: scancel, the daemons
# stopped, the folder removed); every wait is bounded.
#
# usage: slurm_array_test.sh SHAPESPLINE_BINARY MODEL
# Exit 77 (ctest SKIP_RETURN_CODE) with the reason when a Slurm or munge binary is absent or this
# is not root (SlurmUser=root); scripts/setup.sh installs the packages and CI runs as root.
set -uo pipefail

readonly SKIP=77
BIN=$(realpath "${1:?usage: slurm_array_test.sh SHAPESPLINE_BINARY MODEL}")
MODEL=$(realpath "${2:?usage: slurm_array_test.sh SHAPESPLINE_BINARY MODEL}")
readonly BIN MODEL
T0=$(date +%s%N)
readonly T0

skip() {
  echo "SKIP: $*"
  exit "$SKIP"
}
for tool in munged mungekey slurmctld slurmd sbatch sinfo squeue scontrol scancel cmp sha256sum timeout; do
  command -v "$tool" >/dev/null 2>&1 ||
    skip "'$tool' is not installed (scripts/setup.sh installs slurm-wlm and munge from Debian)"
done
[[ $(id -u) -eq 0 ]] || skip "needs root: the test cluster runs with SlurmUser=root (CI runs as root)"
[[ -x "$BIN" ]] || { echo "FAIL: $BIN is not an executable" >&2; exit 1; }

W=$(mktemp -d /tmp/shapespline-slurm.XXXXXX)
chmod 755 "$W"  # munged wants its socket's folders searchable by all
mkdir -p "$W/state" "$W/spool" "$W/out" "$W/logs"
PIDS=()
JOB=""

elapsed() {
  local ms=$((($(date +%s%N) - T0) / 1000000))
  printf '%d.%03d' $((ms / 1000)) $((ms % 1000))
}

cleanup() {
  local rc=$? queue
  trap - EXIT INT TERM HUP
  # Every job of this private cluster (our slurmctld, through SLURM_CONF) is ours: cancel them all,
  # and give their steps up to 5 s to end before the daemons stop.
  if [[ -n "${SLURM_CONF:-}" ]]; then
    timeout 5 scancel --quiet --partition=test >/dev/null 2>&1
    for _ in $(seq 1 25); do
      queue=$(timeout 2 squeue -h 2>/dev/null) || break  # no controller: nothing left to wait for
      [[ -z "$queue" ]] && break
      sleep 0.2
    done
  fi
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for _ in $(seq 1 50); do  # at most 5 s for a clean stop, then SIGKILL
    local alive=0
    for p in "${PIDS[@]}"; do kill -0 "$p" 2>/dev/null && alive=1; done
    ((alive)) || break
    sleep 0.1
  done
  for p in "${PIDS[@]}"; do kill -KILL "$p" 2>/dev/null; done
  for p in "${PIDS[@]}"; do wait "$p" 2>/dev/null; done
  rm -rf "$W"
  echo "slurm test: wall time $(elapsed) s (exit $rc)"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM HUP

fail() {
  echo "FAIL: $*" >&2
  for f in "$W"/slurmctld.log "$W"/slurmd.log "$W"/munged.log "$W"/logs/*; do
    [[ -f "$f" ]] || continue
    echo "---- $(basename "$f") (last lines)" >&2
    tail -n 25 "$f" >&2
  done
  exit 1
}

# Two free TCP ports on 127.0.0.1 for slurmctld and slurmd.
read -r CTLD_PORT SLURMD_PORT < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])' 2>/dev/null || echo "$((20000 + RANDOM % 20000)) $((40000 + RANDOM % 20000))")

# ---- munge ---------------------------------------------------------------------------------------
mungekey --create --keyfile="$W/munge.key" >/dev/null 2>&1 || fail "mungekey could not create a key"
chmod 400 "$W/munge.key"
munged -F --force --key-file="$W/munge.key" --socket="$W/munge.socket" --pid-file="$W/munged.pid" \
  --log-file="$W/munged.log" --seed-file="$W/munged.seed" >"$W/logs/munged.out" 2>&1 &
PIDS+=($!)
for _ in $(seq 1 50); do [[ -S "$W/munge.socket" ]] && break; sleep 0.1; done
[[ -S "$W/munge.socket" ]] || fail "munged did not create its socket within 5 s"

# ---- slurm.conf, slurmctld, slurmd ------------------------------------------------------------------
cat >"$W/slurm.conf" <<EOF
ClusterName=shapespline-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$W/munge.socket
CredType=cred/munge
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/slurmctld.log
SlurmdLogFile=$W/slurmd.log
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
SlurmdParameters=config_overrides
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$W/slurm.conf"
slurmctld -D -c -f "$SLURM_CONF" >"$W/logs/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" >"$W/logs/slurmd.out" 2>&1 &
PIDS+=($!)
state=""
for _ in $(seq 1 100); do  # at most 20 s
  state=$(timeout 5 sinfo -h -N -n localhost -o '%T' 2>/dev/null)
  [[ "$state" == idle* ]] && break
  sleep 0.2
done
[[ "$state" == idle* ]] || fail "the node did not become idle within 20 s (sinfo: '${state}')"
echo "slurm test: cluster up (node $state, ports $CTLD_PORT/$SLURMD_PORT) after $(elapsed) s"

# ---- the array job ----------------------------------------------------------------------------------
cat >"$W/job.sh" <<EOF
#!/usr/bin/env bash
set -euo pipefail
echo "task \$SLURM_ARRAY_TASK_ID of \$SLURM_ARRAY_TASK_MIN-\$SLURM_ARRAY_TASK_MAX"
for ext in f32 ply; do
  env -u JOB_COMPLETION_INDEX -u SHAPESPLINE_SHARD_COUNT "$BIN" sample "$MODEL" --grid 9 --device cpu \
    --shard auto -o "$W/out/out-{shard:02d}-of-{count:02d}.\$ext"
done
EOF
chmod 755 "$W/job.sh"
submit=$(timeout 60 sbatch --parsable --wait --array=1-4 -D "$W/out" -o "$W/logs/task-%a.log" "$W/job.sh")
rc=$?
JOB=${submit%%;*}
[[ $rc -eq 0 && -n "$JOB" ]] || fail "sbatch --array=1-4 --wait failed (exit $rc, job '${submit}')"
echo "slurm test: array job $JOB done after $(elapsed) s"
for k in 1 2 3 4; do
  grep -q "task $k of 1-4" "$W/logs/task-$k.log" || fail "task $k did not run as array task $k of 1-4"
  for ext in f32 ply; do
    f="$W/out/out-0$k-of-04.$ext"
    [[ -f "$f" && -f "$f.shard.json" ]] || fail "task $k wrote no $f with its shard record"
  done
done

# ---- merge by pattern, compare with the unsharded job -------------------------------------------------
for ext in f32 ply; do
  "$BIN" sample "$MODEL" --grid 9 --device cpu -q -o "$W/whole.$ext" || fail "the unsharded .$ext job failed"
  "$BIN" merge -o "$W/merged.$ext" "$W/out/out-{shard:02d}-of-{count:02d}.$ext" || fail "merge of the .$ext shards failed"
  cmp "$W/merged.$ext" "$W/whole.$ext" || fail "the merged .$ext differs from the unsharded job's"
done
echo "slurm test: merged .f32 and .ply are byte for byte the unsharded files"

# ---- rerun array task 3: its shard verifies, nothing is written -------------------------------------
stamp() {
  for f in "$W"/out/out-03-of-04.f32 "$W"/out/out-03-of-04.f32.json "$W"/out/out-03-of-04.f32.shard.json \
    "$W"/out/out-03-of-04.ply "$W"/out/out-03-of-04.ply.shard.json; do
    stat -c '%i %y %s' "$f"
    sha256sum <"$f"
  done
}
before=$(stamp)
timeout 10 scontrol requeue "${JOB}_3" || fail "scontrol requeue ${JOB}_3 failed"
timeout 10 scontrol update JobId="${JOB}_3" StartTime=now || fail "scontrol update ${JOB}_3 StartTime=now failed"
done_again=0
for _ in $(seq 1 150); do  # at most 30 s
  line=$(timeout 5 scontrol -o show job "${JOB}_3" 2>/dev/null)
  if [[ "$line" == *"JobState=COMPLETED"* && "$line" != *"Restarts=0"* ]]; then done_again=1; break; fi
  if [[ "$line" == *"JobState=FAILED"* ]]; then fail "the requeued task 3 failed"; fi
  sleep 0.2
done
((done_again)) || fail "the requeued task 3 did not complete within 30 s ($line)"
for ext in f32 ply; do
  grep -q "out-03-of-04.$ext: shard 3/4 is complete: its files verify against" "$W/logs/task-3.log" ||
    fail "the rerun of task 3 did not say that its .$ext shard is complete"
done
if grep -q "wrote" "$W/logs/task-3.log"; then fail "the rerun of task 3 wrote a file"; fi
[[ "$(stamp)" == "$before" ]] || fail "the rerun of task 3 touched its files"
echo "slurm test: requeued task 3 verified its shards and left them untouched after $(elapsed) s"
echo "PASS"
