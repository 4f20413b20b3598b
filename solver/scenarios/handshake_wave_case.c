/*
 * handshake_wave_case: a step stress wave from the MPM into the MD (Guo &
 * Yang 2005, section 2.3, Figs. 3-7), `type: handshake_wave`.
 *
 * A bar along [100]: MPM | handshake | MD | handshake | MPM, coarsening
 * hierarchically towards both ends, lateral faces sliding in the MPM and
 * periodic in the MD, the x_lo face sliding, 0 K.  At t = 0 a uniform
 * traction (500 MPa tension in the paper) is switched on over the last
 * layer of cells at the x_hi end; the step wave runs through the right
 * MPM part, the MD region and into the left MPM part.  The analytical
 * solution (from the MPM's elastic constants, as in the paper) is a step
 * sigma_xx = traction moving at c = sqrt(C_L / rho); behind it the lateral
 * stress sigma_zz is C_xz / C_L sigma_xx (uniaxial strain).  Along [100]
 * C_L = C11 and C_xz = C12; along [110] C_L = (C11 + C12 + 2 C44) / 2 and
 * C_xz = C12 (z along [001]).
 *
 *   load: {traction: 0.5, ramp: 0}   GPa (tension > 0), ps to full value
 *   probes: {every: 10}              steps between probe samples
 *   + the sections of handshake_case.h (elastic.c11_scale: 2 is Fig. 5/6)
 *
 * Measured (result.json):
 *   front_speed_md        from the times the MD probe slabs (2 lattice
 *                         constants thick, a quarter of the MD length in
 *                         from each interface) reach half the traction;
 *   front_speed_error     relative to the analytical speed;
 *   sxx_md_right / sxx_mpm_right (and _left): time averages of sigma_xx
 *                         over the 4 lattice constants on each side of the
 *                         interface, over the samples after the front has
 *                         passed it by 6 lattice constants and before its
 *                         reflection returns; sxx_jump = the larger
 *                         |MD - MPM| of the two interfaces;
 *   sxx_noise_md          standard deviation of sigma_xx of the MD slabs
 *                         behind the front over those samples: the MD
 *                         fluctuation level the jump is compared with
 *                         (sxx_jump_over_noise);
 *   szz_md_right, szz_mpm_right, szz_jump_right and the values the elastic
 *                         constants predict (impedance mismatch when the
 *                         constants differ).
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/wave_arrival.h"
#include "analysis/wave_front.h"
#include "core/units.h"
#include "scenarios/handshake_case.h"

struct front {
    double L, xr, xl, c_mpm, c_md;
};

struct analytic_ctx {
    double L, c, s0, t;
};

/* Running sums of a windowed time average. */
struct avg {
    double sum, sum2;
    long n;
};

enum { W_SXX_MD_R, W_SXX_MPM_R, W_SXX_MD_L, W_SXX_MPM_L, W_NOISE, W_SZZ_MD_R, W_SZZ_MPM_R, W_NAVG };

struct wave_case {
    struct hs_case c;
    double traction;      /* eV/Å^3 */
    double ramp;          /* ps */
    long probe_every;
    /* set up when the run starts */
    struct front fr;
    struct analytic_ctx an;
    double px[4];         /* probe positions (Å) */
    int nfp;              /* MD front probes (analysis/wave_front.h) */
    double *fx;           /* their positions (Å) */
    double *fs;           /* nsamp x nfp: their sigma_xx samples */
    long nsamp;           /* room for probe samples */
    double *ts;           /* sample times, then the 4 probes' series (nsamp each) */
    /* accumulated over the run (checkpointed) */
    long ns;              /* samples taken */
    struct avg avg[W_NAVG];
    double probe_now[4];  /* the probes at the last sample (thermo columns) */
};
_Static_assert(offsetof(struct wave_case, c) == 0, "hs_case first");

