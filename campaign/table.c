/* table: text, CSV and JSON-lines output of SQL rows. */
#include "table.h"

#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "util/canon.h"
#include "util/mem.h"

void table_cell(sqlite3_stmt *st, int col, char *buf, size_t len)
{
    switch (sqlite3_column_type(st, col)) {
    case SQLITE_NULL: buf[0] = '\0'; break;
    case SQLITE_INTEGER: snprintf(buf, len, "%lld", (long long)sqlite3_column_int64(st, col)); break;
    case SQLITE_FLOAT: canon_real(sqlite3_column_double(st, col), buf, len); break;
    default: {
        const char *t = (const char *)sqlite3_column_text(st, col);
        snprintf(buf, len, "%s", t ? t : "");
    }
    }
}

void table_csv_field(FILE *out, const char *s)
{
    if (!strpbrk(s, ",\"\n\r")) {
        fputs(s, out);
        return;
    }
    fputc('"', out);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', out);
        fputc(*s, out);
    }
    fputc('"', out);
}

static json_t *json_cell(sqlite3_stmt *st, int col)
{
    switch (sqlite3_column_type(st, col)) {
    case SQLITE_NULL: return json_null();
    case SQLITE_INTEGER: return json_integer((json_int_t)sqlite3_column_int64(st, col));
    case SQLITE_FLOAT: return json_real(sqlite3_column_double(st, col));
    default: {
        const char *t = (const char *)sqlite3_column_text(st, col);
        return json_string(t ? t : "");
    }
    }
}

/* Display width of UTF-8 text (code points; enough for Å and friends). */
static int width(const char *s)
{
    int w = 0;
    for (; *s; s++)
        w += ((unsigned char)*s & 0xC0) != 0x80;
    return w;
}

static void pad(FILE *out, const char *s, int w)
{
    fputs(s, out);
    for (int k = width(s); k < w; k++)
        fputc(' ', out);
}

#define CELL_MAX 4096

int table_print(sqlite3 *db, sqlite3_stmt *st, enum table_format f, FILE *out, long *nrows,
                struct err *e)
{
    int nc = sqlite3_column_count(st);
    *nrows = 0;
    char cell[CELL_MAX];
    if (f == TABLE_CSV) {
        for (int c = 0; c < nc; c++) {
            if (c)
                fputc(',', out);
            table_csv_field(out, sqlite3_column_name(st, c));
        }
        if (nc)
            fputc('\n', out);
    }
    /* text: buffer rows to size the columns */
    char **cells = NULL;
    long cap = 0, n = 0;
    int *w = mem_calloc((size_t)(nc ? nc : 1), sizeof *w);
    if (!w)
        return err_nomem(e, "table");
    for (int c = 0; c < nc; c++)
        w[c] = width(sqlite3_column_name(st, c));
    int r, rc = 0;
    while ((r = sqlite3_step(st)) == SQLITE_ROW) {
        (*nrows)++;
        if (f == TABLE_CSV) {
            for (int c = 0; c < nc; c++) {
                if (c)
                    fputc(',', out);
                table_cell(st, c, cell, sizeof cell);
                table_csv_field(out, cell);
            }
            fputc('\n', out);
        } else if (f == TABLE_JSON) {
            /* written member by member: columns in their order, reals in
             * the shortest form that reads back (json_dumps writes %.17g:
             * 7.2199999999999998 for 7.22) */
            fputc('{', out);
            for (int c = 0; c < nc; c++) {
                json_t *k = json_string(sqlite3_column_name(st, c)), *v = json_cell(st, c);
                char *kt = k ? canon_json(k) : NULL, *vt = v ? canon_json(v) : NULL;
                fprintf(out, "%s%s:%s", c ? "," : "", kt ? kt : "\"\"", vt ? vt : "null");
                free(kt);
                free(vt);
                json_decref(k);
                json_decref(v);
            }
            fputs("}\n", out);
        } else {
            if ((n + 1) * nc > cap) {
                long ncap = cap ? 2 * cap : 256 * (nc ? nc : 1);
                char **g = mem_realloc(cells, (size_t)ncap * sizeof *g);
                if (!g) {
                    rc = err_nomem(e, "table");
                    break;
                }
                cells = g;
                cap = ncap;
            }
            for (int c = 0; c < nc; c++) {
                table_cell(st, c, cell, sizeof cell);
                for (char *p = cell; *p; p++)   /* one line per row */
                    if (*p == '\n' || *p == '\t')
                        *p = ' ';
                cells[n * nc + c] = mem_strdup(cell);
                int cw = width(cell);
                if (cw > w[c])
                    w[c] = cw > 80 ? 80 : cw;
            }
            n++;
        }
    }
    if (!rc && r != SQLITE_DONE)
        rc = err_set(e, ERR_INPUT, "SQL: %s", sqlite3_errmsg(db));
    if (f == TABLE_TEXT && nc > 0) {
        for (int c = 0; c < nc; c++) {
            pad(out, sqlite3_column_name(st, c), c + 1 < nc ? w[c] : 0);
            fputs(c + 1 < nc ? "  " : "\n", out);
        }
        for (int c = 0; c < nc; c++) {
            for (int k = 0; k < w[c]; k++)
                fputc('-', out);
            fputs(c + 1 < nc ? "  " : "\n", out);
        }
        for (long i = 0; i < n; i++)
            for (int c = 0; c < nc; c++) {
                const char *s = cells[i * nc + c];
                pad(out, s ? s : "", c + 1 < nc ? w[c] : 0);
                fputs(c + 1 < nc ? "  " : "\n", out);
            }
    }
    for (long i = 0; i < n * nc; i++)
        free(cells[i]);
    free(cells);
    free(w);
    return rc;
}
