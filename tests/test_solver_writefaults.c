/*
 * Fault injection into cascade-solver's output writers (util/fault.h): a
 * tiny MD run with every output on (thermo.csv, fields.h5 + fields.xdmf,
 * snapshots.xyz, final.xyz, a final state in LAMMPS data format,
 * checkpoints, result.json) first counts its file writes (allocations)
 * with CASCADE_FAULT_WRITE=0 (CASCADE_FAULT_ALLOC=0), then runs from scratch
 * once for each N with the Nth failing.  Each time:
 *
 *   - the run exits 0 (the fault fell past its last call) or 1 with
 *     "error: ..." naming what failed (a file of the output directory for a
 *     write), never a crash or a sanitizer report;
 *   - no NAME.tmp is left, and every file present is complete: the text
 *     files equal those of an undisturbed run, fields.h5 opens and holds its
 *     /series (written last), each checkpoint is accepted by the restart
 *     reader (ckpt_open: format, version, case key, step);
 *   - result.json, when present, is JSON, and says "ok" only when the run
 *     exited 0.
 *
 * And the campaign: a job whose solver fails to write records the attempt
 * as an infrastructure failure with the solver's message.
 *
 * Every N from 1 to one past the count is tried; where the count exceeds
 * MAX_POINTS, every k-th (k = count / MAX_POINTS; the log line says).
 */
#include <criterion/criterion.h>
#include <criterion/logging.h>
#include <dirent.h>
#include <hdf5.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "helpers/ct.h"
#include "output/checkpoint.h"

#define MAX_POINTS 50

static const char *case_text =
    "seed: 3\n"
    "system: {lattice: {style: fcc, a: 3.61, cells: [2, 2, 2]}, element: Cu}\n"
    "potential: {style: sutton_chen}\n"
    "md: {timestep: 0.002, steps: 20, temperature: 300}\n"
    "output: {thermo_every: 5, snapshot_every: 10, xyz_every: 10, checkpoint_every: 8,\n"
    "         final_state: end.data}\n";

static const char *solver(void)
{
    const char *s = getenv("CASCADE_SOLVER");
    return s && *s ? s : "bin/cascade-solver";
}

/* cascade-solver run case.yaml --out OUT in dir, with `fault` (or none). */
static int solve(const char *dir, const char *out_name, const char *fault, char *out, size_t len)
{
    const char *env[] = {fault, NULL};
    const char *argv[] = {solver(), "run",     "case.yaml", "--out", out_name, "--threads",
                          "1",      "--quiet", NULL};
    return ct_exec(dir, fault ? env : NULL, argv, out, len);
}

static long counted(const char *out, const char *hook, long *failed)
{
    char pat[64];
    snprintf(pat, sizeof pat, "cascade-solver: fault injection: %s: ", hook);
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

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), t = strlen(tail);
    return n >= t && strcmp(s + n - t, tail) == 0;
}

/* Every file of got/ is complete (see the top); `rc` the run's exit. */
static void outputs_complete(const char *got, const char *ref, const char *key, int rc,
                             const char *what)
{
    DIR *d = opendir(got);
    if (!d)
        return;
    struct dirent *de;
    while ((de = readdir(d))) {
        const char *name = de->d_name;
        if (name[0] == '.')
            continue;
        char a[512], b[512];
        snprintf(a, sizeof a, "%s/%s", got, name);
        snprintf(b, sizeof b, "%s/%s", ref, name);
        cr_assert(!ends_with(name, ".tmp"), "%s: %s left", what, a);
        if (strcmp(name, "result.json") == 0) {
            json_t *r = json_load_file(a, 0, NULL);
            cr_assert(r, "%s: %s is not JSON", what, a);
            const char *st = json_string_value(json_object_get(r, "status"));
            cr_assert(st && (rc == 0) == (strcmp(st, "ok") == 0),
                      "%s: result.json says '%s' after exit %d", what, st ? st : "(none)", rc);
            json_decref(r);
        } else if (strcmp(name, "fields.h5") == 0) {
            hid_t f = H5Fopen(a, H5F_ACC_RDONLY, H5P_DEFAULT);
            cr_assert(f >= 0, "%s: %s does not open", what, a);
            cr_assert(H5Lexists(f, "/series/etotal_eV", H5P_DEFAULT) > 0,
                      "%s: %s lacks its series (incomplete)", what, a);
            H5Fclose(f);
        } else if (strncmp(name, "checkpoint-", 11) == 0) {
            struct ckpt c;
            struct err e = {0};
            long step = -1;
            cr_assert_eq(ckpt_open(&c, a, key, &step, &e), 0, "%s: %s refused: %s", what, a,
                         e.msg);
            cr_assert(step == 8 || step == 16, "%s: %s: step %ld", what, a, step);
            ckpt_close(&c);
        } else {
            char *x = slurp(a), *y = slurp(b);
            cr_assert(x && y, "%s: %s has no counterpart %s", what, a, b);
            cr_assert_str_eq(x, y, "%s: %s is not complete", what, a);
            free(x);
            free(y);
        }
    }
    closedir(d);
}