static int wave_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct wave_case *w = calloc(1, sizeof *w);
    if (!w)
        return err_nomem(root->cfg->err, "handshake_wave case");
    struct hs_case *c = &w->c;
    double regions[3] = {2, 2, 2};
    memcpy(c->regions, regions, sizeof regions);
    c->cell = 1;
    c->fine = 8;
    c->levels = 2;
    c->coarsen = 7;
    c->layer = 8;
    c->dt = 0.001;
    c->steps = 6000;
    c->skin = 1.0;
    c->slab = 1;
    c->profile_every = 250;
    c->bar_mpm[0] = c->bar_mpm[1] = 32;
    c->bar_md = 32;
    c->bar_width = 8;
    struct cfg_obj o;
    double t = 0;   /* read below; an error path leaves it unused */
    int rc = hs_case_read(root, c);
    if (!rc && !(rc = cfg_section(root, "load", &o)) &&
        !(rc = cfg_real(&o, "traction", 0.5, CFG_ANY, &t)) &&
        !(rc = cfg_real(&o, "ramp", 0, CFG_GE(0), &w->ramp)))
        rc = cfg_close(&o);
    w->traction = t / UNITS_EVA3_TO_GPA;
    if (!rc && !(rc = cfg_section(root, "probes", &o)) &&
        !(rc = cfg_int(&o, "every", 10, CFG_GE(1), &w->probe_every)))
        rc = cfg_close(&o);
    if (!rc && !root->cfg->shallow)
        rc = hs_case_build(c, MPM_FACE_FREE, 1, common);
    if (rc || root->cfg->shallow) {
        hs_case_free(c);
        free(w);
        return rc;
    }
    *state = w;
    return 0;
}

/* Where the front is at time t (Å), travelling from the x_hi end at the
 * MPM's speed, through the MD at the MD's speed, and on at the MPM's. */
static double front_x(const struct front *f, double t)
{
    double tr = (f->L - f->xr) / f->c_mpm;
    if (t <= tr)
        return f->L - f->c_mpm * t;
    double tl = tr + (f->xr - f->xl) / f->c_md;
    if (t <= tl)
        return f->xr - f->c_md * (t - tr);
    return f->xl - f->c_mpm * (t - tl);
}

static double step_analytic(const void *ctx, double x)
{
    const struct analytic_ctx *a = ctx;
    return x > a->L - a->c * a->t ? a->s0 : 0.0;
}

static void avg_add(struct avg *a, double x)
{
    if (!isfinite(x))
        return;
    a->sum += x;
    a->sum2 += x * x;
    a->n++;
}
static double avg_mean(const struct avg *a) { return a->n ? a->sum / a->n : NAN; }
static double avg_std(const struct avg *a)
{
    if (a->n < 2)
        return NAN;
    double m = a->sum / a->n;
    return sqrt(fmax(0.0, a->sum2 / a->n - m * m));
}

static const int psrc[4] = {HS_SRC_MD, HS_SRC_MD, HS_SRC_MPM, HS_SRC_MPM};

/* The probes and the windowed averages at step `step` (the state is that
 * of the step), and the profile when it is due. */
