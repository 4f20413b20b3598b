/*
 * The numbers behind `cascade report`, without a database: which axis is
 * the resolution axis and how its values map to h (named axes, cell counts,
 * cutoffs; no guess for a cluster-size study); least-squares fits against a
 * textbook case; the analysis of a hand-made study -- repeats averaged,
 * groups formed from the other axes, observed orders of exact sequences
 * (p = 2 and p = 1 with their extrapolated limits), local orders, flags for
 * oscillatory and divergent sequences and for orders off the formal one, a
 * linear fit against a non-resolution axis; and the `report`/`regress`
 * sections of a study rejected with file:line:col messages.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "campaign/fit.h"
#include "campaign/rdata.h"
#include "campaign/report_spec.h"
#include "campaign/resolution.h"
#include "campaign/study.h"
#include "campaign/study_analysis.h"
#include "helpers/th.h"

static int choose(const char *const *names, const char *const *values, int n,
                  const struct report_spec *rs, struct resolution *r)
{
    struct res_axis_info ai[8] = {{0}};
    json_t *vals[8] = {0};
    for (int i = 0; i < n; i++) {
        vals[i] = json_loads(values[i], 0, NULL);
        cr_assert_not_null(vals[i], "%s", values[i]);
        ai[i] = (struct res_axis_info){names[i], i, 0, vals[i]};
    }
    struct err e = {0};
    int rc = resolution_choose(rs, ai, n, r, &e);
    for (int i = 0; i < n; i++)
        json_decref(vals[i]);
    return rc;
}

Test(report_analysis, resolution_axis_inferred_from_names_only)
{
    struct report_spec rs;
    report_spec_init(&rs);
    struct resolution r;
    /* a time-step study: md.timestep is the axis; the zipped step count is not */
    const char *n1[] = {"md.skin", "md.timestep", "md.steps"};
    const char *v1[] = {"[1.0, 2.0]", "[0.001, 0.002, 0.004]", "[400, 200, 100]"};
    cr_assert_eq(choose(n1, v1, 3, &rs, &r), 0);
    cr_assert_eq(r.axis, 1);
    cr_assert(r.inferred && r.map_inferred && r.hmap == HMAP_VALUE);
    cr_assert_str_eq(r.axis_words, "the time step md.timestep");   /* figure titles */
    /* cluster size x speed with a zipped target size: no resolution axis is guessed */
    const char *n2[] = {"cluster.atoms", "target.cells", "cluster.speed"};
    const char *v2[] = {"[14, 128, 1052]", "[[20,20,14],[26,26,20],[36,36,28]]", "[5.0, 10.0, 15.0]"};
    cr_assert_eq(choose(n2, v2, 3, &rs, &r), 0);
    cr_assert_eq(r.axis, -1);
    cr_assert_not_null(strstr(r.why, "report.resolution"), "%s", r.why);
    /* a spatial grid cell wins over a zipped time step */
    const char *n3[] = {"mpm.grid.cell", "mpm.timestep"};
    const char *v3[] = {"[2.0, 4.0, 8.0]", "[0.001, 0.002, 0.004]"};
    cr_assert_eq(choose(n3, v3, 2, &rs, &r), 0);
    cr_assert_eq(r.axis, 0);
    cr_assert_str_eq(r.axis_words, "the grid size mpm.grid.cell");
    report_spec_free(&rs);
}

Test(report_analysis, resolution_mappings_give_h)
{
    struct report_spec rs;
    report_spec_init(&rs);
    rs.res_mode = RES_AXIS;
    struct resolution r;
    /* cell counts as lists: h = (1/N)^(1/3), N = 4*4*4 */
    snprintf(rs.res_axis, sizeof rs.res_axis, "system.lattice.cells");
    const char *n1[] = {"system.lattice.cells"};
    const char *v1[] = {"[[4,4,4],[8,8,8],[16,16,16]]"};
    cr_assert_eq(choose(n1, v1, 1, &rs, &r), 0);
    cr_assert_eq(r.hmap, HMAP_CELLS);
    cr_assert_str_eq(r.axis_words, "the cell size from system.lattice.cells");
    json_t *v = json_loads("[4,4,4]", 0, NULL);
    cr_assert_float_eq(resolution_h(&r, v), 0.25, 1e-15);
    json_decref(v);
    /* a cutoff: h = 1/rc, inferred from the name */
    snprintf(rs.res_axis, sizeof rs.res_axis, "potential.cutoff");
    const char *n2[] = {"potential.cutoff"};
    const char *v2[] = {"[5.0, 8.0, 10.0]"};
    cr_assert_eq(choose(n2, v2, 1, &rs, &r), 0);
    cr_assert_eq(r.hmap, HMAP_INVERSE);
    cr_assert_str_eq(r.axis_words, "1 / potential.cutoff");
    v = json_real(8.0);
    cr_assert_float_eq(resolution_h(&r, v), 0.125, 1e-15);
    json_decref(v);
    /* a one-element list counts as its number; a named axis that is not swept is an error */
    rs.hmap = HMAP_VALUE;
    snprintf(rs.res_axis, sizeof rs.res_axis, "hugoniot.particle_velocities");
    const char *n3[] = {"hugoniot.particle_velocities"};
    const char *v3[] = {"[[0.5], [1.0], [2.0]]"};
    cr_assert_eq(choose(n3, v3, 1, &rs, &r), 0);
    v = json_loads("[1.5]", 0, NULL);
    cr_assert_float_eq(resolution_h(&r, v), 1.5, 1e-15);
    json_decref(v);
    snprintf(rs.res_axis, sizeof rs.res_axis, "md.dt");
    cr_assert_eq(choose(n3, v3, 1, &rs, &r), ERR_INPUT);
    report_spec_free(&rs);
}

