#!/bin/sh
# make demo: runs the default study and writes its report.  Until the
# campaign runner is in place it runs one real solver case and prints its
# metrics.
#   usage: sh bench/demo.sh BINDIR
set -eu
BIN=${1:?usage: demo.sh BINDIR}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${DEMO_OUT:-runs/demo}
mkdir -p "$OUT"
echo "demo: 500 steps of 4,000-atom Mishin EAM copper at 300 K (docs/examples/cu_nve.yaml)"
"$BIN/cascade-solver" run "$ROOT/docs/examples/cu_nve.yaml" --out "$OUT/cu_nve"
echo
echo "demo: metrics (from $OUT/cu_nve/result.json):"
tr -d '\n' < "$OUT/cu_nve/result.json" | sed 's/.*"metrics": *{//; s/}, *"particles".*//' \
    | tr '}' '\n' | sed -n 's/^[ ,]*"\([a-z_]*\)": *{ *"unit": *"\([^"]*\)", *"value": *\([^ ,]*\).*/  \1 = \3 \2/p'
echo
echo "demo: open $OUT/cu_nve/fields.xdmf in ParaView; thermo in $OUT/cu_nve/thermo.csv"
echo
echo "demo: DPD-only flyer/target and tensile rod of Chen et al. 2014, quick variant"
echo "      (studies/chen2014/dpd_quick.yaml: 2,304-particle bar; outputs in runs/chen2014_quick)"
sh "$ROOT/studies/chen2014/run_dpd.sh" quick "$BIN/cascade-solver"