static int wave_sample(struct wave_case *w, struct run *run, long step, struct err *e)
{
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    const struct front *fr = &w->fr;
    const double a = c->unit[0], margin = 6 * a, side = 4 * a;   /* a along [100] */
    int probe = step % w->probe_every == 0 || step == c->steps;
    int prof = run_due(step, c->steps, c->profile_every);
    int rc = 0;
    if (probe || prof) {
        timer_start(&run->timers, TIMER_ANALYSIS);
        hs_profile_compute(&c->prof, hs);
        for (int k = 0; k < 4; k++)
            hs_profile_mean(&c->prof, psrc[k], 0, w->px[k] - a, w->px[k] + a, &w->probe_now[k]);
        if (probe && w->ns < w->nsamp) {
            w->ts[w->ns] = hs->time;
            for (int k = 0; k < 4; k++)
                w->ts[(k + 1) * w->nsamp + w->ns] = w->probe_now[k];
            for (int k = 0; k < w->nfp; k++)
                hs_profile_mean(&c->prof, HS_SRC_MD, 0, w->fx[k] - a, w->fx[k] + a,
                                &w->fs[w->ns * w->nfp + k]);
            w->ns++;
        }
        double xf = front_x(fr, hs->time);
        struct avg *av = w->avg;
        if (probe && xf > 0) {   /* before the front reaches the x_lo face */
            double v;
            if (xf < fr->xr - margin) {
                hs_profile_mean(&c->prof, HS_SRC_MD, 0, fr->xr - side, fr->xr, &v);
                avg_add(&av[W_SXX_MD_R], v);
                hs_profile_mean(&c->prof, HS_SRC_MPM, 0, fr->xr, fr->xr + side, &v);
                avg_add(&av[W_SXX_MPM_R], v);
                hs_profile_mean(&c->prof, HS_SRC_MD, 2, fr->xr - side, fr->xr, &v);
                avg_add(&av[W_SZZ_MD_R], v);
                hs_profile_mean(&c->prof, HS_SRC_MPM, 2, fr->xr, fr->xr + side, &v);
                avg_add(&av[W_SZZ_MPM_R], v);
                /* MD slabs behind the front */
                for (long k = 0; k < c->prof.nbins; k++) {
                    double x = hs_profile_x(&c->prof, k);
                    if (c->prof.md[k].n > 0 && x > fmax(xf + margin, fr->xl) && x < fr->xr)
                        avg_add(&av[W_NOISE], c->prof.md[k].stress[0]);
                }
            }
            if (xf < fr->xl - margin) {
                hs_profile_mean(&c->prof, HS_SRC_MD, 0, fr->xl, fr->xl + side, &v);
                avg_add(&av[W_SXX_MD_L], v);
                hs_profile_mean(&c->prof, HS_SRC_MPM, 0, fr->xl - side, fr->xl, &v);
                avg_add(&av[W_SXX_MPM_L], v);
            }
        }
        timer_stop(&run->timers, TIMER_ANALYSIS);
    }
    if (prof) {
        timer_start(&run->timers, TIMER_OUTPUT);
        w->an.t = hs->time;
        rc = hs_case_profile(c, run, step_analytic, &w->an, e);
        timer_stop(&run->timers, TIMER_OUTPUT);
    }
    return rc;
}

static const char *const probe_cols[] = {"sxx_probe_md1_GPa", "sxx_probe_md2_GPa",
                                         "sxx_probe_mpm1_GPa", "sxx_probe_mpm2_GPa"};

static int wave_begin(void *state, struct sim *s, struct err *e)
{
    struct wave_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    struct run *run = s->run;
    int rc = hs_case_output_begin(c, run, probe_cols, 4, e);
    if (rc)
        return rc;
    run_log(run,
            "handshake_wave: %ld atoms (%ld in region I), %ld material points (%ld in II, %ld "
            "in III), %ld nodes; c_MPM = %.1f m/s, c_MD = %.1f m/s, traction %.4g GPa",
            hs->counts[HS_CORE] + hs->counts[HS_I], hs->counts[HS_I], hs->npoints,
            hs->counts[HS_II], hs->counts[HS_III], hs->mpm.grid.nnodes,
            w->fr.c_mpm * UNITS_APS_TO_MS, w->fr.c_md * UNITS_APS_TO_MS,
            w->traction * UNITS_EVA3_TO_GPA);
    return s->restarted_from < 0 ? wave_sample(w, run, 0, e) : 0;
}

static int wave_after_step(void *state, struct sim *s, struct err *e)
{
    return wave_sample(state, s->run, s->step, e);
}

static int wave_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct wave_case *w = state;
    int rc = 0;
    if (due & SIM_DUE_THERMO) {
        double row[4];
        for (int k = 0; k < 4; k++)
            row[k] = w->probe_now[k] * UNITS_EVA3_TO_GPA;
        rc = hs_case_thermo(&w->c, s->run, row, 4, e);
    }
    if (!rc && (due & SIM_DUE_SNAPSHOT))
        rc = hs_case_snapshot(&w->c, s->run, e);
    return rc;
}

/* The threshold-free front speed in the MD (analysis/wave_front.h):
 * sigma_xx of MD slabs 2a thick every a/2 between the two MD probes, the
 * time each first reaches f = 0.1/0.2/0.5 of its own peak, fitted over the
 * slabs.  Each slab's peak is taken before the wave reflected at the x_lo
 * face can return (at 1.15 times the faster of the two speeds).  The
 * lateral faces are periodic (MD) and sliding (MPM): uniaxial strain, no
 * free lateral surface, so the front is longitudinal and no bar speed
 * applies. */
