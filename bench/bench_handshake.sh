#!/bin/sh
# MPM/MD handshake benchmark: the step-wave case (bench/cases/
# handshake_step_wave.yaml: 8192 MD atoms, 5376 material points, 400 coupled
# steps, 1 thread).
#   BENCH handshake_us_per_step       whole coupled step (MPM step, copies,
#                                     MD step; the run's loop time / steps)
#   BENCH handshake_md_us_per_step    of which the MD forces
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

median() { sort -g | awk '{a[NR]=$1} END {if (NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }
timer() { tr -d ' \n' < "$1/result.json" | grep -o "\"$2\":{\"calls\":[0-9]*,\"seconds\":[0-9.eE+-]*" | sed 's/.*"seconds"://'; }
metric() { tr -d ' \n' < "$1/result.json" | grep -o "\"$2\":{\"unit\":\"[^\"]*\",\"value\":[-0-9.eE+]*" | sed 's/.*"value"://'; }

: > "$WORK/hs.t"; : > "$WORK/hs.f"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/hs_$i"
    OMP_NUM_THREADS=1 "$BIN/cascade-solver" run "$CASE" --out "$out" --threads 1 --quiet --no-progress
    timer "$out" loop >> "$WORK/hs.t"
    timer "$out" force >> "$WORK/hs.f"
done
t=$(median < "$WORK/hs.t")
f=$(median < "$WORK/hs.f")
last="$WORK/hs_$REPEAT"
atoms=$(metric "$last" atoms)
replaced=$(metric "$last" atoms_replaced)
points=$(metric "$last" points)
echo "BENCH handshake_us_per_step $(echo "$t * 1000000 / $steps" | bc -l | xargs printf '%.0f') us"
echo "BENCH handshake_md_us_per_step $(echo "$f * 1000000 / $steps" | bc -l | xargs printf '%.0f') us"
echo "BENCH handshake_atoms_replaced $(printf '%.0f' "$replaced") atoms"
echo "BENCH handshake_mpm_points $(printf '%.0f' "$points") points"
echo "handshake bench: the MPM part replaces $(printf '%.0f' "$replaced") atoms by $(printf '%.0f' "$points") material points ($(echo "$replaced / $points" | bc -l | xargs printf '%.2f') atoms per point); MD atoms $(printf '%.0f' "$atoms")" >&2
echo "handshake bench: loop seconds $(tr '\n' ' ' < "$WORK/hs.t"); load average $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) on $(nproc --all) cores" >&2
