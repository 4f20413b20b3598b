#!/bin/sh
# Campaign runner speed (run by bench/bench.sh with BIN, ROOT, WORK, REPEAT):
#   campaign_dispatch_ms        the runner's time per job with a no-op job (the
#                               stand-in, action ok), 400 jobs one at a time:
#                               claim, directory, process start, reading and
#                               recording the result (as the runner reports it)
#   campaign_slot_idle_ms       of it, what a job waits for: the slot's idle
#                               time from a job's exit (reaped) to the next
#                               one's start (the clone; the child's own set-up
#                               and exec follow beside the runner), as the
#                               runner reports it (the claim and the directory
#                               of the next job are done ahead, while the job
#                               runs)
#   campaign_metric_rows_per_s  metric rows recorded per second (20 jobs of
#                               5,000 metrics each)
#   campaign_status_1m_ms       `cascade status` (the slower of its two forms:
#                               all studies, one study) on a database of
#                               1,000,000 jobs, registered by `cascade plan`
#                               (a few minutes on a busy machine)
# Medians of REPEAT runs.
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}" "${REPEAT:=3}"
D="$WORK/campaign"
mkdir -p "$D"
FAKE="$BIN/fake-solver"
if [ ! -x "$FAKE" ]; then
    variant=$(basename "$(dirname "$BIN")")
    if [ "$BIN" = "$ROOT/bin" ]; then
        make -s -C "$ROOT" bin/fake-solver >&2
    else
        make -s -C "$ROOT" BUILD="$variant" "build/$variant/bin/fake-solver" >&2
    fi
fi
. "$ROOT/bench/lib.sh"
now_ns() { date +%s%N; }
values() { # values N -> [1, 2, ..., N]
    seq -s ', ' 1 "$1" | sed 's/^/[/; s/$/]/'
}

# --- dispatch --------------------------------------------------------------
# The runner reports the time it spends per job between the jobs' own work
# (claim in the database, run directory and case.yaml, process start, reading
# result.json and hashing the files, recording), and how long a slot stood
# empty between two jobs (the claim and directory of the next job are made
# while the job before runs, and the job before is recorded after the next
# one started: docs/campaign.md, "Claiming ahead").  For
# scale, the wall-clock cost of one more job (slope from 100 to 400 jobs, one
# at a time) and of the no-op run alone are printed too.
#
# Every campaign here runs in a directory of its own, and the directories
# are deleted only after the last measurement: on an ext4 file system
# without a journal (this machine's) the kernel skips, for every new inode,
# the inodes freed in the last one to two minutes (ext4's recently_deleted
# check), so deleting the previous round's 2,800 files right before a round
# made every mkdir, symlink and create of the runner scan past them -- a
# third of the runner's time in perf, a cost of the bench, not of a
# campaign (docs/bench.md, "Campaign dispatch, sixth round").
for n in 100 400; do
    printf 'name: noop%s\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: %s}}\n' \
        "$n" "$(values $n)" > "$D/noop$n.yaml"
done
rm -rf "$D"/round-* "$D/solo"
fresh_s() { # fresh_s DIR STUDY.yaml: seconds of a no-op campaign in a new DIR
    mkdir -p "$1"
    t0=$(now_ns)
    (cd "$1" && "$BIN/cascade" run "$D/$2" --solver "$FAKE" --jobs 1 2>&1) > "$1/report"
    t1=$(now_ns)
    echo "($t1 - $t0) / 1000000000" | bc -l
}
bare_s() { # the no-op job run directly, 300 times
    t0=$(now_ns)
    n=0
    while [ $n -lt 300 ]; do
        n=$((n + 1))
        "$FAKE" run "$D/solo/case.yaml" --out "$D/solo" --threads 1 --quiet --no-progress \
            >"$D/solo/stdout" 2>"$D/solo/stderr"
    done
    t1=$(now_ns)
    echo "($t1 - $t0) / 1000000000" | bc -l
}
: > "$D/dispatch"; : > "$D/idle"; : > "$D/perjob"; : > "$D/bare"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    a=$(fresh_s "$D/round-$i-100" noop100.yaml)
    b=$(fresh_s "$D/round-$i-400" noop400.yaml)
    sed -n 's/.*runner time per job: \([0-9.]*\) ms.*/\1/p' "$D/round-$i-400/report" >> "$D/dispatch"
    sed -n 's/.*slot idle between jobs: \([0-9.]*\) ms.*/\1/p' "$D/round-$i-400/report" >> "$D/idle"
    echo "($b - $a) * 1000 / 300" | bc -l >> "$D/perjob"
