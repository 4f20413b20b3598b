#!/bin/sh
# The DPD/MPM-grid and concurrent DPD/MPM experiments without the campaign
# runner, from the equilibrated state that run_dpd.sh leaves in runs/:
#   demo   the quick 4 Å grid impact and the quick concurrent impact (~30 s)
#   quick  the quick bar: grid impact and tensile at 2, 4, 8 Å, concurrent
#   full   the paper's bar: the same (run_dpd.sh full first; about an hour)
#   usage: sh studies/chen2014/run_dpd_mpm.sh [demo|quick|full] [SOLVER]
# Outputs go to runs/chen2014*/ under the repository root.
set -eu
MODE=${1:-demo}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SOLVER=$(cd "$(dirname "${2:-$ROOT/bin/cascade-solver}")" && pwd)/$(basename "${2:-cascade-solver}")
cd "$ROOT"
case "$MODE" in
    demo) PRE=quick_; OUT=runs/chen2014_quick; CELLS=4; TENSILE=0 ;;
    quick) PRE=quick_; OUT=runs/chen2014_quick; CELLS="2 4 8"; TENSILE=1 ;;
    full) PRE=; OUT=runs/chen2014; CELLS="2 4 8"; TENSILE=1 ;;
    *) echo "usage: run_dpd_mpm.sh [demo|quick|full] [SOLVER]" >&2; exit 2 ;;
esac
if [ ! -f "$OUT/equilibrate/equilibrated.data" ]; then
    echo "run_dpd_mpm.sh: $OUT/equilibrate/equilibrated.data missing: run run_dpd.sh $([ "$PRE" ] && echo quick || echo full) first" >&2
    exit 2
fi
CASES=studies/chen2014/cases
metric() { # metric RESULT NAME
    tr -d ' \n' < "$1" | grep -o "\"$2\":{[^}]*}" | grep -o '"value":[-0-9.eE+null]*' | cut -d: -f2
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for h in $CELLS; do
    for t in impact $([ "$TENSILE" = 1 ] && echo tensile); do
        echo "== grid $t, cell $h Å"
        sed "s/^  cell: .*/  cell: $h/; s|^  parameters: \.\./|  parameters: $ROOT/studies/chen2014/|" \
            "$CASES/${PRE}dpd_grid_$t.yaml" > "$tmp/case.yaml"
        "$SOLVER" run "$tmp/case.yaml" --out "$OUT/grid_${t}_$h" --no-progress --quiet
    done
done
echo "== concurrent DPD/MPM impact, cell 4 Å"
"$SOLVER" run "$CASES/${PRE}dpd_mpm_impact.yaml" --out "$OUT/concurrent" --no-progress --quiet
echo
for h in $CELLS; do
    r=$OUT/grid_impact_$h/result.json
    echo "grid $h Å: wave speed (front fit) $(metric "$r" wave_speed_fit) m/s, spread $(metric "$r" wave_speed_spread), 0.01 Å threshold $(metric "$r" wave_speed_threshold) m/s, energy deviation $(metric "$r" energy_deviation_max), grid heat $(metric "$r" heat_grid) eV"
    [ "$TENSILE" = 1 ] && echo "          peak stress $(metric "$OUT/grid_tensile_$h/result.json" peak_stress) GPa"
done
[ -f "$OUT/impact/result.json" ] && echo "DPD-only:  wave speed (front fit) $(metric "$OUT/impact/result.json" wave_speed_fit) m/s"
[ -f "$OUT/tensile/result.json" ] && [ "$TENSILE" = 1 ] && echo "DPD-only:  peak stress $(metric "$OUT/tensile/result.json" peak_stress) GPa"
r=$OUT/concurrent/result.json
echo "concurrent: wave speed (front fit) $(metric "$r" wave_speed_fit) m/s, spread $(metric "$r" wave_speed_spread), 0.01 Å threshold $(metric "$r" wave_speed_threshold) m/s, reflection ratio $(metric "$r" reflection_ratio) (reflected / incident particle velocity), transmission $(metric "$r" transmission_ratio)"
