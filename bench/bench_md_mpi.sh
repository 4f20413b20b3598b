#!/bin/sh
# MD on MPI bricks: 256,000-atom EAM Cu (bench/cases/md_eam_256k.yaml, 100
# steps) on 1 rank (serial) and 2 ranks (brick decomposition), side by side
# with Debian's LAMMPS (`lmp`, `mpirun -np 2 lmp`) on the same system
# (bench/lammps_eam_256k.in), 1 OpenMP thread per rank.
#   BENCH md_eam_256k_us_per_atom_step_1_rank     loop time / (steps x atoms)
#   BENCH md_eam_256k_us_per_atom_step_2_ranks
#   BENCH md_eam_256k_speedup_2_ranks            1-rank loop time / 2-rank loop time
#   BENCH md_eam_256k_lammps_speedup_2_ranks     the same for LAMMPS
#   BENCH md_eam_256k_ratio_vs_lammps_1_rank     our serial loop time / LAMMPS' on 1 rank
#   BENCH md_eam_256k_ratio_vs_lammps_2_ranks    our 2-rank loop time / LAMMPS' (< 1: faster)
#   BENCH md_eam_256k_peak_rss_mib_1_rank        peak resident memory of the serial run
#   BENCH md_eam_256k_peak_rss_mib_per_rank_2_ranks   largest peak over the 2 ranks
#   BENCH md_eam_256k_rss_per_rank_2_over_1      the two above, divided
#   BENCH md_eam_256k_rss_per_rank_2_over_1_mpirun  the same over a 1-rank run
#                                                under mpirun (`mpirun -np 1`, once):
#                                                the MPI runtime's own memory (about
#                                                7 MiB a process) on both sides
#   BENCH md_eam_256k_comm_ms_per_step_2_ranks   rank 0's `comm` timer per step on 2
#                                                ranks (ghost builds, position, force and
#                                                virial passes; docs/parallel.md)
# Medians of REPEAT rounds; each round runs the four programs one after
# the other, so a load change on this shared machine hits them alike.  Run
# by bench/bench.sh (run_bench) with BIN, ROOT, WORK, REPEAT set;
# standalone: sh bench/bench_md_mpi.sh BINDIR.
set -eu
BIN=${BIN:-${1:?usage: bench_md_mpi.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-mdmpi.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
CASE="$ROOT/bench/cases/md_eam_256k.yaml"
LMPIN="$ROOT/bench/lammps_eam_256k.in"
natoms=256000
steps=100
export OMP_NUM_THREADS=1
MPIRUN="mpirun --oversubscribe -np 2"
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

. "$ROOT/bench/lib.sh"
loop_seconds() { json_timer "$1/result.json" loop; }
# the largest per-rank peak of the parallel record in result.json
rank_rss_max() { tr -d ' \n' < "$1/result.json" | grep -o '"peak_rss_mib_per_rank":\[[^]]*\]' \
    | sed 's/.*\[//; s/\]//' | tr ',' '\n' | sort -g | tail -n1; }
us() { echo "$1 * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f'; }

have_lmp=0; command -v lmp >/dev/null 2>&1 && have_lmp=1
for f in s1 s2 r1 r2 l1 l2 c2; do : > "$WORK/mdmpi.$f"; done
i=0
while [ "$i" -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/mdmpi1-$i"
    /usr/bin/time -f '%M' -o "$WORK/mdmpi.rss" "$BIN/cascade-solver" run "$CASE" --out "$out" \
        --threads 1 --quiet --no-progress
    loop_seconds "$out" >> "$WORK/mdmpi.s1"
    echo "$(cat "$WORK/mdmpi.rss") / 1024" | bc -l >> "$WORK/mdmpi.r1"
    if [ "$i" = 1 ]; then   # memory only: once
        out="$WORK/mdmpi1m-$i"
        mpirun -np 1 "$BIN/cascade-solver" run "$CASE" --out "$out" --threads 1 --quiet --no-progress
        tr -d ' \n' < "$out/result.json" | grep -o '"peak_rss_mib":[0-9.]*' | head -n1 \
            | cut -d: -f2 > "$WORK/mdmpi.r1m"
    fi
    out="$WORK/mdmpi2-$i"
    $MPIRUN "$BIN/cascade-solver" run "$CASE" --out "$out" --threads 1 --quiet --no-progress
    loop_seconds "$out" >> "$WORK/mdmpi.s2"
    json_timer "$out/result.json" comm >> "$WORK/mdmpi.c2"
    rank_rss_max "$out" >> "$WORK/mdmpi.r2"
    if [ $have_lmp = 1 ]; then
        (cd "$WORK" && lmp -in "$LMPIN" -log none -screen "$WORK/mdmpi-lmp1.out" >/dev/null 2>&1)
        grep 'Loop time of' "$WORK/mdmpi-lmp1.out" | awk '{print $4}' >> "$WORK/mdmpi.l1"
        (cd "$WORK" && $MPIRUN lmp -in "$LMPIN" -log none -screen "$WORK/mdmpi-lmp2.out" \
            >/dev/null 2>&1)
        grep 'Loop time of' "$WORK/mdmpi-lmp2.out" | awk '{print $4}' >> "$WORK/mdmpi.l2"
    fi
    # the round's loop times, for a reader who wants more than medians
    echo "bench_md_mpi: round $i loop s: ours 1 rank $(tail -n1 "$WORK/mdmpi.s1"), 2 ranks" \
        "$(tail -n1 "$WORK/mdmpi.s2"); lammps 1 rank $(tail -n1 "$WORK/mdmpi.l1"), 2 ranks" \
        "$(tail -n1 "$WORK/mdmpi.l2"); load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
s1=$(median < "$WORK/mdmpi.s1"); s2=$(median < "$WORK/mdmpi.s2")
r1=$(median < "$WORK/mdmpi.r1"); r2=$(median < "$WORK/mdmpi.r2")
load=$(bench_load)
bench_line md_eam_256k_us_per_atom_step_1_rank "$(us "$s1")" us "serial, 1 thread; $load"
bench_line md_eam_256k_us_per_atom_step_2_ranks "$(us "$s2")" us "2 ranks x 1 thread, bricks"
bench_line md_eam_256k_speedup_2_ranks "$(echo "$s1 / $s2" | bc -l | xargs printf '%.3f')" x \
    "target 1.8; needs 2 free cores"
bench_line md_eam_256k_peak_rss_mib_1_rank "$(printf '%.1f' "$r1")" MiB "serial"
bench_line md_eam_256k_peak_rss_mib_per_rank_2_ranks "$(printf '%.1f' "$r2")" MiB "largest rank"
bench_line md_eam_256k_rss_per_rank_2_over_1 "$(echo "$r2 / $r1" | bc -l | xargs printf '%.3f')" x \
    "target 0.6"
r1m=$(cat "$WORK/mdmpi.r1m")
bench_line md_eam_256k_rss_per_rank_2_over_1_mpirun "$(echo "$r2 / $r1m" | bc -l | xargs printf '%.3f')" x \
    "1 rank under mpirun: $(printf '%.1f' "$r1m") MiB"
c2=$(median < "$WORK/mdmpi.c2")
bench_line md_eam_256k_comm_ms_per_step_2_ranks "$(echo "$c2 * 1000 / $steps" | bc -l | xargs printf '%.3f')" ms \
    "rank 0, exchange of the 1 x 1 x 2 grid"
if [ $have_lmp = 1 ]; then
    l1=$(median < "$WORK/mdmpi.l1"); l2=$(median < "$WORK/mdmpi.l2")
    bench_line md_eam_256k_lammps_us_per_atom_step_1_rank "$(us "$l1")" us "LAMMPS, same system"
    bench_line md_eam_256k_lammps_us_per_atom_step_2_ranks "$(us "$l2")" us "mpirun -np 2 lmp"
    bench_line md_eam_256k_ratio_vs_lammps_1_rank "$(echo "$s1 / $l1" | bc -l | xargs printf '%.3f')" x \
        "LAMMPS $(us "$l1") us"
    bench_line md_eam_256k_lammps_speedup_2_ranks "$(echo "$l1 / $l2" | bc -l | xargs printf '%.3f')" x \
        "LAMMPS gives about 1.9 on 2 free cores"
    bench_line md_eam_256k_ratio_vs_lammps_2_ranks "$(echo "$s2 / $l2" | bc -l | xargs printf '%.3f')" x \
        "target 1.0; LAMMPS $(us "$l2") us"
else
    echo "bench: lmp not installed (apt-get install lammps) -- no LAMMPS ratio" >&2
fi
