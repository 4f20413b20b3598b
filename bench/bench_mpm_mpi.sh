#!/bin/sh
# MPM on MPI bricks: the two-cube reference problem (250,000 points, 61 x 35
# x 35 cells; bench/cases/mpm_two_cubes_mpi.yaml, 100 MUSL steps, no HDF5)
# on 1 rank (serial) and on 2 ranks (the grid cut in two along x, each
# rank owning one cube's points and half the nodes; solver/mpm/mpm_bricks.h),
# 1 OpenMP thread per rank.
#   BENCH mpm_speedup_2_ranks            1-rank loop wall time / 2-rank loop wall time
#                                        (target 1.7; needs 2 free cores)
#   BENCH mpm_speedup_2_ranks_cpu        the same from the loops' CPU seconds (rank 0's
#                                        on 2 ranks): what 2 free cores would give when
#                                        the machine is shared, as long as a rank does
#                                        not burn CPU waiting for the other
#   BENCH mpm_ns_per_point_step_2_ranks  2-rank loop wall time / (steps x points)
#   BENCH mpm_comm_ms_per_step_2_ranks   rank 0's `comm` timer per step: migration,
#                                        ghost-node sums and copies, global sums
#   BENCH mpm_rss_per_rank_2_over_1      largest peak resident memory of a rank on 2
#                                        ranks / the serial run's
# Medians of REPEAT rounds, each round running 1 then 2 ranks, so a load
# change hits both.  Run by bench/bench.sh (run_bench) with BIN, ROOT, WORK,
# REPEAT set; standalone: sh bench/bench_mpm_mpi.sh BINDIR.
set -eu
BIN=${BIN:-${1:?usage: bench_mpm_mpi.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-mpmmpi.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
CASE="$ROOT/bench/cases/mpm_two_cubes_mpi.yaml"
points=250000
steps=100
export OMP_NUM_THREADS=1
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
MPIRUN="mpirun --oversubscribe -np 2"
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

. "$ROOT/bench/lib.sh"
loop_seconds() { json_timer "$1/result.json" loop; }
rank_rss_max() { tr -d ' \n' < "$1/result.json" | grep -o '"peak_rss_mib_per_rank":\[[^]]*\]' \
    | sed 's/.*\[//; s/\]//' | tr ',' '\n' | sort -g | tail -n1; }

for f in s1 s2 c1 c2 r1 r2 m2; do : > "$WORK/mpmmpi.$f"; done
i=0
while [ "$i" -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/mpmmpi1-$i"
    /usr/bin/time -f '%M' -o "$WORK/mpmmpi.rss" "$BIN/cascade-solver" run "$CASE" --out "$out" \
        --threads 1 --quiet --no-progress
    loop_seconds "$out" >> "$WORK/mpmmpi.s1"
    json_cpu "$out/result.json" loop >> "$WORK/mpmmpi.c1"
    echo "$(cat "$WORK/mpmmpi.rss") / 1024" | bc -l >> "$WORK/mpmmpi.r1"
    out="$WORK/mpmmpi2-$i"
    $MPIRUN "$BIN/cascade-solver" run "$CASE" --out "$out" --threads 1 --quiet --no-progress
    loop_seconds "$out" >> "$WORK/mpmmpi.s2"
    json_cpu "$out/result.json" loop >> "$WORK/mpmmpi.c2"
    json_timer "$out/result.json" comm >> "$WORK/mpmmpi.m2"
    rank_rss_max "$out" >> "$WORK/mpmmpi.r2"
    echo "bench_mpm_mpi: round $i loop s (cpu s): 1 rank $(tail -n1 "$WORK/mpmmpi.s1")" \
        "($(tail -n1 "$WORK/mpmmpi.c1")), 2 ranks $(tail -n1 "$WORK/mpmmpi.s2")" \
        "($(tail -n1 "$WORK/mpmmpi.c2")); load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
s1=$(median < "$WORK/mpmmpi.s1"); s2=$(median < "$WORK/mpmmpi.s2")
c1=$(median < "$WORK/mpmmpi.c1"); c2=$(median < "$WORK/mpmmpi.c2")
r1=$(median < "$WORK/mpmmpi.r1"); r2=$(median < "$WORK/mpmmpi.r2")
m2=$(median < "$WORK/mpmmpi.m2")
load=$(bench_load)
bench_line mpm_speedup_2_ranks "$(echo "$s1 / $s2" | bc -l | xargs printf '%.3f')" x \
    "target 1.7; needs 2 free cores; $load"
bench_line mpm_speedup_2_ranks_cpu "$(echo "$c1 / $c2" | bc -l | xargs printf '%.3f')" x \
    "loop CPU s $c1 / $c2 (rank 0)"
bench_line mpm_ns_per_point_step_2_ranks \
    "$(echo "$s2 * 1000000000 / ($points * $steps)" | bc -l | xargs printf '%.1f')" ns \
    "2 ranks x 1 thread, 2 x 1 x 1 bricks"
bench_line mpm_comm_ms_per_step_2_ranks "$(echo "$m2 * 1000 / $steps" | bc -l | xargs printf '%.3f')" ms \
    "rank 0: migration, node halo, global sums"
bench_line mpm_rss_per_rank_2_over_1 "$(echo "$r2 / $r1" | bc -l | xargs printf '%.3f')" x \
    "largest rank $(printf '%.1f' "$r2") MiB / serial $(printf '%.1f' "$r1") MiB"
