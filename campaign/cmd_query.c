/* cascade query: read-only SQL on the results database. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "db.h"
#include "table.h"
#include "util/mem.h"

static const char *usage =
    "usage: cascade query \"SQL\" [--db FILE] [--csv | --json] [--param NAME=VALUE ...]\n"
    "       cascade query -f FILE.sql [...]      (-f - reads the SQL from stdin)\n"
    "\n"
    "Runs SQL on a read-only connection to the results database and prints the\n"
    "rows as an aligned table (default), CSV or JSON lines.  Several statements\n"
    "may be given; each prints its rows.  A statement that may write (VACUUM,\n"
    "VACUUM INTO, a PRAGMA that sets) is refused before it runs.  Named parameters (:name) take their\n"
    "values from --param (numbers bind as numbers), so the saved queries in\n"
    "db/queries/ run as, for example:\n"
    "  cascade query -f db/queries/metric_vs_param.sql \\\n"
    "      --param study=md_timestep --param metric=energy_drift --param param=md.timestep\n"
    "The tables and views are described in db/README.md.\n";

struct param {
    char name[128];
    char value[1024];
    int used;
};

static void bind_value(sqlite3_stmt *st, int idx, const char *v)
{
    char *end;
    long long i = strtoll(v, &end, 10);
    if (*v && !*end) {
        sqlite3_bind_int64(st, idx, i);
        return;
    }
    double d = strtod(v, &end);
    if (*v && !*end) {
        sqlite3_bind_double(st, idx, d);
        return;
    }
    sqlite3_bind_text(st, idx, v, -1, SQLITE_TRANSIENT);
}

static char *read_file(const char *path)
{
    FILE *f = strcmp(path, "-") == 0 ? stdin : fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0, got;
    char *buf = mem_alloc(cap);
    while (buf && (got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (n + 1 == cap) {
            char *g = mem_realloc(buf, cap *= 2);
            if (!g) {
                free(buf);
                buf = NULL;
            }
            buf = g;
        }
    }
    if (buf)
        buf[n] = '\0';
    if (f != stdin)
        fclose(f);
    return buf;
}

int cmd_query(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    const char *db_path = CASCADE_DB_DEFAULT, *sql_arg = NULL, *file = NULL;
    enum table_format fmt = TABLE_TEXT;
    struct param params[64];
    int np = 0;
    for (int i = 0; i < argc; i++) {
        const char *v;
        int m;
        if ((m = cli_opt(argc, argv, &i, "--db", &db_path)) ||
            (m = cli_opt(argc, argv, &i, "-f", &file)) ||
            (m = cli_opt(argc, argv, &i, "--file", &file))) {
            if (m < 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--param", &v))) {
            if (m < 0)
                return 2;
            const char *eq = strchr(v, '=');
            if (!eq || eq == v || (size_t)(eq - v) >= sizeof params[0].name || np == 64)
                return cli_usage_error(usage, "--param needs NAME=VALUE, got '%s'", v);
            snprintf(params[np].name, sizeof params[np].name, "%.*s", (int)(eq - v), v);
            snprintf(params[np].value, sizeof params[np].value, "%s", eq + 1);
            params[np].used = 0;
            np++;
        } else if (strcmp(argv[i], "--csv") == 0) {
            fmt = TABLE_CSV;
        } else if (strcmp(argv[i], "--json") == 0) {
            fmt = TABLE_JSON;
        } else if (!sql_arg && argv[i][0] != '-') {
            sql_arg = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!sql_arg == !file)
        return cli_usage_error(usage, "give the SQL or -f FILE (one of them)");
    char *text = file ? read_file(file) : mem_strdup(sql_arg);
    if (!text) {
        fprintf(stderr, "error: cannot read %s\n", file ? file : "the query");
        return 2;
    }
    struct err e = {0};
    sqlite3 *db = NULL;
    int rc = db_open_readonly(db_path, &db, &e);
    const char *tail = text;
    int nstmt = 0;
    while (!rc && tail && *tail) {
        sqlite3_stmt *st = NULL;
        const char *next = NULL;
        if (sqlite3_prepare_v2(db, tail, -1, &st, &next) != SQLITE_OK) {
            rc = err_set(&e, ERR_INPUT, "SQL: %s", sqlite3_errmsg(db));
            break;
        }
        tail = next;
        if (!st)   /* only whitespace or comments left */
            break;
        /* The connection is read-only, but SQLite refuses some writes only
         * when they run: VACUUM INTO creates its output file first.  A
         * statement that may write is therefore refused before its first
         * step (EXPLAIN of one only describes it). */
        if (!sqlite3_stmt_readonly(st) && !sqlite3_stmt_isexplain(st)) {
            rc = err_set(&e, ERR_INPUT,
                         "SQL: cascade query runs read-only statements; refused: %.120s",
                         sqlite3_sql(st));
            sqlite3_finalize(st);
            break;
        }
        for (int k = 1; k <= sqlite3_bind_parameter_count(st) && !rc; k++) {
            const char *pname = sqlite3_bind_parameter_name(st, k);
            int found = 0;
            for (int q = 0; pname && q < np; q++)
                if (strcmp(pname + 1, params[q].name) == 0) {
                    bind_value(st, k, params[q].value);
                    params[q].used = found = 1;
                }
            if (!found)
                rc = err_set(&e, ERR_INPUT, "the query needs --param %s=VALUE",
                             pname ? pname + 1 : "?");
        }
        if (!rc) {
            if (nstmt++ && fmt == TABLE_TEXT && sqlite3_column_count(st))
                fputc('\n', stdout);
            long nrows;
            rc = table_print(db, st, fmt, stdout, &nrows, &e);
        }
        sqlite3_finalize(st);
    }
    for (int q = 0; !rc && q < np; q++)
        if (!params[q].used)
            rc = err_set(&e, ERR_INPUT, "--param %s: the query has no parameter :%s",
                         params[q].name, params[q].name);
    db_close(&db);
    free(text);
    if (rc)
        fprintf(stderr, "error: %s\n", e.msg);
    return cli_exit_code(rc);
}
