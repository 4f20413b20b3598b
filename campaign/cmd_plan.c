/* cascade plan: a study's jobs and keys, without running anything. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "plan.h"
#include "store.h"
#include "util/canon.h"
#include "util/mem.h"

static const char *usage =
    "usage: cascade plan STUDY.yaml [--json] [--register [--db FILE]] [--solver PATH]\n"
    "\n"
    "Expands the study into jobs, has the solver resolve every case (defaults\n"
    "filled in, keys checked) and prints one line per job: its number, key, kind\n"
    "and swept values.  Errors name the study file, line and column.  Nothing runs.\n"
    "\n"
    "  --json          one JSON object per job (key, kind, params, deps, case)\n"
    "  --register      also record the study and its jobs in the database\n"
    "  --db FILE       the database for --register (default ./" CASCADE_DB_DEFAULT ")\n"
    "  --solver PATH   the solver (default: $CASCADE_SOLVER, or cascade-solver next\n"
    "                  to cascade, or on PATH)\n";

int cmd_plan(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *file = NULL, *db_path = CASCADE_DB_DEFAULT, *solver_path = NULL;
    int json = 0, reg = 0;
    for (int i = 0; i < argc; i++) {
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "--solver", &solver_path))) {
            if (m < 0)
                return 2;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (strcmp(argv[i], "--register") == 0) {
            reg = 1;
        } else if (argv[i][0] != '-' && !file) {
            file = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!file)
        return cli_usage_error(usage, "give a study file");
    struct err e = {0};
    struct study s;
    struct solver sv;
    struct plan p;
    int rc = study_load(&s, file, &e);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    rc = solver_open(&sv, solver_path, &e);
    if (!rc)
        rc = plan_build(&p, &s, &sv, &e);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        study_free(&s);
        return cli_exit_code(rc);
    }
    if (!json) {
        printf("study %s: %ld job%s (%d preparation, %ld sweep); solver %s (%s)\n", s.name,
               p.njobs, p.njobs == 1 ? "" : "s", p.nprep, s.njobs, sv.version, sv.git);
        for (int a = 0; a < s.naxes; a++) {
            /* shortest round-trip reals: 7.22 as written, not 7.2199999999999998 */
            char *vals = canon_json(s.axes[a].values);
            printf("  axis %s (%s, factor %d): %s\n", s.axes[a].path,
                   s.axes[a].kind == AXIS_GRID ? "grid" : s.axes[a].kind == AXIS_ZIP ? "zip"
                                                                                      : "repeat",
                   s.axes[a].group + 1, vals ? vals : "?");
            free(vals);
        }
        printf("%6s  %-16s  %-5s  %s\n", "#", "key", "kind", "parameters");
    }
    for (long j = 0; j < p.njobs; j++) {
        const struct plan_job *pj = &p.jobs[j];
        if (json) {
            json_t *deps = json_array();
            for (int d = 0; d < pj->ndeps; d++)
                json_array_append_new(deps, json_string(p.jobs[pj->deps[d]].key));
            json_t *params = json_loads(pj->params_json, 0, NULL);
            json_t *cs = json_loads(pj->case_json, 0, NULL);
            json_t *o = json_pack("{s:I, s:s, s:s, s:s?, s:o?, s:o, s:o?}", "seq", (json_int_t)j,
                                  "key", pj->key, "kind", pj->prep >= 0 ? "prep" : "sweep",
                                  "name", pj->prep >= 0 ? s.preps[pj->prep].name : NULL, "params",
                                  params, "deps", deps, "case", cs);
            char *text = canon_json(o);   /* keys sorted, reals shortest */
            printf("%s\n", text ? text : "{}");
            free(text);
            json_decref(o);
        } else {
            char lab[1024];
            plan_job_label(&p, j, lab, sizeof lab);
            printf("%6ld  %-16s  %-5s  %s\n", j, pj->key, pj->prep >= 0 ? "prep" : "sweep", lab);
        }
    }
    if (reg) {
        sqlite3 *db = NULL;
        struct store st;
        long long study_id;
        long long *ids = mem_calloc((size_t)p.njobs, sizeof *ids);
        rc = ids ? db_open(db_path, &db, &e) : err_nomem(&e, "job ids");
        if (!rc) {
            rc = store_init(&st, db, &s, &sv, 60, &e);
            if (!rc) {
                rc = store_register(&st, &s, &p, &study_id, ids, &e);
                store_fini(&st);
            }
        }
        db_close(&db);
        free(ids);
        if (rc)
            fprintf(stderr, "error: %s\n", e.msg);
        else
            fprintf(stderr, "registered study %s (%ld jobs) in %s\n", s.name, p.njobs, db_path);
    }
    plan_free(&p);
    study_free(&s);
    return cli_exit_code(rc);
}
