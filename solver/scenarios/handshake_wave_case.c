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
 * sigma_xx = traction moving at c = sqrt(C11 / rho); behind it the lateral
 * stresses are C12 / C11 sigma_xx (uniaxial strain).
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
#include <stdlib.h>
#include <string.h>

#include "analysis/wave_arrival.h"
#include "core/units.h"
#include "scenarios/handshake_case.h"

struct wave_case {
    struct hs_case c;
    double traction;      /* eV/Å^3 */
    double ramp;          /* ps */
    long probe_every;
};
/* the shared callbacks (hs_case_destroy, ...) see the struct hs_case */
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
    double t;
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
        rc = hs_case_build(c, MPM_FACE_FREE, 1, common->nthreads);
    if (rc || root->cfg->shallow) {
        hs_case_free(c);
        free(w);
        return rc;
    }
    *state = w;
    return 0;
}

struct front {
    double L, xr, xl, c_mpm, c_md;
};

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

struct analytic_ctx {
    double L, c, s0, t;
};
static double step_analytic(const void *ctx, double x)
{
    const struct analytic_ctx *a = ctx;
    return x > a->L - a->c * a->t ? a->s0 : 0.0;
}

/* Running sums of a windowed time average. */
struct avg {
    double sum, sum2;
    long n;
};
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

