#!/bin/sh
# MD Stillinger-Weber silicon, 13,824 atoms (diamond 12^3 cells, 600 K,
# 200 steps, bench/cases/md_sw_si_14k.yaml), ours against LAMMPS `pair sw`
# on the same system (bench/lammps_sw_si_14k.in), one thread each.
# Debian's LAMMPS has no sw/opt (its OPT package covers eam, lj, morse), so
# plain LAMMPS is the one peer.
#   BENCH md_sw_us_per_atom_step     our loop wall time per atom-step
#   BENCH md_sw_ratio_vs_lammps      loop CPU seconds, ours / LAMMPS
# Ratios of CPU seconds (ours: timing.cpu_seconds.loop; LAMMPS: "Loop time"
# x "% CPU use") as in bench.sh's MD section; medians of REPEAT rounds.
# Run by bench/bench.sh (BIN ROOT WORK REPEAT set); standalone:
#   sh bench/bench_sw.sh BINDIR
set -eu
BIN=${BIN:-${1:?usage: bench_sw.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-sw.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
. "$ROOT/bench/lib.sh"
export OMP_NUM_THREADS=1
natoms=13824
steps=200
: > "$WORK/sw.t"; : > "$WORK/sw.c"; : > "$WORK/sw.lmp"; : > "$WORK/sw.lmpt"
i=0
while [ "$i" -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/sw-$i"
    "$BIN/cascade-solver" run "$ROOT/bench/cases/md_sw_si_14k.yaml" --out "$out" --threads 1 \
        --quiet --no-progress
    json_timer "$out/result.json" loop >> "$WORK/sw.t"
    json_cpu "$out/result.json" loop >> "$WORK/sw.c"
    if command -v lmp >/dev/null 2>&1; then
        (cd "$WORK" && lmp -in "$ROOT/bench/lammps_sw_si_14k.in" -log none \
            -screen "$WORK/sw-lmp.out" >/dev/null 2>&1)
        lmp_loop_cpu "$WORK/sw-lmp.out" >> "$WORK/sw.lmp"
        grep 'Loop time of' "$WORK/sw-lmp.out" | awk '{print $4}' >> "$WORK/sw.lmpt"
    fi
    echo "bench_sw: round $i loop cpu s: ours $(tail -n1 "$WORK/sw.c"), lammps $(tail -n1 "$WORK/sw.lmp");" \
        "$(bench_load)" >&2
done
us() { echo "$1 * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f'; }
t=$(median < "$WORK/sw.t"); c=$(median < "$WORK/sw.c")
if [ -s "$WORK/sw.lmp" ]; then
    cl=$(median < "$WORK/sw.lmp")
    bench_line md_sw_us_per_atom_step "$(us "$t")" us "LAMMPS $(us "$(median < "$WORK/sw.lmpt")") us in this run"
    bench_line md_sw_ratio_vs_lammps "$(echo "$c / $cl" | bc -l | xargs printf '%.3f')" x \
        "target 0.75; loop CPU s, ours $c, LAMMPS pair sw $cl"
else
    bench_line md_sw_us_per_atom_step "$(us "$t")" us "lmp not installed: no peer"
fi