static void front_fit_report(const struct wave_case *w, struct result *res)
{
    const struct front *fr = &w->fr;
    const int np = w->nfp;
    double *x = malloc((size_t)(np ? np : 1) * 2 * sizeof *x);
    if (!x)
        return;
    double *tmax = x + (np ? np : 1);
    double cmax = 1.15 * fmax(fr->c_mpm, fr->c_md);
    double t_lo = (fr->L - fr->xr) / fr->c_mpm + (fr->xr - fr->xl) / fr->c_md + fr->xl / fr->c_mpm;
    for (int k = 0; k < np; k++) {
        x[k] = fr->L - w->fx[k];   /* distance from the loaded end: the front moves to -x */
        tmax[k] = t_lo + w->fx[k] / cmax;
    }
    /* the step's sign is the traction's: measure +sigma_xx for tension,
     * -sigma_xx for compression */
    double sgn = w->traction < 0 ? -1.0 : 1.0;
    size_t nv = (size_t)(w->ns ? w->ns : 1) * (size_t)(np ? np : 1);
    double *sig = malloc(nv * sizeof *sig);
    if (!sig) {
        free(x);
        return;
    }
    for (long j = 0; j < w->ns * np; j++)
        sig[j] = sgn * w->fs[j];
    struct wave_front_result r;
    /* a step: its peak is the largest value of the window */
    wave_front_measure(w->ts, w->ns, sig, np, x, tmax, 0.0, &r);
    free(sig);
    const double ms = UNITS_APS_TO_MS;
    result_metric(res, "wave_speed", r.speed * ms, "m/s");
    result_metric(res, "wave_speed_fit", r.speed_fit * ms, "m/s");
    result_metric(res, "wave_speed_stderr", r.stderr_ * ms, "m/s");
    result_metric(res, "wave_speed_spread", r.spread, "1");
    result_metric(res, "wave_speed_flag", (double)r.flag, "1");
    result_metric(res, "wave_speed_probes", (double)r.fit[WAVE_FRONT_PRIMARY].nprobes, "1");
    result_metric(res, "wave_speed_error", (r.speed_fit - fr->c_mpm) / fr->c_mpm, "1");
    double v[WAVE_FRONT_NFRAC];
    for (int q = 0; q < WAVE_FRONT_NFRAC; q++)
        v[q] = r.fit[q].speed * ms;
    result_series(res, "front_fractions", wave_front_fractions, WAVE_FRONT_NFRAC, "1");
    result_series(res, "wave_speed_fractions", v, WAVE_FRONT_NFRAC, "m/s");
    /* the two MD probes, each at half its own peak */
    double *p12 = malloc((size_t)(w->ns ? w->ns : 1) * 2 * sizeof *p12), va = NAN;
    if (p12) {
        double *p1 = p12, *p2 = p12 + (w->ns ? w->ns : 1);
        for (long j = 0; j < w->ns; j++) {
            p1[j] = sgn * w->ts[w->nsamp + j];
            p2[j] = sgn * w->ts[2 * w->nsamp + j];
        }
        va = wave_front_arrival_speed(w->ts, w->ns, p1, t_lo + w->px[0] / cmax, p2,
                                      t_lo + w->px[1] / cmax, 0.0, w->px[0] - w->px[1], 0.5, NULL,
                                      NULL);
        free(p12);
    }
    result_metric(res, "wave_speed_arrival", va * ms, "m/s");
    result_metric(res, "longitudinal_speed", fr->c_md * ms, "m/s");
    free(x);
}

