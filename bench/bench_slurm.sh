#!/bin/sh
# Slurm backend (run by bench/bench.sh with BIN, ROOT, WORK, REPEAT), against
# a one-node Slurm cluster this script starts for itself (munged, slurmctld,
# slurmd under $WORK/slurm, ports of its own; the node claims 256 CPUs so a
# 1000-job sweep is not held back by this machine's cores) and stops at the
# end, by the pids it started:
#   slurm_submit_ms_per_job   a 1000-job sweep of no-op jobs (the stand-in,
#                             action ok): the runner's time per job to claim
#                             it, write its directory and job script
#                             ("claim and start"), plus the backend's time per
#                             job to write the array script, sbatch it, record
#                             the ids and release the array
#   slurm_runner_cpu_ms_per_job  CPU time (user + system) of the runner process
#                             per job over the whole run (submitting, 8 s of
#                             polling, cancelling): what the wall figure is
#                             on a machine that is not shared
#   slurm_calls_per_poll      Slurm client calls per poll interval while the
#                             1000 jobs are queued and running (squeue, plus
#                             scontrol/sacct when needed): O(1), not O(jobs)
# Each repeat: submit, follow the queue for 8 s, then cascade cancel.  Medians
# of REPEAT runs.  Skipped (with the reason) when the daemons cannot start.
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}" "${REPEAT:=3}"
. "$ROOT/bench/lib.sh"
for p in munged slurmctld slurmd sbatch squeue; do
    if ! command -v $p >/dev/null 2>&1; then
        echo "bench_slurm: $p not installed (make deps installs slurm-wlm and munge); skipped" >&2
        exit 0
    fi
done
FAKE="$BIN/fake-solver"
if [ ! -x "$FAKE" ]; then
    variant=$(basename "$(dirname "$BIN")")
    if [ "$BIN" = "$ROOT/bin" ]; then
        make -s -C "$ROOT" bin/fake-solver >&2
    else
        make -s -C "$ROOT" BUILD="$variant" "build/$variant/bin/fake-solver" >&2
    fi
fi

# munged wants every directory up to its socket searchable by all, which
# $WORK (mktemp -d) is not: the cluster gets a directory of its own
S=$(mktemp -d /tmp/cascade-slurm-bench.XXXXXX)
mkdir -p "$S/state" "$S/spool" "$S/log" "$S/munge"
chmod 755 "$S" "$S/munge"
head -c 1024 /dev/urandom > "$S/munge/munge.key"
chmod 400 "$S/munge/munge.key"
port=$((21000 + $$ % 2000 * 8))
host=$(hostname -s)
cat > "$S/slurm.conf" <<EOF
ClusterName=cascadebench
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$S/munge/sock
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/log/slurmctld.log
SlurmdLogFile=$S/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SlurmdParameters=config_overrides
DefMemPerCPU=100
MpiDefault=none
ReturnToService=2
KillWait=2
MinJobAge=60
SchedulerParameters=sched_interval=2
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=256 RealMemory=100000 State=UNKNOWN
PartitionName=bench Nodes=ALL Default=YES MaxTime=10:00 State=UP
EOF
export SLURM_CONF="$S/slurm.conf"
pids=""
stop_cluster() {
    scancel --user="$(id -un)" >/dev/null 2>&1 || true
    sleep 1
    for p in $pids; do kill "$p" 2>/dev/null || true; done
    for p in $pids; do wait "$p" 2>/dev/null || true; done
    rm -rf "$S"
}
trap 'stop_cluster' EXIT
munged -F --socket="$S/munge/sock" --key-file="$S/munge/munge.key" \
    --pid-file="$S/munge/munged.pid" --seed-file="$S/munge/seed" \
    --log-file="$S/log/munged.log" >"$S/log/munged.out" 2>&1 &
pids="$!"
i=0; while [ ! -S "$S/munge/sock" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
slurmctld -D -i -f "$S/slurm.conf" >"$S/log/slurmctld.out" 2>&1 &
pids="$! $pids"
slurmd -D -f "$S/slurm.conf" >"$S/log/slurmd.out" 2>&1 &
pids="$! $pids"
i=0
until [ "$(sinfo -h -N -o %t 2>/dev/null)" = idle ]; do
    i=$((i + 1))
    if [ $i -gt 300 ]; then
        echo "bench_slurm: the node did not come up idle in 30 s; skipped. slurmd.log:" >&2
        tail -5 "$S/log/slurmd.log" >&2 || true
        exit 0
    fi
    sleep 0.1
done

D="$WORK/slurm-study"
mkdir -p "$D"
cat > "$D/b.yaml" <<EOF
name: slurmbench
base: {fake: {action: ok}}
sweep: {grid: {fake.x: [$(seq -s ', ' 1 1000)]}}
backend: slurm
slurm: {poll: 1, time: 5}
EOF
: > "$WORK/slurm.submit"; : > "$WORK/slurm.calls"; : > "$WORK/slurm.cpu"
r=0
while [ $r -lt "$REPEAT" ]; do
    r=$((r + 1))
    rm -rf "$D/runs" "$D"/cascade.db*
    (cd "$D" && exec /usr/bin/time -f '%U %S' -o "$D/cpu" "$BIN/cascade" run b.yaml \
        --solver "$FAKE" >"$D/run.log" 2>&1) &
    runner=$!
    # all 1000 submitted, then 8 s of polling
    i=0
    while [ "$(sqlite3 "$D/cascade.db" "SELECT count(*) FROM runs WHERE slurm_job_id IS NOT NULL" 2>/dev/null || echo 0)" -lt 1000 ] && [ $i -lt 1200 ]; do
        sleep 0.1; i=$((i + 1))
    done
    sleep 8
    (cd "$D" && "$BIN/cascade" cancel slurmbench >/dev/null 2>&1) || true
    wait "$runner" 2>/dev/null || true
    start=$(grep -o 'claim and start [0-9.]* ms' "$D/run.log" | awk '{print $4}')
    sub=$(grep -o 'arrays*, [0-9.]* ms per attempt' "$D/run.log" | awk '{print $2}')
    calls=$(grep -o '[0-9.]* client calls per poll' "$D/run.log" | awk '{print $1}')
    if [ -z "$start" ] || [ -z "$sub" ] || [ -z "$calls" ]; then
        echo "bench_slurm: run $r did not report its figures:" >&2
        tail -5 "$D/run.log" >&2
        continue
    fi
    echo "$start + $sub" | bc -l >> "$WORK/slurm.submit"
    awk '{print ($1 + $2) * 1000 / 1000}' "$D/cpu" >> "$WORK/slurm.cpu"
    echo "$calls" >> "$WORK/slurm.calls"
    scancel --user="$(id -un)" >/dev/null 2>&1 || true
    sleep 1
done
if [ -s "$WORK/slurm.submit" ]; then
    bench_line slurm_submit_ms_per_job "$(median < "$WORK/slurm.submit" | xargs printf '%.3f')" ms \
        "target 2"
    bench_line slurm_runner_cpu_ms_per_job "$(median < "$WORK/slurm.cpu" | xargs printf '%.3f')" ms
    bench_line slurm_calls_per_poll "$(median < "$WORK/slurm.calls" | xargs printf '%.2f')" calls \
        "target O(1): 1"
fi
