-- Mean, spread and count of a metric for each value of a swept parameter,
-- over every other parameter (repeats, seeds): the table behind a plot of
-- the metric against the parameter.
--   cascade query -f db/queries/metric_stats_by_param.sql \
--       --param study=md_timestep --param metric=energy_drift --param param=md.timestep
SELECT p.value AS param_value, count(*) AS n, avg(r.value) AS mean,
       min(r.value) AS min, max(r.value) AS max, r.unit AS unit
FROM results r
JOIN job_params p ON p.job_id = r.job_id AND p.name = :param
WHERE r.study = :study AND r.metric = :metric
GROUP BY p.value, r.unit
ORDER BY p.value;