static int wave_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct wave_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    const struct front *fr = &w->fr;
    const struct avg *av = w->avg;
    const double G = UNITS_EVA3_TO_GPA;
    const double *ts = w->ts, *ps[4];
    for (int k = 0; k < 4; k++)
        ps[k] = w->ts + (k + 1) * w->nsamp;
    long ns = w->ns;
    const double *px = w->px;
    struct result *res = &s->run->result;
    result_metric(res, "traction", w->traction * G, "GPa");
    result_metric(res, "wave_speed_analytic", fr->c_mpm * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "wave_speed_md_constants", fr->c_md * UNITS_APS_TO_MS, "m/s");
    double thr = 0.5 * w->traction;
    double t1 = wave_arrival_time(ts, ps[0], ns, thr), t2 = wave_arrival_time(ts, ps[1], ns, thr);
    double cmd = wave_speed(px[0] - px[1], t1, t2);
    result_metric(res, "front_speed_md", cmd * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "front_speed_error", (cmd - fr->c_mpm) / fr->c_mpm, "1");
    double t3 = wave_arrival_time(ts, ps[2], ns, thr), t4 = wave_arrival_time(ts, ps[3], ns, thr);
    double cmpm = wave_speed(px[2] - px[3], t3, t4);
    result_metric(res, "front_speed_mpm", cmpm * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "arrival_md1", t1, "ps");
    result_metric(res, "arrival_md2", t2, "ps");
    front_fit_report(w, res);
    double jr = fabs(avg_mean(&av[W_SXX_MD_R]) - avg_mean(&av[W_SXX_MPM_R]));
    double jl = fabs(avg_mean(&av[W_SXX_MD_L]) - avg_mean(&av[W_SXX_MPM_L]));
    double jump = isfinite(jl) ? fmax(jr, jl) : jr;
    result_metric(res, "sxx_md_right", avg_mean(&av[W_SXX_MD_R]) * G, "GPa");
    result_metric(res, "sxx_mpm_right", avg_mean(&av[W_SXX_MPM_R]) * G, "GPa");
    result_metric(res, "sxx_md_left", avg_mean(&av[W_SXX_MD_L]) * G, "GPa");
    result_metric(res, "sxx_mpm_left", avg_mean(&av[W_SXX_MPM_L]) * G, "GPa");
    result_metric(res, "sxx_jump", jump * G, "GPa");
    result_metric(res, "sxx_noise_md", avg_std(&av[W_NOISE]) * G, "GPa");
    result_metric(res, "sxx_plateau_md", avg_mean(&av[W_NOISE]) * G, "GPa");
    result_metric(res, "sxx_jump_over_noise", jump / avg_std(&av[W_NOISE]), "1");
    result_metric(res, "window_samples", (double)av[W_SXX_MD_R].n, "1");
    /* lateral stress: uniaxial strain on each side, sigma_xx carried
     * through the interface with the transmission coefficient of the two
     * impedances (1 when the constants match) */
    double zmd = sqrt(c->cl_md * hs->rho), zmpm = sqrt(c->cl * hs->rho);
    double sxx_t = 2 * zmd / (zmd + zmpm) * w->traction;
    double szz_md = avg_mean(&av[W_SZZ_MD_R]), szz_mpm = avg_mean(&av[W_SZZ_MPM_R]);
    result_metric(res, "szz_md_right", szz_md * G, "GPa");
    result_metric(res, "szz_mpm_right", szz_mpm * G, "GPa");
    result_metric(res, "szz_jump_right", (szz_md - szz_mpm) * G, "GPa");
    result_metric(res, "szz_ratio_md_mpm", szz_md / szz_mpm, "1");
    result_metric(res, "sxx_transmitted_predicted", sxx_t * G, "GPa");
    result_metric(res, "szz_md_predicted", c->cxz_md / c->cl_md * sxx_t * G, "GPa");
    result_metric(res, "szz_mpm_predicted", c->cxz / c->cl * sxx_t * G, "GPa");
    return hs_case_output_end(c, s->run, e);
}

/* The probe samples and the window sums: the series up to the samples
 * taken, the sums as (sum, sum2, n) triples. */
static int wave_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct wave_case *w = state;
    int rc = hs_case_checkpoint_write(&w->c, ck);
    double sums[3 * W_NAVG];
    for (int k = 0; k < W_NAVG; k++) {
        sums[3 * k] = w->avg[k].sum;
        sums[3 * k + 1] = w->avg[k].sum2;
        sums[3 * k + 2] = (double)w->avg[k].n;
    }
    if (!rc) rc = ckpt_put_doubles(ck, "window_sums", sums, 3 * W_NAVG);
    if (!rc) rc = ckpt_put_doubles(ck, "probe_now", w->probe_now, 4);
    if (!rc) rc = ckpt_put_long(ck, "samples", w->ns);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_time", w->ts, w->ns);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_front", w->fs, w->ns * w->nfp);
    for (int k = 0; !rc && k < 4; k++) {
        char name[32];
        snprintf(name, sizeof name, "sample_probe%d", k + 1);
        rc = ckpt_put_doubles(ck, name, w->ts + (k + 1) * w->nsamp, w->ns);
    }
    return rc;
}