Test(report_analysis, least_squares_fits)
{
    /* y = 0, 1, 3 at x = 0, 1, 2: b = 1.5, a = -1/6, s^2 = SSR/(n-2) = 1/6 */
    double x[3] = {0, 1, 2}, y[3] = {0, 1, 3};
    struct fit_result f;
    cr_assert_eq(fit_points(FIT_LINEAR, x, y, 3, &f), 0);
    cr_assert_float_eq(f.p1, 1.5, 1e-14);
    cr_assert_float_eq(f.p0, -1.0 / 6, 1e-14);
    cr_assert_float_eq(f.s1, sqrt(1.0 / 12), 1e-14);            /* sqrt(s^2 / Sxx), Sxx = 2 */
    cr_assert_float_eq(f.s0, sqrt(1.0 / 6 * (1.0 / 3 + 0.5)), 1e-14);
    cr_assert_float_eq(f.r2, 1 - (1.0 / 6) / (14.0 / 3), 1e-14); /* Syy = 14/3 */
    /* a power law through exact points; two points give no standard errors */
    double u[4] = {1, 2, 4, 8}, w[4];
    for (int i = 0; i < 4; i++)
        w[i] = 0.3 * pow(u[i], 1.7);
    cr_assert_eq(fit_points(FIT_POWER, u, w, 4, &f), 0);
    cr_assert_float_eq(f.p0, 0.3, 1e-12);
    cr_assert_float_eq(f.p1, 1.7, 1e-12);
    cr_assert_eq(fit_points(FIT_LINEAR, u, w, 2, &f), 0);
    cr_assert(isnan(f.s0) && isnan(f.s1));
    cr_assert_eq(fit_points(FIT_LINEAR, (double[]){1, 1}, (double[]){1, 2}, 2, &f), -1);
}

/* --- a hand-made study ------------------------------------------------------ */

static void add_axis(struct rdata *d, const char *name, int grp, int repeat, const char *values)
{
    d->axes = realloc(d->axes, (size_t)(d->naxes + 1) * sizeof *d->axes);
    struct rd_axis *a = &d->axes[d->naxes++];
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%s", name);
    a->grp = grp;
    a->repeat = repeat;
    a->values = json_loads(values, 0, NULL);
    cr_assert_not_null(a->values);
}

static void add_job(struct rdata *d, const char *params, const char *state, const double *vals)
{
    d->jobs = realloc(d->jobs, (size_t)(d->njobs + 1) * sizeof *d->jobs);
    struct rd_job *j = &d->jobs[d->njobs];
    memset(j, 0, sizeof *j);
    j->id = d->njobs + 1;
    snprintf(j->key, sizeof j->key, "%016lx", (unsigned long)d->njobs);
    j->seq = d->njobs;
    j->params = json_loads(params, 0, NULL);
    cr_assert_not_null(j->params, "%s", params);
    snprintf(j->state, sizeof j->state, "%s", state);
    j->exit_code = j->signal = -1;
    j->val = malloc((size_t)d->nmetrics * sizeof *j->val);
    for (int m = 0; m < d->nmetrics; m++)
        j->val[m] = vals ? vals[m] : NAN;
    if (vals)
        j->solver = strdup("test (0)");
    d->njobs++;
}

/* Metrics a, b, c, d along `h` (zipped with `n`), grid axis `g` with two
 * values and two repeats each:
 *   a = 3 + 0.7 h^2 (+ g),    b = 10 - 2 h (repeats differ by +-0.01),
 *   c oscillates, d grows as h falls;  g = 2 loses its finest job. */
