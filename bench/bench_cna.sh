#!/bin/sh
# bench_cna: microseconds per atom of one common neighbour analysis
# (fixed fcc cutoff, 108,000 displaced fcc atoms, one thread), the median
# of REPEAT runs of the median of 5 classifications each; wall clock, and
# process CPU time (less disturbed when the machine is shared).
#   env: BIN (release binaries), ROOT (source tree), WORK (scratch), REPEAT
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}"
REPEAT=${REPEAT:-3}
. "$ROOT/bench/lib.sh"
: > "$WORK/cna.t"; : > "$WORK/cna.c"
i=0
while [ "$i" -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/cna$i"
    "$BIN/cascade-solver" run "$ROOT/bench/cases/cna_fcc_108k.yaml" --out "$out" --threads 1 \
        --quiet --no-progress
    tr -d ' \n' < "$out/result.json" | grep -o '"cna_us_per_atom":{[^}]*}' \
        | grep -o '"value":[-0-9.eE+]*' | cut -d: -f2 >> "$WORK/cna.t"
    tr -d ' \n' < "$out/result.json" | grep -o '"cna_cpu_us_per_atom":{[^}]*}' \
        | grep -o '"value":[-0-9.eE+]*' | cut -d: -f2 >> "$WORK/cna.c"
done
bench_line cna_us_per_atom "$(median < "$WORK/cna.t" | xargs printf '%.4f')" us "108,000 atoms, 1 thread, wall clock"
bench_line cna_cpu_us_per_atom "$(median < "$WORK/cna.c" | xargs printf '%.4f')" us "process CPU time, less disturbed by load"