static void sweep(const char *var, const char *hook)
{
    char dir[64], spec[96], what[192], got[128], ref[128];
    static char out[65536];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "case.yaml", case_text);
    snprintf(ref, sizeof ref, "%s/ref", dir);
    snprintf(got, sizeof got, "%s/got", dir);
    snprintf(spec, sizeof spec, "%s=0", var);
    cr_assert_eq(solve(dir, "ref", spec, out, sizeof out), 0, "%s", out);
    long total = counted(out, hook, NULL);
    cr_assert_gt(total, 20, "%s: only %ld calls counted", var, total);
    char path[192];
    snprintf(path, sizeof path, "%s/result.json", ref);
    json_t *r = json_load_file(path, 0, NULL);
    cr_assert(r);
    char key[64];
    snprintf(key, sizeof key, "%s", json_string_value(json_object_get(r, "case_key")));
    json_decref(r);
    long step = total > MAX_POINTS ? (total + MAX_POINTS - 1) / MAX_POINTS : 1;
    long tried = 0, stopped = 0;
    for (long n = 1; n <= total + 1; n += step) {
        ct_rmrf(got);
        snprintf(spec, sizeof spec, "%s=%ld", var, n);
        snprintf(what, sizeof what, "cascade-solver run with %s (%s)", spec, dir);
        int rc = solve(dir, "got", spec, out, sizeof out);
        cr_assert(rc == 0 || rc == 1, "%s: exit %d:\n%s", what, rc, out);
        cr_assert_null(strstr(out, "Sanitizer"), "%s:\n%s", what, out);
        cr_assert_null(strstr(out, "runtime error"), "%s:\n%s", what, out);
        long failed;
        counted(out, hook, &failed);
        cr_assert_eq(rc != 0, failed > 0, "%s: exit %d with %ld calls failed:\n%s", what, rc,
                     failed, out);
        if (rc) {
            const char *msg = strstr(out, "error: ");
            cr_assert(msg, "%s: no message:\n%s", what, out);
            if (strcmp(hook, "write") == 0)
                cr_assert(strstr(msg, "got"), "%s: the message names no output:\n%s", what, out);
            else
                cr_assert(strstr(msg, "out of memory"), "%s:\n%s", what, out);
        }
        tried++;
        stopped += rc != 0;
        outputs_complete(got, ref, key, rc, what);
    }
    cr_log_info("cascade-solver run, %s: %ld calls, %ld runs (every %ld-th), %ld stopped",
                var, total, tried, step, stopped);
    ct_rmrf(dir);
}

Test(solver_writefaults, md_run_with_each_file_write_failing, .timeout = 300)
{
    sweep("CASCADE_FAULT_WRITE", "write");
}

Test(solver_writefaults, md_run_with_each_allocation_failing, .timeout = 300)
{
    sweep("CASCADE_FAULT_ALLOC", "alloc");
}

/* The campaign runs the solver through a wrapper that fails its Nth write
 * (the runner strips CASCADE_FAULT_* from its children, so the fault must
 * come from the wrapper): each attempt is recorded as an infrastructure
 * failure (not charged to the job) with the solver's message, and the
 * runner stops after three in a row, naming the cause. */
