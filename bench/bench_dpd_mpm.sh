#!/bin/sh
# DPD/MPM-grid speed: the 12,000-particle flyer/target of Chen et al. 2014
# (plus an 800-particle rigid flyer) on a 4 Å MPM grid, DPDE, 200 steps, one
# thread.  Prints the median over REPEAT runs of the time loop per
# particle-step (pair forces, the grid's s1-s14, the DPDE bookkeeping).
# Environment (from bench.sh): BIN, ROOT, WORK, REPEAT.
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}" "${REPEAT:=3}"
. "$ROOT/bench/lib.sh"
: > "$WORK/dpd_mpm.t"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/dpd_mpm$i"
    OMP_NUM_THREADS=1 "$BIN/cascade-solver" run "$ROOT/bench/cases/dpd_mpm_grid_flyer_target_12k.yaml" \
        --out "$out" --threads 1 --quiet --no-progress
    tr -d ' \n' < "$out/result.json" | grep -o '"loop":{[^}]*}' \
        | grep -o '"us_per_particle_step":[0-9.eE+-]*' | cut -d: -f2 >> "$WORK/dpd_mpm.t"
done
bench_line dpd_mpm_grid_us_per_particle_step "$(median < "$WORK/dpd_mpm.t" | xargs printf '%.4f')" us "beside dpd_us_per_particle_step"
