#!/bin/sh
# make bench: speed and memory figures, one "BENCH <name> <value> <unit>
# (<anchor>)" line each -- the anchor is what to read the figure against: a
# target, a peer measured in the same run, or a physical limit -- and all of
# them in bench.json (BENCH_JSON, default ./bench.json) with the commit,
# date and load, so that `sh bench/compare old.json new.json` shows two runs
# side by side.  Runs are repeated and interleaved with the reference code,
# and the medians are reported, because this machine is shared and noisy.
#   usage: bench.sh BINDIR
#   BENCH_REPEAT=N   runs per figure (3); BENCH_JSON=FILE (./bench.json)
#   BENCH_ONLY="md stream md256 sw md_kernel mpm dpd ..."   only these parts
#                    (md and stream are the sections of this file, the
#                    others bench/bench_NAME.sh)
# A benchmark of its own is bench/bench_NAME.sh reporting through bench_line
# (bench/lib.sh) and one run_bench line at the end of this file.
set -eu
BIN=${1:?usage: bench.sh BINDIR}
BIN=$(cd "$BIN" && pwd)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
REPEAT=${BENCH_REPEAT:-3}
BENCH_JSON=${BENCH_JSON:-$PWD/bench.json}
WORK=$(mktemp -d /tmp/cascade-bench.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
export OMP_NUM_THREADS=1
. "$ROOT/bench/lib.sh"
BENCH_RECORD="$WORK/records.jsonl"
: > "$BENCH_RECORD"
export BENCH_RECORD
load_start=$(bench_load)
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
echo "bench: $load_start at start" >&2

wanted() { [ -z "${BENCH_ONLY:-}" ] || case " $BENCH_ONLY " in *" $1 "*) true ;; *) false ;; esac; }

# --- MD: 32,000-atom EAM Cu, ours against LAMMPS plain and -sf opt ---------
# Each round runs the three programs one after the other; the ratios are of
# the loops' CPU seconds (ours: result.json timing.cpu_seconds.loop; LAMMPS:
# "Loop time" x "% CPU use"), which a loaded machine moves far less than
# the wall-clock times (equal on an idle one).
if wanted md; then
for f in ours.t ours.c ours.f ours.rss lmp.t lmp.c lmp.rss opt.c; do : > "$WORK/$f"; done
have_lmp=0; command -v lmp >/dev/null 2>&1 && have_lmp=1
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/md$i"
    /usr/bin/time -f '%M' -o "$WORK/rss" "$BIN/cascade-solver" run "$ROOT/bench/cases/md_eam_32k.yaml" \
        --out "$out" --threads 1 --quiet --no-progress
    json_timer "$out/result.json" loop >> "$WORK/ours.t"
    json_cpu "$out/result.json" loop >> "$WORK/ours.c"
    json_timer "$out/result.json" force >> "$WORK/ours.f"
    echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/ours.rss"
    if [ $have_lmp = 1 ]; then
        (cd "$WORK" && /usr/bin/time -f '%M' -o "$WORK/rss" lmp -in "$ROOT/bench/lammps_eam_32k.in" \
            -log none -screen "$WORK/lmp.out" >/dev/null 2>&1)
        grep 'Loop time of' "$WORK/lmp.out" | awk '{print $4}' >> "$WORK/lmp.t"
        lmp_loop_cpu "$WORK/lmp.out" >> "$WORK/lmp.c"
        echo "$(cat "$WORK/rss") / 1024" | bc -l >> "$WORK/lmp.rss"
        (cd "$WORK" && lmp -sf opt -in "$ROOT/bench/lammps_eam_32k.in" -log none \
            -screen "$WORK/opt.out" >/dev/null 2>&1)
        lmp_loop_cpu "$WORK/opt.out" >> "$WORK/opt.c"
    fi
    echo "bench: md round $i loop cpu s: ours $(tail -n1 "$WORK/ours.c"), lammps $(tail -n1 "$WORK/lmp.c")," \
        "opt $(tail -n1 "$WORK/opt.c"); $(bench_load)" >&2
