/* cascade regress: rerun a study and compare it with its reviewed baseline. */
#include <errno.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "baseline.h"
#include "baseline_db.h"
#include "cli.h"
#include "backend.h"
#include "db.h"
#include "launch.h"
#include "regress_history.h"
#include "report_run.h"
#include "study.h"
#include "refine_run.h"
#include "study_run.h"
#include "sysinfo.h"

static const char *usage =
    "usage: cascade regress STUDY.yaml [--baseline FILE] [--update-baseline] [--no-run]\n"
    "                      [--db FILE] [--runs DIR] [--out DIR] [--format md,html]\n"
    "                      [--solver PATH] [--jobs N] [--brief] [--quiet]\n"
    "\n"
    "Runs the study (only the jobs not done for this solver version, as `cascade\n"
    "run` does), compares every metric value and every observed order along the\n"
    "resolution axis with the baseline within the tolerances of the study's\n"
    "`regress:` section, prints the differences, writes the report with a\n"
    "regression section, and records the baseline and the verdict in the\n"
    "database.  Exit code 0 when nothing regressed, 1 when a value or an order is\n"
    "outside its tolerance, a baseline entry has no value now or a job failed,\n"
    "2 on bad input (a missing baseline among them), 130 when interrupted.\n"
    "\n"
    "  --baseline FILE     the baseline (default: the study's regress.baseline, else\n"
    "                      baselines/STUDY.json next to the study file)\n"
    "  --update-baseline   write the baseline from the current results instead of\n"
    "                      comparing (every job must be done); review and commit it\n"
    "  --no-run            compare what the database holds; run nothing\n"
    "  --db FILE           results database (default ./" CASCADE_DB_DEFAULT ")\n"
    "  --runs DIR          run directories (default ./runs)\n"
    "  --out DIR           report directory (default reports/STUDY)\n"
    "  --format LIST       report formats: md, html or md,html (default)\n"
    "  --solver PATH       the solver (as for cascade run)\n"
    "  --jobs N            jobs at a time (as for cascade run)\n"
    "  --brief             print only the entries that did not pass\n"
    "  --quiet             no progress output while running\n";

struct regress_args {
    const char *file, *baseline, *db_path, *runs, *out, *formats, *solver;
    long jobs;
    int update, no_run, brief, quiet;
};

