/*
 * Database fault injection (campaign/db_fault.h), in the spirit of SQLite's
 * own I/O-error and malloc tests: `cascade run` of a small stand-in study
 * first counts the SQLite writes/syncs (or allocations) it makes, then runs
 * again, from scratch, once for each of a range of N with the Nth call
 * failing.  Each time the runner either stops with exit 1 and a message
 * naming the database, or (the fault fell where SQLite or Cascade recovers,
 * or past the run's last call) completes the study; it never crashes (no
 * signal, no sanitizer report).  The database it leaves is consistent
 * (integrity_check, foreign keys, a done run has its metrics and files, a
 * 'running' run has its lease), the summary's done count is the number of
 * jobs the database holds as done, and a second `cascade run` without the
 * fault completes the study with each job done exactly once and no lease
 * left.
 *
 * Faults during opening and migrating a new database, during registering
 * and running on a database migrated before (where the runner's own
 * transactions are), transient (one call) and persistent (every call from
 * the Nth on: a disk that stays full).
 */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "helpers/ct.h"

#define NJOBS 4
static const char *study_text = "name: s\n"
                                "base: {fake: {action: ok}}\n"
                                "sweep: {grid: {fake.x: [1, 2, 3, 4]}}\n";

static int run(const char *dir, const char *fault, char *out, size_t len)
{
    const char *env[] = {fault, NULL};
    return ct_cascade(dir, fault ? env : NULL, out, len, "run", "s.yaml", "--solver",
                      ct_standin(), "--jobs", "2", NULL);
}

/* A database created and migrated by a run of another study (the template
 * of the runs on an existing database), into dir/cascade.db. */
static void make_template(const char *dir)
{
    char out[8192];
    ct_write(0, dir, "w.yaml", "name: warm\nbase: {fake: {action: ok}}\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "w.yaml", "--solver", ct_standin(),
                        "--quiet", NULL);
    cr_assert_eq(rc, 0, "%s", out);
}

static void copy_file(const char *from, const char *to)
{
    FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
    cr_assert(a && b, "copying %s to %s", from, to);
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, a)) > 0)
        cr_assert_eq(fwrite(buf, 1, n, b), n);
    fclose(a);
    fclose(b);
}

/* A fresh directory with the study (and a copy of the template database). */
static void setup(char *dir, size_t len, const char *template_dir)
{
    ct_mkdir(dir, len);
    ct_write(1, dir, "s.yaml", study_text);
    if (template_dir) {
        char from[256], to[256];
        snprintf(from, sizeof from, "%s/cascade.db", template_dir);
        snprintf(to, sizeof to, "%s/cascade.db", dir);
        copy_file(from, to);
    }
}

/* The calls of one hook in a run, from its report line. */
static long counted(const char *out, const char *hook)
{
    char pat[64];
    snprintf(pat, sizeof pat, "fault injection: %s: ", hook);
    const char *p = strstr(out, pat);
    cr_assert(p, "no fault injection report in:\n%s", out);
    return strtol(p + strlen(pat), NULL, 10);
}

static void consistent(const char *dir, const char *what)
{
    sqlite3 *db = ct_db(dir);
    char ic[256];
    ct_text(db, "PRAGMA integrity_check", ic, sizeof ic);
    cr_assert_str_eq(ic, "ok", "%s: integrity_check: %s", what, ic);
    if (ct_int(db, "SELECT count(*) FROM sqlite_master WHERE name = 'runs'")) {
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM pragma_foreign_key_check"), 0,
                     "%s: foreign keys", what);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs r WHERE status = 'done' AND "
                                "(NOT EXISTS (SELECT 1 FROM metrics WHERE run_id = r.id) OR "
                                "NOT EXISTS (SELECT 1 FROM artifacts WHERE run_id = r.id))"),
                     0, "%s: a done run without its metrics or files", what);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs r WHERE status = 'running' AND "
                                "NOT EXISTS (SELECT 1 FROM leases WHERE run_id = r.id)"),
                     0, "%s: a running run without a lease", what);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases l WHERE NOT EXISTS (SELECT 1 FROM "
                                "runs WHERE id = l.run_id AND status = 'running')"),
                     0, "%s: a lease on a run that is not running", what);
    }
    sqlite3_close(db);
}

static void complete(const char *dir, const char *what)
{
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs j JOIN studies s ON s.id = j.study_id "
                            "WHERE s.name = 's' AND (SELECT count(*) FROM runs WHERE job_id = "
                            "j.id AND status = 'done') = 1"),
                 NJOBS, "%s: not every job done exactly once", what);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0, "%s: a lease left", what);
    sqlite3_close(db);
}

struct tally {
    long tried, errors, completed;
};

