-- Schema version 5: convergence results as data, imported reference values
-- and the state of adaptive refinement.
--
-- convergence: one row per study, metric, series (the values of the other
-- swept keys) and source, for each set of three finest grids the Celik et
-- al. (2008) procedure was run on -- written by `cascade report` and by the
-- refining runner, every number at full double precision.
-- imports, import_rows, import_params, import_values: reference rows of a
-- named external source (experiment, another code, a paper's table) brought
-- in with `cascade import`.
-- refine_groups: per study, metric and series of a study with `refine:`,
-- how far the runner refined it and why it stopped.  See db/README.md.

CREATE TABLE convergence (
    id             INTEGER PRIMARY KEY,
    study_id       INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    metric         TEXT NOT NULL,
    unit           TEXT NOT NULL,
    series         TEXT NOT NULL,           -- canonical JSON of the other swept values ('{}': one series)
    source         TEXT NOT NULL,           -- 'campaign', or the imported source
    axis           TEXT NOT NULL,           -- the resolution axis
    levels         INTEGER NOT NULL,        -- grids with a value in the series
    h              TEXT NOT NULL,           -- JSON list of every grid size with a value, finest first
    phi            TEXT NOT NULL,           -- JSON list of their values
    h1 REAL NOT NULL, h2 REAL NOT NULL, h3 REAL NOT NULL,   -- the three finest (1 = finest)
    phi1 REAL, phi2 REAL, phi3 REAL,
    r21 REAL, r32 REAL,
    ratio          REAL,                    -- R = eps21 / eps32
    kind           TEXT NOT NULL,           -- monotone | oscillatory | divergent | indeterminate | error
    p              REAL,                    -- observed order
    phi_ext        REAL,                    -- Richardson-extrapolated value (Eq. 6a)
    e_a21 REAL, e_ext21 REAL,
    gci_fine REAL, gci_medium REAL,         -- fractions (0.01 = 1 %)
    band           REAL,                    -- Fs |eps21| / (r21^p - 1), in the metric's unit
    asymptotic     REAL,                    -- GCI_32 / (r21^p GCI_21)
    oscillatory    INTEGER NOT NULL,
    divergent      INTEGER NOT NULL,
    non_asymptotic INTEGER NOT NULL,
    flags          TEXT NOT NULL,           -- the report's flags, '; '-separated
    computed       TEXT NOT NULL,
    UNIQUE (study_id, metric, series, source, h1, h2, h3)
);
CREATE INDEX convergence_study ON convergence (study_id, metric);

CREATE TABLE imports (
    id             INTEGER PRIMARY KEY,
    study_id       INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    source         TEXT NOT NULL,           -- 'experiment', 'lammps', free text
    file           TEXT NOT NULL,           -- absolute path of the file imported
    sha256         TEXT NOT NULL,
    imported       TEXT NOT NULL,
    nrows          INTEGER NOT NULL,
    UNIQUE (study_id, source)               -- importing a source again replaces it
);

CREATE TABLE import_rows (
    id             INTEGER PRIMARY KEY,
    import_id      INTEGER NOT NULL REFERENCES imports(id) ON DELETE CASCADE,
    line           INTEGER NOT NULL,        -- line of the file (JSON: index of the row + 1)
    params         TEXT NOT NULL            -- canonical JSON {key: value}
);

CREATE TABLE import_params (
    row_id         INTEGER NOT NULL REFERENCES import_rows(id) ON DELETE CASCADE,
    name           TEXT NOT NULL,
    value,
    PRIMARY KEY (row_id, name)
) WITHOUT ROWID;

CREATE TABLE import_values (
    row_id         INTEGER NOT NULL REFERENCES import_rows(id) ON DELETE CASCADE,
    metric         TEXT NOT NULL,
    value          REAL,
    unit           TEXT NOT NULL,
    PRIMARY KEY (row_id, metric)
) WITHOUT ROWID;

CREATE VIEW reference_results AS
SELECT s.name AS study, i.source AS source, i.file AS file, r.id AS row_id, r.line AS line,
       r.params AS params, v.metric AS metric, v.value AS value, v.unit AS unit
FROM import_values v
JOIN import_rows r ON r.id = v.row_id
JOIN imports i ON i.id = r.import_id
JOIN studies s ON s.id = i.study_id;

CREATE TABLE refine_groups (
    study_id       INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    metric         TEXT NOT NULL,
    series         TEXT NOT NULL,           -- canonical JSON of the other swept values
    axis           TEXT NOT NULL,
    levels         INTEGER NOT NULL,        -- levels with a value
    finest         TEXT NOT NULL,           -- JSON: the finest level's value of the axis
    value          REAL,                    -- the finest level's value of the metric
    phi_ext        REAL,
    gci_fine       REAL,
    band           REAL,
    asymptotic     REAL,
    state          TEXT NOT NULL CHECK (state IN ('refining', 'converged', 'stopped')),
    reason         TEXT NOT NULL,
    spent_core_s   REAL,                    -- core-seconds of the study's runs so far
    next_core_s    REAL,                    -- predicted core-seconds of the next level
    updated        TEXT NOT NULL,
    PRIMARY KEY (study_id, metric, series)
) WITHOUT ROWID;
