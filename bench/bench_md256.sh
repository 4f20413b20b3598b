#!/bin/sh
# MD EAM at 256,000 atoms on one rank and one thread (the memory-bound
# regime: positions, forces and lists no longer fit the caches), ours
# against LAMMPS plain and `lmp -sf opt` on the same system
# (bench/cases/md_eam_256k.yaml, bench/lammps_eam_256k.in, 100 steps).
#   BENCH md_eam_256k_ratio_vs_lammps      loop CPU seconds, ours / LAMMPS
#   BENCH md_eam_256k_ratio_vs_lammps_opt  ours / LAMMPS -sf opt
#   BENCH md_eam_256k_us_per_atom_cpu      our loop CPU time per atom-step
# CPU seconds (ours: timing.cpu_seconds.loop of result.json; LAMMPS: "Loop
# time" x "% CPU use") because this machine is shared: the wall time grows
# with the other processes' load.  Medians of REPEAT rounds, each round
# running the three programs one after the other.  (bench_md_mpi.sh has the
# wall-clock figures of the same system on 1 and 2 ranks.)
# Run by bench/bench.sh (BIN ROOT WORK REPEAT set); standalone:
#   sh bench/bench_md256.sh BINDIR
set -eu
BIN=${BIN:-${1:?usage: bench_md256.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-md256.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
. "$ROOT/bench/lib.sh"
export OMP_NUM_THREADS=1
natoms=256000
steps=100
if ! command -v lmp >/dev/null 2>&1; then
    echo "bench_md256: lmp not installed (apt-get install lammps) -- no LAMMPS ratio" >&2
fi
: > "$WORK/md256.ours"; : > "$WORK/md256.lmp"; : > "$WORK/md256.opt"
i=0
while [ "$i" -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/md256-$i"
    "$BIN/cascade-solver" run "$ROOT/bench/cases/md_eam_256k.yaml" --out "$out" --threads 1 \
        --quiet --no-progress
    json_cpu "$out/result.json" loop >> "$WORK/md256.ours"
    if command -v lmp >/dev/null 2>&1; then
        (cd "$WORK" && lmp -in "$ROOT/bench/lammps_eam_256k.in" -log none \
            -screen "$WORK/md256-lmp.out" >/dev/null 2>&1)
        lmp_loop_cpu "$WORK/md256-lmp.out" >> "$WORK/md256.lmp"
        (cd "$WORK" && lmp -sf opt -in "$ROOT/bench/lammps_eam_256k.in" -log none \
            -screen "$WORK/md256-opt.out" >/dev/null 2>&1)
        lmp_loop_cpu "$WORK/md256-opt.out" >> "$WORK/md256.opt"
    fi
    rm -rf "$out"
    echo "bench_md256: round $i loop cpu s: ours $(tail -n1 "$WORK/md256.ours")," \
        "lammps $(tail -n1 "$WORK/md256.lmp"), opt $(tail -n1 "$WORK/md256.opt"); $(bench_load)" >&2
done
c_ours=$(median < "$WORK/md256.ours")
bench_line md_eam_256k_us_per_atom_cpu "$(echo "$c_ours * 1000000 / ($natoms * $steps)" | bc -l \
    | xargs printf '%.4f')" us "loop CPU time, 1 thread; $(bench_load)"
if [ -s "$WORK/md256.lmp" ]; then
    c_lmp=$(median < "$WORK/md256.lmp"); c_opt=$(median < "$WORK/md256.opt")
    bench_line md_eam_256k_ratio_vs_lammps "$(echo "$c_ours / $c_lmp" | bc -l | xargs printf '%.3f')" x \
        "target 0.75; loop CPU s, ours $c_ours, LAMMPS $c_lmp"
    bench_line md_eam_256k_ratio_vs_lammps_opt "$(echo "$c_ours / $c_opt" | bc -l | xargs printf '%.3f')" x \
        "target 0.85; LAMMPS -sf opt $c_opt CPU s"
fi
