/* report_run: load, analyse and write a study report (see report_run.h). */
#include "report_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "launch.h"
#include "rdata_ref.h"
#include "refine_state.h"
#include "report_build.h"
#include "report_extra.h"
#include "report_json.h"
#include "sysinfo.h"
#include "util/mem.h"
#include "util/yamldoc.h"

/* The study's own `metrics:` order, then the report's.  The study text
 * was read before (report_spec_from_text): failing now means no memory. */
static int order_metrics(struct report_ctx *c, struct err *e)
{
    json_t *doc = NULL;
    struct locmap *locs = NULL;
    const char *text = c->d.spec_text ? c->d.spec_text : "";
    int rc = yamldoc_load_string(text, strlen(text), "study", &doc, &locs, e);
    if (!rc) {
        json_t *list = json_object_get(doc, "metrics");
        size_t n = json_is_array(list) ? json_array_size(list) : 0;
        const char **names = mem_calloc(n + 1, sizeof *names);
        int k = 0;
        for (size_t i = 0; names && i < n; i++)
            if (json_is_string(json_array_get(list, i)))
                names[k++] = json_string_value(json_array_get(list, i));
        if (names)
            rdata_order_metrics(&c->d, names, k);
        else
            rc = err_nomem(e, "metric order");
        free(names);
    }
    json_decref(doc);
    locmap_destroy(&locs);
    if (!rc && c->rs->metrics)
        rdata_order_metrics(&c->d, (const char *const *)c->rs->metrics, c->rs->nmetrics);
    return rc;
}

/* Which rows to analyse: the campaign's, or one imported source's; then
 * the reference rows and the refinement state for the report. */
static int report_pick_source(struct report_ctx *c, sqlite3 *db, const char *source,
                              struct err *e)
{
    int rc = 0;
    long sweep = 0;
    for (long j = 0; j < c->d.njobs; j++)
        sweep += !c->d.jobs[j].prep;
    if (!source || strcmp(source, "campaign") == 0) {
        json_t *names = NULL;
        if (!source && sweep == 0 && (rc = rdata_sources(db, c->d.study_id, &names, e)) == 0) {
            if (json_array_size(names) == 1)
                source = json_string_value(json_array_get(names, 0));
            else if (json_array_size(names) > 1) {
                char *list = json_dumps(names, JSON_COMPACT);
                rc = err_set(e, ERR_INPUT, "study %s has no runs of its own and %zu imported "
                                           "sources %s: choose one with --source",
                             c->d.name, json_array_size(names), list ? list : "");
                free(list);
            }
        }
        if (!rc && source && strcmp(source, "campaign") != 0)
            rc = rdata_use_source(db, &c->d, source, e);
        snprintf(c->source, sizeof c->source, "%s", source ? source : "campaign");
        json_decref(names);
    } else {
        rc = rdata_use_source(db, &c->d, source, e);
        snprintf(c->source, sizeof c->source, "%s", source);
    }
    if (!rc && strcmp(c->source, "campaign") == 0)
        rc = rdata_ref_rows(db, c->d.study_id, &c->refs, e);
    if (!rc)
        rc = refine_state_json(db, c->d.study_id, &c->refine, e);
    return rc;
}

int report_load(struct report_ctx *c, sqlite3 *db, const char *name, const struct report_spec *rs,
                struct err *e)
{
    return report_load_source(c, db, name, NULL, rs, e);
}

int report_load_source(struct report_ctx *c, sqlite3 *db, const char *name, const char *source,
                       const struct report_spec *rs, struct err *e)
{
    memset(c, 0, sizeof *c);
    report_spec_init(&c->own);
    int rc = rdata_load(db, name, &c->d, e);
    if (rc)
        return rc;
    c->loaded = 1;
    if ((rc = report_pick_source(c, db, source, e)))
        return rc;
    if (rs) {
        c->rs = rs;
    } else {
        const char *text = c->d.spec_text ? c->d.spec_text : "";
        char shown[4200];
        snprintf(shown, sizeof shown, "%s (as registered)", c->d.spec_path ? c->d.spec_path : name);
        if ((rc = report_spec_from_text(text, strlen(text), shown, &c->own, e)))
            return rc;
        c->rs = &c->own;
    }
    if ((rc = order_metrics(c, e)))
        return rc;
    rc = sa_build(&c->a, &c->d, c->rs, e);
    if (!rc) {
        c->analysed = 1;
        c->a.refine = c->refine;
    }
    if (!rc && c->refs)
        rdata_ref_compare(c->refs, &c->a);
    return rc;
}

int report_emit(struct report_ctx *c, const char *dir, int md, int html, const char *db_path,
                struct err *e)
{
    int rc = launch_mkdirs(dir, e);
    if (rc)
        return rc;
    if (!c->doc) {
        char title[256];
        snprintf(title, sizeof title, "Study %s: results and convergence", c->d.name);
        c->doc = rdoc_create(title);
        if (!c->doc)
            return err_nomem(e, "report");
    }
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    struct report_info ri = {db_path, now};
    if (md || html)
        rc = report_build(c->doc, &c->a, &ri, dir, e);
    if (!rc && (md || html))
        report_extra_sections(c->doc, c->refs, c->refine);
    if (!rc && (md || html))
        rc = report_write(c->doc, dir, md, html, e);
    if (!rc) {
        json_t *doc = report_json(&c->a, c->source, now, json_incref(c->refs),
                                  json_incref(c->refine));
        char path[4096 + 16];
        snprintf(path, sizeof path, "%s/report.json", dir);
        rc = doc ? report_json_write(doc, path, e) : err_nomem(e, "report.json");
        json_decref(doc);
    }
    return rc;
}

void report_ctx_free(struct report_ctx *c)
{
    if (c->analysed)
        sa_free(&c->a);
    if (c->loaded)
        rdata_free(&c->d);
    report_spec_free(&c->own);
    rdoc_destroy(&c->doc);
    json_decref(c->refs);
    json_decref(c->refine);
    memset(c, 0, sizeof *c);
}
