/*
 * Fault injection into the runner's own code (util/fault.h), in the spirit
 * of SQLite's malloc and I/O-error tests: a command first runs with
 * CASCADE_FAULT_ALLOC=0 (or CASCADE_FAULT_WRITE=0) to count its allocations
 * (file writes), then once from scratch for each N with the Nth failing.
 *
 *   cascade run    a 3-job stand-in study: the command either stops (exit 1,
 *                  "error: ..." naming what failed) or completes the study,
 *                  the failed attempt recorded as an infrastructure failure
 *                  whose message names what failed (or a note naming the
 *                  file, for the `current` link); no crash, no sanitizer
 *                  report; the database is consistent (integrity_check,
 *                  foreign keys, no done run without all its metrics or
 *                  with a recorded file missing on disk, no running run
 *                  without a lease); a second run without the fault
 *                  completes every job exactly once.
 *   cascade report a finished study: exit 0 with the complete report, or
 *                  exit 1 naming what failed, and every file in the report
 *                  directory then is complete (equal to an undisturbed
 *                  report's), no .tmp file left.
 *   cascade export the same for the CSV file (--out).
 *
 * Every N from 1 to one past the count is tried; where a command has more
 * than MAX_POINTS points, every k-th with k = count / MAX_POINTS (the log
 * line says which).
 */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/ct.h"

#define NJOBS 3
#define NMETRICS 3   /* the stand-in's metrics: seed, sum, x_squared */
#define MAX_POINTS 50

static const char *study_text = "name: s\n"
                                "base: {fake: {action: ok}}\n"
                                "sweep: {grid: {fake.x: [1, 2, 3]}}\n";

static int run(const char *dir, const char *fault, char *out, size_t len)
{
    const char *env[] = {fault, NULL};
    return ct_cascade(dir, fault ? env : NULL, out, len, "run", "s.yaml", "--solver",
                      ct_standin(), "--jobs", "2", "--infra-pause", "0.01", NULL);
}

/* The calls a hook counted, and how many it failed, from its report line. */
static long counted(const char *out, const char *hook, long *failed)
{
    char pat[64];
    snprintf(pat, sizeof pat, "cascade: fault injection: %s: ", hook);
    const char *p = strstr(out, pat);
    cr_assert(p, "no fault injection report in:\n%s", out);
    char *end;
    long n = strtol(p + strlen(pat), &end, 10);
    const char *f = strstr(end, "failed ");
    cr_assert(f, "%s", out);
    if (failed)
        *failed = strtol(f + 7, NULL, 10);
    return n;
}

static int says_what_failed(const char *text)
{
    return strstr(text, "cannot ") || strstr(text, "out of memory");
}

static void no_crash(int rc, const char *out, const char *what)
{
    cr_assert(rc == 0 || rc == 1, "%s: exit %d:\n%s", what, rc, out);
    cr_assert_null(strstr(out, "Sanitizer"), "%s:\n%s", what, out);
    cr_assert_null(strstr(out, "runtime error"), "%s:\n%s", what, out);
    if (rc == 1) {
        const char *msg = strstr(out, "error: ");
        cr_assert(msg && says_what_failed(msg), "%s: exit 1 without a message naming what "
                                                "failed:\n%s",
                  what, out);
    }
}

/* Every file a done run recorded is on disk with the recorded size. */
static void files_on_disk(sqlite3 *db, const char *what)
{
    sqlite3_stmt *st;
    cr_assert_eq(sqlite3_prepare_v2(db, "SELECT a.path, a.bytes FROM artifacts a JOIN runs r ON "
                                        "r.id = a.run_id WHERE r.status = 'done'",
                                    -1, &st, NULL),
                 SQLITE_OK);
    while (sqlite3_step(st) == SQLITE_ROW) {
        const char *path = (const char *)sqlite3_column_text(st, 0);
        struct stat sb;
        cr_assert(stat(path, &sb) == 0 && sb.st_size == sqlite3_column_int64(st, 1),
                  "%s: recorded file %s missing or of another size", what, path);
    }
    sqlite3_finalize(st);
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
                                "(SELECT count(*) FROM metrics WHERE run_id = r.id) != 3"),
                     0, "%s: a done run without all its %d metrics", what, NMETRICS);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs r WHERE status = 'done' AND "
                                "(NOT EXISTS (SELECT 1 FROM artifacts WHERE run_id = r.id AND "
                                "kind = 'result') OR NOT EXISTS (SELECT 1 FROM artifacts WHERE "
                                "run_id = r.id AND kind = 'case'))"),
                     0, "%s: a done run without its result.json or case.yaml", what);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs r WHERE status = 'running' AND "
                                "NOT EXISTS (SELECT 1 FROM leases WHERE run_id = r.id)"),
                     0, "%s: a running run without a lease", what);
        cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status NOT IN ('done', "
                                "'running') AND (message IS NULL OR (message NOT LIKE "
                                "'%cannot %' AND message NOT LIKE '%out of memory%'))"),
                     0, "%s: a failed attempt whose message does not say what failed", what);
        files_on_disk(db, what);
    }
    sqlite3_close(db);
}