static int parse(int argc, char **argv, struct regress_args *a)
{
    memset(a, 0, sizeof *a);
    a->db_path = CASCADE_DB_DEFAULT;
    a->runs = "runs";
    a->formats = "md,html";
    for (int i = 0; i < argc; i++) {
        const char *v;
        int m;
        if ((m = cli_opt(argc, argv, &i, "--jobs", &v)) || (m = cli_opt(argc, argv, &i, "-j", &v))) {
            if (m < 0 || cli_int("--jobs", v, 1, 4096, &a->jobs) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--baseline", &a->baseline)) ||
                   (m = cli_opt(argc, argv, &i, "--db", &a->db_path)) ||
                   (m = cli_opt(argc, argv, &i, "--runs", &a->runs)) ||
                   (m = cli_opt(argc, argv, &i, "--out", &a->out)) ||
                   (m = cli_opt(argc, argv, &i, "--format", &a->formats)) ||
                   (m = cli_opt(argc, argv, &i, "--solver", &a->solver))) {
            if (m < 0)
                return 2;
        } else if (strcmp(argv[i], "--update-baseline") == 0) {
            a->update = 1;
        } else if (strcmp(argv[i], "--no-run") == 0) {
            a->no_run = 1;
        } else if (strcmp(argv[i], "--brief") == 0) {
            a->brief = 1;
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            a->quiet = 1;
        } else if (argv[i][0] != '-' && !a->file) {
            a->file = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!a->file)
        return cli_usage_error(usage, "give a study file");
    return 0;
}

/* The baseline file: --baseline, the study's regress.baseline (relative to
 * the study file), or baselines/NAME.json next to the study file. */
static void baseline_path(const struct regress_args *a, const struct study *s, char *out,
                          size_t len)
{
    if (a->baseline)
        snprintf(out, len, "%s", a->baseline);
    else if (s->report.baseline[0] == '/')
        snprintf(out, len, "%s", s->report.baseline);
    else if (s->report.baseline[0])
        snprintf(out, len, "%s/%s", s->dir, s->report.baseline);
    else
        snprintf(out, len, "%s/baselines/%s.json", s->dir, s->name);
}

/* Metric names of the items that did not pass, for the last line. */
static void regressed_names(const struct cmp_report *r, char *out, size_t len)
{
    out[0] = '\0';
    for (int i = 0; i < r->n; i++) {
        const struct cmp_item *it = &r->it[i];
        if (it->verdict == CMP_OK || it->verdict == CMP_NEW)
            continue;
        char one[256];
        if (strcmp(it->what, "job") == 0)
            snprintf(one, sizeof one, "failed jobs");
        else
            snprintf(one, sizeof one, "%s %s", it->metric, it->what);
        if (strstr(out, one))
            continue;
        size_t used = strlen(out);
        snprintf(out + used, len - used, "%s%s", used ? ", " : "", one);
    }
}

static int update_baseline(const struct regress_args *a, struct report_ctx *c, sqlite3 *db,
                           const char *path, struct err *e)
{
    long notdone = 0;
    for (long j = 0; j < c->d.njobs; j++)
        notdone += strcmp(c->d.jobs[j].state, "done") != 0;
    if (notdone)
        return err_set(e, ERR_RUNTIME, "%ld job%s of %s %s not done (cascade status %s); a "
                                       "baseline needs every job done",
                       notdone, notdone == 1 ? "" : "s", c->d.name, notdone == 1 ? "is" : "are",
                       c->d.name);
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    json_t *b = baseline_build(&c->a, now);
    if (!b)
        return err_nomem(e, "baseline");
    /* show what changes against the baseline being replaced */
    json_t *old = NULL;
    char *oldtext = NULL;
    struct err ignore = {0};
    if (baseline_read(path, c->d.name, &old, &oldtext, &ignore) == 0) {
        struct cmp_report r;
        if (baseline_compare(old, &c->a, c->rs, &r, &ignore) == 0) {
            printf("changes against the baseline being replaced (%d of %d entries outside "
                   "tolerance, %d new):\n",
                   r.regressed, r.compared, r.added);
            cmp_print(&r, stdout, 0);
            cmp_free(&r);
        }
        json_decref(old);
        free(oldtext);
    }
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    int rc = launch_mkdirs(dirname(dir), e);
    if (!rc)
        rc = baseline_write(b, path, e);
    json_t *back = NULL;
    char *text = NULL;
    if (!rc)
        rc = baseline_read(path, c->d.name, &back, &text, e);
    long long id;
    if (!rc)
        rc = baseline_db_record(db, c->d.study_id, path, text, back, &id, e);
    if (!rc)
        printf("baseline of %s written: %s (%zu values, %zu orders; review and commit it)\n",
               c->d.name, path, json_array_size(json_object_get(b, "values")),
               json_array_size(json_object_get(b, "orders")));
    json_decref(b);
    json_decref(back);
    free(text);
    (void)a;
    return rc;
}

static int compare(const struct regress_args *a, struct report_ctx *c, sqlite3 *db,
                   const char *path, int *regressed, struct err *e)
{
    json_t *b = NULL;
    char *text = NULL;
    int rc = baseline_read(path, c->d.name, &b, &text, e);
    long long id = 0;
    if (!rc)
        rc = baseline_db_record(db, c->d.study_id, path, text, b, &id, e);
    struct cmp_report r;
    memset(&r, 0, sizeof r);
    if (!rc)
        rc = baseline_compare(b, &c->a, c->rs, &r, e);
    char now_solver[256], base_solver[256];
    baseline_solver_of(&c->a, now_solver, sizeof now_solver);
    const json_t *sv = json_object_get(b, "solver");
    const char *bver = json_string_value(json_object_get(sv, "version"));
    const char *bgit = json_string_value(json_object_get(sv, "git"));
    snprintf(base_solver, sizeof base_solver, "%s (%s)", bver ? bver : "?", bgit ? bgit : "?");
    if (!rc) {
        printf("regress %s: baseline %s (solver %s); now solver %s\n", c->d.name, path,
               base_solver, now_solver[0] ? now_solver : "(no values)");
        cmp_print(&r, stdout, !a->brief);
        rc = regress_history_record(db, id, now_solver, &r, &c->a, e);
    }
    if (!rc) {
        char title[256];
        snprintf(title, sizeof title, "Study %s: regression check and convergence", c->d.name);
        c->doc = rdoc_create(title);
        if (!c->doc)
            rc = err_nomem(e, "report");
        else
            cmp_to_doc(&r, c->doc, path, base_solver);
        *regressed = r.regressed;
        char names[1024];
        regressed_names(&r, names, sizeof names);
        if (r.regressed)
            printf("regress %s: REGRESSED: %d of %d baseline entries (%s)%s\n", c->d.name,
                   r.regressed, r.compared, names, r.added ? "; new entries not in the baseline too" : "");
        else
            printf("regress %s: passed: %d baseline entries within tolerance%s\n", c->d.name,
                   r.compared, r.added ? " (and new entries not in the baseline)" : "");
    }
    cmp_free(&r);
    json_decref(b);
    free(text);
    return rc;
}

int cmd_regress(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    struct regress_args a;
    int rc = parse(argc, argv, &a);
    if (rc)
        return rc;
    int md, html;
    if (cli_parse_formats(a.formats, &md, &html) != 0)
        return cli_usage_error(usage, "--format: give md, html or md,html, not '%s'", a.formats);
    struct err e = {0};
    struct study s;
    if ((rc = study_load(&s, a.file, &e))) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    char path[4096 + 64];
    baseline_path(&a, &s, path, sizeof path);
    struct stat sb;
    if (!a.update && stat(path, &sb) != 0) {
        fprintf(stderr, "error: %s: no baseline (%s); write one with cascade regress %s "
                        "--update-baseline, review it and commit it\n",
                path, strerror(errno), a.file);
        study_free(&s);
        return 2;
    }
    int code = 0;
    if (!a.no_run) {
        backend_block_signals();
        struct study_run_opts o = {a.db_path, a.runs, a.solver, a.jobs, 60,
                                   a.quiet,   1,      NULL,     NULL,   0};
        struct runner_summary sum;
        rc = study_run_any(&s, &o, &sum, &e);   /* refines first when the study says so */
        if (!rc && sum.interrupted) {
            fprintf(stderr, "regress %s: interrupted\n", s.name);
            study_free(&s);
            return 128 + sum.interrupted;
        }
        if (!rc)
            printf("regress %s: %ld jobs: %ld done (%ld earlier), %ld failed\n", s.name, sum.total,
                   sum.done, sum.done_before, sum.failed + sum.not_run);
    }
    sqlite3 *db = NULL;
    struct report_ctx c;
    memset(&c, 0, sizeof c);
    if (!rc)
        rc = db_open(a.db_path, &db, &e);
    if (!rc)
        rc = report_load(&c, db, s.name, &s.report, &e);
    int regressed = 0;
    if (!rc)
        rc = a.update ? update_baseline(&a, &c, db, path, &e)
                      : compare(&a, &c, db, path, &regressed, &e);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", a.out ? a.out : "");
    if (!a.out)
        snprintf(dir, sizeof dir, "reports/%s", s.name);
    if (!rc) {
        rc = report_emit(&c, dir, md, html, a.db_path, &e);
        if (!rc)
            printf("regress %s: report in %s/%s\n", s.name, dir, html ? "report.html" : "report.md");
    }
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        code = cli_exit_code(rc);
    } else {
        code = regressed ? 1 : 0;
    }
    report_ctx_free(&c);
    db_close(&db);
    study_free(&s);
    return code;
}