static void make_study(struct rdata *d)
{
    memset(d, 0, sizeof *d);
    snprintf(d->name, sizeof d->name, "handmade");
    const char *names[4] = {"a", "b", "c", "d"};
    d->nmetrics = 4;
    d->metric = calloc(4, sizeof *d->metric);
    d->unit = calloc(4, sizeof *d->unit);
    for (int m = 0; m < 4; m++) {
        d->metric[m] = strdup(names[m]);
        d->unit[m] = strdup(m == 0 ? "eV" : "1");
    }
    add_axis(d, "g", 0, 0, "[1, 2]");
    add_axis(d, "x.h", 1, 0, "[0.1, 0.2, 0.4, 0.8]");
    add_axis(d, "x.n", 1, 0, "[8, 4, 2, 1]");
    add_axis(d, "seed", 2, 1, "[1, 2]");
    const double hs[4] = {0.1, 0.2, 0.4, 0.8}, cs[4] = {1.0, 1.2, 0.7, 0.9};
    const int ns[4] = {8, 4, 2, 1};
    for (int g = 1; g <= 2; g++)
        for (int i = 0; i < 4; i++)
            for (int s = 1; s <= 2; s++) {
                char p[160];
                snprintf(p, sizeof p, "{\"g\": %d, \"x.h\": %g, \"x.n\": %d, \"seed\": %d}", g,
                         hs[i], ns[i], s);
                double h = hs[i];
                double v[4] = {3 + 0.7 * h * h + g, 10 - 2 * h + (s == 1 ? 0.01 : -0.01), cs[i],
                               1.0 / h};
                int lost = g == 2 && i == 0;
                add_job(d, p, lost ? "failed" : "done", lost ? NULL : v);
                if (lost)
                    d->jobs[d->njobs - 1].message = strdup("exit 3: fake failure");
            }
}

Test(report_analysis, handmade_study_orders_flags_and_groups)
{
    struct rdata d;
    make_study(&d);
    struct report_spec rs;
    report_spec_init(&rs);
    rs.res_mode = RES_AXIS;
    snprintf(rs.res_axis, sizeof rs.res_axis, "x.h");
    rs.order_default = 2;
    struct study_analysis a;
    struct err e = {0};
    cr_assert_eq(sa_build(&a, &d, &rs, &e), 0, "%s", e.msg);
    cr_assert_eq(a.npts, 8, "repeats averaged into 8 points");
    cr_assert_eq(a.ngroups, 2, "one group per value of g");
    cr_assert_eq(a.nsweep, 16);
    /* a: p = 2 exactly, limit 3 + g, in both groups; g = 2 lost its finest grid */
    struct sa_conv *c = sa_conv_at(&a, 0, 0);
    cr_assert_eq(c->status, SA_OK);
    cr_assert_float_eq(c->c.p, 2.0, 1e-9);
    cr_assert_float_eq(c->c.phi_ext, 4.0, 1e-9);
    cr_assert_float_eq(c->local_p[1], 2.0, 1e-9, "local order of grids 2, 3, 4");
    cr_assert_str_eq(c->flags, "");
    c = sa_conv_at(&a, 0, 1);
    cr_assert_eq(c->npts, 3);
    cr_assert(c->finest_missing);
    cr_assert_float_eq(c->c.phi_ext, 5.0, 1e-9);
    cr_assert_not_null(strstr(c->flags, "finest grid has no value"), "%s", c->flags);
    /* b: the repeats average out: p = 1, limit 10, flagged against the formal order 2 */
    c = sa_conv_at(&a, 1, 0);
    cr_assert_float_eq(c->c.p, 1.0, 1e-9);
    cr_assert_float_eq(c->c.phi_ext, 10.0, 1e-9);
    cr_assert_float_eq(a.pts[a.groups[0].pts[0]].sd[1], sqrt(2) * 0.01, 1e-12);
    cr_assert_not_null(strstr(c->flags, "p far from the formal order 2"), "%s", c->flags);
    /* c oscillates (R = eps21/eps32 = 0.2/-0.5), d diverges */
    c = sa_conv_at(&a, 2, 0);
    cr_assert_eq(c->c.kind, CONV_OSCILLATORY);
    cr_assert_not_null(strstr(c->flags, "oscillatory"));
    cr_assert(c->flagged);
    c = sa_conv_at(&a, 3, 0);
    cr_assert_eq(c->c.kind, CONV_DIVERGENT);
    cr_assert(isnan(c->c.phi_ext));
    cr_assert_not_null(strstr(c->flags, "divergent"));
    /* against the other axis g: finest-grid and extrapolated values of a */
    cr_assert_gt(a.nxplots, 0);
    const struct sa_xplot *xp = &a.xplots[0];
    cr_assert_eq(xp->metric, 0);
    cr_assert_str_eq(d.axes[xp->xaxis].name, "g");
    const struct sa_xseries *xs = &a.xs[xp->first];
    cr_assert_eq(xs->n, 2);
    cr_assert_float_eq(xs->yext[0], 4.0, 1e-9);
    cr_assert_float_eq(xs->yext[1], 5.0, 1e-9);
    cr_assert_float_eq(xs->y[1], 3 + 0.7 * 0.04 + 2, 1e-12, "g = 2: finest grid with a value");
    sa_free(&a);
    /* a linear fit of a's extrapolated value against g: 3 + 1 g */
    rs.fits = calloc(1, sizeof *rs.fits);
    rs.nfits = 1;
    snprintf(rs.fits[0].metric, sizeof rs.fits[0].metric, "a");
    snprintf(rs.fits[0].against, sizeof rs.fits[0].against, "g");
    rs.fits[0].model = FIT_LINEAR;
    rs.fits[0].extrapolated = 1;
    cr_assert_eq(sa_build(&a, &d, &rs, &e), 0, "%s", e.msg);
    xs = &a.xs[a.xplots[0].first];
    cr_assert_eq(xs->fit, 0);
    cr_assert(xs->fit_ok);
    cr_assert_float_eq(xs->fr.p0, 3.0, 1e-9);
    cr_assert_float_eq(xs->fr.p1, 1.0, 1e-9);
    sa_free(&a);
    report_spec_free(&rs);
    /* rdata_free releases what make_study built */
    rdata_free(&d);
}

