#!/bin/sh
# make bench: speed and memory figures, one "BENCH <name> <value> <unit>"
# line each.  Runs are repeated and interleaved with the reference code, and
# the medians are reported, because this machine is shared and noisy.
#   usage: sh bench/bench.sh BINDIR
set -eu
BIN=${1:?usage: bench.sh BINDIR}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
REPEAT=${BENCH_REPEAT:-3}
WORK=$(mktemp -d /tmp/cascade-bench.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
export OMP_NUM_THREADS=1

median() { sort -g | awk '{a[NR]=$1} END {if (NR%2) print a[(NR+1)/2]; else print (a[NR/2]+a[NR/2+1])/2}'; }
jget() { # jget FILE key.path  -> number (result.json)
    sed 's/[[:space:]]//g' "$1" | tr -d '\n' | grep -o "\"$2\":{[^}]*}" | grep -o '"value":[-0-9.eE+]*' | head -n1 | cut -d: -f2
}

# --- MD: 32,000-atom EAM Cu, ours against LAMMPS ---------------------------
: > "$WORK/ours.t"; : > "$WORK/ours.rss"; : > "$WORK/lmp.t"; : > "$WORK/lmp.rss"
have_lmp=0; command -v lmp >/dev/null 2>&1 && have_lmp=1
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/md$i"
    /usr/bin/time -f '%M' -o "$WORK/rss" "$BIN/cascade-solver" run "$ROOT/bench/cases/md_eam_32k.yaml" \
        --out "$out" --threads 1 --quiet --no-progress
    tr -d ' \n' < "$out/result.json" | grep -o '"loop":{"calls":[0-9]*,"seconds":[0-9.eE+-]*' \
        | sed 's/.*"seconds"://' >> "$WORK/ours.t"
    echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/ours.rss"
    if [ $have_lmp = 1 ]; then
        (cd "$WORK" && /usr/bin/time -f '%M' -o "$WORK/rss" lmp -in "$ROOT/bench/lammps_eam_32k.in" \
            -log none -screen "$WORK/lmp.out" >/dev/null 2>&1)
        grep 'Loop time of' "$WORK/lmp.out" | awk '{print $4}' >> "$WORK/lmp.t"
        echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/lmp.rss"
    fi
done
natoms=32000; steps=200
t_ours=$(median < "$WORK/ours.t")
echo "BENCH md_eam_us_per_atom_step $(echo "$t_ours * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f') us"
echo "BENCH md_eam_peak_rss_mib $(median < "$WORK/ours.rss" | xargs printf '%.1f') MiB"
if [ $have_lmp = 1 ]; then
    t_lmp=$(median < "$WORK/lmp.t")
    echo "BENCH md_eam_lammps_us_per_atom_step $(echo "$t_lmp * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f') us"
    echo "BENCH md_eam_lammps_peak_rss_mib $(median < "$WORK/lmp.rss" | xargs printf '%.1f') MiB"
    echo "BENCH md_eam_ratio_vs_lammps $(echo "$t_ours / $t_lmp" | bc -l | xargs printf '%.3f') x"
else
    echo "bench: lmp not installed (apt-get install lammps) -- no LAMMPS ratio" >&2
fi

# further benchmarks register themselves as bench/bench_*.sh
for extra in "$ROOT"/bench/bench_*.sh; do
    [ -f "$extra" ] || continue
    BIN="$BIN" ROOT="$ROOT" WORK="$WORK" REPEAT="$REPEAT" sh "$extra"
done
