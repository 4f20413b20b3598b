#!/bin/sh
# The DPD-only flyer/target and tensile studies without the campaign runner:
# 0 K relaxation -> 298 K equilibration -> impact and tensile runs, each
# reading the previous run's final state from runs/.
#   usage: sh studies/chen2014/run_dpd.sh [quick|full] [SOLVER]
# Outputs go to runs/chen2014*/ under the repository root (the cases name
# those paths), wherever it is started from.
set -eu
MODE=${1:-quick}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SOLVER=$(cd "$(dirname "${2:-$ROOT/bin/cascade-solver}")" && pwd)/$(basename "${2:-cascade-solver}")
cd "$ROOT"
case "$MODE" in
    quick) PRE=quick_; OUT=runs/chen2014_quick ;;
    full) PRE=; OUT=runs/chen2014 ;;
    *) echo "usage: run_dpd.sh [quick|full] [SOLVER]" >&2; exit 2 ;;
esac
CASES=studies/chen2014/cases
for job in quench equilibrate impact tensile; do
    echo "== $job"
    "$SOLVER" run "$CASES/${PRE}dpd_$job.yaml" --out "$OUT/$job" --no-progress
done
metric() { # metric RESULT NAME
    tr -d ' \n' < "$1" | grep -o "\"$2\":{[^}]*}" | grep -o '"value":[-0-9.eE+null]*' | cut -d: -f2
}
echo
echo "wave speed:  front fit $(metric "$OUT/impact/result.json" wave_speed_fit) m/s (spread $(metric "$OUT/impact/result.json" wave_speed_spread)), fixed 0.01 Å threshold $(metric "$OUT/impact/result.json" wave_speed_threshold) m/s (Chen et al. 2014: about 3846 m/s)"
echo "DPDE energy: max |E - E0| / |E0| = $(metric "$OUT/impact/result.json" energy_deviation_max)"
echo "peak stress: $(metric "$OUT/tensile/result.json" peak_stress) GPa at strain $(metric "$OUT/tensile/result.json" strain_at_peak)"
