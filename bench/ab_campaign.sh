#!/bin/sh
# bench/ab_campaign.sh: the campaign runner's dispatch, two builds side by
# side, rounds alternated (A, B, A, B, ...) so that both see the same load.
# Each round and build: 100 and then 400 no-op jobs (the stand-in, action
# ok) with `cascade run --jobs 1` on a fresh runs/ and database; the
# wall-clock cost of one more job (slope from 100 to 400), the runner's CPU
# per job (perf stat --no-inherit task-clock on the 400, when perf is
# there), its own report (runner time per job; slot idle between jobs,
# builds that report it); then 300 bare runs of the no-op job.  Prints every
# round and the medians.  Both builds run B's stand-in.  JOBS=N (default 1)
# runs the studies with --jobs N instead: with several slots the runner's
# work and a start that makes a job wait show in the slope too.
#   usage: [JOBS=N] sh bench/ab_campaign.sh BINDIR_A BINDIR_B [ROUNDS]
# e.g. main built in /tmp/before against this tree (release builds):
#   sh bench/ab_campaign.sh /tmp/before/build/release/bin build/release/bin 5
set -eu
A=${1:?usage: ab_campaign.sh BINDIR_A BINDIR_B [ROUNDS]}
B=${2:?usage: ab_campaign.sh BINDIR_A BINDIR_B [ROUNDS]}
ROUNDS=${3:-5}
JOBS=${JOBS:-1}
A=$(cd "$A" && pwd)
B=$(cd "$B" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/bench/lib.sh"
FAKE="$B/fake-solver"
WORK=$(mktemp -d /tmp/cascade-abc.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
for n in 100 400; do
    printf 'name: noop%s\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.x: [%s]}}\n' \
        "$n" "$(seq -s ', ' 1 "$n")" > "noop$n.yaml"
done
PERF=""
command -v perf >/dev/null 2>&1 && PERF="perf stat --no-inherit -x, -e task-clock -o $WORK/perf"
now_ns() { date +%s%N; }
one() { # one BINDIR N -> "wall_us cpu_ms report_ms idle_ms" (NA when not reported)
    rm -rf runs cascade.db*
    : > perf
    t0=$(now_ns)
    $PERF "$1/cascade" run "noop$2.yaml" --solver "$FAKE" --jobs "$JOBS" > out 2>&1 || true
    t1=$(now_ns)
    cpu=$(sed -n 's/^\([0-9.]*\),[^,]*,task-clock.*/\1/p' perf)
    rep=$(sed -n 's/.*runner time per job: \([0-9.]*\) ms.*/\1/p' out)
    idle=$(sed -n 's/.*slot idle between jobs: \([0-9.]*\) ms.*/\1/p' out)
    echo "$(( (t1 - t0) / 1000 )) ${cpu:-NA} ${rep:-NA} ${idle:-NA}"
}
bare() { # ms per bare run of the no-op job
    mkdir -p solo
    [ -f solo/case.yaml ] || cp "$(ls -d runs/noop400/* | head -n1)/current/case.yaml" solo/case.yaml
    t0=$(now_ns)
    i=0
    while [ $i -lt 300 ]; do
        i=$((i + 1))
        "$FAKE" run solo/case.yaml --out solo --threads 1 --quiet --no-progress \
            > solo/stdout 2> solo/stderr
    done
    t1=$(now_ns)
    echo "($t1 - $t0) / 300000000" | bc -l
}
r=0
while [ $r -lt "$ROUNDS" ]; do
    r=$((r + 1))
    for v in A B; do
        if [ $v = A ]; then bin=$A; else bin=$B; fi
        set -- $(one "$bin" 100)
        w100=$1
        set -- $(one "$bin" 400)
        slope=$(echo "($1 - $w100) / 300000" | bc -l)
        cpu=NA
        [ "$2" = NA ] || cpu=$(echo "$2 / 400" | bc -l | xargs printf '%.3f')
        printf '%s %s %s %s\n' "$slope" "$cpu" "$3" "$4" >> "$v.rounds"
        printf 'round %d %s (--jobs %s): one more job %.3f ms; runner CPU %s ms/job; report %s ms; slot idle %s ms; %s\n' \
            $r $v "$JOBS" "$slope" "$cpu" "$3" "$4" "$(bench_load)"
    done
    bare >> bare.rounds
    printf 'round %d: the no-op run alone %.3f ms\n' $r "$(tail -n1 bare.rounds)"
done
col() { # median of column c of a rounds file, NA when no round has it
    awk -v c="$1" '$c != "NA" {print $c}' "$2" > col.tmp
    if [ -s col.tmp ]; then median < col.tmp; else echo NA; fi
}
for v in A B; do
    printf 'median %s: one more job %.3f ms; runner CPU %s ms/job; report %s ms; slot idle %s ms\n' \
        $v "$(col 1 $v.rounds)" "$(col 2 $v.rounds)" "$(col 3 $v.rounds)" "$(col 4 $v.rounds)"
done
printf 'median: the no-op run alone %.3f ms\n' "$(median < bare.rounds)"
