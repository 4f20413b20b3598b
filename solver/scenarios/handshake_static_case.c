/*
 * handshake_static_case: the quasi-static end-loaded bar (Guo & Yang 2005,
 * section 2.3, Fig. 8), `type: handshake_static`.
 *
 * The bar of handshake_wave, loaded by a traction ramped up at the x_hi
 * end and quieted by damping -- nodal velocity damping in the MPM
 * (mpm.damping) and a force -alpha m v on the MD atoms -- until "all
 * velocities of material points and atoms approach zero and the final
 * solution corresponds to a static loading".  Then sigma_xx should equal
 * the traction everywhere; the paper finds the MD slightly above and the
 * MPM slightly below, by at most 0.36 %.
 *
 *   load: {traction: 0.5, ramp: 5}   GPa, ps
 *   damping: 0.5                     1/ps, both sides
 *   exclude: 8                       lattice constants at the loaded end
 *                                    left out of the deviation ("solutions
 *                                    are usually not very accurate on the
 *                                    boundary just like FE method")
 *
 * Metrics: stress_deviation_md / _mpm / _max: largest |sigma_xx / t - 1|
 * over the MD slabs / MPM slabs of the last profile; sxx_md_mean,
 * sxx_mpm_mean; residual kinetic energy.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "scenarios/handshake_case.h"

struct static_case {
    struct hs_case c;
    double traction;   /* eV/Å^3 */
    double ramp;       /* ps */
    double damping;    /* 1/ps */
    double exclude;    /* lattice constants */
};
/* the shared callbacks (hs_case_destroy, ...) see the struct hs_case */
_Static_assert(offsetof(struct static_case, c) == 0, "hs_case first");

static int static_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct static_case *w = calloc(1, sizeof *w);
    if (!w)
        return err_nomem(root->cfg->err, "handshake_static case");
    struct hs_case *c = &w->c;
    double regions[3] = {2, 2, 2};
    memcpy(c->regions, regions, sizeof regions);
    c->cell = 1;
    c->fine = 6;
    c->levels = 1;
    c->coarsen = 7;
    c->layer = 8;
    c->dt = 0.002;
    c->steps = 20000;
    c->skin = 1.0;
    c->slab = 1;
    c->profile_every = 2000;
    c->bar_mpm[0] = c->bar_mpm[1] = 16;
    c->bar_md = 16;
    c->bar_width = 4;
    struct cfg_obj o;
    double t = 0.5;
    int rc = hs_case_read(root, c);
    if (!rc && !(rc = cfg_section(root, "load", &o)) &&
        !(rc = cfg_real(&o, "traction", 0.5, CFG_ANY, &t)) &&
        !(rc = cfg_real(&o, "ramp", 5, CFG_GE(0), &w->ramp)))
        rc = cfg_close(&o);
    w->traction = t / UNITS_EVA3_TO_GPA;
    if (!rc)
        rc = cfg_real(root, "damping", 0.5, CFG_GT(0), &w->damping);
    if (!rc)
        rc = cfg_real(root, "exclude", 8, CFG_GE(0), &w->exclude);
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

struct const_ctx {
    double s0;
};
static double const_analytic(const void *ctx, double x)
{
    (void)x;
    return ((const struct const_ctx *)ctx)->s0;
}

/* The profile at step `step` when it is due. */
static int static_sample(struct static_case *w, struct run *run, long step, struct err *e)
{
    struct hs_case *c = &w->c;
    if (!run_due(step, c->steps, c->profile_every))
        return 0;
    struct const_ctx an = {w->traction};
    timer_start(&run->timers, TIMER_OUTPUT);
    int rc = hs_case_profile(c, run, const_analytic, &an, e);
    timer_stop(&run->timers, TIMER_OUTPUT);
    return rc;
}

