-- Schema version 8: the history of the nightly regressions, one row per
-- compared entry per night (cascade regress), for trends and the nightly
-- dashboard (cascade report --nightly).
--
-- regress_checks gains the machine the check ran on.  regress_values holds
-- every entry of every check -- the ones that passed too -- with the value
-- of that night, the baseline, the tolerance and the verdict, and the run
-- directories the value came from.  The view regress_history joins them
-- with the study and the commit.  Checks recorded before version 8 have
-- no rows here (their failures stay in regress_checks.diff).  See
-- db/README.md and docs/nightly.md.
ALTER TABLE regress_checks ADD COLUMN machine TEXT;

CREATE TABLE regress_values (
    check_id   INTEGER NOT NULL REFERENCES regress_checks(id) ON DELETE CASCADE,
    seq        INTEGER NOT NULL,        -- order of the entry in the check
    metric     TEXT NOT NULL,           -- '-' for a job that did not succeed
    what       TEXT NOT NULL,           -- 'value', 'order p', 'job'; 'level', 'converged'
                                        -- for a refined series (docs/reports.md)
    point      TEXT NOT NULL,           -- the swept values, the series, or the job
    unit       TEXT NOT NULL,           -- the metric's unit; '1' for an order
    baseline   REAL,                    -- NULL where there is none (new, job)
    value      REAL,                    -- that night's value; NULL when there was none
    tolerance  REAL,                    -- the allowed |value - baseline|
    verdict    TEXT NOT NULL CHECK (verdict IN ('ok', 'REGRESSED', 'MISSING', 'FAILED', 'new')),
    run_dirs   TEXT NOT NULL,           -- JSON list of the attempt directories of the value
    note       TEXT NOT NULL,
    PRIMARY KEY (check_id, seq)
) WITHOUT ROWID;
CREATE INDEX regress_values_metric ON regress_values (metric, what, point);

CREATE VIEW regress_history AS
SELECT s.name AS study, c.id AS check_id, c.checked AS checked, c.solver_git AS commit_git,
       c.solver_version AS solver_version, c.machine AS machine, c.passed AS night_passed,
       v.metric AS metric, v.what AS what, v.point AS point, v.unit AS unit,
       v.baseline AS baseline, v.value AS value, v.tolerance AS tolerance,
       v.verdict AS verdict, v.run_dirs AS run_dirs, v.note AS note
FROM regress_values v
JOIN regress_checks c ON c.id = v.check_id
JOIN baselines b ON b.id = c.baseline_id
JOIN studies s ON s.id = b.study_id;
