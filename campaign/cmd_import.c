/* cascade import: reference values of an external source into a study. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "db.h"
#include "import_store.h"

static const char *usage =
    "usage: cascade import STUDY FILE.csv [--source NAME] [--db FILE]\n"
    "       cascade import STUDY FILE.json --json [--source NAME] [--db FILE]\n"
    "       (a study holding references only: [--resolution KEY [--h value|inverse|cells]\n"
    "        [--dim N] [--volume V]])\n"
    "\n"
    "Records rows of parameters and metric values from outside the campaign --\n"
    "experiment, another code, a paper's table -- as reference rows of a named\n"
    "source.  CSV: a header of parameters and metrics written 'name [unit]', one\n"
    "row per line, '# source: NAME' in a comment line; JSON: {\"source\": NAME,\n"
    "\"rows\": [{\"params\": {...}, \"metrics\": {NAME: {\"value\": x, \"unit\": u}}}]}.\n"
    "For a study the campaign has run, parameters must be its swept keys and\n"
    "metrics those it records, in the same units; a study not in the database\n"
    "is created holding the references only (cascade report then runs the\n"
    "convergence analysis on them).  Errors name the file and line; nothing is\n"
    "written unless every row is good.  Importing a source again replaces it.\n"
    "\n"
    "  --source NAME   the source (overrides the file's)\n"
    "  --json          the file is JSON (or YAML); default: CSV unless it ends in\n"
    "                  .json, .yaml or .yml\n"
    "  --resolution K  references-only study: the resolution axis of its reports\n"
    "  --h MAP         ... and how a value maps to h: value, inverse, cells\n"
    "  --dim N, --volume V   ... h = (V/N)^(1/dim) for cells\n"
    "  --db FILE       results database (default ./" CASCADE_DB_DEFAULT ")\n";

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n > m && strcmp(s + n - m, tail) == 0;
}

static int dry_run(const struct import_set *s, const struct import_opts *o,
                   struct import_result *res, struct err *e)
{
    const char *tmp = getenv("TMPDIR");
    char dir[4096], path[4200], side[4300];
    snprintf(dir, sizeof dir, "%s/cascade-import.XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(dir))
        return err_set(e, ERR_RUNTIME, "cannot create a scratch directory in %s",
                       tmp && tmp[0] ? tmp : "/tmp");
    snprintf(path, sizeof path, "%s/check.db", dir);
    sqlite3 *db = NULL;
    int rc = db_open(path, &db, e);
    if (!rc)
        rc = import_store(db, s, o, res, e);
    db_close(&db);
    static const char *const suffix[] = {"", "-wal", "-shm", "-journal"};
    for (int i = 0; i < 4; i++) {
        snprintf(side, sizeof side, "%s%s", path, suffix[i]);
        unlink(side);
    }
    rmdir(dir);
    return rc;
}

int cmd_import(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *study = NULL, *file = NULL, *v;
    struct import_opts o = {0};
    int json = -1;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "--source", &o.source)) ||
            (m = cli_opt(argc, argv, &i, "--resolution", &o.resolution)) ||
            (m = cli_opt(argc, argv, &i, "--h", &o.hmap))) {
            if (m < 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--dim", &v))) {
            if (m < 0 || cli_int("--dim", v, 1, 3, &o.dim) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--volume", &v))) {
            if (m < 0 || cli_real("--volume", v, 1e-300, &o.volume) != 0)
                return 2;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (argv[i][0] != '-' && !study) {
            study = argv[i];
        } else if (argv[i][0] != '-' && !file) {
            file = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!study || !file)
        return cli_usage_error(usage, "give a study name and a file");
    if (o.hmap && strcmp(o.hmap, "value") && strcmp(o.hmap, "inverse") && strcmp(o.hmap, "cells"))
        return cli_usage_error(usage, "--h: give value, inverse or cells, not '%s'", o.hmap);
    if ((o.hmap || o.dim || o.volume > 0) && !o.resolution)
        return cli_usage_error(usage, "--h, --dim and --volume go with --resolution");
    if (json < 0)
        json = ends_with(file, ".json") || ends_with(file, ".yaml") || ends_with(file, ".yml");
    o.study = study;
    struct err e = {0};
    struct import_set s;
    int rc = import_parse(file, json, &s, &e);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    sqlite3 *db = NULL;
    struct import_result res;
    struct stat sb;
    if (stat(db_path, &sb) != 0) {
        /* no database yet: check the whole import on an empty scratch one
         * first, so a bad file creates no database file */
        rc = dry_run(&s, &o, &res, &e);
    }
    if (!rc)
        rc = db_open(db_path, &db, &e);
    if (!rc)
        rc = import_store(db, &s, &o, &res, &e);
    db_close(&db);
    import_set_free(&s);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    printf("imported %d row%s (%d value%s) of source '%s' into study %s%s%s; cascade report %s "
           "shows them\n",
           res.nrows, res.nrows == 1 ? "" : "s", res.nvalues, res.nvalues == 1 ? "" : "s",
           res.source, study, res.created ? " (created: references only)" : "",
           res.replaced ? " (replacing the earlier import of that source)" : "", study);
    return 0;
}