static const char *study_with(const char *report)
{
    static char text[2048];
    snprintf(text, sizeof text,
             "name: bad\n"
             "base: {type: fake}\n"
             "sweep:\n"
             "  grid:\n"
             "    fake.x: [0.1, 0.2, 0.4]\n"
             "metrics: [sum, x_squared]\n"
             "%s",
             report);
    return text;
}

static void expect_error(const char *report, const char *where, const char *what)
{
    const char *path = th_write_temp(0, "study.yaml", study_with(report));
    struct study s;
    struct err e = {0};
    cr_assert_neq(study_load(&s, path, &e), 0, "accepted:\n%s", report);
    cr_assert_not_null(strstr(e.msg, where), "message '%s' lacks '%s'", e.msg, where);
    cr_assert_not_null(strstr(e.msg, what), "message '%s' lacks '%s'", e.msg, what);
}

Test(report_analysis, report_sections_checked_with_locations)
{
    expect_error("report:\n  resolution: fake.y\n", "study.yaml:8:3: report.resolution",
                 "not a swept key");
    expect_error("report:\n  resolutoin: fake.x\n", "study.yaml:8:3: report.resolutoin",
                 "did you mean 'resolution'");
    expect_error("report:\n  resolution: {axis: fake.x, h: log}\n", "report.resolution.h",
                 "value, inverse, cells");
    expect_error("report:\n  fits:\n    - {metric: pressure, against: fake.x}\n",
                 "report.fits[0]", "'pressure' is not among the study's metrics");
    expect_error("report:\n  fits:\n    - {metric: sum, against: fake.x, names: [a]}\n",
                 "report.fits[0].names", "two parameter names");
    expect_error("report:\n  fits:\n    - {metric: sum, against: fake.x, range: [2, 1]}\n",
                 "report.fits[0].range", "low < high");
    expect_error("regress:\n  tolerances:\n    sum: {abs: -1}\n", "regress.tolerances.sum.abs",
                 ">= 0");
    expect_error("regress:\n  tolerances:\n    sun: {abs: 1}\n", "regress.tolerances.sun",
                 "not among the study's metrics");
    /* a good one */
    const char *path = th_write_temp(0, "study.yaml",
                                     study_with("report:\n  resolution: {axis: fake.x}\n"
                                                "  order: {default: 2, sum: 1}\n"
                                                "regress:\n  tolerances:\n"
                                                "    default: {rel: 1.0e-6}\n"
                                                "    sum: {abs: 0.5, order: 0.2}\n"));
    struct study s;
    struct err e = {0};
    cr_assert_eq(study_load(&s, path, &e), 0, "%s", e.msg);
    cr_assert_eq(s.report.res_mode, RES_AXIS);
    cr_assert_float_eq(report_spec_order(&s.report, "sum"), 1.0, 0);
    cr_assert_float_eq(report_spec_order(&s.report, "x_squared"), 2.0, 0);
    double abs, rel, ord;
    report_spec_tol(&s.report, "sum", &abs, &rel, &ord);
    cr_assert(abs == 0.5 && rel == 1e-6 && ord == 0.2, "%g %g %g", abs, rel, ord);
    report_spec_tol(&s.report, "x_squared", &abs, &rel, &ord);
    cr_assert(abs == 0 && rel == 1e-6 && ord == 0.05, "%g %g %g", abs, rel, ord);
    study_free(&s);
}