static int static_begin(void *state, struct sim *s, struct err *e)
{
    struct static_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    int rc = hs_case_output_begin(c, s->run, NULL, 0, e);
    if (rc)
        return rc;
    run_log(s->run,
            "handshake_static: %ld atoms, %ld material points, traction %.4g GPa ramped over %g "
            "ps, damping %g /ps",
            hs->counts[HS_CORE] + hs->counts[HS_I], hs->npoints,
            w->traction * UNITS_EVA3_TO_GPA, w->ramp, w->damping);
    return s->restarted_from < 0 ? static_sample(w, s->run, 0, e) : 0;
}

static int static_after_step(void *state, struct sim *s, struct err *e)
{
    return static_sample(state, s->run, s->step, e);
}

static int static_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct static_case *w = state;
    int rc = 0;
    if (due & SIM_DUE_THERMO)
        rc = hs_case_thermo(&w->c, s->run, NULL, 0, e);
    if (!rc && (due & SIM_DUE_SNAPSHOT))
        rc = hs_case_snapshot(&w->c, s->run, e);
    return rc;
}

static int static_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct static_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    const double G = UNITS_EVA3_TO_GPA;
    /* deviation from the applied traction over the last profile */
    struct hs_profile *pr = &c->prof;
    hs_profile_compute(pr, hs);
    double xcut = hs_case_length(c) - w->exclude * c->unit[0];
    double dmd = 0, dmpm = 0, smd = 0, smpm = 0;
    long nmd = 0, nmpm = 0;
    for (long k = 0; k < pr->nbins; k++) {
        double x = hs_profile_x(pr, k);
        if (pr->md[k].n > 0) {
            double r = pr->md[k].stress[0] / w->traction - 1;
            dmd = fmax(dmd, fabs(r));
            smd += pr->md[k].stress[0];
            nmd++;
        }
        if (pr->mpm[k].n > 0 && x < xcut) {
            double r = pr->mpm[k].stress[0] / w->traction - 1;
            dmpm = fmax(dmpm, fabs(r));
            smpm += pr->mpm[k].stress[0];
            nmpm++;
        }
    }
    struct result *res = &s->run->result;
    struct handshake_energy en;
    handshake_energy(hs, &en);
    result_metric(res, "traction", w->traction * G, "GPa");
    result_metric(res, "stress_deviation_md", dmd, "1");
    result_metric(res, "stress_deviation_mpm", dmpm, "1");
    result_metric(res, "stress_deviation_max", fmax(dmd, dmpm), "1");
    result_metric(res, "sxx_md_mean", nmd ? smd / nmd * G : NAN, "GPa");
    result_metric(res, "sxx_mpm_mean", nmpm ? smpm / nmpm * G : NAN, "GPa");
    result_metric(res, "kinetic_residual", en.md_kinetic + en.mpm_kinetic, "eV");
    result_metric(res, "damping", w->damping, "1/ps");
    return hs_case_output_end(c, s->run, e);
}

/* Nothing accumulates but the rows written so far. */
static int static_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct static_case *w = state;
    return hs_case_checkpoint_write(&w->c, ck);
}

static int static_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct static_case *w = state;
    return hs_case_checkpoint_read(&w->c, ck, e);
}

static const struct sim_case_ops static_ops = {
    .begin = static_begin,
    .after_step = static_after_step,
    .output = static_output,
    .report = static_report,
    .checkpoint_write = static_checkpoint_write,
    .checkpoint_read = static_checkpoint_read,
};

static int static_run(void *state, struct run *run, struct err *e)
{
    struct static_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    hs->ramp = w->ramp;
    hs->md_damping = w->damping;
    hs->mpm.damping = w->damping;
    int rc = hs_apply_end_traction(hs, w->traction, e);
    return rc ? rc : hs_case_run(c, run, &static_ops, w, e);
}

const struct case_type handshake_static_case_type = {
    "handshake_static",
    "MPM/MD handshake: quasi-static end-loaded bar with damping (Guo & Yang 2005, Fig. 8)",
    static_read, static_run, hs_case_destroy, hs_case_particles, hs_case_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