static void complete(const char *dir, const char *what)
{
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs j WHERE (SELECT count(*) FROM runs "
                            "WHERE job_id = j.id AND status = 'done') = 1"),
                 NJOBS, "%s: not every job done exactly once", what);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM leases"), 0, "%s: a lease left", what);
    sqlite3_close(db);
}

/* Whether a run that exited 0 after a fault fired said what failed: in a
 * recorded attempt, or in a note on stderr. */
static int reported(const char *dir, const char *out)
{
    if (strstr(out, "[cascade] ") && says_what_failed(strstr(out, "[cascade] ")))
        return 1;
    sqlite3 *db = ct_db(dir);
    long long n = ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled' AND "
                             "failure_class = 'infrastructure'");
    sqlite3_close(db);
    return n > 0;
}

static long stride_for(long total)
{
    return total > MAX_POINTS ? (total + MAX_POINTS - 1) / MAX_POINTS : 1;
}

static void run_sweep(const char *var, const char *hook)
{
    char dir[64], spec[96], what[160];
    static char out[65536], out2[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml", study_text);
    snprintf(spec, sizeof spec, "%s=0", var);
    cr_assert_eq(run(dir, spec, out, sizeof out), 0, "%s", out);
    long total = counted(out, hook, NULL);
    ct_rmrf(dir);
    cr_assert_gt(total, 10, "%s: only %ld calls counted", var, total);
    long step = stride_for(total), tried = 0, stopped = 0, fired = 0;
    for (long n = 1; n <= total + 1; n += step) {
        ct_mkdir(dir, sizeof dir);
        ct_write(0, dir, "s.yaml", study_text);
        snprintf(spec, sizeof spec, "%s=%ld", var, n);
        snprintf(what, sizeof what, "cascade run with %s (%s)", spec, dir);
        int rc = run(dir, spec, out, sizeof out);
        no_crash(rc, out, what);
        long failed;
        counted(out, hook, &failed);
        tried++;
        fired += failed > 0;
        stopped += rc == 1;
        char db[128];
        snprintf(db, sizeof db, "%s/cascade.db", dir);
        if (access(db, F_OK) == 0)
            consistent(dir, what);
        if (rc == 0) {
            complete(dir, what);
            if (failed)
                cr_assert(reported(dir, out), "%s: the fault fired, nothing says so:\n%s", what,
                          out);
        }
        int rc2 = run(dir, NULL, out2, sizeof out2);
        cr_assert_eq(rc2, 0, "%s: the run after it:\n%s\nfirst run:\n%s", what, out2, out);
        consistent(dir, what);
        complete(dir, what);
        ct_rmrf(dir);
    }
    cr_assert_gt(stopped, 0, "%s: no fault ever stopped the runner", var);
    cr_log_info("cascade run, %s: %ld calls, %ld runs (every %ld-th), %ld with the fault fired, "
                "%ld stopped with an error",
                var, total, tried, step, fired, stopped);
}

Test(campaign_ownfaults, run_with_each_allocation_failing, .timeout = 300)
{
    run_sweep("CASCADE_FAULT_ALLOC", "alloc");
}

Test(campaign_ownfaults, run_with_each_file_write_failing, .timeout = 300)
{
    run_sweep("CASCADE_FAULT_WRITE", "write");
}

/* --- report and export ------------------------------------------------------ */

/* A directory with a finished study s (dir/cascade.db). */
static void finished_study(char *dir, size_t len)
{
    char out[16384];
    ct_mkdir(dir, len);
    ct_write(0, dir, "s.yaml", study_text);
    cr_assert_eq(run(dir, NULL, out, sizeof out), 0, "%s", out);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    cr_assert(buf);
    cr_assert_eq(fread(buf, 1, (size_t)n, f), (size_t)n);
    buf[n] = '\0';
    fclose(f);
    return buf;
}

/* The text without its time stamps ("Generated <time>" in report.md and
 * .html, "generated": "<time>" in report.json: what differs between two
 * runs). */
static void unstamp(char *s)
{
    char *g;
    while ((g = strstr(s, "\"generated\": \""))) {
        char *end = strchr(g + 14, '"');
        if (!end)
            break;
        memmove(g, end + 1, strlen(end + 1) + 1);
    }
    while ((g = strstr(s, "Generated 2"))) {
        char *end = g;
        while (*end && *end != '.' && *end != '\n')
            end++;
        while (*end == '.' && end[1] >= '0' && end[1] <= '9') {   /* the fraction of seconds */
            end++;
            while (*end && *end != '.' && *end != '\n')
                end++;
        }
        memmove(g, end, strlen(end) + 1);
    }
}

/* Every file in `got` is complete: the same as in `ref` (stamps aside);
 * no temporary file is left. */
static void complete_files(const char *got, const char *ref, const char *what)
{
    DIR *d = opendir(got);
    if (!d)
        return;
    struct dirent *de;
    while ((de = readdir(d))) {
        if (de->d_name[0] == '.')
            continue;
        size_t n = strlen(de->d_name);
        cr_assert(n < 4 || strcmp(de->d_name + n - 4, ".tmp") != 0, "%s: %s/%s left", what, got,
                  de->d_name);
        char a[512], b[512];
        snprintf(a, sizeof a, "%s/%s", got, de->d_name);
        snprintf(b, sizeof b, "%s/%s", ref, de->d_name);
        char *x = slurp(a), *y = slurp(b);
        cr_assert(x && y, "%s: %s has no counterpart %s", what, a, b);
        unstamp(x);
        unstamp(y);
        cr_assert_str_eq(x, y, "%s: %s is not complete", what, a);
        free(x);
        free(y);
    }
    closedir(d);
}

/* `cascade report s` (args: the rest) with each fault point failing. */
static void reader_sweep(const char *var, const char *hook, const char *const *args,
                         const char *out_name)
{
    char dir[64], spec[96], what[160], ref[128], got[128];
    static char out[65536];
    finished_study(dir, sizeof dir);
    snprintf(ref, sizeof ref, "%s/ref", dir);
    snprintf(got, sizeof got, "%s/got", dir);
    mkdir(ref, 0777);
    mkdir(got, 0777);
    const char *argv[16];
    int k = 0;
    argv[k++] = ct_cascade_bin();
    for (int i = 0; args[i]; i++)
        argv[k++] = args[i];
    argv[k++] = "--out";
    int out_arg = k;
    argv[k++] = NULL;
    argv[k] = NULL;
    char refp[192], gotp[192];
    snprintf(refp, sizeof refp, "ref%s%s", out_name[0] ? "/" : "", out_name);
    snprintf(gotp, sizeof gotp, "got%s%s", out_name[0] ? "/" : "", out_name);
    snprintf(spec, sizeof spec, "%s=0", var);
    const char *env[] = {spec, NULL};
    argv[out_arg] = refp;
    cr_assert_eq(ct_exec(dir, env, argv, out, sizeof out), 0, "%s", out);
    long total = counted(out, hook, NULL);
    cr_assert_gt(total, 2, "%s: only %ld calls counted", var, total);
    argv[out_arg] = gotp;
    long step = stride_for(total), tried = 0, stopped = 0;
    for (long n = 1; n <= total + 1; n += step) {
        ct_rmrf(got);
        cr_assert_eq(mkdir(got, 0777), 0);
        snprintf(spec, sizeof spec, "%s=%ld", var, n);
        snprintf(what, sizeof what, "cascade %s with %s (%s)", args[0], spec, dir);
        int rc = ct_exec(dir, env, argv, out, sizeof out);
        no_crash(rc, out, what);
        long failed;
        counted(out, hook, &failed);
        cr_assert(!failed || rc == 1, "%s: the fault fired but the command succeeded:\n%s", what,
                  out);
        tried++;
        stopped += rc == 1;
        complete_files(got, ref, what);
        consistent(dir, what);
    }
    cr_assert_gt(stopped, 0, "%s: no fault ever surfaced", var);
    cr_log_info("cascade %s, %s: %ld calls, %ld runs (every %ld-th), %ld stopped with an error",
                args[0], var, total, tried, step, stopped);
    ct_rmrf(dir);
}

static const char *const report_args[] = {"report", "s", NULL};
static const char *const export_args[] = {"export", "s", "--csv", NULL};

Test(campaign_ownfaults, report_with_each_allocation_failing, .timeout = 300)
{
    reader_sweep("CASCADE_FAULT_ALLOC", "alloc", report_args, "");
}

Test(campaign_ownfaults, report_with_each_file_write_failing, .timeout = 300)
{
    reader_sweep("CASCADE_FAULT_WRITE", "write", report_args, "");
}

Test(campaign_ownfaults, export_with_each_allocation_failing, .timeout = 120)
{
    reader_sweep("CASCADE_FAULT_ALLOC", "alloc", export_args, "x.csv");
}

Test(campaign_ownfaults, export_with_each_file_write_failing, .timeout = 120)
{
    reader_sweep("CASCADE_FAULT_WRITE", "write", export_args, "x.csv");
}

/* A malformed value is refused naming the variable, before anything runs. */
Test(campaign_ownfaults, a_malformed_fault_value_is_refused)
{
    char dir[64], out[4096];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "s.yaml", study_text);
    int rc = run(dir, "CASCADE_FAULT_WRITE=3x", out, sizeof out);
    cr_assert_eq(rc, 2, "%s", out);
    cr_assert_not_null(strstr(out, "CASCADE_FAULT_WRITE=3x"), "%s", out);
    char db[128];
    snprintf(db, sizeof db, "%s/cascade.db", dir);
    cr_assert_neq(access(db, F_OK), 0, "a database was created");
    ct_rmrf(dir);
}
