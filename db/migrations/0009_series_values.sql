-- Schema version 9: time series from result.json, for the series a study
-- lists under `series:` (cascade run records them with the run's metrics;
-- the damage-shape series of cluster impacts, docs/impact.md).  One row
-- per value: idx is the value's place in the series, so a series is read
-- back in order and joined with another of the same run (the analysis
-- times, analysis_time_ps) on idx.  See db/README.md.
CREATE TABLE series_values (
    run_id  INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
    name    TEXT NOT NULL,           -- the series' name in result.json
    idx     INTEGER NOT NULL,        -- 0, 1, ... in the order of result.json
    value   REAL,                    -- NULL where result.json has null (not a finite number)
    unit    TEXT NOT NULL,
    PRIMARY KEY (run_id, name, idx)
) WITHOUT ROWID;
