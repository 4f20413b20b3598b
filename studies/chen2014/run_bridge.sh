#!/bin/sh
# The MD->DPD bridge without the campaign runner: run the MD isotherm points
# of md_isotherm_298K.yaml one by one, collect (density, pressure) into a
# CSV, and fit the coarse-grained parameters to it (dpd_fit.yaml's case).
#   usage: sh studies/chen2014/run_bridge.sh [SOLVER] [OUTDIR]
# With the campaign runner the same is `cascade run md_isotherm_298K.yaml`
# followed by the fit study.
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
SOLVER=${1:-$HERE/../../bin/cascade-solver}
OUT=${2:-runs/chen2014_bridge}
mkdir -p "$OUT"
CSV="$OUT/md_isotherm_298K.csv"
# the lattice constants of the study's sweep (system.lattice.a)
AXIS=$(sed -n 's/^ *system\.lattice\.a: *\[\(.*\)\].*/\1/p' "$HERE/md_isotherm_298K.yaml" | tr -d ' ' | tr ',' ' ')
metric() { # metric RESULT NAME
    tr -d ' \n' < "$1" | grep -o "\"$2\":{[^}]*}" | grep -o '"value":[-0-9.eE+]*' | cut -d: -f2
}
echo "lattice_constant_A,density_g_cm3,pressure_GPa,pressure_sem_GPa,temperature_K" > "$CSV"
for a in $AXIS; do
    sed "s/a: 3.61,/a: $a,/" "$HERE/cases/md_isotherm_point.yaml" > "$OUT/md_a$a.yaml"
    "$SOLVER" run "$OUT/md_a$a.yaml" --out "$OUT/md_a$a" --quiet --no-progress
    r="$OUT/md_a$a/result.json"
    echo "$a,$(metric "$r" density),$(metric "$r" pressure_mean),$(metric "$r" pressure_sem),$(metric "$r" temperature_mean)" >> "$CSV"
    echo "a = $a Å: $(tail -n 1 "$CSV")"
done
sed "s#points_file: .*#points_file: $(cd "$OUT" && pwd)/md_isotherm_298K.csv#" "$HERE/cases/dpd_fit.yaml" > "$OUT/dpd_fit.yaml"
"$SOLVER" run "$OUT/dpd_fit.yaml" --out "$OUT/fit" --no-progress
echo "parameter file: $OUT/fit/$(sed -n 's/^output_file: *//p' "$HERE/cases/dpd_fit.yaml")"
