/* fuzz_baseline: regression baselines (studies/baselines/NAME.json) as
 * `cascade regress` reads them: baseline_read, then the comparison with the
 * analysis of a fixed, made-up run of the nightly study (4 time steps x 2
 * potentials, one job failed), the diff table, the report section and the
 * failure list. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "campaign/baseline.h"
#include "campaign/rdata.h"
#include "campaign/report_doc.h"
#include "campaign/report_spec.h"
#include "campaign/study_analysis.h"

static void add_axis(struct rdata *d, const char *name, int grp, const char *values)
{
    struct rd_axis *a = &d->axes[d->naxes++];
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%s", name);
    a->grp = grp;
    a->values = json_loads(values, 0, NULL);
    if (!a->values)
        abort();
}

static void make_rdata(struct rdata *d, const char *name)
{
    static const char *const metrics[] = {"energy_drift", "pe_per_atom", "pressure",
                                          "temperature_mean"};
    static const char *const units[] = {"1", "eV/atom", "GPa", "K"};
    static const char *const pots[] = {
        "{\"file\": \"Cu_mishin1.eam.alloy\", \"style\": \"eam/alloy\"}",
        "{\"style\": \"sutton_chen\"}"};
    static const double dt[] = {0.0005, 0.001, 0.002, 0.004};
    static const int steps[] = {800, 400, 200, 100};
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "%s", name);
    d->nmetrics = 4;
    d->metric = calloc(4, sizeof *d->metric);
    d->unit = calloc(4, sizeof *d->unit);
    d->axes = calloc(3, sizeof *d->axes);
    d->jobs = calloc(8, sizeof *d->jobs);
    if (!d->metric || !d->unit || !d->axes || !d->jobs)
        abort();
    for (int m = 0; m < 4; m++) {
        d->metric[m] = strdup(metrics[m]);
        d->unit[m] = strdup(units[m]);
    }
    add_axis(d, "md.timestep", 0, "[0.0005, 0.001, 0.002, 0.004]");
    add_axis(d, "md.steps", 0, "[800, 400, 200, 100]");
    add_axis(d, "potential", 1, "[{\"file\": \"Cu_mishin1.eam.alloy\", \"style\": \"eam/alloy\"}, "
                                "{\"style\": \"sutton_chen\"}]");
    for (int g = 0; g < 2; g++)
        for (int i = 0; i < 4; i++) {
            struct rd_job *j = &d->jobs[d->njobs];
            j->id = d->njobs + 1;
            snprintf(j->key, sizeof j->key, "%016lx", (unsigned long)d->njobs);
            j->seq = d->njobs;
            char p[256];
            snprintf(p, sizeof p, "{\"md.timestep\": %g, \"md.steps\": %d, \"potential\": %s}",
                     dt[i], steps[i], pots[g]);
            j->params = json_loads(p, 0, NULL);
            int failed = g == 1 && i == 0;
            snprintf(j->state, sizeof j->state, "%s", failed ? "failed" : "done");
            j->attempt = 1;
            j->exit_code = failed ? 3 : 0;
            j->signal = -1;
            j->message = failed ? strdup("exit 3: fuzz") : NULL;
            j->solver = failed ? NULL : strdup("0.1.0 (fuzz)");
            j->val = malloc(4 * sizeof *j->val);
            if (!j->params || !j->val)
                abort();
            double h = dt[i];
            j->val[0] = failed ? NAN : 0.2 * h * h;
            j->val[1] = failed ? NAN : -3.54 + 0.1 * g + 2.0 * h * h;
            j->val[2] = failed ? NAN : 1.5 - 30.0 * h * h;
            j->val[3] = failed ? NAN : 300.0 + 100.0 * h;
            d->njobs++;
        }
}

int fuzz_baseline_one(const uint8_t *data, size_t size)
{
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "baseline.json", data, size, path, sizeof path);
    /* the study the baseline names (the name check itself is one strcmp) */
    char name[128] = "nightly";
    json_t *peek = json_loadb((const char *)data, size, 0, NULL);
    const char *sn = json_string_value(json_object_get(peek, "study"));
    if (sn)
        snprintf(name, sizeof name, "%s", sn);
    json_decref(peek);

    struct err e = {0};
    json_t *b = NULL;
    char *text = NULL;
    int rc = baseline_read(path, name, &b, &text, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        struct rdata d;
        make_rdata(&d, name);
        struct report_spec rs;
        report_spec_init(&rs);
        rs.res_mode = RES_AXIS;
        snprintf(rs.res_axis, sizeof rs.res_axis, "md.timestep");
        rs.order_default = 2;
        rs.order_tol = 0.01;
        struct study_analysis a;
        if (sa_build(&a, &d, &rs, &e) != 0)
            abort();   /* the made-up study is fine */
        struct cmp_report r;
        rc = baseline_compare(b, &a, &rs, &r, &e);
        fuzz_check_error(rc, e.msg);
        if (!rc) {
            FILE *devnull = fopen("/dev/null", "w");
            if (!devnull)
                abort();
            cmp_print(&r, devnull, 1);
            fclose(devnull);
            struct rdoc *doc = rdoc_create("fuzz");
            if (!doc)
                abort();
            const json_t *sv = json_object_get(b, "solver");
            const char *ver = json_string_value(json_object_get(sv, "version"));
            const char *git = json_string_value(json_object_get(sv, "git"));
            char solver[256];
            snprintf(solver, sizeof solver, "%s (%s)", ver ? ver : "?", git ? git : "?");
            cmp_to_doc(&r, doc, path, solver);
            char out[FUZZ_PATH_MAX + 64];
            snprintf(out, sizeof out, "%s/report.md", dir);
            rc = rdoc_write_markdown(doc, out, &e);
            fuzz_check_error(rc, e.msg);
            snprintf(out, sizeof out, "%s/report.html", dir);
            rc = rdoc_write_html(doc, out, &e);
            fuzz_check_error(rc, e.msg);
            rdoc_destroy(&doc);
            json_decref(cmp_failures_json(&r));
            cmp_free(&r);
        }
        sa_free(&a);
        report_spec_free(&rs);
        rdata_free(&d);
    }
    json_decref(b);
    free(text);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(baseline)
