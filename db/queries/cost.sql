-- What a study's runs cost: wall time and peak memory per job (latest
-- attempt), most expensive first.
--   cascade query -f db/queries/cost.sql --param study=md_timestep
SELECT j.key AS job_key, j.kind AS kind, j.params AS params, r.status AS status,
       round(r.wall_s, 3) AS wall_s, round(r.peak_rss_mib, 1) AS peak_rss_mib, r.host AS host
FROM jobs j
JOIN studies s ON s.id = j.study_id
JOIN runs r ON r.id = j.last_run_id
WHERE s.name = :study AND j.active = 1
ORDER BY r.wall_s DESC;
