#!/bin/sh
# bench/ab.sh: two builds of cascade-solver side by side on one case, runs
# alternated (A, B, A, B, ...) so that both see the same load; prints the
# median of each timer of result.json for A and B, the ratio B/A, and
# whether the metrics of the last runs are identical.  loop_cpu and
# total_cpu are CPU seconds (builds that record them): on a loaded machine
# they move far less than the wall-clock timers.
#   usage: sh bench/ab.sh BINDIR_A BINDIR_B CASE.yaml [REPEAT [THREADS]]
# e.g. main's code built in /tmp/before against this tree:
#   sh bench/ab.sh /tmp/before/build/release/bin build/release/bin \
#       bench/cases/handshake_step_wave.yaml 5
set -eu
A=${1:?usage: ab.sh BINDIR_A BINDIR_B CASE.yaml [REPEAT [THREADS]]}
B=${2:?usage: ab.sh BINDIR_A BINDIR_B CASE.yaml [REPEAT [THREADS]]}
CASE=${3:?usage: ab.sh BINDIR_A BINDIR_B CASE.yaml [REPEAT [THREADS]]}
REPEAT=${4:-5}
THREADS=${5:-1}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
. "$ROOT/bench/lib.sh"
WORK=$(mktemp -d /tmp/cascade-ab.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
timers() { # timers RESULT.json -> "key seconds" lines (CPU seconds as loop_cpu, total_cpu)
    tr -d ' \n' < "$1" | grep -o '"timing":{.*' | grep -o '"[a-z0-9_]*":{"calls":[0-9]*,"seconds":[0-9.eE+-]*' \
        | sed 's/^"\([a-z0-9_]*\)":{"calls":[0-9]*,"seconds":/\1 /'
    for k in loop total; do
        c=$(json_cpu "$1" $k)
        [ -n "$c" ] && echo "${k}_cpu $c"
    done
    return 0
}
echo "ab: $(bench_load) at start" >&2
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    for side in A B; do
        eval "bin=\$$side"
        OMP_NUM_THREADS=$THREADS "$bin/cascade-solver" run "$CASE" --out "$WORK/$side" \
            --threads "$THREADS" --quiet --no-progress
        timers "$WORK/$side/result.json" | sed "s/^/$side /" >> "$WORK/t"
        echo "ab: run $i $side loop $(json_timer "$WORK/$side/result.json" loop) s" \
            "(cpu $(json_cpu "$WORK/$side/result.json" loop)), $(bench_load)" >&2
    done
done
echo "ab: $(bench_load) at end" >&2
printf '%-12s %12s %12s %8s\n' timer "A median s" "B median s" "B/A"
for key in $(awk '{print $2}' "$WORK/t" | sort -u); do
    a=$(awk -v k="$key" '$1 == "A" && $2 == k {print $3}' "$WORK/t" | median)
    b=$(awk -v k="$key" '$1 == "B" && $2 == k {print $3}' "$WORK/t" | median)
    r=$(echo "$a $b" | awk '{ if ($1 > 0) printf "%.3f", $2 / $1; else print "-" }')
    printf '%-12s %12.4f %12.4f %8s\n' "$key" "$a" "$b" "$r"
done
# the "metrics" and "series" blocks of result.json (sorted keys, two-space
# indent): what the physics produced, compared as text
physics() {
    awk '/^  "(metrics|series)": / {on = 1}
         on {print}
         on && (/^  }/ || /^  "[a-z_]*": \{\},?$/) {on = 0}' "$1"
}
if [ "$(physics "$WORK/A/result.json")" = "$(physics "$WORK/B/result.json")" ]; then
    echo "metrics and series: identical"
else
    echo "metrics and series: DIFFER (diff $WORK/A/result.json $WORK/B/result.json)"
    trap - EXIT
fi
