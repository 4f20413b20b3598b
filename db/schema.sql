-- Cascade results database: schema version 1.
--
-- Applied by `cascade` to a new database (PRAGMA user_version 0 -> 1); later
-- changes go into db/migrations/NNNN_name.sql (NNNN = the version they
-- produce), never into this file.  The tables are a user interface: see
-- db/README.md.  Connections run with foreign_keys = ON and journal_mode =
-- WAL.  Times are ISO 8601 UTC text ('2024-05-01T12:00:00.123Z').

-- One row per study name.  spec_text is the study file as last registered.
CREATE TABLE studies (
    id          INTEGER PRIMARY KEY,
    name        TEXT NOT NULL UNIQUE,
    description TEXT NOT NULL DEFAULT '',
    spec_path   TEXT NOT NULL,              -- absolute path of the study file
    spec_text   TEXT NOT NULL,
    spec_hash   TEXT NOT NULL,              -- SHA-256 (hex) of spec_text
    created     TEXT NOT NULL,
    updated     TEXT NOT NULL
);

-- The swept parameters of a study, in product order.  Axes of one zip group
-- share `grp`; repeats appear as the axis 'seed' of kind 'repeat'.
CREATE TABLE study_axes (
    study_id    INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,              -- case-key path, e.g. 'md.timestep'
    position    INTEGER NOT NULL,           -- 0, 1, ... as written in the study
    grp         INTEGER NOT NULL,           -- product factor this axis belongs to
    kind        TEXT NOT NULL CHECK (kind IN ('grid', 'zip', 'repeat')),
    nvalues     INTEGER NOT NULL,
    vals        TEXT NOT NULL,              -- JSON list of the values as written
    PRIMARY KEY (study_id, name)
) WITHOUT ROWID;

-- One row per job of a study: a preparation job or a point of the sweep.
-- The key is the solver's hash of the canonical resolved case.
CREATE TABLE jobs (
    id          INTEGER PRIMARY KEY,
    study_id    INTEGER NOT NULL REFERENCES studies(id) ON DELETE CASCADE,
    key         TEXT NOT NULL,
    kind        TEXT NOT NULL CHECK (kind IN ('prep', 'sweep')),
    name        TEXT,                       -- the preparation job's name
    seq         INTEGER NOT NULL,           -- position in the expansion
    params      TEXT NOT NULL,              -- JSON object {axis: value}
    case_json   TEXT NOT NULL,              -- canonical resolved case
    active      INTEGER NOT NULL DEFAULT 1, -- 0: no longer produced by the study file
    state       TEXT NOT NULL DEFAULT 'pending',  -- status of the latest attempt
    last_run_id INTEGER,                    -- runs.id of the latest attempt
    solver      TEXT,                       -- 'version (git hash)' of the latest attempt
    retry_after INTEGER NOT NULL DEFAULT 0, -- attempts up to this one are forgiven
    UNIQUE (study_id, key)
);
CREATE INDEX jobs_study_state ON jobs (study_id, active, state, solver);
CREATE INDEX jobs_study_seq ON jobs (study_id, seq);
CREATE INDEX jobs_key ON jobs (key);

-- One row per swept parameter of a job.  `value` holds numbers as numbers
-- (so WHERE value = 0.002 and ORDER BY value work), strings as text, lists
-- and mappings as JSON text.
CREATE TABLE job_params (
    job_id      INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    value,
    PRIMARY KEY (job_id, name)
) WITHOUT ROWID;
CREATE INDEX job_params_name_value ON job_params (name, value);

-- Preparation jobs a job reads from (${prep.NAME} references).
CREATE TABLE job_deps (
    job_id      INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
    needs_id    INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
    PRIMARY KEY (job_id, needs_id)
) WITHOUT ROWID;

-- One row per attempt to run a job.
CREATE TABLE runs (
    id          INTEGER PRIMARY KEY,
    job_id      INTEGER NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,
    attempt     INTEGER NOT NULL,           -- 1, 2, ... per job
    status      TEXT NOT NULL CHECK (status IN ('running', 'done', 'failed', 'crashed',
                                                'timeout', 'diverged', 'cancelled')),
    exit_code   INTEGER,                    -- when the solver exited
    signal      INTEGER,                    -- when a signal ended it
    message     TEXT,                       -- the solver's message or the runner's reason
    started     TEXT NOT NULL,
    finished    TEXT,
    wall_s      REAL,
    peak_rss_mib REAL,                      -- of the job's processes (getrusage)
    host        TEXT NOT NULL,
    runner      TEXT NOT NULL,              -- host:pid:start of the cascade process
    pid         INTEGER,                    -- of the job's process group leader
    launcher    TEXT NOT NULL,              -- 'local' or the mpirun command
    solver_version TEXT NOT NULL,
    solver_git  TEXT NOT NULL,
    run_dir     TEXT NOT NULL,
    stderr_tail TEXT,                       -- last lines of the job's stderr
    UNIQUE (job_id, attempt)
);
CREATE INDEX runs_job_status ON runs (job_id, status, attempt);
CREATE INDEX runs_solver ON runs (solver_version, solver_git);

