#!/bin/bash
# Run libFuzzer targets (docs/fuzzing.md); called by `make fuzz`.
#
#   fuzz/run.sh BINDIR SECONDS MAX_LEN PARALLEL TARGET...
#
# Each target fuzzes for SECONDS over tests/fuzz/corpus/<target>/ (new
# inputs go to build/fuzz/new/<target>/ and are merged back into the corpus
# afterwards; crashing inputs land in tests/fuzz/crashes/<target>/).
# PARALLEL targets run at a time (1: one after the other, as before).
# Every line of a target's log carries the seconds since the target
# started, so the summary can say when coverage last grew: a target that
# ran 30 minutes past its last new input without a crash has stopped finding
# anything at this effort.  Extra libFuzzer options come from FUZZ_ARGS.
set -u
bindir=$1; seconds=$2; max_len=$3; parallel=$4; shift 4
root=$(pwd)
logdir=build/fuzz/log
mkdir -p "$logdir"
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp"
export OMP_NUM_THREADS=1

# One target: fuzz, merge the new inputs into the corpus, summarise.
fuzz_one() {
    t=$1
    bin=$bindir/fuzz_$t; corpus=tests/fuzz/corpus/$t; new=build/fuzz/new/$t
    log=$logdir/$t.log; summary=$logdir/$t.summary
    mkdir -p "$corpus" "tests/fuzz/crashes/$t" "$new"
    rc=0
    # shellcheck disable=SC2086  # FUZZ_ARGS is a list of options
    ( SECONDS=0
      "$bin" -max_total_time="$seconds" -max_len="$max_len" -timeout=10 \
          -rss_limit_mb=2048 -print_final_stats=1 \
          -artifact_prefix="tests/fuzz/crashes/$t/" ${FUZZ_ARGS:-} "$new" "$corpus" 2>&1
      echo "exit $?" ) | { SECONDS=0; while IFS= read -r line; do
          printf '%7d %s\n' "$SECONDS" "$line"; done; } > "$log"
    tail -n 1 "$log" | grep -q ' exit 0$' || rc=1
    "$bin" -merge=1 -max_len="$max_len" -timeout=10 "$corpus" "$new" >> "$log" 2>&1 \
        && rm -rf "$new"
    awk -v t="$t" -v rc="$rc" '
        done_fuzzing { next }
        $1 ~ /^[0-9]+$/ && $2 == "exit" { end = $1; done_fuzzing = 1; next }
        $2 ~ /^#[0-9]+$/ && ($3 == "NEW" || $3 == "INITED") { last_new = $1 }
        $2 ~ /^#[0-9]+$/ { for (i = 3; i < NF; i++) { if ($i == "cov:") cov = $(i+1); if ($i == "ft:") ft = $(i+1) } }
        $2 ~ /^stat::number_of_executed_units:/ { execs = $3 }
        $2 ~ /^stat::average_exec_per_sec:/ { eps = $3 }
        END {
            printf "fuzz %-12s %s  execs %s  exec/s %s  cov %s  ft %s  ran %d s  last new input at %d s  quiet for %d s\n",
                   t, (rc == 0 ? "ok   " : "CRASH"), execs, eps, cov, ft, end, last_new, end - last_new
        }' "$log" > "$summary"
    cat "$summary"
    return $rc
}

fail=""
running=0
pids=(); names=()
for t in "$@"; do
    echo "== fuzz $t: $seconds s ($logdir/$t.log)"
    fuzz_one "$t" & pids+=($!); names+=("$t")
    running=$((running + 1))
    if [ "$running" -ge "$parallel" ]; then
        wait -n || true
        running=$((running - 1))
    fi
done
wait
for t in "${names[@]}"; do
    grep -q ' CRASH ' "$logdir/$t.summary" 2>/dev/null && fail="$fail $t"
done
echo "== summary"
for t in "${names[@]}"; do cat "$logdir/$t.summary" 2>/dev/null; done
if [ -n "$fail" ]; then
    echo "fuzz: crashes or sanitizer reports in:$fail (inputs in tests/fuzz/crashes/)" >&2
    exit 1
fi
