/* store: registering studies, leases, and recording outcomes. */
#include "store.h"
#include "util/canon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "db.h"
#include "launch.h"
#include "sysinfo.h"
#include "util/mem.h"

enum {
    Q_LEASE_GET,
    Q_RETRY_AFTER,
    Q_DONE,
    Q_FAILS,
    Q_DEPS,
    Q_NEXT_ATTEMPT,
    Q_RUN_INSERT,
    Q_LEASE_INSERT,
    Q_RUN_UPDATE,
    Q_METRIC_INSERT,
    Q_ARTIFACT_INSERT,
    Q_LEASE_DELETE,
    Q_HEARTBEAT,
    Q_DONE_DIR,
    Q_SAME_CRASH,
    Q_SERIES_INSERT,
    Q_COUNT
};

static const char *const queries[Q_COUNT] = {
    [Q_LEASE_GET] = "SELECT runner, expires, run_id, "
                    "(SELECT slurm_job_id IS NOT NULL FROM runs WHERE id = leases.run_id) "
                    "FROM leases WHERE job_id = ?1",
    [Q_RETRY_AFTER] = "SELECT retry_after FROM jobs WHERE id = ?1",
    [Q_DONE] = "SELECT 1 FROM runs WHERE job_id = ?1 AND status = 'done' AND solver_version = ?2 "
               "AND solver_git = ?3 AND attempt > ?4 LIMIT 1",
    /* infrastructure failures are not the job's: they never count */
    [Q_FAILS] = "SELECT count(*) FILTER (WHERE status IN ('failed', 'crashed', 'timeout') "
                "AND failure_class IS NOT 'infrastructure'), "
                "count(*) FILTER (WHERE status = 'diverged' OR failure_class = 'deterministic') "
                "FROM runs WHERE job_id = ?1 "
                "AND solver_version = ?2 AND solver_git = ?3 AND attempt > ?4",
    [Q_DEPS] = "SELECT needs_id FROM job_deps WHERE job_id = ?1",
    [Q_NEXT_ATTEMPT] = "SELECT coalesce(max(attempt), 0) + 1 FROM runs WHERE job_id = ?1",
    [Q_RUN_INSERT] = "INSERT INTO runs (job_id, attempt, status, started, host, runner, launcher, "
                     "solver_version, solver_git, run_dir) "
                     "VALUES (?1, ?2, 'running', ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
    [Q_LEASE_INSERT] = "INSERT INTO leases (job_id, run_id, runner, host, pid, expires) "
                       "VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
    [Q_RUN_UPDATE] = "UPDATE runs SET status = ?2, exit_code = ?3, signal = ?4, message = ?5, "
                     "started = ?6, finished = ?7, wall_s = ?8, peak_rss_mib = ?9, host = ?10, "
                     "pid = ?11, stderr_tail = ?12, solver_version = ?13, solver_git = ?14, "
                     "failure_class = ?15, last_step = ?16, resumed_from_step = ?17, "
                     "slurm_state = ?18 WHERE id = ?1",
    [Q_METRIC_INSERT] = "INSERT OR REPLACE INTO metrics (run_id, name, value, unit) "
                        "VALUES (?1, ?2, ?3, ?4)",
    [Q_ARTIFACT_INSERT] = "INSERT OR REPLACE INTO artifacts (run_id, path, kind, bytes, sha256) "
                          "VALUES (?1, ?2, ?3, ?4, ?5)",
    [Q_LEASE_DELETE] = "DELETE FROM leases WHERE job_id = ?1 AND run_id = ?2",
    [Q_HEARTBEAT] = "UPDATE leases SET expires = ?2 WHERE runner = ?1",
    [Q_DONE_DIR] = "SELECT run_dir FROM runs WHERE job_id = ?1 AND status = 'done' "
                   "AND solver_version = ?2 AND solver_git = ?3 "
                   "AND attempt > (SELECT retry_after FROM jobs WHERE id = ?1) "
                   "ORDER BY attempt DESC LIMIT 1",
    [Q_SAME_CRASH] = "SELECT attempt, last_step FROM runs WHERE job_id = ?1 AND id <> ?2 "
                     "AND status = 'crashed' AND signal = ?3 AND solver_version = ?4 "
                     "AND solver_git = ?5 "
                     "AND attempt > (SELECT retry_after FROM jobs WHERE id = ?1) "
                     "ORDER BY attempt DESC",
    [Q_SERIES_INSERT] = "INSERT OR REPLACE INTO series_values (run_id, name, idx, value, unit) "
                        "VALUES (?1, ?2, ?3, ?4, ?5)",
};

int store_init(struct store *st, sqlite3 *db, const struct study *s, const struct solver *sv,
               double lease_s, struct err *e)
{
    memset(st, 0, sizeof *st);
    st->db = db;
    sys_runner_id(st->runner, sizeof st->runner);
    sys_hostname(st->host, sizeof st->host);
    st->pid = (int)getpid();
    snprintf(st->solver_version, sizeof st->solver_version, "%s", sv->version);
    snprintf(st->solver_git, sizeof st->solver_git, "%s", sv->git);
    snprintf(st->launcher, sizeof st->launcher, "%s",
             s->backend == STUDY_BACKEND_SLURM ? "slurm" : s->launcher);
    st->lease_s = lease_s;
    st->retries = s->retries;
    st->metrics = (const char *const *)s->metrics;
    st->nmetrics = s->nmetrics;
    st->series = (const char *const *)s->series;
    st->nseries = s->nseries;
    for (int q = 0; q < Q_COUNT; q++) {
        int rc = db_prepare(db, queries[q], &st->st[q], e);
        if (rc) {
            store_fini(st);
            return rc;
        }
    }
    return 0;
}

