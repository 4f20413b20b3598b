#!/bin/sh
# make demo: runs the quick demo study (studies/demo.yaml) with the campaign
# runner -- a preparation job equilibrates copper at 300 K, six NVE jobs
# continue from its final state with three time steps and two neighbour-list
# skins -- records everything in an SQLite database, prints the status and a
# table of metrics against the swept parameters, and writes the study's
# convergence report (reports/demo/report.html and report.md).  Running it
# again resumes: jobs already done for this solver version are not run again.
#   usage: sh bench/demo.sh BINDIR
set -eu
BIN=${1:?usage: demo.sh BINDIR}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=${DEMO_OUT:-runs/demo}
mkdir -p "$OUT"
DB="$OUT/cascade.db"
CASCADE="$BIN/cascade"

echo "demo: cascade run studies/demo.yaml (database $DB, run directories $OUT/runs)"
"$CASCADE" run "$ROOT/studies/demo.yaml" --db "$DB" --runs "$OUT/runs"
echo
"$CASCADE" status demo --db "$DB"
echo
echo "demo: NVE energy drift against the time step (velocity Verlet: drift ~ dt^2),"
echo "      and the neighbour-list skin, which must not change the physics:"
"$CASCADE" query --db "$DB" --param study=demo "
SELECT max(CASE WHEN p.name = 'md.timestep' THEN p.value END) AS timestep_ps,
       max(CASE WHEN p.name = 'md.skin' THEN p.value END) AS skin_A,
       printf('%.3e', max(CASE WHEN r.metric = 'energy_drift' THEN r.value END)) AS energy_drift,
       printf('%.2f', max(CASE WHEN r.metric = 'temperature_mean' THEN r.value END)) AS T_mean_K,
       printf('%.5f', max(CASE WHEN r.metric = 'pe_per_atom' THEN r.value END)) AS pe_eV_per_atom,
       max(CASE WHEN r.metric = 'neighbor_rebuilds' THEN r.value END) AS rebuilds
FROM results r JOIN job_params p ON p.job_id = r.job_id
WHERE r.study = :study AND r.kind = 'sweep'
GROUP BY r.job_id ORDER BY timestep_ps, skin_A"
echo
echo "demo: more with  $CASCADE query --db $DB \"SELECT * FROM results\""
echo "      or  $CASCADE export demo --csv --db $DB"

echo
echo "demo: DPD-only flyer/target and tensile rod of Chen et al. 2014, quick variant"
echo "      (studies/chen2014/dpd_quick.yaml: 2,304-particle bar; outputs in runs/chen2014_quick)"
sh "$ROOT/studies/chen2014/run_dpd.sh" quick "$BIN/cascade-solver"

echo
echo "demo: the same target carried by a 4 Å MPM grid (DPD/MPM-grid model) and split into"
echo "      DPD particles and material points (concurrent DPD/MPM model), about 30 s"
sh "$ROOT/studies/chen2014/run_dpd_mpm.sh" demo "$BIN/cascade-solver"

# --- the report of the study -------------------------------------------------
REPORT=${DEMO_REPORT:-reports/demo}
echo
"$CASCADE" report demo --db "$DB" --out "$REPORT"
echo "demo: the report of the study (observed order of each metric against the time step,"
echo "      GCI, figures) is $REPORT/report.html (self-contained) and $REPORT/report.md"
