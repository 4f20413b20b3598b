/* cascade report: a study's convergence report as Markdown and HTML. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "db.h"
#include "report_cli.h"
#include "report_run.h"
#include "study.h"

static const char *usage =
    "usage: cascade report STUDY [--format md,html,json] [--out DIR] [--db FILE]\n"
    "                     [--source NAME]\n"
    "\n"
    "Writes the report of a study from the results database: for each metric and\n"
    "each combination of the other swept values, the values along the resolution\n"
    "axis, the observed order p from the three finest grids, the Richardson-\n"
    "extrapolated value, the GCI (fine and medium) and the asymptotic-range ratio\n"
    "(Celik et al. 2008), flags for oscillatory or divergent convergence, plots of\n"
    "the value and of the error against h; the metrics against the other swept\n"
    "values with the fits the study asks for; the failed and missing jobs with\n"
    "their reasons.  The study's `report:` section sets the resolution axis and\n"
    "the rest (docs/reports.md).\n"
    "\n"
    "  STUDY           a study name in the database, or the study file (a path\n"
    "                  ending in .yaml; its `report:` section is then read from it)\n"
    "  --format LIST   md, html, json, or a list of them (default md,html); json\n"
    "                  also prints report.json on stdout (and nothing else)\n"
    "  --out DIR       output directory (default reports/STUDY); it receives\n"
    "                  report.md with its SVG figures, a self-contained report.html\n"
    "                  and always report.json (every number at full precision)\n"
    "  --source NAME   analyse the rows imported from NAME (cascade import) instead\n"
    "                  of the campaign's runs\n"
    "\n"
    "The convergence results are also written to the database's convergence table\n"
    "(db/README.md); a database that cannot be written gets a warning.\n"
    "  --db FILE       results database (default ./" CASCADE_DB_DEFAULT ")\n";

/* A study argument is a file when it looks like a path (a '/' or a .yaml /
 * .yml ending) and names an existing regular file; otherwise a study name. */
static int is_file(const char *arg)
{
    size_t n = strlen(arg);
    int pathlike = strchr(arg, '/') || (n > 5 && strcmp(arg + n - 5, ".yaml") == 0) ||
                   (n > 4 && strcmp(arg + n - 4, ".yml") == 0);
    struct stat sb;
    return pathlike && stat(arg, &sb) == 0 && S_ISREG(sb.st_mode);
}

int cmd_report(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL, *out = NULL, *formats = "md,html";
    const char *source = NULL;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "--out", &out)) ||
            (m = cli_opt(argc, argv, &i, "--format", &formats)) ||
            (m = cli_opt(argc, argv, &i, "--source", &source))) {
            if (m < 0)
                return 2;
        } else if (argv[i][0] != '-' && !study) {
            study = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!study)
        return cli_usage_error(usage, "give a study name or a study file");
    int md, html, json;
    if (report_parse_formats(formats, &md, &html, &json) != 0)
        return cli_usage_error(usage, "--format: give md, html, json or a list of them, not '%s'",
                               formats);
    struct err e = {0};
    struct study s;
    int have_study = 0, rc = 0;
    const char *name = study;
    if (is_file(study)) {
        if ((rc = study_load(&s, study, &e))) {
            fprintf(stderr, "error: %s\n", e.msg);
            return cli_exit_code(rc);
        }
        have_study = 1;
        name = s.name;
    }
    char dir[4096];
    if (out)
        snprintf(dir, sizeof dir, "%s", out);
    else
        snprintf(dir, sizeof dir, "reports/%s", name);
    sqlite3 *db = NULL;
    struct report_ctx c;
    memset(&c, 0, sizeof c);
    rc = db_open_readonly(db_path, &db, &e);
    if (!rc)
        rc = report_load_source(&c, db, name, source, have_study ? &s.report : NULL, &e);
    db_close(&db);
    if (!rc)
        rc = report_emit(&c, dir, md, html, db_path, &e);
    if (!rc)
        report_store_convergence(&c, db_path);
    if (!rc && json)
        rc = report_print_json(dir, &e);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
    } else if (!json) {
        int flagged = 0;
        for (int k = 0; c.a.conv && k < c.a.nmetrics * c.a.ngroups; k++)
            flagged += c.a.conv[k].flagged;
        if (c.a.res.axis >= 0)
            printf("report of %s: %d metric%s, %d series along %s%s", name, c.a.nmetrics,
                   c.a.nmetrics == 1 ? "" : "s", c.a.ngroups, c.d.axes[c.a.res.axis].name,
                   flagged ? "" : "\n");
        else
            printf("report of %s: %d metric%s, no resolution axis\n", name, c.a.nmetrics,
                   c.a.nmetrics == 1 ? "" : "s");
        if (flagged)
            printf(" (%d flagged: see the summary)\n", flagged);
        if (md)
            printf("  %s/report.md\n", dir);
        if (html)
            printf("  %s/report.html\n", dir);
        printf("  %s/report.json\n", dir);
    }
    report_ctx_free(&c);
    if (have_study)
        study_free(&s);
    return cli_exit_code(rc);
}