void store_fini(struct store *st)
{
    for (int q = 0; q < Q_COUNT; q++)
        sqlite3_finalize(st->st[q]);
    memset(st->st, 0, sizeof st->st);
}

static sqlite3_stmt *q(struct store *st, int which)
{
    sqlite3_stmt *s = st->st[which];
    sqlite3_reset(s);
    sqlite3_clear_bindings(s);
    return s;
}

int store_flush(struct store *st, struct err *e)
{
    if (!st->pending)
        return 0;
    st->pending = 0;
    int rc = sqlite3_get_autocommit(st->db)
                 ? db_err(st->db, e, ERR_RUNTIME, "recording the run: the transaction was "
                                                  "rolled back (%s)", sqlite3_errmsg(st->db))
                 : db_commit(st->db, e);
    if (rc) {
        db_rollback(st->db);
        st->pending_lost = 1;
    }
    return rc;
}

/* A write transaction of its own: a pending outcome is committed first. */
static int begin_own(struct store *st, struct err *e)
{
    int rc = store_flush(st, e);
    return rc ? rc : db_begin(st->db, e);
}

static void bind_text(sqlite3_stmt *s, int i, const char *t)
{
    sqlite3_bind_text(s, i, t, -1, SQLITE_STATIC);
}

/* --- registering ---------------------------------------------------------- */

static int step_done(sqlite3 *db, sqlite3_stmt *s, struct err *e, const char *what)
{
    int r = sqlite3_step(s);
    if (r != SQLITE_DONE && r != SQLITE_ROW)
        return db_fail(db, e, what);
    return 0;
}

static const char *axis_kind_name(enum axis_kind k)
{
    return k == AXIS_GRID ? "grid" : k == AXIS_ZIP ? "zip" : "repeat";
}

