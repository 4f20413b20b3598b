-- A metric of every job of a study for each solver version that ran it:
-- how a code change moved the results (one row per job and version, newest
-- done run of that version).
--   cascade query -f db/queries/metric_across_versions.sql --param study=sc_cutoff \
--       --param metric=c11
SELECT m.job_key AS job_key, m.params AS params, m.solver_version AS solver_version,
       m.solver_git AS solver_git, m.value AS value, m.unit AS unit, m.finished AS finished
FROM run_metrics m
WHERE m.study = :study AND m.metric = :metric AND m.status = 'done'
  AND m.attempt = (SELECT max(x.attempt) FROM run_metrics x
                   WHERE x.job_id = m.job_id AND x.metric = m.metric AND x.status = 'done'
                     AND x.solver_version = m.solver_version AND x.solver_git = m.solver_git)
ORDER BY m.params, m.finished;
