#!/bin/sh
# bench_cna: microseconds per atom of one common neighbour analysis
# (fixed fcc cutoff, 108,000 displaced fcc atoms, one thread), the median
# of REPEAT runs of the median of 5 classifications each; wall clock, and
# process CPU time (less disturbed when the machine is shared).
#   env: BIN (release binaries), ROOT (source tree), WORK (scratch), REPEAT
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}"
REPEAT=${REPEAT:-3}
median() { sort -g | awk '{a[NR]=$1} END {if (NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }
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
echo "BENCH cna_us_per_atom $(median < "$WORK/cna.t" | xargs printf '%.4f') us"
echo "BENCH cna_cpu_us_per_atom $(median < "$WORK/cna.c" | xargs printf '%.4f') us"