static int register_study(struct store *st, const struct study *s, long long *study_id,
                          struct err *e)
{
    sqlite3 *db = st->db;
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    sqlite3_stmt *up;
    int rc = db_prepare(db,
                        "INSERT INTO studies (name, description, spec_path, spec_text, spec_hash, "
                        "created, updated) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?6) "
                        "ON CONFLICT (name) DO UPDATE SET description = excluded.description, "
                        "spec_path = excluded.spec_path, spec_text = excluded.spec_text, "
                        "spec_hash = excluded.spec_hash, updated = excluded.updated "
                        "RETURNING id",
                        &up, e);
    if (rc)
        return rc;
    bind_text(up, 1, s->name);
    bind_text(up, 2, s->description);
    bind_text(up, 3, s->abspath);
    sqlite3_bind_text(up, 4, s->text, (int)s->textlen, SQLITE_STATIC);
    bind_text(up, 5, s->hash);
    bind_text(up, 6, now);
    if (sqlite3_step(up) != SQLITE_ROW) {
        rc = db_fail(db, e, "registering the study");
        sqlite3_finalize(up);
        return rc;
    }
    *study_id = sqlite3_column_int64(up, 0);
    sqlite3_finalize(up);
    char sql[512];
    snprintf(sql, sizeof sql,
             "DELETE FROM study_axes WHERE study_id = %lld; "
             "DELETE FROM job_params WHERE job_id IN (SELECT id FROM jobs WHERE study_id = %lld); "
             "DELETE FROM job_deps WHERE job_id IN (SELECT id FROM jobs WHERE study_id = %lld); "
             "UPDATE jobs SET active = 0 WHERE study_id = %lld",
             *study_id, *study_id, *study_id, *study_id);
    if ((rc = db_exec(db, sql, e)))
        return rc;
    sqlite3_stmt *ax;
    if ((rc = db_prepare(db,
                         "INSERT INTO study_axes (study_id, name, position, grp, kind, nvalues, "
                         "vals) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                         &ax, e)))
        return rc;
    for (int i = 0; i < s->naxes && !rc; i++) {
        sqlite3_reset(ax);
        char *vals = canon_json(s->axes[i].values);   /* reals as written: 7.22 */
        if (!vals) {
            rc = err_nomem(e, "the axis values");
            break;
        }
        sqlite3_bind_int64(ax, 1, *study_id);
        bind_text(ax, 2, s->axes[i].path);
        sqlite3_bind_int(ax, 3, i);
        sqlite3_bind_int(ax, 4, s->axes[i].group);
        bind_text(ax, 5, axis_kind_name(s->axes[i].kind));
        sqlite3_bind_int64(ax, 6, (sqlite3_int64)json_array_size(s->axes[i].values));
        sqlite3_bind_text(ax, 7, vals, -1, SQLITE_TRANSIENT);
        free(vals);
        rc = step_done(db, ax, e, "registering the axes");
    }
    sqlite3_finalize(ax);
    return rc;
}

int store_register(struct store *st, const struct study *s, const struct plan *p,
                   long long *study_id, long long *job_ids, struct err *e)
{
    sqlite3 *db = st->db;
    int rc = begin_own(st, e);
    if (rc)
        return rc;
    rc = register_study(st, s, study_id, e);
    sqlite3_stmt *job = NULL, *par = NULL, *dep = NULL;
    if (!rc)
        rc = db_prepare(db,
                        "INSERT INTO jobs (study_id, key, kind, name, seq, params, case_json) "
                        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7) ON CONFLICT (study_id, key) DO UPDATE "
                        "SET kind = excluded.kind, name = excluded.name, seq = excluded.seq, "
                        "params = excluded.params, case_json = excluded.case_json, active = 1 "
                        "RETURNING id",
                        &job, e);
    if (!rc)
        rc = db_prepare(db, "INSERT INTO job_params (job_id, name, value) VALUES (?1, ?2, ?3)",
                        &par, e);
    if (!rc)
        rc = db_prepare(db, "INSERT OR IGNORE INTO job_deps (job_id, needs_id) VALUES (?1, ?2)",
                        &dep, e);
    long idx[64];
    for (long j = 0; j < p->njobs && !rc; j++) {
        const struct plan_job *pj = &p->jobs[j];
        sqlite3_reset(job);
        sqlite3_bind_int64(job, 1, *study_id);
        bind_text(job, 2, pj->key);
        bind_text(job, 3, pj->prep >= 0 ? "prep" : "sweep");
        if (pj->prep >= 0)
            bind_text(job, 4, s->preps[pj->prep].name);
        else
            sqlite3_bind_null(job, 4);
        sqlite3_bind_int64(job, 5, j);
        bind_text(job, 6, pj->params_json);
        bind_text(job, 7, pj->case_json);
        if (sqlite3_step(job) != SQLITE_ROW) {
            rc = db_fail(db, e, "registering a job");
            break;
        }
        job_ids[j] = sqlite3_column_int64(job, 0);
        sqlite3_reset(job);
        if (pj->sweep >= 0) {
            study_job_indices(s, pj->sweep, idx);
            for (int a = 0; a < s->naxes && !rc; a++) {
                sqlite3_reset(par);
                sqlite3_bind_int64(par, 1, job_ids[j]);
                bind_text(par, 2, s->axes[a].path);
                db_bind_json_value(par, 3,
                                   json_array_get(s->axes[a].values, (size_t)idx[s->axes[a].group]));
                rc = step_done(db, par, e, "registering parameters");
            }
        }
        for (int d = 0; d < pj->ndeps && !rc; d++) {
            sqlite3_reset(dep);
            sqlite3_bind_int64(dep, 1, job_ids[j]);
            sqlite3_bind_int64(dep, 2, job_ids[pj->deps[d]]);
            rc = step_done(db, dep, e, "registering dependencies");
        }
    }
    sqlite3_finalize(job);
    sqlite3_finalize(par);
    sqlite3_finalize(dep);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

/* --- verdicts, leases ------------------------------------------------------- */

static int job_done(struct store *st, long long job_id, long long retry_after, int *done,
                    struct err *e)
{
    sqlite3_stmt *s = q(st, Q_DONE);
    sqlite3_bind_int64(s, 1, job_id);
    bind_text(s, 2, st->solver_version);
    bind_text(s, 3, st->solver_git);
    sqlite3_bind_int64(s, 4, retry_after);
    int r = sqlite3_step(s);
    if (r != SQLITE_ROW && r != SQLITE_DONE)
        return db_fail(st->db, e, "checking done runs");
    *done = r == SQLITE_ROW;
    sqlite3_reset(s);
    return 0;
}

static int job_retry_after(struct store *st, long long job_id, long long *ra, struct err *e)
{
    sqlite3_stmt *s = q(st, Q_RETRY_AFTER);
    sqlite3_bind_int64(s, 1, job_id);
    if (sqlite3_step(s) != SQLITE_ROW) {
        sqlite3_reset(s);
        return db_err(st->db, e, ERR_RUNTIME, "no job %lld", job_id);
    }
    *ra = sqlite3_column_int64(s, 0);
    sqlite3_reset(s);
    return 0;
}

/* DONE, EXHAUSTED or OK (may run) for one job, ignoring leases and deps. */
static int own_verdict(struct store *st, long long job_id, enum claim_result *res, struct err *e)
{
    long long ra = 0;
    int done = 0, rc = job_retry_after(st, job_id, &ra, e);
    if (!rc)
        rc = job_done(st, job_id, ra, &done, e);
    if (rc)
        return rc;
    if (done) {
        *res = CLAIM_DONE;
        return 0;
    }
    sqlite3_stmt *s = q(st, Q_FAILS);
    sqlite3_bind_int64(s, 1, job_id);
    bind_text(s, 2, st->solver_version);
    bind_text(s, 3, st->solver_git);
    sqlite3_bind_int64(s, 4, ra);
    if (sqlite3_step(s) != SQLITE_ROW) {
        sqlite3_reset(s);
        return db_fail(st->db, e, "counting failed runs");
    }
    long fails = (long)sqlite3_column_int64(s, 0), diverged = (long)sqlite3_column_int64(s, 1);
    sqlite3_reset(s);
    *res = (diverged > 0 || fails > st->retries) ? CLAIM_EXHAUSTED : CLAIM_OK;
    return 0;
}

static int deps_verdict(struct store *st, long long job_id, enum claim_result *res, struct err *e)
{
    *res = CLAIM_OK;
    long long deps[256];
    int n = 0;
    sqlite3_stmt *s = q(st, Q_DEPS);
    sqlite3_bind_int64(s, 1, job_id);
    while (sqlite3_step(s) == SQLITE_ROW && n < 256)
        deps[n++] = sqlite3_column_int64(s, 0);
    sqlite3_reset(s);
    for (int i = 0; i < n; i++) {
        enum claim_result d;
        int rc = own_verdict(st, deps[i], &d, e);
        if (rc)
            return rc;
        if (d == CLAIM_EXHAUSTED) {
            *res = CLAIM_BLOCKED;
            return 0;
        }
        if (d != CLAIM_DONE)
            *res = CLAIM_WAIT;
    }
    return 0;
}

int store_job_verdict(struct store *st, long long job_id, enum claim_result *res, struct err *e)
{
    int rc = own_verdict(st, job_id, res, e);
    if (!rc && *res == CLAIM_OK)
        rc = deps_verdict(st, job_id, res, e);
    return rc;
}

/* A run whose runner is gone or lost its lease: not the job's fault. */
static int cancel_run(sqlite3 *db, long long run_id, const char *why, struct err *e)
{
    sqlite3_stmt *s;
    int rc = db_prepare(db,
                        "UPDATE runs SET status = 'cancelled', message = ?2, finished = ?3, "
                        "failure_class = 'infrastructure' WHERE id = ?1 AND status = 'running'",
                        &s, e);
    if (rc)
        return rc;
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    sqlite3_bind_int64(s, 1, run_id);
    sqlite3_bind_text(s, 2, why, -1, SQLITE_STATIC);
    sqlite3_bind_text(s, 3, now, -1, SQLITE_STATIC);
    rc = step_done(db, s, e, "cancelling a lost run");
    sqlite3_finalize(s);
    return rc;
}

/* Whether a lease is stale; fills why. */
static int lease_stale(const char *runner, double expires, char *why, size_t len)
{
    int alive = sys_runner_alive(runner);
    if (alive == 0) {
        snprintf(why, len, "runner %s is gone (killed?); the job will run again", runner);
        return 1;
    }
    if (expires < sys_now()) {
        snprintf(why, len, "the lease of runner %s expired; the job will run again", runner);
        return 1;
    }
    return 0;
}

static int drop_lease(sqlite3 *db, long long job_id, struct err *e)
{
    char sql[96];
    snprintf(sql, sizeof sql, "DELETE FROM leases WHERE job_id = %lld", job_id);
    return db_exec(db, sql, e);
}

/* The claim itself, in an open transaction; the caller commits or undoes
 * it (claim_end). */
static int claim_body(struct store *st, long long job_id, const char *job_dir,
                      enum claim_result *res, long long *run_id, int *attempt, char *run_dir,
                      size_t run_dir_len, struct err *e)
{
    sqlite3 *db = st->db;
    int rc;
    /* a lease: live (someone else runs it) or stale (reap it here) */
    sqlite3_stmt *s = q(st, Q_LEASE_GET);
    sqlite3_bind_int64(s, 1, job_id);
    if (sqlite3_step(s) == SQLITE_ROW) {
        char runner[320], why[512];
        snprintf(runner, sizeof runner, "%s", (const char *)sqlite3_column_text(s, 0));
        double expires = sqlite3_column_double(s, 1);
        long long old_run = sqlite3_column_int64(s, 2);
        int in_slurm = sqlite3_column_int(s, 3);
        sqlite3_reset(s);
        /* an attempt in Slurm outlives its runner: the next Slurm runner of
         * the study adopts it (store_adopt); running it again here would run
         * the job twice */
        if (in_slurm || !lease_stale(runner, expires, why, sizeof why)) {
            *res = CLAIM_LEASED;   /* nothing written */
            return 0;
        }
        if ((rc = cancel_run(db, old_run, why, e)) || (rc = drop_lease(db, job_id, e)))
            return rc;
    }
    sqlite3_reset(s);
    rc = store_job_verdict(st, job_id, res, e);
    if (rc || *res != CLAIM_OK)
        return rc;   /* committed all the same: keeps a reaped lease reaped */
    s = q(st, Q_NEXT_ATTEMPT);
    sqlite3_bind_int64(s, 1, job_id);
    /* an I/O error here would read as attempt 0: a run row and a
     * directory no attempt numbering has */
    if (sqlite3_step(s) != SQLITE_ROW) {
        rc = db_fail(db, e, "numbering the next attempt");
        sqlite3_reset(s);
        return rc;
    }
    *attempt = sqlite3_column_int(s, 0);
    sqlite3_reset(s);
    launch_attempt_dir(job_dir, *attempt, run_dir, run_dir_len);
    char now[40];
    double t = sys_now();
    sys_iso_time(t, now, sizeof now);
    s = q(st, Q_RUN_INSERT);
    sqlite3_bind_int64(s, 1, job_id);
    sqlite3_bind_int(s, 2, *attempt);
    bind_text(s, 3, now);
    bind_text(s, 4, st->host);
    bind_text(s, 5, st->runner);
    bind_text(s, 6, st->launcher);
    bind_text(s, 7, st->solver_version);
    bind_text(s, 8, st->solver_git);
    bind_text(s, 9, run_dir);
    if (sqlite3_step(s) != SQLITE_DONE) {
        rc = db_fail(db, e, "recording a new run");
        sqlite3_reset(s);
        return rc;
    }
    sqlite3_reset(s);
    *run_id = sqlite3_last_insert_rowid(db);
    s = q(st, Q_LEASE_INSERT);
    sqlite3_bind_int64(s, 1, job_id);
    sqlite3_bind_int64(s, 2, *run_id);
    bind_text(s, 3, st->runner);
    bind_text(s, 4, st->host);
    sqlite3_bind_int(s, 5, st->pid);
    sqlite3_bind_double(s, 6, t + st->lease_s);
    if (sqlite3_step(s) != SQLITE_DONE) {
        rc = db_fail(db, e, "taking the lease");
        sqlite3_reset(s);
        return rc;
    }
    sqlite3_reset(s);
    return 0;
}

/* Commit a claim's transaction, or undo it when rc says the claim failed.
 * Nested in a pending outcome's transaction (a savepoint), a failed claim
 * undoes only itself and the outcome is committed alone. */
static int claim_end(struct store *st, int nested, int rc, struct err *e)
{
    sqlite3 *db = st->db;
    if (!nested) {
        if (!rc)
            rc = db_commit(db, e);
        if (rc)
            db_rollback(db);
        return rc;
    }
    if (!rc)
        rc = db_exec(db, "RELEASE claim", e);
    if (rc) {
        /* an I/O error may have rolled back the whole transaction already:
         * store_flush then finds none and says the outcome is lost */
        if (!sqlite3_get_autocommit(db))
            sqlite3_exec(db, "ROLLBACK TO claim; RELEASE claim", NULL, NULL, NULL);
        struct err fe = {0};
        store_flush(st, &fe);
        return rc;
    }
    return store_flush(st, e);
}

int store_claim(struct store *st, long long job_id, const char *job_dir, enum claim_result *res,
                long long *run_id, int *attempt, char *run_dir, size_t run_dir_len,
                struct err *e)
{
    /* a failed statement in between (a heartbeat's I/O error) may have
     * rolled the pending outcome's transaction back: a savepoint would then
     * open a transaction of its own, and the claim commit without it */
    if (st->pending && sqlite3_get_autocommit(st->db))
        return store_flush(st, e);   /* fails: pending_lost */
    int nested = st->pending;
    int rc = nested ? db_exec(st->db, "SAVEPOINT claim", e) : db_begin(st->db, e);
    if (rc) {
        struct err fe = {0};
        store_flush(st, &fe);
        return rc;
    }
    rc = claim_body(st, job_id, job_dir, res, run_id, attempt, run_dir, run_dir_len, e);
    return claim_end(st, nested, rc, e);
}

/* --- recording -------------------------------------------------------------- */

static int wanted(const struct store *st, const char *name)
{
    if (!st->metrics)
        return 1;
    for (int i = 0; i < st->nmetrics; i++)
        if (strcmp(st->metrics[i], name) == 0)
            return 1;
    return 0;
}

/* A crash the same as an earlier one of the job (same signal; same step
 * when both are known) is deterministic: o is reclassified, its message
 * says which attempt it repeats. */
static int check_repeat_crash(struct store *st, long long job_id, long long run_id,
                              struct outcome *o, struct err *e)
{
    if (o->status != RS_CRASHED || !o->signal)
        return 0;
    sqlite3_stmt *s = q(st, Q_SAME_CRASH);
    sqlite3_bind_int64(s, 1, job_id);
    sqlite3_bind_int64(s, 2, run_id);
    sqlite3_bind_int(s, 3, o->signal);
    bind_text(s, 4, o->solver_version[0] ? o->solver_version : st->solver_version);
    bind_text(s, 5, o->solver_git[0] ? o->solver_git : st->solver_git);
    int r;
    while ((r = sqlite3_step(s)) == SQLITE_ROW) {
        int attempt = sqlite3_column_int(s, 0);
        int known = sqlite3_column_type(s, 1) != SQLITE_NULL && o->last_step >= 0;
        if (known && sqlite3_column_int64(s, 1) != o->last_step)
            continue;
        o->failure = FC_DETERMINISTIC;
        size_t used = strlen(o->message);
        if (known)
            snprintf(o->message + used, sizeof o->message - used,
                     "; deterministic: the same signal at step %ld as attempt %d, not retried "
                     "again",
                     o->last_step, attempt);
        else
            snprintf(o->message + used, sizeof o->message - used,
                     "; deterministic: the same signal as attempt %d (step unknown), not retried "
                     "again",
                     attempt);
        break;
    }
    sqlite3_reset(s);
    if (r != SQLITE_ROW && r != SQLITE_DONE)
        return db_fail(st->db, e, "looking for earlier crashes");
    return 0;
}

/* The study's `series:` from result.json's {name: {"values": [...], "unit": u}}:
 * one row per value (a missing series is no error: not every case writes
 * every series). */
static int record_series(struct store *st, long long run_id, json_t *series, struct err *e)
{
    sqlite3_stmt *s = q(st, Q_SERIES_INSERT);
    int rc = 0;
    for (int k = 0; k < st->nseries && !rc; k++) {
        json_t *ser = json_object_get(series, st->series[k]);
        json_t *vals = json_object_get(ser, "values");
        const char *unit = json_string_value(json_object_get(ser, "unit"));
        size_t i;
        json_t *v;
        json_array_foreach(vals, i, v)
        {
            sqlite3_reset(s);
            sqlite3_bind_int64(s, 1, run_id);
            bind_text(s, 2, st->series[k]);
            sqlite3_bind_int64(s, 3, (sqlite3_int64)i);
            double x = json_number_value(v);
            if (json_is_number(v) && isfinite(x))
                sqlite3_bind_double(s, 4, x);
            else
                sqlite3_bind_null(s, 4);
            bind_text(s, 5, unit ? unit : "");
            if (sqlite3_step(s) != SQLITE_DONE) {
                rc = db_fail(st->db, e, "recording a series");
                break;
            }
        }
    }
    sqlite3_reset(s);
    return rc;
}

int store_finish(struct store *st, long long job_id, long long run_id, const char *run_dir,
                 struct outcome *o, int *lost, int defer, struct err *e)
{
    sqlite3 *db = st->db;
    *lost = 0;
    st->last_metric_rows = 0;
    st->note[0] = '\0';
    int rc = begin_own(st, e);
    if (rc)
        return rc;
    sqlite3_stmt *s = q(st, Q_LEASE_GET);
    sqlite3_bind_int64(s, 1, job_id);
    int step = sqlite3_step(s);
    if (step != SQLITE_ROW && step != SQLITE_DONE) {
        /* the lease could not be read (out of memory, I/O): that is no
         * sign that another runner took the job -- taking it for one left
         * the run 'running' under a lease this runner kept renewing, and
         * the runner waited for it for ever */
        rc = db_fail(db, e, "checking the lease");
        sqlite3_reset(s);
        db_rollback(db);
        return rc;
    }
    int ours = step == SQLITE_ROW &&
               strcmp((const char *)sqlite3_column_text(s, 0), st->runner) == 0 &&
               sqlite3_column_int64(s, 2) == run_id;
    sqlite3_reset(s);
    if (!ours) {
        *lost = 1;
        db_rollback(db);
        return 0;
    }
    /* a requested metric the solver did not write is worth a message */
    char missing[OUTCOME_MSG_MAX] = "";
    if (o->status == RS_DONE && st->metrics)
        for (int i = 0; i < st->nmetrics; i++)
            if (!json_object_get(o->metrics, st->metrics[i])) {
                size_t used = strlen(missing);
                snprintf(missing + used, sizeof missing - used, "%s%s",
                         used ? ", " : "result.json lacks the study's metrics: ", st->metrics[i]);
            }
    if ((rc = check_repeat_crash(st, job_id, run_id, o, e)) != 0) {
        db_rollback(db);
        return rc;
    }
    char t0[40], t1[40];
    sys_iso_time(o->started, t0, sizeof t0);
    sys_iso_time(o->finished, t1, sizeof t1);
    s = q(st, Q_RUN_UPDATE);
    sqlite3_bind_int64(s, 1, run_id);
    bind_text(s, 2, run_status_name(o->status));
    if (o->exit_code >= 0)
        sqlite3_bind_int(s, 3, o->exit_code);
    if (o->signal)
        sqlite3_bind_int(s, 4, o->signal);
    if (o->message[0] || missing[0])
        bind_text(s, 5, o->message[0] ? o->message : missing);
    bind_text(s, 6, t0);
    bind_text(s, 7, t1);
    sqlite3_bind_double(s, 8, o->wall_s);
    sqlite3_bind_double(s, 9, o->peak_rss_mib);
    bind_text(s, 10, o->host);
    sqlite3_bind_int(s, 11, o->pid);
    if (o->stderr_tail[0])
        bind_text(s, 12, o->stderr_tail);
    bind_text(s, 13, o->solver_version[0] ? o->solver_version : st->solver_version);
    bind_text(s, 14, o->solver_git[0] ? o->solver_git : st->solver_git);
    if (failure_class_name(o->failure))
        bind_text(s, 15, failure_class_name(o->failure));
    if (o->last_step >= 0)
        sqlite3_bind_int64(s, 16, o->last_step);
    if (o->resumed_from_step >= 0)
        sqlite3_bind_int64(s, 17, o->resumed_from_step);
    if (o->slurm_state[0])
        bind_text(s, 18, o->slurm_state);
    if (sqlite3_step(s) != SQLITE_DONE)
        rc = db_fail(db, e, "recording the run");
    sqlite3_reset(s);
    const char *name;
    json_t *m;
    if (!rc && json_is_object(o->metrics)) {
        s = q(st, Q_METRIC_INSERT);
        json_object_foreach(o->metrics, name, m)
        {
            if (!wanted(st, name))
                continue;
            json_t *v = json_object_get(m, "value");
            const char *unit = json_string_value(json_object_get(m, "unit"));
            sqlite3_reset(s);
            sqlite3_bind_int64(s, 1, run_id);
            bind_text(s, 2, name);
            double x = json_number_value(v);
            if (json_is_number(v) && isfinite(x))
                sqlite3_bind_double(s, 3, x);
            else
                sqlite3_bind_null(s, 3);
            bind_text(s, 4, unit ? unit : "");
            if (sqlite3_step(s) != SQLITE_DONE) {
                rc = db_fail(db, e, "recording a metric");
                break;
            }
            st->last_metric_rows++;
        }
        sqlite3_reset(s);
    }
    if (!rc && json_is_object(o->series))
        rc = record_series(st, run_id, o->series, e);
    if (!rc) {
        s = q(st, Q_ARTIFACT_INSERT);
        for (int i = 0; i < o->nartifacts && !rc; i++) {
            const struct artifact *a = &o->artifacts[i];
            sqlite3_reset(s);
            sqlite3_bind_int64(s, 1, run_id);
            bind_text(s, 2, a->path);
            bind_text(s, 3, a->kind);
            sqlite3_bind_int64(s, 4, a->bytes);
            bind_text(s, 5, a->sha256);
            if (sqlite3_step(s) != SQLITE_DONE)
                rc = db_fail(db, e, "recording an artifact");
        }
        sqlite3_reset(s);
    }
    if (!rc) {
        s = q(st, Q_LEASE_DELETE);
        sqlite3_bind_int64(s, 1, job_id);
        sqlite3_bind_int64(s, 2, run_id);
        if (sqlite3_step(s) != SQLITE_DONE)
            rc = db_fail(db, e, "releasing the lease");
        sqlite3_reset(s);
    }
    /* The link is a convenience (runs.run_dir is the record): a failure to
     * write it does not lose the outcome.  Written while this transaction
     * holds the write lock, so no later attempt can be recorded before it. */
    struct err le = {0};
    if (!rc && run_dir && launch_point_current(run_dir, &le) != 0)
        snprintf(st->note, sizeof st->note, "%s", le.msg);
    if (!rc && defer) {
        st->pending = 1;
        return 0;
    }
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

int store_heartbeat(struct store *st, struct err *e)
{
    sqlite3_stmt *s = q(st, Q_HEARTBEAT);
    bind_text(s, 1, st->runner);
    sqlite3_bind_double(s, 2, sys_now() + st->lease_s);
    int rc = sqlite3_step(s) == SQLITE_DONE ? 0 : db_fail(st->db, e, "heartbeat");
    sqlite3_reset(s);
    return rc;
}

/* The statements of store_unclaim, in order: the lease (which must be
 * ours), the run that never started, and the job's state back to what its
 * latest remaining attempt says ('pending' when it has none; the
 * job_counts triggers follow). */
static const char *const unclaim_sql[] = {
    "DELETE FROM leases WHERE job_id = ?1 AND run_id = ?2 AND runner = ?3",
    "DELETE FROM runs WHERE id = ?2 AND job_id = ?1 AND status = 'running'",
    "UPDATE jobs SET state = 'pending', last_run_id = NULL, solver = NULL WHERE id = ?1",
    "UPDATE jobs SET (state, last_run_id, solver) = "
    "(SELECT status, id, solver_version || ' (' || solver_git || ')' FROM runs "
    "WHERE job_id = ?1 ORDER BY id DESC LIMIT 1) "
    "WHERE id = ?1 AND EXISTS (SELECT 1 FROM runs WHERE job_id = ?1)",
};

int store_unclaim(struct store *st, long long job_id, long long run_id, struct err *e)
{
    int rc = begin_own(st, e);
    for (size_t i = 0; !rc && i < sizeof unclaim_sql / sizeof unclaim_sql[0]; i++) {
        sqlite3_stmt *s = NULL;
        rc = db_prepare(st->db, unclaim_sql[i], &s, e);
        if (rc)
            break;
        sqlite3_bind_int64(s, 1, job_id);
        if (sqlite3_bind_parameter_count(s) >= 2)
            sqlite3_bind_int64(s, 2, run_id);
        if (sqlite3_bind_parameter_count(s) >= 3)
            bind_text(s, 3, st->runner);
        rc = step_done(st->db, s, e, "undoing a claim");
        /* no lease of ours: the job is another runner's now, leave it */
        int ours = i > 0 || sqlite3_changes(st->db) == 1;
        sqlite3_finalize(s);
        if (!rc && !ours)
            break;
    }
    if (!rc)
        rc = db_commit(st->db, e);
    if (rc)
        db_rollback(st->db);
    return rc;
}

int store_lease_held(struct store *st, long long job_id, long long run_id, int *held,
                     struct err *e)
{
    sqlite3_stmt *s = q(st, Q_LEASE_GET);
    sqlite3_bind_int64(s, 1, job_id);
    int r = sqlite3_step(s);
    if (r != SQLITE_ROW && r != SQLITE_DONE) {
        sqlite3_reset(s);
        return db_fail(st->db, e, "looking at a lease");
    }
    *held = r == SQLITE_ROW && strcmp((const char *)sqlite3_column_text(s, 0), st->runner) == 0 &&
            sqlite3_column_int64(s, 2) == run_id;
    sqlite3_reset(s);
    return 0;
}

int store_done_dir(struct store *st, long long job_id, char *dir, size_t len, struct err *e)
{
    sqlite3_stmt *s = q(st, Q_DONE_DIR);
    sqlite3_bind_int64(s, 1, job_id);
    bind_text(s, 2, st->solver_version);
    bind_text(s, 3, st->solver_git);
    int r = sqlite3_step(s);
    if (r == SQLITE_ROW)
        snprintf(dir, len, "%s", (const char *)sqlite3_column_text(s, 0));
    sqlite3_reset(s);
    if (r == SQLITE_ROW)
        return 0;
    if (r != SQLITE_DONE)
        return db_fail(st->db, e, "looking up a preparation job's run directory");
    return db_err(st->db, e, ERR_RUNTIME, "the preparation job has no done run for this solver "
                                          "(retried meanwhile?)");
}

int store_reap(struct store *st, int *n, struct err *e)
{
    sqlite3 *db = st->db;
    *n = 0;
    int rc = begin_own(st, e);
    if (rc)
        return rc;
    sqlite3_stmt *s;
    /* attempts in Slurm are adopted, not reaped (store_adopt) */
    if ((rc = db_prepare(db,
                         "SELECT l.job_id, l.run_id, l.runner, l.expires FROM leases l "
                         "JOIN runs r ON r.id = l.run_id WHERE r.slurm_job_id IS NULL",
                         &s, e))) {
        db_rollback(db);
        return rc;
    }
    long long (*stale)[2] = NULL;
    char (*why)[512] = NULL;
    int cap = 0;
    while (sqlite3_step(s) == SQLITE_ROW) {
        char w[512];
        if (!lease_stale((const char *)sqlite3_column_text(s, 2), sqlite3_column_double(s, 3), w,
                         sizeof w))
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 16;
            void *g1 = mem_realloc(stale, (size_t)cap * sizeof *stale);
            if (g1)
                stale = g1;
            void *g2 = mem_realloc(why, (size_t)cap * sizeof *why);
            if (g2)
                why = g2;
            if (!g1 || !g2)
                break;
        }
        stale[*n][0] = sqlite3_column_int64(s, 0);
        stale[*n][1] = sqlite3_column_int64(s, 1);
        snprintf(why[*n], sizeof why[*n], "%s", w);
        (*n)++;
    }
    sqlite3_finalize(s);
    for (int i = 0; i < *n && !rc; i++) {
        rc = cancel_run(db, stale[i][1], why[i], e);
        if (!rc)
            rc = drop_lease(db, stale[i][0], e);
    }
    free(stale);
    free(why);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

/* --- Slurm attempts ----------------------------------------------------------- */

int store_record_slurm_ids(struct store *st, int n, const long long *run_ids,
                           const char *const *slurm_ids, const char *state, struct err *e)
{
    sqlite3 *db = st->db;
    int rc = begin_own(st, e);
    if (rc)
        return rc;
    sqlite3_stmt *s;
    if ((rc = db_prepare(db,
                         "UPDATE runs SET slurm_job_id = ?2, slurm_state = ?3 "
                         "WHERE id = ?1 AND status = 'running'",
                         &s, e))) {
        db_rollback(db);
        return rc;
    }
    for (int i = 0; i < n && !rc; i++) {
        sqlite3_reset(s);
        sqlite3_bind_int64(s, 1, run_ids[i]);
        bind_text(s, 2, slurm_ids[i]);
        bind_text(s, 3, state);
        rc = step_done(db, s, e, "recording Slurm job ids");
    }
    sqlite3_finalize(s);
    if (!rc)
        rc = db_commit(db, e);
    if (rc)
        db_rollback(db);
    return rc;
}

int store_adopt(struct store *st, long long study_id, struct store_adopted **out, int *n,
                struct err *e)
{
    sqlite3 *db = st->db;
    *out = NULL;
    *n = 0;
    int rc = begin_own(st, e);
    if (rc)
        return rc;
    sqlite3_stmt *s, *take;
    if ((rc = db_prepare(db,
                         "SELECT r.job_id, r.id, r.attempt, r.run_dir, r.slurm_job_id, l.runner, "
                         "l.expires FROM runs r JOIN jobs j ON j.id = r.job_id "
                         "LEFT JOIN leases l ON l.job_id = r.job_id "
                         "WHERE j.study_id = ?1 AND j.active = 1 AND r.status = 'running' "
                         "AND r.slurm_job_id IS NOT NULL ORDER BY r.job_id",
                         &s, e))) {
        db_rollback(db);
        return rc;
    }
    if ((rc = db_prepare(db,
                         "INSERT OR REPLACE INTO leases (job_id, run_id, runner, host, pid, "
                         "expires) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                         &take, e))) {
        sqlite3_finalize(s);
        db_rollback(db);
        return rc;
    }
    sqlite3_bind_int64(s, 1, study_id);
    int cap = 0, r;
    while (!rc && (r = sqlite3_step(s)) == SQLITE_ROW) {
        const char *runner = (const char *)sqlite3_column_text(s, 5);
        char why[512];
        /* a live runner (another process) follows it: leave it alone */
        if (runner && strcmp(runner, st->runner) != 0 &&
            !lease_stale(runner, sqlite3_column_double(s, 6), why, sizeof why))
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 64;
            struct store_adopted *g = realloc(*out, (size_t)cap * sizeof *g);
            if (!g) {
                rc = err_nomem(e, "adopted jobs");
                break;
            }
            *out = g;
        }
        struct store_adopted *a = &(*out)[*n];
        a->job_id = sqlite3_column_int64(s, 0);
        a->run_id = sqlite3_column_int64(s, 1);
        a->attempt = sqlite3_column_int(s, 2);
        snprintf(a->run_dir, sizeof a->run_dir, "%s", (const char *)sqlite3_column_text(s, 3));
        snprintf(a->slurm_id, sizeof a->slurm_id, "%s", (const char *)sqlite3_column_text(s, 4));
        sqlite3_reset(take);
        sqlite3_bind_int64(take, 1, a->job_id);
        sqlite3_bind_int64(take, 2, a->run_id);
        bind_text(take, 3, st->runner);
        bind_text(take, 4, st->host);
        sqlite3_bind_int(take, 5, st->pid);
        sqlite3_bind_double(take, 6, sys_now() + st->lease_s);
        rc = step_done(db, take, e, "taking over the lease of a Slurm job");
        (*n)++;
    }
    sqlite3_finalize(s);
    sqlite3_finalize(take);
    if (!rc)
        rc = db_commit(db, e);
    if (rc) {
        db_rollback(db);
        free(*out);
        *out = NULL;
        *n = 0;
    }
    return rc;
}

int store_slurm_orphans(struct store *st, long long study_id, int *n, struct err *e)
{
    *n = 0;
    sqlite3_stmt *s;
    int rc = db_prepare(st->db,
                        "SELECT l.runner, l.expires FROM runs r JOIN jobs j ON j.id = r.job_id "
                        "LEFT JOIN leases l ON l.run_id = r.id WHERE j.study_id = ?1 "
                        "AND r.status = 'running' AND r.slurm_job_id IS NOT NULL",
                        &s, e);
    if (rc)
        return rc;
    sqlite3_bind_int64(s, 1, study_id);
    while (sqlite3_step(s) == SQLITE_ROW) {
        const char *runner = (const char *)sqlite3_column_text(s, 0);
        char why[512];
        if (!runner || lease_stale(runner, sqlite3_column_double(s, 1), why, sizeof why))
            (*n)++;
    }
    sqlite3_finalize(s);
    return 0;
}