/* A Hugoniot-like study: one axis (the piston velocity), metrics up and
 * us = c0 + s up with scatter; the study asks for us against the metric up. */
Test(report_analysis, fit_of_a_metric_against_a_metric)
{
    struct rdata d;
    memset(&d, 0, sizeof d);
    snprintf(d.name, sizeof d.name, "hugoniot");
    d.nmetrics = 2;
    d.metric = calloc(2, sizeof *d.metric);
    d.unit = calloc(2, sizeof *d.unit);
    d.metric[0] = strdup("us");
    d.metric[1] = strdup("up_piston");
    d.unit[0] = strdup("km/s");
    d.unit[1] = strdup("km/s");
    add_axis(&d, "hugoniot.particle_velocities", 0, 0, "[[0.5], [1.0], [1.5], [2.0], [3.0]]");
    const double vp[5] = {0.5, 1.0, 1.5, 2.0, 3.0}, noise[5] = {0.01, -0.02, 0.0, 0.02, -0.01};
    double x[5], y[5];
    for (int i = 0; i < 5; i++) {
        char p[96];
        snprintf(p, sizeof p, "{\"hugoniot.particle_velocities\": [%g]}", vp[i]);
        x[i] = 0.98 * vp[i];
        y[i] = 3.94 + 1.49 * x[i] + noise[i];
        double v[2] = {y[i], x[i]};
        add_job(&d, p, "done", v);
    }
    struct report_spec rs;
    report_spec_init(&rs);
    rs.res_mode = RES_NONE;
    rs.fits = calloc(1, sizeof *rs.fits);
    rs.nfits = 1;
    snprintf(rs.fits[0].metric, sizeof rs.fits[0].metric, "us");
    snprintf(rs.fits[0].against, sizeof rs.fits[0].against, "up_piston");
    rs.fits[0].model = FIT_LINEAR;
    struct study_analysis a;
    struct err e = {0};
    cr_assert_eq(sa_build(&a, &d, &rs, &e), 0, "%s", e.msg);
    cr_assert_null(a.conv, "no resolution axis");
    /* us and up against the axis (its one-element lists read as numbers), and us against up */
    cr_assert_eq(a.nxplots, 3);
    const struct sa_xplot *xp = &a.xplots[2];
    cr_assert_eq(xp->xaxis, -1);
    cr_assert_eq(xp->xmetric, 1);
    const struct sa_xseries *xs = &a.xs[xp->first];
    cr_assert_eq(xs->n, 5);
    struct fit_result want;
    cr_assert_eq(fit_points(FIT_LINEAR, x, y, 5, &want), 0);
    cr_assert(xs->fit_ok);
    cr_assert_float_eq(xs->fr.p0, want.p0, 1e-12);
    cr_assert_float_eq(xs->fr.p1, want.p1, 1e-12);
    cr_assert(fabs(xs->fr.p1 - 1.49) < 3 * xs->fr.s1, "s = %g +- %g", xs->fr.p1, xs->fr.s1);
    cr_assert(fabs(xs->fr.p0 - 3.94) < 3 * xs->fr.s0, "c0 = %g +- %g", xs->fr.p0, xs->fr.s0);
    sa_free(&a);
    /* range: [0.9, 2.0] fits the three middle points only (x = 0.98, 1.47, 1.96) */
    rs.fits[0].has_range = 1;
    rs.fits[0].range[0] = 0.9;
    rs.fits[0].range[1] = 2.0;
    cr_assert_eq(sa_build(&a, &d, &rs, &e), 0, "%s", e.msg);
    xs = &a.xs[a.xplots[2].first];
    cr_assert_eq(xs->n, 5, "the plot keeps every point");
    cr_assert(xs->fit_ok);
    cr_assert_eq(xs->fr.n, 3);
    cr_assert_eq(fit_points(FIT_LINEAR, x + 1, y + 1, 3, &want), 0);
    cr_assert_float_eq(xs->fr.p1, want.p1, 1e-12);
    cr_assert_float_eq(xs->fr.s1, want.s1, 1e-12);
    sa_free(&a);
    report_spec_free(&rs);
    rdata_free(&d);
}
