#!/bin/sh
# DPD speed: the 12,000-particle flyer/target of Chen et al. 2014 (plus an
# 800-particle rigid flyer), DPDE, 200 steps of 5 fs from a 298 K lattice,
# one thread.  Medians over REPEAT runs:
#   BENCH dpd_us_per_particle_step   the time loop per particle-step
#   BENCH dpd_share_sweep_pct        the Shardlow sweep's share of the loop
#   BENCH dpd_sweep_ns_per_pair      sweep time per pair within the cutoff
#   BENCH dpd_force_ns_per_pair      the conservative (Sutton-Chen density,
#                                    embedding and pair force) call per pair
#                                    -- beside md_eam_ns_per_pair, our EAM's
#   BENCH dpd_bytes_moved_per_particle_step, dpd_roofline_pct
#                                    the traffic model below against the
#                                    stream bandwidth, as for the MPM
# Pairs: those of the target's perfect lattice closer than the cutoff
# (10.845 Å, a = 7.23 Å, 30 x 10 x 10 cells, free surfaces): 283,488, 23.6
# per particle (the flyer's own pairs are skipped by the sweep, its pairs
# with the target are few until contact).
# Traffic model, per particle per step: the half list (33.8 entries of 4 B
# within cutoff + 1 Å skin) read by the density and sweep passes (270 B),
# the inner list (23.6 entries of 4 B within the cutoff, dpd_conservative_
# fast.c) written by the density pass and read by the force pass (189 B),
# and the particle's own arrays -- x 24 read by 3 passes, v 24 + 24, f 24 +
# 24, u 8 + 8, rho and F' 16 + 16, mask 4, origin 4, id 8, image 12, type 4
# -- (268 B): 727 B.  The j-side reads hit the caches (20 MiB in all, sorted
# by cell); the sweep is serial and latency-bound.
# Environment (from bench.sh): BIN, ROOT, WORK, REPEAT.
set -eu
: "${BIN:?}" "${ROOT:?}" "${WORK:?}" "${REPEAT:=3}"
. "$ROOT/bench/lib.sh"
: > "$WORK/dpd.t"; : > "$WORK/dpd.loop"; : > "$WORK/dpd.sweep"; : > "$WORK/dpd.force"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/dpd$i"
    OMP_NUM_THREADS=1 "$BIN/cascade-solver" run "$ROOT/bench/cases/dpd_flyer_target_12k.yaml" \
        --out "$out" --threads 1 --quiet --no-progress
    tr -d ' \n' < "$out/result.json" | grep -o '"loop":{[^}]*}' \
        | grep -o '"us_per_particle_step":[0-9.eE+-]*' | cut -d: -f2 >> "$WORK/dpd.t"
    json_timer "$out/result.json" loop >> "$WORK/dpd.loop"
    json_timer "$out/result.json" dpd_sweep >> "$WORK/dpd.sweep"
    json_timer "$out/result.json" force >> "$WORK/dpd.force"
done
steps=200
pairs=$(fcc_pairs 7.23 10.845 30 10 10)
us=$(median < "$WORK/dpd.t" | xargs printf '%.4f')
bench_line dpd_us_per_particle_step "$us" us "target 1.5, 1 thread"
loop=$(median < "$WORK/dpd.loop")
sweep=$(median < "$WORK/dpd.sweep")
bench_line dpd_share_sweep_pct "$(echo "100 * $sweep / $loop" | bc -l | xargs printf '%.1f')" % "of the loop"
bench_line dpd_sweep_ns_per_pair "$(echo "$sweep * 1000000000 / ($pairs * $steps)" | bc -l | xargs printf '%.1f')" ns \
    "$pairs pairs in the cutoff; serial, each waits on one division and two short polynomials"
bench_line dpd_force_ns_per_pair "$(median < "$WORK/dpd.force" | awk -v p="$pairs" -v s=$((steps + 1)) '{printf "%.1f", $1 * 1e9 / (p * s)}')" ns \
    "conservative call per pair; see md_eam_ns_per_pair"
moved=727   # the traffic model above
gbs=$(bench_stream_gbs)
bench_line dpd_bytes_moved_per_particle_step $moved B "model in bench_dpd.sh; at $gbs GB/s: $(echo "$moved / $gbs" | bc -l | xargs printf '%.1f') ns"
bench_line dpd_roofline_pct "$(echo "100 * $moved / $gbs / ($us * 1000)" | bc -l | xargs printf '%.1f')" % \
    "time the traffic takes at the stream bandwidth / measured time"
echo "dpd bench: loop seconds $(tr '\n' ' ' < "$WORK/dpd.loop"); $(bench_load)" >&2
