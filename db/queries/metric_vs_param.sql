-- One metric against one swept parameter: a row per job, ordered by the
-- parameter, with the job's other parameters alongside (latest done runs).
--   cascade query -f db/queries/metric_vs_param.sql \
--       --param study=md_timestep --param metric=energy_drift --param param=md.timestep
SELECT p.value AS param_value, r.value AS value, r.unit AS unit, r.params AS params,
       r.job_key AS job_key, r.solver_version AS solver_version
FROM results r
JOIN job_params p ON p.job_id = r.job_id AND p.name = :param
WHERE r.study = :study AND r.metric = :metric
ORDER BY p.value, r.params;
