#!/bin/bash
# Soak test of the campaign runner (make soak; docs/campaign.md "Soak test").
#
#   bench/soak.sh [BINDIR]      (default: bin/ next to this script's parent)
#
# A study of SOAK_JOBS quick stand-in jobs (tests/standin/fake_solver.c):
# most succeed at once, 3 in 10 sleep SOAK_SLEEP s first (by default so
# that the study takes about SOAK_SECONDS), every 10th crashes
# (SIGSEGV: retried once, then failed for good as deterministic).
# SOAK_RUNNERS `cascade run` processes share it (--jobs 2, --lease
# SOAK_LEASE) while, spread over SOAK_SECONDS, SOAK_KILLS kill -9s hit a
# random runner (a new one takes its place) or a random solver (each job at
# most once), and SOAK_FREEZES runners are frozen (SIGSTOP) for longer than
# the lease and woken up again (SIGCONT).  Then one last runner finishes
# what is left, and the database is checked:
#   - every job that does not crash has exactly one done run, the crashing
#     ones none; no job is done and pending/running at once;
#   - no lease and no 'running' run is left;
#   - PRAGMA integrity_check is ok, PRAGMA foreign_key_check empty;
#   - every recorded artifact's sha256 matches its file on disk.
# Prints the figures and exits 0 when every check passed, 1 otherwise.
# The work directory (SOAK_DIR, default a fresh /tmp/cascade-soak.XXXXXX) is
# removed on success unless SOAK_KEEP=1.
set -u

SOAK_JOBS=${SOAK_JOBS:-300}
SOAK_KILLS=${SOAK_KILLS:-12}
SOAK_RUNNERS=${SOAK_RUNNERS:-3}
SOAK_SECONDS=${SOAK_SECONDS:-60}
SOAK_FREEZES=${SOAK_FREEZES:-3}
SOAK_LEASE=${SOAK_LEASE:-2}
# the sleeping jobs (3 in 10) last about SOAK_SECONDS on the runners' slots
SOAK_SLEEP=${SOAK_SLEEP:-$(awk -v s="${SOAK_SECONDS}" -v r="${SOAK_RUNNERS}" -v j="${SOAK_JOBS}" \
    'BEGIN { x = 0.7 * s * 2 * r / (0.3 * j); printf "%.2f", x < 0.05 ? 0.05 : x }')}
SOAK_SEED=${SOAK_SEED:-$$}
SOAK_KEEP=${SOAK_KEEP:-0}

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/bin}
CASCADE=$BIN/cascade
FAKE=$BIN/fake-solver
for p in "$CASCADE" "$FAKE"; do
    [ -x "$p" ] || { echo "soak: $p missing (make all bin/fake-solver)" >&2; exit 2; }
done
command -v sqlite3 >/dev/null || { echo "soak: needs the sqlite3 shell" >&2; exit 2; }
command -v sha256sum >/dev/null || { echo "soak: needs sha256sum" >&2; exit 2; }
if [ "$SOAK_RUNNERS" -lt 1 ] || [ "$SOAK_JOBS" -lt 10 ]; then
    echo "soak: SOAK_RUNNERS >= 1 and SOAK_JOBS >= 10, please" >&2; exit 2
fi
RANDOM=$SOAK_SEED

D=${SOAK_DIR:-$(mktemp -d /tmp/cascade-soak.XXXXXX)}
mkdir -p "$D"
cd "$D" || exit 2
rm -rf runs cascade.db* runner-*.log

# --- the study: zipped lists, one entry per job -----------------------------
xs=""; acts=""; secs=""
for ((i = 1; i <= SOAK_JOBS; i++)); do
    case $((i % 10)) in
    0) a=crash; s=0 ;;
    1 | 2 | 3) a=sleep; s=$SOAK_SLEEP ;;
    *) a=ok; s=0 ;;
    esac
    xs+="${xs:+, }$i"; acts+="${acts:+, }$a"; secs+="${secs:+, }$s"
done
cat > soak.yaml <<EOF
name: soak
description: runner soak test (bench/soak.sh)
retries: 3
base: {fake: {action: ok}}
sweep:
  zip:
    fake.x: [$xs]
    fake.action: [$acts]
    fake.seconds: [$secs]
EOF
NCRASH=$((SOAK_JOBS / 10))

