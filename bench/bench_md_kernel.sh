#!/bin/sh
# The MD kernels alone (bench/md_kernel_probe.c, linked against the release
# build's libraries): one force call and one neighbour-list build on a
# perfect crystal displaced by up to 0.1 Å -- 32,000 atoms of EAM Cu and
# 13,824 of SW Si -- as the fastest of many calls in CPU time, the figure a
# shared machine moves least.  The list build is measured apart from the
# force call because a run pays it only when atoms moved half the skin.
#   BENCH md_eam_force_ms / md_eam_kernel_ns_per_pair / md_eam_list_build_ms
#   BENCH md_sw_force_ms / md_sw_list_build_ms
# Run by bench/bench.sh (BIN ROOT WORK REPEAT set); standalone:
#   sh bench/bench_md_kernel.sh BINDIR
set -eu
BIN=${BIN:-${1:?usage: bench_md_kernel.sh BINDIR}}
ROOT=${ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
if [ -z "${WORK:-}" ]; then
    WORK=$(mktemp -d /tmp/cascade-bench-kernel.XXXXXX)
    trap 'rm -rf "$WORK"' EXIT
fi
. "$ROOT/bench/lib.sh"
OBJ=$(cd "$BIN/../obj" && pwd)
PKGS="hdf5-openmpi jansson yaml-0.1 gsl sqlite3 nettle"
probe="$WORK/md_kernel_probe"
# shellcheck disable=SC2046  # pkg-config's flags are words
mpicc -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -O2 -fopenmp -I"$ROOT" -I"$ROOT/solver" \
    $(pkg-config --cflags $PKGS) -o "$probe" "$ROOT/bench/md_kernel_probe.c" \
    "$OBJ/libcascade_solver.a" "$OBJ/libcascade_util.a" $(pkg-config --libs $PKGS) -lm
export OMP_NUM_THREADS=1
field() { echo "$1" | awk -v k="$2" '{for (i = 1; i < NF; i++) if ($i == k) print $(i + 1)}'; }
eam=$("$probe" eam 20 60)
bench_line md_eam_force_ms "$(field "$eam" force_min_ms)" ms \
    "one force call, 32,000 atoms, fastest of 60 in CPU time (median $(field "$eam" force_median_ms)); $(bench_load)"
bench_line md_eam_kernel_ns_per_pair "$(field "$eam" ns_per_pair)" ns \
    "the same over $(field "$eam" pairs) pairs within the cutoff"
bench_line md_eam_list_build_ms "$(field "$eam" list_min_ms)" ms \
    "half list, cutoff + 1 Å skin, fastest of 10; $(echo "$(field "$eam" list_min_ms) $(field "$eam" force_min_ms)" \
        | awk '{printf "%.1f", $1 / $2}') force calls"
sw=$("$probe" sw 12 60)
bench_line md_sw_force_ms "$(field "$sw" force_min_ms)" ms \
    "one force call, 13,824 atoms, fastest of 60 in CPU time (median $(field "$sw" force_median_ms))"
bench_line md_sw_list_build_ms "$(field "$sw" list_min_ms)" ms \
    "full list, cutoff + 1 Å skin; $(echo "$(field "$sw" list_min_ms) $(field "$sw" force_min_ms)" \
        | awk '{printf "%.1f", $1 / $2}') force calls"