done
# the bare runs rewrite result.json (a new inode each time, the old one
# freed) after the campaigns, not between them
mkdir -p "$D/solo"
cp "$(ls -d "$D"/round-1-400/runs/noop400/* | head -n1)/current/case.yaml" "$D/solo/case.yaml"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    c=$(bare_s)
    echo "$c * 1000 / 300" | bc -l >> "$D/bare"
done
rm -rf "$D"/round-*
echo "bench: wall clock: one more no-op job costs $(median < "$D/perjob" | xargs printf '%.2f') ms" \
     "in a campaign; the no-op run alone $(median < "$D/bare" | xargs printf '%.2f') ms" >&2
bench_line campaign_dispatch_ms "$(median < "$D/dispatch" | xargs printf '%.2f')" ms "target 0.5; $(bench_load)"
bench_line campaign_slot_idle_ms "$(median < "$D/idle" | xargs printf '%.2f')" ms \
    "from a job's exit to the next one's start; the wall-clock figures above"

# --- metric rows -------------------------------------------------------------
# 20 jobs writing 5,000 metrics each; the time is what the runner reports for
# reading result.json, hashing the files and writing the database (the
# stand-in's own time to write the metrics is not the runner's)
printf 'name: rows\nbase: {fake: {action: ok, metrics: 5000}}\nsweep: {grid: {fake.x: %s}}\n' \
    "$(values 20)" > "$D/rows.yaml"
: > "$D/rows"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    rm -rf "$D/runs" "$D"/cascade.db*
    (cd "$D" && "$BIN/cascade" run rows.yaml --solver "$FAKE" --jobs 1 2>&1) \
        | sed -n 's/.* \([0-9]*\) metric rows recorded in \([0-9.]*\) s.*/\1 \2/p' \
        | awk '{print $1 / $2}' >> "$D/rows"
done
bench_line campaign_metric_rows_per_s "$(median < "$D/rows" | xargs printf '%.0f')" rows/s "20 jobs x 5,000 metrics"

# --- status on 1,000,000 jobs ------------------------------------------------
rm -rf "$D/runs" "$D"/cascade.db*
printf 'name: big\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: %s, fake.y: %s}}\nrepeats: 1\n' \
    "$(values 1000)" "$(values 1000)" > "$D/big.yaml"
t0=$(now_ns)
(cd "$D" && "$BIN/cascade" plan big.yaml --solver "$FAKE" --register >/dev/null 2>&1)
t1=$(now_ns)
# a realistic state: 90 % done, 5 % failed, 1 % running, the rest pending
# (no metrics: status does not read them)
sqlite3 "$D/cascade.db" <<'SQL'
PRAGMA foreign_keys = ON;
PRAGMA cache_size = -1048576;
BEGIN;
INSERT INTO runs (job_id, attempt, status, exit_code, message, started, finished, wall_s,
                  peak_rss_mib, host, runner, launcher, solver_version, solver_git, run_dir)
SELECT id, 1,
       CASE WHEN id % 100 < 90 THEN 'done' WHEN id % 100 < 95 THEN 'failed' ELSE 'running' END,
       CASE WHEN id % 100 < 90 THEN 0 WHEN id % 100 < 95 THEN 3 END,
       CASE WHEN id % 100 BETWEEN 90 AND 94 THEN 'exit 3: bench' END,
       '2024-01-01T00:00:00.000Z', '2024-01-01T00:00:01.000Z', 1.0, 10.0, 'bench',
       'bench:1:1', 'local', 'fake-1.0', 'standin', '/tmp/bench/' || key
FROM jobs WHERE id % 100 < 96;
COMMIT;
SQL
t2=$(now_ns)
echo "bench: 1,000,000 jobs registered in $(( (t1 - t0) / 1000000000 )) s, runs recorded in $(( (t2 - t1) / 1000000000 )) s" >&2
: > "$D/status"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    for args in "" "big"; do
        t0=$(now_ns)
        (cd "$D" && "$BIN/cascade" status $args >/dev/null)
        t1=$(now_ns)
        echo "$args $(( (t1 - t0) / 1000 ))" >> "$D/status"
    done
done
s_all=$(grep -v '^big' "$D/status" | awk '{print $NF}' | median)
s_big=$(grep '^big' "$D/status" | awk '{print $NF}' | median)
worst=$(printf '%s\n%s\n' "$s_all" "$s_big" | sort -g | tail -n1)
echo "bench: cascade status: $(echo "$s_all / 1000" | bc -l | xargs printf '%.1f') ms (all studies)," \
     "$(echo "$s_big / 1000" | bc -l | xargs printf '%.1f') ms (cascade status big)" >&2
bench_line campaign_status_1m_ms "$(echo "$worst / 1000" | bc -l | xargs printf '%.1f')" ms "target 200"
rm -rf "$D/runs" "$D"/cascade.db*
