/* report_json: the numbers of a report as JSON (see report_json.h). */
#include "report_json.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "util/wfile.h"

json_t *report_json_num(double x)
{
    return isfinite(x) ? json_real(x) : json_null();
}

static const char *status_name(enum sa_conv_status s)
{
    return s == SA_OK ? "ok" : s == SA_FEW ? "few" : "error";
}

/* The report's flags, split at "; ". */
static json_t *flag_list(const char *flags)
{
    json_t *l = json_array();
    const char *p = flags;
    while (p && *p) {
        const char *end = strstr(p, "; ");
        size_t n = end ? (size_t)(end - p) : strlen(p);
        json_array_append_new(l, json_stringn(p, n));
        p = end ? end + 2 : NULL;
    }
    return l;
}

static json_t *celik(const struct sa_conv *c)
{
    const struct conv_result *r = &c->c;
    json_t *o = json_object();
    json_object_set_new(o, "h", json_pack("[ooo]", report_json_num(r->h[0]),
                                          report_json_num(r->h[1]), report_json_num(r->h[2])));
    json_object_set_new(o, "phi", json_pack("[ooo]", report_json_num(r->phi[0]),
                                            report_json_num(r->phi[1]),
                                            report_json_num(r->phi[2])));
    json_object_set_new(o, "r21", report_json_num(r->r21));
    json_object_set_new(o, "r32", report_json_num(r->r32));
    json_object_set_new(o, "ratio", report_json_num(r->ratio));
    json_object_set_new(o, "kind", json_string(conv_kind_names[r->kind]));
    json_object_set_new(o, "p", report_json_num(r->p));
    json_object_set_new(o, "iterations", json_integer(r->iterations));
    json_object_set_new(o, "phi_ext", report_json_num(r->phi_ext));
    json_object_set_new(o, "e_a21", report_json_num(r->e_a21));
    json_object_set_new(o, "e_ext21", report_json_num(r->e_ext21));
    json_object_set_new(o, "gci_fine", report_json_num(r->gci_fine));
    json_object_set_new(o, "gci_medium", report_json_num(r->gci_medium));
    json_object_set_new(o, "band", report_json_num(c->abs_unc));
    json_object_set_new(o, "asymptotic", report_json_num(r->asymptotic));
    json_object_set_new(o, "limit_near_zero", json_boolean(c->limit_near_zero));
    return o;
}

static json_t *levels(const struct study_analysis *a, const struct sa_conv *c, int g, int m)
{
    json_t *l = json_array();
    const struct sa_group *gr = &a->groups[g];
    for (int i = 0; i < gr->npts; i++) {
        const struct sa_point *pt = &a->pts[gr->pts[i]];
        json_t *o = json_object();
        json_object_set_new(o, "h", report_json_num(pt->h));
        json_object_set(o, "params", pt->params);
        json_object_set_new(o, "value", report_json_num(pt->mean[m]));
        json_object_set_new(o, "sd", report_json_num(pt->sd[m]));
        json_object_set_new(o, "n", json_integer(pt->n[m]));
        int ci = -1;
        for (int q = 0; q < c->npts; q++)
            if (c->pts[q] == gr->pts[i])
                ci = q;
        json_object_set_new(o, "local_p", report_json_num(ci >= 0 ? c->local_p[ci] : NAN));
        json_object_set_new(o, "local_kind", ci >= 0 && c->local_kind[ci] >= 0
                                                 ? json_string(conv_kind_names[c->local_kind[ci]])
                                                 : json_null());
        json_array_append_new(l, o);
    }
    return l;
}

json_t *report_json(const struct study_analysis *a, const char *source, const char *generated,
                    json_t *references, json_t *refinement)
{
    const struct rdata *d = a->d;
    json_t *doc = json_object();
    json_object_set_new(doc, "format", json_string("cascade-report 1"));
    json_object_set_new(doc, "study", json_string(d->name));
    json_object_set_new(doc, "source", json_string(source ? source : "campaign"));
    json_object_set_new(doc, "generated", json_string(generated ? generated : ""));
    json_t *res = json_object();
    json_object_set_new(res, "axis", a->res.axis >= 0 ? json_string(d->axes[a->res.axis].name)
                                                      : json_null());
    json_object_set_new(res, "h", a->res.axis >= 0 ? json_string(hmap_names[a->res.hmap])
                                                   : json_null());
    json_object_set_new(res, "why", json_string(a->res.why));
    json_object_set_new(doc, "resolution", res);
    json_object_set_new(doc, "safety", report_json_num(a->rs->safety));
    json_object_set_new(doc, "jobs", json_pack("{sI sI}", "sweep", (json_int_t)a->nsweep, "done",
                                               (json_int_t)a->ndone));
    json_t *series = json_array();
    for (int k = 0; a->conv && k < a->nmetrics; k++)
        for (int g = 0; g < a->ngroups; g++) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            int m = a->metrics[k];
            json_t *o = json_object();
            json_object_set_new(o, "metric", json_string(d->metric[m]));
            json_object_set_new(o, "unit", json_string(d->unit[m] && d->unit[m][0] ? d->unit[m]
                                                                                     : "1"));
            json_object_set(o, "series", a->groups[g].params);
            json_object_set_new(o, "status", json_string(status_name(c->status)));
            json_object_set_new(o, "note", json_string(c->note));
            json_object_set_new(o, "levels", levels(a, c, g, m));
            json_object_set_new(o, "celik", c->status == SA_OK ? celik(c) : json_null());
            json_object_set_new(o, "formal_order", report_json_num(c->formal));
            json_object_set_new(o, "flags", flag_list(c->flags));
            json_object_set_new(o, "flagged", json_boolean(c->flagged));
            json_array_append_new(series, o);
        }
    json_object_set_new(doc, "series", series);
    json_object_set_new(doc, "references", references ? references : json_array());
    json_object_set_new(doc, "refinement", refinement ? refinement : json_array());
    return doc;
}

int report_json_write(const json_t *doc, const char *path, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    if (json_dumpf(doc, w.f, JSON_INDENT(1) | JSON_REAL_PRECISION(17)) != 0) {
        wfile_discard(&w);
        return err_set(e, ERR_RUNTIME, "cannot write %s: write error", path);
    }
    return wfile_commit(&w, e);
}
