/* report_cli: formats, convergence rows and JSON output of cascade report (see report_cli.h). */
#include "report_cli.h"

#include <stdio.h>
#include <string.h>

#include "conv_store.h"
#include "db.h"

int report_parse_formats(const char *list, int *md, int *html, int *json)
{
    *md = *html = *json = 0;
    char buf[64];
    if (strlen(list) >= sizeof buf)
        return -1;
    snprintf(buf, sizeof buf, "%s", list);
    char *save = NULL;
    for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
        if (strcmp(t, "md") == 0 || strcmp(t, "markdown") == 0)
            *md = 1;
        else if (strcmp(t, "html") == 0)
            *html = 1;
        else if (strcmp(t, "json") == 0)
            *json = 1;
        else
            return -1;
    }
    return *md || *html || *json ? 0 : -1;
}

void report_store_convergence(const struct report_ctx *c, const char *db_path)
{
    if (!c->a.conv)
        return;
    struct err e = {0};
    sqlite3 *db = NULL;
    int rows = 0;
    int rc = db_open(db_path, &db, &e);
    if (!rc)
        rc = conv_store_write(db, &c->a, c->source, &rows, &e);
    db_close(&db);
    if (rc)
        fprintf(stderr, "warning: the convergence table was not written: %s\n", e.msg);
}

int report_print_json(const char *dir, struct err *e)
{
    char path[4096 + 16];
    snprintf(path, sizeof path, "%s/report.json", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return err_set(e, ERR_RUNTIME, "cannot read %s", path);
    char buf[8192];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        fwrite(buf, 1, n, stdout);
    fclose(f);
    fputc('\n', stdout);
    return 0;
}