Test(solver_writefaults, campaign_records_a_solver_write_failure_as_infrastructure,
     .timeout = 120)
{
    char dir[64], out[65536];
    ct_mkdir(dir, sizeof dir);
    char wrapper[4096];
    snprintf(wrapper, sizeof wrapper, "#!/bin/sh\nCASCADE_FAULT_WRITE=3 exec %s \"$@\"\n",
             solver());
    const char *wpath = ct_write(0, dir, "solver.sh", wrapper);
    cr_assert_eq(chmod(wpath, 0755), 0);
    ct_write(1, dir, "s.yaml",
             "name: w\n"
             "base:\n"
             "  seed: 3\n"
             "  system: {lattice: {style: fcc, a: 3.61, cells: [2, 2, 2]}, element: Cu}\n"
             "  potential: {style: sutton_chen}\n"
             "  md: {timestep: 0.002, steps: 10, temperature: 300}\n"
             "  output: {thermo_every: 5}\n");
    int rc = ct_cascade(dir, NULL, out, sizeof out, "run", "s.yaml", "--solver", wpath,
                        "--infra-pause", "0.01", NULL);
    cr_assert_eq(rc, 1, "%s", out);
    cr_assert_not_null(strstr(out, "infrastructure failures in a row"), "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs"), 3);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'cancelled' AND "
                            "failure_class = 'infrastructure' AND message LIKE '%No space left "
                            "on device%' AND message LIKE '%cannot write %'"),
                 3, "every attempt an infrastructure failure with the solver's message");
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs WHERE state = 'done'"), 0);
    char msg[1024];
    ct_text(db, "SELECT message FROM runs ORDER BY id LIMIT 1", msg, sizeof msg);
    cr_log_info("recorded: %s", msg);
    sqlite3_close(db);
    ct_rmrf(dir);
}

/* A run killed on the way leaves its streams as NAME.tmp (never a
 * thermo.csv cut short under its own name); --restart keeps the killed
 * run's snapshots as NAME.before-STEP and ends with the same complete files
 * as an uninterrupted run. */
Test(solver_writefaults, a_killed_run_leaves_tmp_streams_and_restart_completes, .timeout = 120)
{
    char dir[64], out[65536], got[128], ref[128], path[256];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "case.yaml", case_text);
    snprintf(ref, sizeof ref, "%s/ref", dir);
    snprintf(got, sizeof got, "%s/got", dir);
    cr_assert_eq(solve(dir, "ref", NULL, out, sizeof out), 0, "%s", out);
    int rc = solve(dir, "got", "CASCADE_SOLVER_KILL_AT_STEP=12", out, sizeof out);
    cr_assert_eq(rc, 128 + 9, "%s", out);
    struct stat sb;
    static const char *const streams[] = {"thermo.csv", "snapshots.xyz", "fields.h5"};
    for (int k = 0; k < 3; k++) {
        snprintf(path, sizeof path, "%s/%s", got, streams[k]);
        cr_assert_neq(stat(path, &sb), 0, "%s exists after the kill", path);
        snprintf(path, sizeof path, "%s/%s.tmp", got, streams[k]);
        cr_assert_eq(stat(path, &sb), 0, "%s missing after the kill", path);
    }
    const char *argv[] = {solver(), "run", "case.yaml", "--out", "got", "--threads", "1",
                          "--quiet", "--restart", NULL};
    cr_assert_eq(ct_exec(dir, NULL, argv, out, sizeof out), 0, "%s", out);
    snprintf(path, sizeof path, "%s/snapshots.before-0000000008.xyz", got);
    cr_assert_eq(stat(path, &sb), 0, "%s: the killed run's frames were not kept", path);
    snprintf(path, sizeof path, "%s/result.json", ref);
    json_t *r = json_load_file(path, 0, NULL);
    cr_assert(r);
    char key[64];
    snprintf(key, sizeof key, "%s", json_string_value(json_object_get(r, "case_key")));
    json_decref(r);
    /* the same files as the uninterrupted run (the kept ones aside) */
    DIR *d = opendir(got);
    cr_assert(d);
    struct dirent *de;
    while ((de = readdir(d))) {
        /* the continued run's frames and snapshots start after step 8 */
        if (strstr(de->d_name, ".before-") || strcmp(de->d_name, "snapshots.xyz") == 0 ||
            strcmp(de->d_name, "fields.xdmf") == 0) {
            snprintf(path, sizeof path, "%s/%s", got, de->d_name);
            cr_assert_eq(unlink(path), 0);
        }
    }
    closedir(d);
    outputs_complete(got, ref, key, 0, "after --restart");
    ct_rmrf(dir);
}
