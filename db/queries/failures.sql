-- The jobs of a study whose latest attempt did not succeed, with the reason,
-- whom it is charged to (failure_class: job, deterministic, infrastructure)
-- and the tail of stderr.
--   cascade query -f db/queries/failures.sql --param study=demo
SELECT j.key AS job_key, j.state AS state, r.attempt AS attempt, r.exit_code AS exit_code,
       r.signal AS signal, r.failure_class AS failure_class, r.message AS message, j.params AS params, r.run_dir AS run_dir,
       r.stderr_tail AS stderr_tail
FROM jobs j
JOIN studies s ON s.id = j.study_id
LEFT JOIN runs r ON r.id = j.last_run_id
WHERE s.name = :study AND j.active = 1 AND j.state NOT IN ('done', 'running')
ORDER BY j.seq;