/* One run with the fault `var`=`spec`, then the checks and a second run. */
static void one(const char *var, const char *spec, const char *template_dir, struct tally *t)
{
    char dir[64], fault[64], what[128], out[32768], out2[32768];
    setup(dir, sizeof dir, template_dir);
    snprintf(fault, sizeof fault, "%s=%s", var, spec);
    snprintf(what, sizeof what, "%s (%s database, %s)", fault, template_dir ? "migrated" : "new",
             dir);
    int rc = run(dir, fault, out, sizeof out);
    cr_assert(rc == 0 || rc == 1, "%s: exit %d:\n%s", what, rc, out);
    cr_assert_null(strstr(out, "Sanitizer"), "%s:\n%s", what, out);
    cr_assert_null(strstr(out, "runtime error"), "%s:\n%s", what, out);
    t->tried++;
    if (rc == 1) {
        t->errors++;
        const char *msg = strstr(out, "error: ");
        cr_assert(msg, "%s: exit 1 without an error message:\n%s", what, out);
        cr_assert(strstr(msg, "cascade.db"), "%s: the message does not name the database:\n%s",
                  what, out);
    } else {
        t->completed++;
    }
    char path[128];
    snprintf(path, sizeof path, "%s/cascade.db", dir);
    if (access(path, F_OK) == 0)
        consistent(dir, what);
    /* the summary counts as done only outcomes the database holds (a done
     * job's outcome is committed with the next claim: when that commit
     * fails, the job is not done) */
    const char *sum = strstr(out, "study s: 4 jobs: ");
    if (sum && access(path, F_OK) == 0) {
        long said = strtol(sum + strlen("study s: 4 jobs: "), NULL, 10);
        sqlite3 *db = ct_db(dir);
        long held = ct_int(db, "SELECT count(*) FROM sqlite_master WHERE name = 'runs'")
                        ? ct_int(db, "SELECT count(DISTINCT r.job_id) FROM runs r JOIN jobs j ON "
                                     "j.id = r.job_id JOIN studies s ON s.id = j.study_id "
                                     "WHERE s.name = 's' AND r.status = 'done'")
                        : 0;
        sqlite3_close(db);
        cr_assert_eq(said, held, "%s: the summary says %ld done, the database holds %ld:\n%s",
                     what, said, held, out);
    }
    if (rc == 0)
        complete(dir, what);
    int rc2 = run(dir, NULL, out2, sizeof out2);
    cr_assert_eq(rc2, 0, "%s: the run after it failed:\n%s\nfirst run:\n%s", what, out2, out);
    consistent(dir, what);
    complete(dir, what);
    ct_rmrf(dir);
}

/* Count the calls of `hook` in an undisturbed run, then fail the Nth for
 * about `points` values of N from 1 to past the count (plus `persist`
 * persistent ones). */
static void sweep(const char *var, const char *hook, const char *template_dir, long points,
                  long persist)
{
    char dir[64], out[32768];
    char count_env[64];
    snprintf(count_env, sizeof count_env, "%s=0", var);
    setup(dir, sizeof dir, template_dir);
    cr_assert_eq(run(dir, count_env, out, sizeof out), 0, "%s", out);
    long total = counted(out, hook);
    ct_rmrf(dir);
    cr_assert_gt(total, 10, "%s: only %ld calls counted", var, total);
    long step = total / points > 1 ? total / points : 1;
    struct tally t = {0};
    char spec[32];
    for (long n = 1; n <= total + step; n += step) {
        snprintf(spec, sizeof spec, "%ld", n);
        one(var, spec, template_dir, &t);
    }
    for (long k = 0; k < persist; k++) {
        snprintf(spec, sizeof spec, "%ld+", 1 + k * total / persist);
        one(var, spec, template_dir, &t);
    }
    cr_assert_gt(t.errors, 0, "%s: no fault ever surfaced: the hook does nothing", var);
    cr_log_info("%s on a %s database: %ld calls counted, %ld runs with a fault (every %ld-th), "
                "%ld stopped with an error, %ld completed",
                var, template_dir ? "migrated" : "new", total, t.tried, step, t.errors,
                t.completed);
}

/* The timeout is a hang guard, not a speed check: a sweep takes 17-20 s
 * in the plain build on an idle machine and 8x that under
 * AddressSanitizer (about 150 s); a runner that hangs on a fault never
 * ends. */
#define SWEEP_TIMEOUT_S 600

Test(campaign_dbfaults, io_errors_on_a_new_database, .timeout = SWEEP_TIMEOUT_S)
{
    sweep("CASCADE_FAULT_IO", "io", NULL, 70, 4);
}

Test(campaign_dbfaults, io_errors_while_running, .timeout = SWEEP_TIMEOUT_S)
{
    char tmpl[64];
    ct_mkdir(tmpl, sizeof tmpl);
    make_template(tmpl);
    sweep("CASCADE_FAULT_IO", "io", tmpl, 70, 4);
    ct_rmrf(tmpl);
}

Test(campaign_dbfaults, malloc_failures_on_a_new_database, .timeout = SWEEP_TIMEOUT_S)
{
    sweep("CASCADE_FAULT_MALLOC", "malloc", NULL, 20, 2);
}

Test(campaign_dbfaults, malloc_failures_while_running, .timeout = SWEEP_TIMEOUT_S)
{
    char tmpl[64];
    ct_mkdir(tmpl, sizeof tmpl);
    make_template(tmpl);
    sweep("CASCADE_FAULT_MALLOC", "malloc", tmpl, 120, 2);
    ct_rmrf(tmpl);
}
