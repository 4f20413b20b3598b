-- Schema version 7: job counts per study, state and solver, kept by triggers,
-- and an index for "the first jobs in a state".
--
-- `cascade status` used to count a study's jobs by state with a scan of the
-- jobs index: 37 ms at 100,000 jobs, about a second at 1,000,000 on a busy
-- machine.  job_counts holds those counts (active jobs only), so the
-- overview and a study's summary read a few rows; the triggers keep them
-- equal to
--   SELECT study_id, state, coalesce(solver, ''), count(*) FROM jobs
--   WHERE active = 1 GROUP BY 1, 2, 3
-- through every insert, delete and change of a job's study, state, solver
-- or active flag (a job's state changes through the runs triggers, which
-- update jobs and so fire these).  Rows whose count fell to 0 stay, with 0.
--
-- jobs_study_state_seq serves "the first 20 jobs running / not done, in
-- expansion order" without visiting the jobs already done.
CREATE TABLE job_counts (
    study_id    INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    state       TEXT NOT NULL,
    solver      TEXT NOT NULL,              -- jobs.solver, '' when NULL
    n           INTEGER NOT NULL,
    PRIMARY KEY (study_id, state, solver)
) WITHOUT ROWID;

INSERT INTO job_counts (study_id, state, solver, n)
SELECT study_id, state, coalesce(solver, ''), count(*) FROM jobs WHERE active = 1
GROUP BY study_id, state, coalesce(solver, '');

CREATE TRIGGER job_counts_insert AFTER INSERT ON jobs WHEN NEW.active = 1
BEGIN
    INSERT INTO job_counts (study_id, state, solver, n)
    VALUES (NEW.study_id, NEW.state, coalesce(NEW.solver, ''), 1)
    ON CONFLICT (study_id, state, solver) DO UPDATE SET n = n + 1;
END;

CREATE TRIGGER job_counts_delete AFTER DELETE ON jobs WHEN OLD.active = 1
BEGIN
    UPDATE job_counts SET n = n - 1
    WHERE study_id = OLD.study_id AND state = OLD.state AND solver = coalesce(OLD.solver, '');
END;

CREATE TRIGGER job_counts_update AFTER UPDATE OF study_id, state, solver, active ON jobs
    WHEN (OLD.active = 1 OR NEW.active = 1)
         AND (OLD.study_id IS NOT NEW.study_id OR OLD.state IS NOT NEW.state
              OR OLD.solver IS NOT NEW.solver OR OLD.active IS NOT NEW.active)
BEGIN
    UPDATE job_counts SET n = n - 1
    WHERE OLD.active = 1 AND study_id = OLD.study_id AND state = OLD.state
          AND solver = coalesce(OLD.solver, '');
    INSERT INTO job_counts (study_id, state, solver, n)
    SELECT NEW.study_id, NEW.state, coalesce(NEW.solver, ''), 1 WHERE NEW.active = 1
    ON CONFLICT (study_id, state, solver) DO UPDATE SET n = n + 1;
END;

CREATE INDEX jobs_study_state_seq ON jobs (study_id, active, state, seq);