static int wave_run(void *state, struct run *run, struct err *e)
{
    struct wave_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    c->md.timers = &run->timers;
    hs->mpm.timers = &run->timers;
    hs->ramp = w->ramp;
    int rc = hs_apply_end_traction(hs, w->traction, e);
    if (rc)
        return rc;
    const double a = c->a, G = UNITS_EVA3_TO_GPA;
    struct front fr = {hs_case_length(c), hs_case_x_right(c), hs_case_x_left(c),
                       hs_case_wave_speed(c, hs->cr.c11), hs_case_wave_speed(c, c->md_cr.c11)};
    struct analytic_ctx an = {fr.L, fr.c_mpm, w->traction, 0};
    /* probes: MD a quarter of the MD length in from each interface, MPM 6
     * and 18 lattice constants beyond the left interface */
    double quarter = 0.25 * (fr.xr - fr.xl);
    double px[4] = {fr.xr - quarter, fr.xl + quarter, fr.xl - 6 * a, fr.xl - 18 * a};
    int psrc[4] = {HS_SRC_MD, HS_SRC_MD, HS_SRC_MPM, HS_SRC_MPM};
    long nsamp = c->steps / w->probe_every + 2;
    double *ts = malloc((size_t)nsamp * 5 * sizeof *ts);
    if (!ts)
        return err_nomem(e, "probe series");
    double *ps[4] = {ts + nsamp, ts + 2 * nsamp, ts + 3 * nsamp, ts + 4 * nsamp};
    long ns = 0;
    static const char *const extra[] = {"sxx_probe_md1_GPa", "sxx_probe_md2_GPa",
                                        "sxx_probe_mpm1_GPa", "sxx_probe_mpm2_GPa"};
    rc = hs_case_output_begin(c, run, extra, 4, e);
    struct avg sxx_md_r = {0}, sxx_mpm_r = {0}, sxx_md_l = {0}, sxx_mpm_l = {0}, noise = {0};
    struct avg szz_md_r = {0}, szz_mpm_r = {0};
    double probe_now[4] = {0, 0, 0, 0};
    const double margin = 6 * a, side = 4 * a;
    run_log(run,
            "handshake_wave: %ld atoms (%ld in region I), %ld material points (%ld in II, %ld "
            "in III), %ld nodes; c_MPM = %.1f m/s, c_MD = %.1f m/s, traction %.4g GPa",
            hs->counts[HS_CORE] + hs->counts[HS_I], hs->counts[HS_I], hs->mpm.pts.n,
            hs->counts[HS_II], hs->counts[HS_III], hs->mpm.grid.nnodes, fr.c_mpm * UNITS_APS_TO_MS,
            fr.c_md * UNITS_APS_TO_MS, w->traction * G);
    progress_start(&run->progress, stderr, c->steps, c->dt, run->opt.progress && !run->opt.quiet);
    timer_start(&run->timers, TIMER_LOOP);
    for (long s = 0; s <= c->steps && !rc; s++) {
        if (s > 0 && (rc = handshake_step(hs, e)))
            break;
        int probe = s % w->probe_every == 0 || s == c->steps;
        int prof = run_due(s, c->steps, c->profile_every);
        if (probe || prof) {
            timer_start(&run->timers, TIMER_ANALYSIS);
            hs_profile_compute(&c->prof, hs);
            for (int k = 0; k < 4; k++)
                hs_profile_mean(&c->prof, psrc[k], 0, px[k] - a, px[k] + a, &probe_now[k]);
            if (probe && ns < nsamp) {
                ts[ns] = hs->time;
                for (int k = 0; k < 4; k++)
                    ps[k][ns] = probe_now[k];
                ns++;
            }
            double xf = front_x(&fr, hs->time);
            if (probe && xf > 0) {   /* before the front reaches the x_lo face */
                double v;
                if (xf < fr.xr - margin) {
                    hs_profile_mean(&c->prof, HS_SRC_MD, 0, fr.xr - side, fr.xr, &v);
                    avg_add(&sxx_md_r, v);
                    hs_profile_mean(&c->prof, HS_SRC_MPM, 0, fr.xr, fr.xr + side, &v);
                    avg_add(&sxx_mpm_r, v);
                    hs_profile_mean(&c->prof, HS_SRC_MD, 2, fr.xr - side, fr.xr, &v);
                    avg_add(&szz_md_r, v);
                    hs_profile_mean(&c->prof, HS_SRC_MPM, 2, fr.xr, fr.xr + side, &v);
                    avg_add(&szz_mpm_r, v);
                    /* MD slabs behind the front */
                    for (long k = 0; k < c->prof.nbins; k++) {
                        double x = hs_profile_x(&c->prof, k);
                        if (c->prof.md[k].n > 0 && x > fmax(xf + margin, fr.xl) && x < fr.xr)
                            avg_add(&noise, c->prof.md[k].stress[0]);
                    }
                }
                if (xf < fr.xl - margin) {
                    hs_profile_mean(&c->prof, HS_SRC_MD, 0, fr.xl, fr.xl + side, &v);
                    avg_add(&sxx_md_l, v);
                    hs_profile_mean(&c->prof, HS_SRC_MPM, 0, fr.xl - side, fr.xl, &v);
                    avg_add(&sxx_mpm_l, v);
                }
            }
            timer_stop(&run->timers, TIMER_ANALYSIS);
        }
        timer_start(&run->timers, TIMER_OUTPUT);
        if (prof && !rc) {
            an.t = hs->time;
            rc = hs_case_profile(c, run, step_analytic, &an, e);
        }
        if (!rc && run_due(s, c->steps, run->out.thermo_every)) {
            double row[4];
            for (int k = 0; k < 4; k++)
                row[k] = probe_now[k] * G;
            hs_case_thermo(c, run, row, 4);
        }
        if (!rc && run_due(s, c->steps, run->out.snapshot_every))
            rc = hs_case_snapshot(c, run, e);
        timer_stop(&run->timers, TIMER_OUTPUT);
        progress_update(&run->progress, s);
    }
    timer_stop(&run->timers, TIMER_LOOP);
    progress_finish(&run->progress, hs->step);
    struct result *res = &run->result;
    result_metric(res, "traction", w->traction * G, "GPa");
    result_metric(res, "wave_speed_analytic", fr.c_mpm * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "wave_speed_md_constants", fr.c_md * UNITS_APS_TO_MS, "m/s");
    double thr = 0.5 * w->traction;
    double t1 = wave_arrival_time(ts, ps[0], ns, thr), t2 = wave_arrival_time(ts, ps[1], ns, thr);
    double cmd = wave_speed(px[0] - px[1], t1, t2);
    result_metric(res, "front_speed_md", cmd * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "front_speed_error", (cmd - fr.c_mpm) / fr.c_mpm, "1");
    double t3 = wave_arrival_time(ts, ps[2], ns, thr), t4 = wave_arrival_time(ts, ps[3], ns, thr);
    double cmpm = wave_speed(px[2] - px[3], t3, t4);
    result_metric(res, "front_speed_mpm", cmpm * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "arrival_md1", t1, "ps");
    result_metric(res, "arrival_md2", t2, "ps");
    double jr = fabs(avg_mean(&sxx_md_r) - avg_mean(&sxx_mpm_r));
    double jl = fabs(avg_mean(&sxx_md_l) - avg_mean(&sxx_mpm_l));
    double jump = isfinite(jl) ? fmax(jr, jl) : jr;
    result_metric(res, "sxx_md_right", avg_mean(&sxx_md_r) * G, "GPa");
    result_metric(res, "sxx_mpm_right", avg_mean(&sxx_mpm_r) * G, "GPa");
    result_metric(res, "sxx_md_left", avg_mean(&sxx_md_l) * G, "GPa");
    result_metric(res, "sxx_mpm_left", avg_mean(&sxx_mpm_l) * G, "GPa");
    result_metric(res, "sxx_jump", jump * G, "GPa");
    result_metric(res, "sxx_noise_md", avg_std(&noise) * G, "GPa");
    result_metric(res, "sxx_plateau_md", avg_mean(&noise) * G, "GPa");
    result_metric(res, "sxx_jump_over_noise", jump / avg_std(&noise), "1");
    result_metric(res, "window_samples", (double)sxx_md_r.n, "1");
    /* lateral stress: uniaxial strain on each side, sigma_xx carried
     * through the interface with the transmission coefficient of the two
     * impedances (1 when the constants match) */
    double zmd = sqrt(c->md_cr.c11 * hs->rho), zmpm = sqrt(hs->cr.c11 * hs->rho);
    double sxx_t = 2 * zmd / (zmd + zmpm) * w->traction;
    double szz_md = avg_mean(&szz_md_r), szz_mpm = avg_mean(&szz_mpm_r);
    result_metric(res, "szz_md_right", szz_md * G, "GPa");
    result_metric(res, "szz_mpm_right", szz_mpm * G, "GPa");
    result_metric(res, "szz_jump_right", (szz_md - szz_mpm) * G, "GPa");
    result_metric(res, "szz_ratio_md_mpm", szz_md / szz_mpm, "1");
    result_metric(res, "sxx_transmitted_predicted", sxx_t * G, "GPa");
    result_metric(res, "szz_md_predicted", c->md_cr.c12 / c->md_cr.c11 * sxx_t * G, "GPa");
    result_metric(res, "szz_mpm_predicted", hs->cr.c12 / hs->cr.c11 * sxx_t * G, "GPa");
    free(ts);
    int rc2 = hs_case_output_end(c, run, e);
    return rc ? rc : rc2;
}

const struct case_type handshake_wave_case_type = {
    "handshake_wave",
    "MPM/MD handshake: step stress wave from the MPM into the MD (Guo & Yang 2005, Figs. 4-7)",
    wave_read, wave_run, hs_case_destroy, hs_case_particles, hs_case_steps,
    .checkpoints = 0,
};
