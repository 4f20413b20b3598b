#!/bin/sh
# Report speed (run by bench/bench.sh with BIN, ROOT, WORK, REPEAT):
#   report_32jobs_s    `cascade report` of a 32-job study (stand-in solver:
#                      4 grids x 8 series, 2 metrics): tables, 20 gnuplot
#                      figures, Markdown and HTML
#   report_4000jobs_s  the same for 4 grids x 1,000 series (the report draws
#                      figures for the first series only; the tables hold all)
#   regress_4000jobs_s `cascade regress --no-run` of the 4,000-job study
#                      against its own baseline (8,000 values, 2,000 orders)
# Medians of REPEAT runs; the studies are run once beforehand.
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}" "${REPEAT:=3}"
D="$WORK/report"
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
values() { seq -s ', ' 1 "$1" | sed 's/^/[/; s/$/]/'; }
study() { # study NAME NSERIES
    printf 'name: %s\nbase: {fake: {action: ok}}\nsweep: {grid: {fake.y: %s, fake.x: [0.1, 0.2, 0.4, 0.8]}}\n' \
        "$1" "$(values "$2")" > "$D/$1.yaml"
    printf 'metrics: [x_squared, sum]\nreport: {resolution: fake.x, order: {x_squared: 2, sum: 1}}\n' >> "$D/$1.yaml"
    (cd "$D" && "$BIN/cascade" run "$1.yaml" --solver "$FAKE" --quiet >/dev/null 2>&1)
}
timed() { # seconds of a command run in $D
    t0=$(now_ns)
    (cd "$D" && "$@" >/dev/null 2>&1)
    t1=$(now_ns)
    echo "($t1 - $t0) / 1000000000" | bc -l
}
study small 8
study large 1000
(cd "$D" && "$BIN/cascade" regress large.yaml --solver "$FAKE" --no-run --update-baseline >/dev/null 2>&1)
: > "$D/t_small"; : > "$D/t_large"; : > "$D/t_regress"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    timed "$BIN/cascade" report small >> "$D/t_small"
    timed "$BIN/cascade" report large >> "$D/t_large"
    timed "$BIN/cascade" regress large.yaml --solver "$FAKE" --no-run >> "$D/t_regress"
done
bench_line report_32jobs_s "$(median < "$D/t_small" | xargs printf '%.2f')" s "32 jobs, 20 figures, Markdown and HTML"
bench_line report_4000jobs_s "$(median < "$D/t_large" | xargs printf '%.2f')" s "4,000 jobs"
bench_line regress_4000jobs_s "$(median < "$D/t_regress" | xargs printf '%.2f')" s "8,000 values, 2,000 orders"
