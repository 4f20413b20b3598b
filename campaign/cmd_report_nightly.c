/* cascade report --nightly: the nightly dashboard page (nightly_page.h). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "nightly_page.h"

static const char *usage =
    "usage: cascade report --nightly [STUDY] [--db FILE] [--out FILE] [--nights N]\n"
    "\n"
    "Writes the nightly dashboard: one self-contained HTML page (inline SVG, no\n"
    "scripts, no server) from the regression history that `cascade regress`\n"
    "records (make nightly: --db runs/nightly/cascade.db).  Per study a table of\n"
    "the nights (date, commit, solver, machine, verdict, links to the run\n"
    "directories) and per metric the trend over the nights with the tolerance\n"
    "band and the baseline, the nights that regressed in red (docs/nightly.md).\n"
    "\n"
    "  STUDY        only this study (default: every study with regression checks)\n"
    "  --db FILE    results database (default ./" CASCADE_DB_DEFAULT ")\n"
    "  --out FILE   the page (default reports/nightly.html)\n"
    "  --nights N   the latest N nights of each study (default 60)\n";

int cmd_report_nightly(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    struct nightly_page_opts o = {"reports/nightly.html", NULL, 60, CASCADE_DB_DEFAULT};
    long nights = 60;
    for (int i = 0; i < argc; i++) {
        const char *v;
        int m;
        if (strcmp(argv[i], "--nightly") == 0)
            continue;
        if ((m = cli_opt(argc, argv, &i, "--nights", &v))) {
            if (m < 0 || cli_int("--nights", v, 1, 100000, &nights) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--db", &o.db_label)) ||
                   (m = cli_opt(argc, argv, &i, "--out", &o.out))) {
            if (m < 0)
                return 2;
        } else if (argv[i][0] != '-' && !o.study) {
            o.study = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    o.nights = (int)nights;
    struct err e = {0};
    sqlite3 *db = NULL;
    int nfig = 0;
    int rc = db_open_readonly(o.db_label, &db, &e);
    if (!rc)
        rc = nightly_page_write(db, &o, &nfig, &e);
    db_close(&db);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    printf("nightly page: %s (%d figure%s)\n", o.out, nfig, nfig == 1 ? "" : "s");
    return 0;
}
