#!/bin/sh
# MPM/MD handshake benchmark: the step-wave case (bench/cases/
# handshake_step_wave.yaml: 8192 MD atoms, 5376 material points, 400 coupled
# steps, 1 thread).
#   BENCH handshake_us_per_step       whole coupled step (MPM step, copies,
#                                     MD step; the run's loop time / steps)
#   BENCH handshake_md_us_per_step    of which the MD forces
#   BENCH handshake_mpm_us_per_step   of which the MPM step (p2g, grid, g2p)
#   BENCH handshake_band_us_per_step  of which the band's transfers (region I
#                                     to the points, the copies to the MD)
#   BENCH handshake_mpm_share_pct     the MPM step's share of the coupled step
#   BENCH handshake_region_I_us_per_step, handshake_region_II_us_per_step,
#         handshake_region_III_us_per_step
#                                     the MD forces of the atoms of region I
#                                     (MD atoms that act as material points)
#                                     and of the MD copies of the points of
#                                     regions II and III: the MD force time
#                                     apportioned by atom count (EAM costs
#                                     the same per atom of a crystal); the
#                                     band's transfers are the band line
#   BENCH handshake_atoms_replaced    lattice sites of the MPM part: the atoms
#                                     a full MD bar would need there
#   BENCH handshake_mpm_points        the material points standing in for them
# Medians of REPEAT runs.  Run by bench/bench.sh with BIN, ROOT, WORK, REPEAT
# set; standalone: sh bench/bench_handshake.sh BINDIR.
set -eu
BIN=${BIN:-${1:?usage: bench_handshake.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
REPEAT=${REPEAT:-3}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-hs.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
CASE="$ROOT/bench/cases/handshake_step_wave.yaml"
steps=400

. "$ROOT/bench/lib.sh"
timer() { json_timer "$1/result.json" "$2"; }
metric() { json_number "$1/result.json" "$2"; }

: > "$WORK/hs.t"; : > "$WORK/hs.f"; : > "$WORK/hs.mpm"; : > "$WORK/hs.band"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/hs_$i"
    OMP_NUM_THREADS=1 "$BIN/cascade-solver" run "$CASE" --out "$out" --threads 1 --quiet --no-progress
    timer "$out" loop >> "$WORK/hs.t"
    timer "$out" force >> "$WORK/hs.f"
    echo "$(timer "$out" mpm_p2g) + $(timer "$out" mpm_grid) + $(timer "$out" mpm_g2p)" | bc -l >> "$WORK/hs.mpm"
    timer "$out" coupling >> "$WORK/hs.band"
done
t=$(median < "$WORK/hs.t")
f=$(median < "$WORK/hs.f")
last="$WORK/hs_$REPEAT"
atoms=$(metric "$last" atoms)
replaced=$(metric "$last" atoms_replaced)
points=$(metric "$last" points)
mpm=$(median < "$WORK/hs.mpm")
band=$(median < "$WORK/hs.band")
bench_line handshake_us_per_step "$(echo "$t * 1000000 / $steps" | bc -l | xargs printf '%.0f')" us "MD + MPM + band + rest"
bench_line handshake_md_us_per_step "$(echo "$f * 1000000 / $steps" | bc -l | xargs printf '%.0f')" us "MD forces, $(printf '%.0f' "$atoms") atoms"
bench_line handshake_mpm_us_per_step "$(echo "$mpm * 1000000 / $steps" | bc -l | xargs printf '%.0f')" us "MPM step, $(printf '%.0f' "$points") points"
bench_line handshake_band_us_per_step "$(echo "$band * 1000000 / $steps" | bc -l | xargs printf '%.0f')" us "region I to the points, copies to the MD"
per_atom=$(echo "$f * 1000000 / $steps / $atoms" | bc -l)
for region in I II III; do
    case $region in
    I) count=$(metric "$last" atoms_region_I) ;;
    *) count=$(metric "$last" "points_region_$region") ;;
    esac
    bench_line "handshake_region_${region}_us_per_step" "$(echo "$per_atom * $count" | bc -l | xargs printf '%.0f')" us \
        "MD forces of its $(printf '%.0f' "$count") atoms, apportioned by atom count"
done
bench_line handshake_mpm_share_pct "$(echo "100 * $mpm / $t" | bc -l | xargs printf '%.1f')" % "target < 15"
bench_line handshake_atoms_replaced "$(printf '%.0f' "$replaced")" atoms "lattice sites the MPM part stands for"
bench_line handshake_mpm_points "$(printf '%.0f' "$points")" points
echo "handshake bench: the MPM part replaces $(printf '%.0f' "$replaced") atoms by $(printf '%.0f' "$points") material points ($(echo "$replaced / $points" | bc -l | xargs printf '%.2f') atoms per point); MD atoms $(printf '%.0f' "$atoms")" >&2
echo "handshake bench: loop seconds $(tr '\n' ' ' < "$WORK/hs.t"); $(bench_load)" >&2