# --- runners -----------------------------------------------------------------
declare -A alive=()      # pid -> 1 while we consider it running
nstarted=0
start_runner() {
    nstarted=$((nstarted + 1))
    "$CASCADE" run soak.yaml --solver "$FAKE" --jobs 2 --lease "$SOAK_LEASE" --quiet \
        > "runner-$nstarted.log" 2>&1 &
    alive[$!]=1
}
reap_runners() {   # forget runners that exited; count their exit codes
    for p in "${!alive[@]}"; do
        if ! kill -0 "$p" 2>/dev/null || [ "$(ps -o stat= -p "$p" 2>/dev/null | cut -c1)" = Z ]; then
            wait "$p" 2>/dev/null; rc=$?
            unset "alive[$p]"
            case $rc in
            0) exit_ok=$((exit_ok + 1)) ;;
            1) exit_failed=$((exit_failed + 1)) ;;
            137) ;;   # ours (kill -9)
            *) exit_other=$((exit_other + 1)); echo "soak: a runner exited $rc" >&2 ;;
            esac
        fi
    done
}
pick_runner() {    # a random live runner pid, or nothing
    local ps=("${!alive[@]}")
    [ ${#ps[@]} -gt 0 ] && echo "${ps[RANDOM % ${#ps[@]}]}"
}
declare -A killed_keys=()
pick_solver() {    # a random solver of our runners whose job was not hit before
    local cands=() pid ppid args key
    while read -r pid ppid args; do
        [ -n "${alive[$ppid]:-}" ] || continue
        case $args in *"fake-solver run"*) ;; *) continue ;; esac
        key=$(sed -n 's|.*/runs/soak/\([0-9a-f]*\)/attempt-.*|\1|p' <<<"$args")
        [ -n "$key" ] && [ -z "${killed_keys[$key]:-}" ] && cands+=("$pid:$key")
    done < <(ps -eo pid=,ppid=,args=)
    [ ${#cands[@]} -gt 0 ] && echo "${cands[RANDOM % ${#cands[@]}]}"
}

exit_ok=0; exit_failed=0; exit_other=0
kills_runner=0; kills_solver=0; freezes=0; freeze_pids=()
T0=$(date +%s.%N)
for ((r = 0; r < SOAK_RUNNERS; r++)); do start_runner; done

# --- chaos: the events in random order, spread over SOAK_SECONDS -------------
events=()
for ((k = 0; k < SOAK_KILLS; k++)); do
    if ((RANDOM % 2)); then events+=(runner); else events+=(solver); fi
done
for ((k = 0; k < SOAK_FREEZES; k++)); do events+=(freeze); done
for ((k = ${#events[@]} - 1; k > 0; k--)); do   # shuffle
    j=$((RANDOM % (k + 1))); t=${events[k]}; events[k]=${events[j]}; events[j]=$t
done
nev=${#events[@]}
gap=$(awk -v s="$SOAK_SECONDS" -v n="$nev" 'BEGIN { printf "%.3f", 0.8 * s / (n + 1) }')
for ev in "${events[@]}"; do
    sleep "$gap"
    reap_runners
    [ ${#alive[@]} -eq 0 ] && break     # the study is complete: nothing left to hit
    case $ev in
    runner)
        p=$(pick_runner) || continue
        kill -9 "$p" 2>/dev/null && { kills_runner=$((kills_runner + 1)); start_runner; }
        ;;
    solver)
        s=$(pick_solver) || { s=""; }
        [ -n "$s" ] || continue
        kill -9 "${s%%:*}" 2>/dev/null && { kills_solver=$((kills_solver + 1)); killed_keys[${s#*:}]=1; }
        ;;
    freeze)
        p=$(pick_runner) || continue
        if kill -STOP "$p" 2>/dev/null; then
            freezes=$((freezes + 1))
            ( sleep "$(awk -v l="$SOAK_LEASE" 'BEGIN { print l * 1.5 + 1 }')"; kill -CONT "$p" 2>/dev/null ) &
            freeze_pids+=($!)
        fi
        ;;
    esac
done
for p in "${freeze_pids[@]}"; do wait "$p" 2>/dev/null; done
# the runners return when the study is complete (or as good as: the
# crashing jobs are failed for good)
deadline=$(( $(date +%s) + 300 ))
while [ ${#alive[@]} -gt 0 ] && [ "$(date +%s)" -lt "$deadline" ]; do sleep 0.2; reap_runners; done
hung=${#alive[@]}
for p in "${!alive[@]}"; do kill -9 "$p" 2>/dev/null; done
# a last runner, undisturbed, finishes whatever a killed one left behind
final_out=$("$CASCADE" run soak.yaml --solver "$FAKE" --jobs 2 --lease "$SOAK_LEASE" --quiet 2>&1)
final_rc=$?
T1=$(date +%s.%N)

# --- checks --------------------------------------------------------------------
q() { sqlite3 -batch -noheader cascade.db "$1"; }
fail=0
check() {   # check WHAT GOT WANT
    if [ "$2" = "$3" ]; then printf '  ok    %s\n' "$1"
    else printf '  FAIL  %s: %s, expected %s\n' "$1" "$2" "$3"; fail=1; fi
}
jobs_n=$(q "SELECT count(*) FROM jobs")
runs_n=$(q "SELECT count(*) FROM runs")
done_n=$(q "SELECT count(*) FROM runs WHERE status = 'done'")
echo "soak: checks"
check "jobs" "$jobs_n" "$SOAK_JOBS"
check "jobs not crashing with exactly one done run" \
    "$(q "SELECT count(*) FROM jobs j WHERE j.params NOT LIKE '%\"crash\"%' AND
          (SELECT count(*) FROM runs WHERE job_id = j.id AND status = 'done') = 1")" \
    "$((SOAK_JOBS - NCRASH))"
check "crashing jobs with a done run" \
    "$(q "SELECT count(*) FROM jobs j WHERE j.params LIKE '%\"crash\"%' AND
          EXISTS (SELECT 1 FROM runs WHERE job_id = j.id AND status = 'done')")" 0
check "jobs with more than one done run" \
    "$(q "SELECT count(*) FROM (SELECT job_id FROM runs WHERE status = 'done'
          GROUP BY job_id HAVING count(*) > 1)")" 0
check "jobs done and pending or running at once" \
    "$(q "SELECT count(*) FROM jobs j WHERE j.state IN ('pending', 'running') AND
          EXISTS (SELECT 1 FROM runs WHERE job_id = j.id AND status = 'done')")" 0
check "jobs pending or running" "$(q "SELECT count(*) FROM jobs WHERE state IN ('pending', 'running')")" 0
check "leases left" "$(q "SELECT count(*) FROM leases")" 0
check "runs left running" "$(q "SELECT count(*) FROM runs WHERE status = 'running'")" 0
check "integrity_check" "$(q "PRAGMA integrity_check")" ok
check "foreign_key_check rows" "$(q "SELECT count(*) FROM pragma_foreign_key_check")" 0
check "done runs without metrics or files" \
    "$(q "SELECT count(*) FROM runs r WHERE status = 'done' AND
          (NOT EXISTS (SELECT 1 FROM metrics WHERE run_id = r.id)
           OR NOT EXISTS (SELECT 1 FROM artifacts WHERE run_id = r.id))")" 0
art_n=$(q "SELECT count(*) FROM artifacts")
bad_art=$(q "SELECT sha256 || '  ' || path FROM artifacts" | sha256sum --check --quiet 2>/dev/null | wc -l)
check "artifacts whose sha256 does not match the file ($art_n checked)" "$bad_art" 0
check "runners that exited other than 0, 1 or killed by us" "$exit_other" 0
check "runners still running after 300 s" "$hung" 0
check "the last runner's exit code (1: the crashing jobs failed)" "$final_rc" 1

T=$(awk -v a="$T0" -v b="$T1" 'BEGIN { printf "%.1f", b - a }')
status_counts=$(q "SELECT group_concat(status || ' ' || n, ', ') FROM
                   (SELECT status, count(*) AS n FROM runs GROUP BY status ORDER BY status)")
result=$([ $fail = 0 ] && echo PASS || echo FAIL)
cat <<EOF
soak: $result in $T s (seed $SOAK_SEED, $D)
  jobs               $jobs_n ($NCRASH crash on purpose, $((SOAK_JOBS * 3 / 10)) sleep ${SOAK_SLEEP} s)
  runs               $runs_n ($status_counts)
  done runs          $done_n
  artifacts          $art_n (sha256 checked against the files)
  runners            $SOAK_RUNNERS at a time, $nstarted started (--jobs 2, --lease $SOAK_LEASE s);
                     exits: $exit_ok ok, $exit_failed with failed jobs; the last: ${final_out##*$'\n'}
  kill -9 runners    $kills_runner
  kill -9 solvers    $kills_solver
  frozen runners     $freezes (SIGSTOP for $(awk -v l="$SOAK_LEASE" 'BEGIN { print l * 1.5 + 1 }') s > lease, then SIGCONT)
  planned            $SOAK_KILLS kills, $SOAK_FREEZES freezes over $SOAK_SECONDS s
EOF
if [ $fail = 0 ] && [ "$SOAK_KEEP" != 1 ] && [ -z "${SOAK_DIR:-}" ]; then
    cd / && rm -rf "$D"
fi
exit $fail
