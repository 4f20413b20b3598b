#!/bin/sh
# MPM benchmark: the reference problem (two elastic cubes, 250,000 points,
# 500 MUSL steps; bench/cases/mpm_two_cubes.yaml), release build.
#   BENCH mpm_ns_per_particle_step   whole step loop / (steps x points), 1 thread
#   BENCH mpm_peak_rss_mib           peak resident memory, 1 thread
#   BENCH mpm_bytes_per_point        that memory per material point
#   BENCH mpm_speedup_2_threads      loop time 1 thread / loop time 2 threads
# Medians of REPEAT runs, 1- and 2-thread runs interleaved (the machine is
# shared, load changes during the benchmark).  Idle OpenMP threads wait
# passively (OMP_WAIT_POLICY=passive unless set): on a busy machine a
# spinning thread takes the core its partner needs; a step has about a
# dozen barriers, so the cost on an idle machine is a few wake-ups per step.  Run by bench/bench.sh with
# BIN, ROOT, WORK, REPEAT set; standalone: sh bench/bench_mpm.sh BINDIR.
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

median() { sort -g | awk '{a[NR]=$1} END {if (NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }
loop_seconds() { tr -d ' \n' < "$1/result.json" | grep -o '"loop":{"calls":[0-9]*,"seconds":[0-9.eE+-]*' | sed 's/.*"seconds"://'; }
metric() { tr -d ' \n' < "$1/result.json" | grep -o "\"$2\":{\"unit\":\"[^\"]*\",\"value\":[-0-9.eE+]*" | sed 's/.*"value"://'; }

: > "$WORK/mpm1.t"; : > "$WORK/mpm2.t"; : > "$WORK/mpm1.rss"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    for nt in 1 2; do
        out="$WORK/mpm_${nt}_$i"
        OMP_NUM_THREADS=$nt /usr/bin/time -f '%M' -o "$WORK/rss" "$BIN/cascade-solver" run "$CASE" \
            --out "$out" --threads $nt --quiet --no-progress
        loop_seconds "$out" >> "$WORK/mpm$nt.t"
        [ $nt = 1 ] && echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/mpm1.rss"
    done
done
t1=$(median < "$WORK/mpm1.t")
t2=$(median < "$WORK/mpm2.t")
rss=$(median < "$WORK/mpm1.rss")
echo "BENCH mpm_ns_per_particle_step $(echo "$t1 * 1000000000 / ($steps * $points)" | bc -l | xargs printf '%.1f') ns"
echo "BENCH mpm_peak_rss_mib $(printf '%.1f' "$rss") MiB"
echo "BENCH mpm_bytes_per_point $(echo "$rss * 1048576 / $points" | bc -l | xargs printf '%.0f') B"
echo "BENCH mpm_speedup_2_threads $(echo "$t1 / $t2" | bc -l | xargs printf '%.2f') x"
echo "mpm bench: loop seconds, 1 thread: $(tr '\n' ' ' < "$WORK/mpm1.t")| 2 threads: $(tr '\n' ' ' < "$WORK/mpm2.t")" >&2
echo "mpm bench: load average $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) on $(nproc --all) cores" >&2
# the physics of the last 1-thread run, for the record
last="$WORK/mpm_1_$REPEAT"
echo "mpm reference: ke at steps 50, 100, 199, 500 = $(metric "$last" ke_step_50) $(metric "$last" ke_step_100) $(metric "$last" ke_step_199) $(metric "$last" ke_step_500) J; energy change $(metric "$last" energy_change)" >&2
