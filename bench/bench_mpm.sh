#!/bin/sh
# MPM benchmark: the reference problem (two elastic cubes, 250,000 points,
# 500 MUSL steps; bench/cases/mpm_two_cubes.yaml), release build.
#   BENCH mpm_ns_per_particle_step   whole step loop / (steps x points), 1 thread
#   BENCH mpm_peak_rss_mib           peak resident memory, 1 thread
#   BENCH mpm_bytes_per_point        that memory per material point
#   BENCH mpm_speedup_2_threads      loop time 1 thread / loop time 2 threads
#   BENCH mpm_share_p2g_pct, mpm_share_grid_pct, mpm_share_g2p_pct
#                                    the stages' shares of the loop, 1 thread:
#                                    p2g = s1-s3 (locating the points, and the
#                                    next step's mapping the fused pass does),
#                                    grid = s4-s5 and s11, g2p = s6, s10 and
#                                    s7-s14 (the points' update)
#   BENCH mpm_bytes_moved_per_point_step  the traffic a step cannot avoid, by
#                                    the model below
#   BENCH mpm_roofline_pct           time that traffic takes at the measured
#                                    stream bandwidth / the measured time
#   BENCH mpm_step_min_ns            one step alone (bench/mpm_kernel_probe.c):
#                                    the fastest of 100 steps in CPU time per
#                                    point, 1 thread, during the impact -- the
#                                    figure a shared machine moves least
#   BENCH mpm_balance_2_threads      how evenly two threads split the coloured
#                                    passes (points per block, blocks taken
#                                    one by one): bounds mpm_speedup_2_threads
#                                    at 2 x this on free cores
# Medians of REPEAT runs, 1- and 2-thread runs interleaved (the machine is
# shared, load changes during the benchmark).  Idle OpenMP threads wait
# passively (OMP_WAIT_POLICY=passive unless set): on a busy machine a
# spinning thread takes the core its partner needs; a step has about a
# dozen barriers, so the cost on an idle machine is a few wake-ups per step.  Run by bench/bench.sh with
# BIN, ROOT, WORK, REPEAT set; standalone: sh bench/bench_mpm.sh BINDIR.
#
# Traffic model (bytes per point per step; linear functions, MUSL, fused
# pass, linear elastic, every array read once per pass that needs it and
# written once when it changes):
#   locate (s9)      block of each point in, sorted order out         8
#   reorder          all 240 B of a point read and written, 1 step in 50  10
#   g2p (s6, s10)    x 24, v 24 + 24, mass 8, body 4, order 4        88
#   fused pass       x 24 + 24, v 24, stress 48 + 48, F 72 + 72,
#                    vol 8 + 8, vol0 8, eint 8 + 8, mass 8, body 4,
#                    block 4, order 4                                 372
#                    points                                           478
#   grid, per node   clear 64, s4-s5 128, s6 reads 64, remap 32 + 32
#                    and its clear 32, s11 64 + 64, fused pass reads
#                    64 + 32, writes 64 + 64                           640
# with nodes / points of the case (80,352 / 250,000): 478 + 640 x 0.321
# = 684 B.  Caches hold none of it from one pass to the next (86 MiB).
set -eu
BIN=${BIN:-${1:?usage: bench_mpm.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-mpm.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
CASE="$ROOT/bench/cases/mpm_two_cubes.yaml"
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
steps=500
points=250000

. "$ROOT/bench/lib.sh"
loop_seconds() { json_timer "$1/result.json" loop; }
metric() { json_number "$1/result.json" "$2"; }

: > "$WORK/mpm1.t"; : > "$WORK/mpm2.t"; : > "$WORK/mpm1.rss"
: > "$WORK/mpm.p2g"; : > "$WORK/mpm.grid"; : > "$WORK/mpm.g2p"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    for nt in 1 2; do
        out="$WORK/mpm_${nt}_$i"
        OMP_NUM_THREADS=$nt /usr/bin/time -f '%M' -o "$WORK/rss" "$BIN/cascade-solver" run "$CASE" \
            --out "$out" --threads $nt --quiet --no-progress
        loop_seconds "$out" >> "$WORK/mpm$nt.t"
        if [ $nt = 1 ]; then
            echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/mpm1.rss"
            for stage in p2g grid g2p; do
                json_timer "$out/result.json" "mpm_$stage" >> "$WORK/mpm.$stage"
            done
        fi
    done
done
t1=$(median < "$WORK/mpm1.t")
t2=$(median < "$WORK/mpm2.t")
rss=$(median < "$WORK/mpm1.rss")
ns=$(echo "$t1 * 1000000000 / ($steps * $points)" | bc -l | xargs printf '%.1f')
bench_line mpm_ns_per_particle_step "$ns" ns "target 75 idle; MPM3D-F90 420-480, Karamelo 1090-1185"
bench_line mpm_peak_rss_mib "$(printf '%.1f' "$rss")" MiB "1 thread, whole process"
bench_line mpm_bytes_per_point "$(echo "$rss * 1048576 / $points" | bc -l | xargs printf '%.0f')" B "target 400"
bench_line mpm_speedup_2_threads "$(echo "$t1 / $t2" | bc -l | xargs printf '%.2f')" x "target 1.8 idle; $(bench_load)"
for stage in p2g grid g2p; do
    bench_line "mpm_share_${stage}_pct" "$(echo "100 * $(median < "$WORK/mpm.$stage") / $t1" | bc -l | xargs printf '%.1f')" % \
        "of the 1-thread loop"
done
moved=684   # the traffic model above
gbs=$(bench_stream_gbs)
bench_line mpm_bytes_moved_per_point_step $moved B "model in bench_mpm.sh; at $gbs GB/s: $(echo "$moved / $gbs" | bc -l | xargs printf '%.1f') ns"
bench_line mpm_roofline_pct "$(echo "100 * $moved / $gbs / $ns" | bc -l | xargs printf '%.0f')" % \
    "time the traffic takes at the stream bandwidth / measured time; 100 = bandwidth-bound"
# one step alone, in CPU time (bench/mpm_kernel_probe.c against the release libraries)
OBJ=$(cd "$BIN/../obj" && pwd)
PKGS="hdf5-openmpi jansson yaml-0.1 gsl sqlite3 nettle"
# shellcheck disable=SC2046  # pkg-config's flags are words
mpicc -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -fopenmp -I"$ROOT" -I"$ROOT/solver" \
    $(pkg-config --cflags $PKGS) -o "$WORK/mpm_kernel_probe" "$ROOT/bench/mpm_kernel_probe.c" \
    "$OBJ/libcascade_solver.a" "$OBJ/libcascade_util.a" $(pkg-config --libs $PKGS) -lm
probe=$(OMP_NUM_THREADS=1 "$WORK/mpm_kernel_probe" 100 130 1)
field() { echo "$probe" | awk -v k="$1" '{for (i = 1; i < NF; i++) if ($i == k) print $(i + 1)}'; }
bench_line mpm_step_min_ns "$(field step_min_ns)" ns \
    "one step, fastest of 100 in CPU time, 1 thread (median $(field step_median_ns)); target 75; $(bench_load)"
bench_line mpm_balance_2_threads "$(field balance2_blocks)" x \
    "2 threads over the colouring blocks, from points per block; 1 = even (slabs: $(field balance2_slabs))"
echo "mpm bench: loop seconds, 1 thread: $(tr '\n' ' ' < "$WORK/mpm1.t")| 2 threads: $(tr '\n' ' ' < "$WORK/mpm2.t")" >&2
echo "mpm bench: $(bench_load)" >&2
# the physics of the last 1-thread run, for the record
last="$WORK/mpm_1_$REPEAT"
echo "mpm reference: ke at steps 50, 100, 199, 500 = $(metric "$last" ke_step_50) $(metric "$last" ke_step_100) $(metric "$last" ke_step_199) $(metric "$last" ke_step_500) J; energy change $(metric "$last" energy_change)" >&2