static int wave_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct wave_case *w = state;
    int rc = hs_case_checkpoint_read(&w->c, ck, e);
    double sums[3 * W_NAVG];
    if (!rc) rc = ckpt_get_doubles(ck, "window_sums", sums, 3 * W_NAVG);
    for (int k = 0; !rc && k < W_NAVG; k++)
        w->avg[k] = (struct avg){sums[3 * k], sums[3 * k + 1], (long)sums[3 * k + 2]};
    if (!rc) rc = ckpt_get_doubles(ck, "probe_now", w->probe_now, 4);
    long ns = 0;
    if (!rc) rc = ckpt_get_long(ck, "samples", &ns);
    if (!rc && (ns < 0 || ns > w->nsamp))
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld probe samples, at most %ld fit",
                     ck->path, ns, w->nsamp);
    if (!rc) {
        w->ns = ns;
        rc = ckpt_get_doubles(ck, "sample_time", w->ts, ns);
    }
    if (!rc) rc = ckpt_get_doubles(ck, "sample_front", w->fs, ns * w->nfp);
    for (int k = 0; !rc && k < 4; k++) {
        char name[32];
        snprintf(name, sizeof name, "sample_probe%d", k + 1);
        rc = ckpt_get_doubles(ck, name, w->ts + (k + 1) * w->nsamp, ns);
    }
    return rc;
}

static const struct sim_case_ops wave_ops = {
    .begin = wave_begin,
    .after_step = wave_after_step,
    .output = wave_output,
    .report = wave_report,
    .checkpoint_write = wave_checkpoint_write,
    .checkpoint_read = wave_checkpoint_read,
};

static int wave_run(void *state, struct run *run, struct err *e)
{
    struct wave_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    hs->ramp = w->ramp;
    int rc = hs_apply_end_traction(hs, w->traction, e);
    if (rc)
        return rc;
    const double a = c->unit[0];   /* the length unit along the bar: a along [100] */
    w->fr = (struct front){hs_case_length(c), hs_case_x_right(c), hs_case_x_left(c),
                           hs_case_wave_speed(c, c->cl), hs_case_wave_speed(c, c->cl_md)};
    w->an = (struct analytic_ctx){w->fr.L, w->fr.c_mpm, w->traction, 0};
    /* probes: MD a quarter of the MD length in from each interface, MPM 6
     * and 18 lattice constants beyond the left interface */
    double quarter = 0.25 * (w->fr.xr - w->fr.xl);
    double px[4] = {w->fr.xr - quarter, w->fr.xl + quarter, w->fr.xl - 6 * a, w->fr.xl - 18 * a};
    memcpy(w->px, px, sizeof px);
    w->nsamp = c->steps / w->probe_every + 2;
    w->ts = malloc((size_t)w->nsamp * 5 * sizeof *w->ts);
    w->nfp = (int)floor((px[0] - px[1]) / (0.5 * a)) + 1;
    w->fx = malloc((size_t)w->nfp * sizeof *w->fx);
    w->fs = malloc((size_t)w->nsamp * w->nfp * sizeof *w->fs);
    if (!w->ts || !w->fx || !w->fs)
        return err_nomem(e, "probe series");
    for (int k = 0; k < w->nfp; k++)
        w->fx[k] = px[0] - 0.5 * a * k;
    return hs_case_run(c, run, &wave_ops, w, e);
}

static void wave_destroy(void *state)
{
    struct wave_case *w = state;
    if (w) {
        free(w->ts);
        free(w->fx);
        free(w->fs);
    }
    hs_case_destroy(state);
}

const struct case_type handshake_wave_case_type = {
    "handshake_wave",
    "MPM/MD handshake: step stress wave from the MPM into the MD (Guo & Yang 2005, Figs. 4-7)",
    wave_read, wave_run, wave_destroy, hs_case_particles, hs_case_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
