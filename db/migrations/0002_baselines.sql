-- Schema version 2: regression baselines and their checks (cascade regress).
--
-- A baseline is a reviewed JSON file in the repository (studies/baselines/
-- NAME.json) holding a study's metric values and observed orders; cascade
-- records each version of it it reads or writes here, with the code version
-- that produced its values, and one row per regression check against it.
-- See db/README.md.

-- One row per distinct baseline file content of a study.
CREATE TABLE baselines (
    id             INTEGER PRIMARY KEY,
    study_id       INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    path           TEXT NOT NULL,           -- the file, absolute, when last seen
    sha256         TEXT NOT NULL,           -- SHA-256 (hex) of its text
    content        TEXT NOT NULL,           -- the file's text (JSON)
    solver_version TEXT NOT NULL,           -- the solver whose runs made the values
    solver_git     TEXT NOT NULL,
    created        TEXT NOT NULL,           -- when the file was written (its "created")
    recorded       TEXT NOT NULL,           -- when cascade first recorded it
    UNIQUE (study_id, sha256)
);

-- The baseline's numbers, one row each: a metric's value at one point of
-- the sweep (quantity 'value', params = the swept values) or its observed
-- order along the resolution axis (quantity 'order', params = the values of
-- the other axes).
CREATE TABLE baseline_values (
    baseline_id    INTEGER NOT NULL REFERENCES baselines(id) ON DELETE CASCADE,
    metric         TEXT NOT NULL,
    quantity       TEXT NOT NULL CHECK (quantity IN ('value', 'order')),
    params         TEXT NOT NULL,           -- canonical JSON object
    value          REAL,
    unit           TEXT NOT NULL,           -- the metric's unit; '1' for an order
    PRIMARY KEY (baseline_id, metric, quantity, params)
) WITHOUT ROWID;

-- One row per `cascade regress` comparison.
CREATE TABLE regress_checks (
    id             INTEGER PRIMARY KEY,
    baseline_id    INTEGER NOT NULL REFERENCES baselines(id) ON DELETE CASCADE,
    checked        TEXT NOT NULL,           -- when
    solver_version TEXT NOT NULL,           -- the solver whose runs were compared
    solver_git     TEXT NOT NULL,
    cascade        TEXT NOT NULL,           -- 'version (git)' of cascade
    compared       INTEGER NOT NULL,        -- values and orders compared
    regressed      INTEGER NOT NULL,        -- outside tolerance, missing, or jobs failed
    passed         INTEGER NOT NULL CHECK (passed IN (0, 1)),
    diff           TEXT NOT NULL            -- JSON list of the items that did not pass
);
CREATE INDEX regress_checks_baseline ON regress_checks (baseline_id, checked);
