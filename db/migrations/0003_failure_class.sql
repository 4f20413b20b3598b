-- Schema version 3: whom a failed attempt is charged to, and how far it got.
--
-- failure_class: 'job' (the job's own failure: failed, crashed, timeout,
-- diverged; counts against the study's retries), 'infrastructure' (the run
-- directory could not be written, the disk was full, the solver could not
-- be started, the runner went away: never charged, the job runs again;
-- recorded with status 'cancelled'), 'deterministic' (a crash that repeated
-- an earlier one of the job: the same signal at the same step, or the same
-- signal when the step is unknown; not retried again), NULL (done, running,
-- cancelled on request).  last_step: the last step in the run's thermo.csv
-- when it did not finish (NULL: unknown).  See db/README.md.
ALTER TABLE runs ADD COLUMN failure_class TEXT
    CHECK (failure_class IN ('job', 'infrastructure', 'deterministic'));
ALTER TABLE runs ADD COLUMN last_step INTEGER;

-- Earlier runs: a failure to start was the environment's, recorded from
-- now on as cancelled (those jobs were marked failed for good; now they run
-- again, and jobs.state follows through the trigger); so was a run closed
-- because its runner went away.  Everything else that failed was the job's.
UPDATE runs SET failure_class = 'job'
    WHERE status IN ('failed', 'crashed', 'timeout', 'diverged');
UPDATE runs SET status = 'cancelled', failure_class = 'infrastructure'
    WHERE status = 'failed' AND message LIKE 'could not start%';
UPDATE runs SET failure_class = 'infrastructure'
    WHERE status = 'cancelled' AND (message LIKE 'runner % is gone%'
                                    OR message LIKE 'the lease of runner % expired%');

-- job_status gains the class of the latest attempt (as its last column, so
-- queries written against version 2 keep working).
DROP VIEW job_status;
CREATE VIEW job_status AS
SELECT s.name AS study, j.key AS job_key, j.id AS job_id, j.kind AS kind, j.name AS job_name,
       j.seq AS seq, j.params AS params, j.state AS state, r.attempt AS attempt,
       r.exit_code AS exit_code, r.signal AS signal, r.message AS message,
       r.wall_s AS wall_s, r.peak_rss_mib AS peak_rss_mib, r.host AS host,
       r.solver_version AS solver_version, r.solver_git AS solver_git,
       r.run_dir AS run_dir, r.finished AS finished, r.failure_class AS failure_class
FROM jobs j
JOIN studies s ON s.id = j.study_id
LEFT JOIN runs r ON r.id = j.last_run_id
WHERE j.active = 1;