-- The scalar metrics of a run, from result.json (name, value, unit).
CREATE TABLE metrics (
    run_id      INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
    name        TEXT NOT NULL,
    value       REAL,                       -- NULL when not a finite number
    unit        TEXT NOT NULL,
    PRIMARY KEY (run_id, name)
) WITHOUT ROWID;
CREATE INDEX metrics_name ON metrics (name);

-- Files a run left in its directory, with checksums.
CREATE TABLE artifacts (
    run_id      INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
    path        TEXT NOT NULL,              -- absolute
    kind        TEXT NOT NULL,              -- case, result, stdout, stderr, hdf5, xdmf, thermo, xyz, other
    bytes       INTEGER NOT NULL,
    sha256      TEXT NOT NULL,
    PRIMARY KEY (run_id, path)
) WITHOUT ROWID;

-- Who runs a job now.  A lease is taken in the transaction that creates the
-- 'running' run row and renewed by heartbeats; an expired lease (or one whose
-- runner process is gone from this host) lets the next runner take over.
CREATE TABLE leases (
    job_id      INTEGER PRIMARY KEY REFERENCES jobs(id) ON DELETE CASCADE,
    run_id      INTEGER NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
    runner      TEXT NOT NULL,
    host        TEXT NOT NULL,
    pid         INTEGER NOT NULL,
    expires     REAL NOT NULL               -- Unix time, seconds
);
CREATE INDEX leases_runner ON leases (runner);

-- jobs.state, last_run_id and solver follow the latest attempt, whoever
-- writes the runs table (so `cascade status` counts jobs without joins).
CREATE TRIGGER runs_state_insert AFTER INSERT ON runs
BEGIN
    UPDATE jobs SET state = NEW.status, last_run_id = NEW.id,
                    solver = NEW.solver_version || ' (' || NEW.solver_git || ')'
    WHERE id = NEW.job_id;
END;
CREATE TRIGGER runs_state_update AFTER UPDATE OF status, solver_version, solver_git ON runs
    WHEN NEW.id = (SELECT last_run_id FROM jobs WHERE id = NEW.job_id)
BEGIN
    UPDATE jobs SET state = NEW.status,
                    solver = NEW.solver_version || ' (' || NEW.solver_git || ')'
    WHERE id = NEW.job_id;
END;

-- Every metric of every finished run, with the job's study, parameters and
-- the solver that produced it: the view to compare solver versions.
CREATE VIEW run_metrics AS
SELECT s.name AS study, j.key AS job_key, j.id AS job_id, j.kind AS kind, j.name AS job_name,
       j.params AS params, r.id AS run_id, r.attempt AS attempt, r.status AS status,
       r.solver_version AS solver_version, r.solver_git AS solver_git,
       r.finished AS finished, m.name AS metric, m.value AS value, m.unit AS unit
FROM metrics m
JOIN runs r ON r.id = m.run_id
JOIN jobs j ON j.id = r.job_id
JOIN studies s ON s.id = j.study_id;

-- The metrics of each active job's latest successful run: the view reports
-- and most questions start from.  Join job_params on job_id to filter or
-- order by a swept parameter.
CREATE VIEW results AS
SELECT s.name AS study, j.key AS job_key, j.id AS job_id, j.kind AS kind, j.name AS job_name,
       j.params AS params, r.id AS run_id, r.attempt AS attempt,
       r.solver_version AS solver_version, r.solver_git AS solver_git,
       r.finished AS finished, m.name AS metric, m.value AS value, m.unit AS unit
FROM jobs j
JOIN studies s ON s.id = j.study_id
JOIN runs r ON r.job_id = j.id AND r.status = 'done'
           AND r.attempt = (SELECT max(x.attempt) FROM runs x
                            WHERE x.job_id = j.id AND x.status = 'done')
JOIN metrics m ON m.run_id = r.id
WHERE j.active = 1;

-- Each active job with its latest attempt (NULL columns when never run).
CREATE VIEW job_status AS
SELECT s.name AS study, j.key AS job_key, j.id AS job_id, j.kind AS kind, j.name AS job_name,
       j.seq AS seq, j.params AS params, j.state AS state, r.attempt AS attempt,
       r.exit_code AS exit_code, r.signal AS signal, r.message AS message,
       r.wall_s AS wall_s, r.peak_rss_mib AS peak_rss_mib, r.host AS host,
       r.solver_version AS solver_version, r.solver_git AS solver_git,
       r.run_dir AS run_dir, r.finished AS finished
FROM jobs j
JOIN studies s ON s.id = j.study_id
LEFT JOIN runs r ON r.id = j.last_run_id
WHERE j.active = 1;