done
natoms=32000; steps=200
# pairs closer than the Mishin cutoff (5.50679 Å) in the perfect 600 K
# lattice's 0 K sites: 27 per atom (thermal motion moves it by a few %)
pairs=$(fcc_pairs 3.615 5.50679 20 20 20 p)
t_ours=$(median < "$WORK/ours.t")
us_ours=$(echo "$t_ours * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f')
t_lmp=""
[ $have_lmp = 1 ] && t_lmp=$(median < "$WORK/lmp.t")
us_lmp=""
[ -n "$t_lmp" ] && us_lmp=$(echo "$t_lmp * 1000000 / ($natoms * $steps)" | bc -l | xargs printf '%.4f')
bench_line md_eam_us_per_atom_step "$us_ours" us "${us_lmp:+LAMMPS $us_lmp us in this run}"
bench_line md_eam_peak_rss_mib "$(median < "$WORK/ours.rss" | xargs printf '%.1f')" MiB \
    "$( [ $have_lmp = 1 ] && echo "LAMMPS $(median < "$WORK/lmp.rss" | xargs printf '%.1f') MiB in this run")"
# the whole force call (density, embedding and force passes) per pair
bench_line md_eam_ns_per_pair "$(median < "$WORK/ours.f" | awk -v p="$pairs" -v s=$((steps + 1)) '{printf "%.2f", $1 * 1e9 / (p * s)}')" ns \
    "force call per pair within the cutoff, $pairs pairs"
if [ $have_lmp = 1 ]; then
    c_ours=$(median < "$WORK/ours.c"); c_lmp=$(median < "$WORK/lmp.c"); c_opt=$(median < "$WORK/opt.c")
    bench_line md_eam_lammps_us_per_atom_step "$us_lmp" us "LAMMPS plain, 1 thread"
    bench_line md_eam_lammps_peak_rss_mib "$(median < "$WORK/lmp.rss" | xargs printf '%.1f')" MiB
    bench_line md_eam_ratio_vs_lammps "$(echo "$c_ours / $c_lmp" | bc -l | xargs printf '%.3f')" x \
        "target 0.75; loop CPU s, ours $c_ours, LAMMPS $c_lmp"
    bench_line md_eam_ratio_vs_lammps_opt "$(echo "$c_ours / $c_opt" | bc -l | xargs printf '%.3f')" x \
        "target 0.85; LAMMPS -sf opt (eam/alloy/opt) $c_opt CPU s"
    bench_line md_eam_lammps_opt_over_plain "$(echo "$c_opt / $c_lmp" | bc -l | xargs printf '%.3f')" x \
        "LAMMPS' own optimised kernel against its plain one"
else
    echo "bench: lmp not installed (apt-get install lammps) -- no LAMMPS ratio" >&2
fi
fi

# The machine's memory bandwidth for the roofline figures of the kernels
# (bench/stream_probe.c, one thread, three arrays of 64 MiB)
if wanted stream || wanted mpm || wanted dpd; then
    set -- $(bench_stream 64)
    BENCH_STREAM_GBS=$2
    export BENCH_STREAM_GBS
    bench_line stream_copy_gbs "$1" GB/s "one thread, 3 x 64 MiB arrays"
    bench_line stream_triad_gbs "$2" GB/s "one thread: the roofline's bandwidth"
fi

# Each benchmark script, one line each (BIN ROOT WORK REPEAT in the environment)
run_bench() {
    name=${1#bench_}
    wanted "${name%.sh}" || return 0
    BIN="$BIN" ROOT="$ROOT" WORK="$WORK" REPEAT="$REPEAT" sh "$ROOT/bench/$1"
}
run_bench bench_md256.sh
run_bench bench_sw.sh
run_bench bench_md_kernel.sh
run_bench bench_mpm.sh
run_bench bench_dpd.sh
run_bench bench_dpd_mpm.sh
run_bench bench_handshake.sh
run_bench bench_campaign.sh
run_bench bench_report.sh
run_bench bench_cna.sh
run_bench bench_checkpoint.sh
run_bench bench_slurm.sh
run_bench bench_md_mpi.sh
run_bench bench_mpm_mpi.sh

# bench.json: the run's circumstances and every BENCH line, one a line
load_end=$(bench_load)
echo "bench: $load_end at end" >&2
commit=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
dirty=$(git -C "$ROOT" status --porcelain --untracked-files=no 2>/dev/null | head -c1)
{
    printf '{\n  "commit": "%s%s",\n  "started": "%s",\n  "finished": "%s",\n' \
        "$commit" "${dirty:+-dirty}" "$started" "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    printf '  "host": "%s",\n  "load_start": "%s",\n  "load_end": "%s",\n  "repeat": %s,\n' \
        "$(bench_json_str "$(uname -n)")" "$load_start" "$load_end" "$REPEAT"
    printf '  "results": [\n'
    sed '$!s/$/,/; s/^/    /' "$BENCH_RECORD"
    printf '  ]\n}\n'
} > "$BENCH_JSON.tmp"
mv "$BENCH_JSON.tmp" "$BENCH_JSON"
echo "bench: wrote $BENCH_JSON" >&2
