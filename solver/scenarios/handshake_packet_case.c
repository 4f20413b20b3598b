/*
 * handshake_packet_case: Gaussian wave packets from the MD into the MPM
 * (Guo & Yang 2005, section 2.3, Fig. 9; after Moseler et al.),
 * `type: handshake_packet`.
 *
 * A bar along [100]: MPM on the left (a uniform, refined grid by default:
 * "each particle occupies a mesh"), the handshake, and MD to the right end,
 * where the last `fixed` lattice constants of atoms are held at their
 * sites.  At t = 0 the MD atoms are displaced along x by
 * u = A exp(-(X - X0)^2 / (2 sigma^2)) at rest; the disturbance splits into
 * two packets of equal energy running in opposite directions.  The left
 * one crosses the handshake into the MPM; the right one stays in the MD as
 * the reference.  When the left packet (and the tail the lattice's
 * dispersion drags behind it) has passed into the MPM beyond region III,
 *
 *   reference_energy    excess energy (kinetic + potential above the
 *                       perfect crystal) of the MD atoms right of X0,
 *   reflected_energy    the same left of X0 (what came back),
 *   transmitted_energy  kinetic + strain energy of the MPM,
 *   transmitted_fraction = transmitted / reference,
 *   reflected_fraction   = reflected / reference,
 *   lost_fraction        = 1 - (transmitted + reflected) / reference.
 *
 *   packet: {sigma: 1.5, amplitude: 0.05, center: 20, fixed: 2}
 *           sigma and center (distance of X0 from the interface) in lattice
 *           constants, amplitude in Å, fixed: held layer at the right end
 *   measure_time: 0       ps; 0: when the left packet's centre has passed
 *                         regions II and III by 5 sigma at the MD's speed
 *   md.steps: 0           0: up to the measure time
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "scenarios/handshake_case.h"

struct packet_case {
    struct hs_case c;
    double sigma, amplitude, center, fixed;   /* lattice constants, Å, lattice constants */
    double measure_time;                      /* ps */
    double x0;                                /* Å */
    double e_init;                            /* eV */
    long smeas;                               /* the step the energies are measured at */
    double el, er, etr;                       /* measured (checkpointed): MD left and right
                                                 of X0, MPM (eV) */
};
/* the shared callbacks (hs_case_destroy, ...) see the struct hs_case */
_Static_assert(offsetof(struct packet_case, c) == 0, "hs_case first");

static int packet_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct packet_case *w = calloc(1, sizeof *w);
    if (!w)
        return err_nomem(root->cfg->err, "handshake_packet case");
    struct hs_case *c = &w->c;
    double regions[3] = {2, 2, 2};
    memcpy(c->regions, regions, sizeof regions);
    c->cell = 0.5;
    c->fine = 8;
    c->levels = 0;
    c->coarsen = 1;
    c->layer = 8;
    c->dt = 0.001;
    c->steps = 0;
    c->skin = 1.0;
    c->slab = 0.5;
    c->profile_every = 200;
    c->bar_mpm[0] = 40;
    c->bar_mpm[1] = 0;
    c->bar_md = 64;
    c->bar_width = 3;
    struct cfg_obj o;
    int rc = hs_case_read(root, c);
    if (!rc && !(rc = cfg_section(root, "packet", &o)) &&
        !(rc = cfg_real(&o, "sigma", 1.5, CFG_GT(0), &w->sigma)) &&
        !(rc = cfg_real(&o, "amplitude", 0.05, CFG_GT(0), &w->amplitude)) &&
        !(rc = cfg_real(&o, "center", 20, CFG_GT(0), &w->center)) &&
        !(rc = cfg_real(&o, "fixed", 2, CFG_GE(0), &w->fixed)))
        rc = cfg_close(&o);
    if (!rc)
        rc = cfg_real(root, "measure_time", 0, CFG_GE(0), &w->measure_time);
    if (!rc && c->bar_mpm[1] != 0)
        rc = cfg_error_at(root->cfg, "bar.mpm",
                          "the packet case has MPM on the left only: give [length, 0]");
    const char *un = hs_case_unit_name(c);
    if (!rc && !(w->center + 4 * w->sigma <= c->bar_md - w->fixed))
        rc = cfg_error_at(root->cfg, "packet.center",
                          "the packet (centre %g, 4 sigma = %g %s) must fit in the MD region of "
                          "%g %s without its fixed end (%g)",
                          w->center, 4 * w->sigma, un, c->bar_md, un, w->fixed);
    /* with the automatic measure time the reflected packet must be back
     * left of X0 and the reference packet short of the held end, both 5
     * sigma clear (the lattice's dispersion spreads them), and the
     * transmitted one inside the MPM */
    double travel = w->center + c->regions[1] + c->regions[2] + 5 * w->sigma;
    if (!rc && w->measure_time <= 0 &&
        !(w->center >= c->regions[1] + c->regions[2] + 10 * w->sigma))
        rc = cfg_error_at(root->cfg, "packet.center",
                          "the centre must lie at least regions II + III + 10 sigma = %g %s from "
                          "the interface, so that the reflected packet is back left of it when "
                          "the energies are measured",
                          c->regions[1] + c->regions[2] + 10 * w->sigma, un);
    if (!rc && w->measure_time <= 0 &&
        !(w->center + travel + 5 * w->sigma <= c->bar_md - w->fixed))
        rc = cfg_error_at(root->cfg, "bar.md",
                          "the reference packet would reach the held end before the energies are "
                          "measured: the MD region needs %g %s",
                          w->center + travel + 5 * w->sigma + w->fixed, un);
    if (!rc && w->measure_time <= 0 &&
        !(c->bar_mpm[0] >= travel - w->center + 3 * w->sigma))
        rc = cfg_error_at(root->cfg, "bar.mpm",
                          "the MPM part must hold the transmitted packet: at least %g %s",
                          travel - w->center + 3 * w->sigma, un);
    if (!rc && !(w->center - 6 * w->sigma >= c->regions[0]))
        rc = cfg_error_at(root->cfg, "packet.center",
                          "the packet's centre (%g %s from the interface) must lie 6 sigma (%g) "
                          "beyond region I (%g): it would start inside the handshake",
                          w->center, un, 6 * w->sigma, c->regions[0]);
    if (!rc && !root->cfg->shallow)
        rc = hs_case_build(c, MPM_FACE_FREE, 0, common);
    if (rc || root->cfg->shallow) {
        hs_case_free(c);
        free(w);
        return rc;
    }
    /* the held end (on bricks each rank marks its own atoms; the counts'
     * changes are sums over the ranks) */
    struct particles *p = c->md.p;
    double xf = hs_case_length(c) - w->fixed * c->unit[0];
    const double *x0 = p->fields[c->hs.f_x0].data;
    double held[3] = {0, 0, 0};   /* from region I, from the core, held */
    for (int i = 0; i < p->n_owned; i++)
        if (!(p->mask[i] & (HS_MASK_II | HS_MASK_III)) && x0[3 * i] >= xf) {
            p->mask[i] |= HS_MASK_FIXED;
            p->fields[c->hs.f_region].data[i] = HS_FIXED;
            held[p->mask[i] & HS_MASK_I ? 0 : 1] += 1;
            held[2] += 1;
        }
    if (c->md.halo)
        halo_sum(c->md.halo, held, 3);
    c->hs.counts[HS_I] -= (long)held[0];
    c->hs.counts[HS_CORE] -= (long)held[1];
    c->hs.counts[HS_FIXED] += (long)held[2];
    c->md.frozen_mask |= HS_MASK_FIXED;
    /* the packet: a Gaussian displacement at rest */
    w->x0 = hs_case_x_left(c) + w->center * c->unit[0];
    double s = w->sigma * c->unit[0];
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III | HS_MASK_FIXED))
            continue;
        double d = x0[3 * i] - w->x0;
        p->x[3 * i] += w->amplitude * exp(-d * d / (2 * s * s));
    }
    c->md.nl->nbuilds = 0;
    struct err *e = root->cfg->err;
    if ((rc = md_compute_forces(&c->md, e))) {
        hs_case_free(c);
        free(w);
        return rc;
    }
    struct handshake_energy en;
    handshake_energy(&c->hs, &en);
    w->e_init = en.total;
    double c_md = hs_case_wave_speed(c, c->cl_md);
    if (w->measure_time <= 0)
        w->measure_time =
            (w->center + c->regions[1] + c->regions[2] + 5 * w->sigma) * c->unit[0] / c_md;
    if (c->steps <= 0)
        c->steps = (long)ceil(w->measure_time / c->dt);
    *state = w;
    return 0;
}

/* Excess energy of the MD atoms left and right of X0 (eV); on bricks over
 * every rank's atoms (collective). */
static void md_halves(const struct packet_case *w, double *left, double *right)
{
    const struct hs_case *c = &w->c;
    const struct particles *p = c->md.p;
    const double *x0 = p->fields[c->hs.f_x0].data;
    *left = *right = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III | HS_MASK_FIXED))
            continue;
        const double *v = p->v + 3 * i;
        double e = 0.5 * p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) *
                       UNITS_MVV2E +
                   p->pe[i] - c->hs.cr.pe_ref;
        if (x0[3 * i] < w->x0)
            *left += e;
        else
            *right += e;
    }
    if (c->md.halo) {   /* bricks: every rank's atoms (collective) */
        double s[2] = {*left, *right};
        halo_sum(c->md.halo, s, 2);
        *left = s[0];
        *right = s[1];
    }
}

/* The energies at the measure time (or at the end of a run that stops
 * before it), and the profile when it is due, at step `step`. */
static int packet_sample(struct packet_case *w, struct run *run, long step, struct err *e)
{
    struct hs_case *c = &w->c;
    if (step == w->smeas || (step == c->steps && w->smeas > c->steps)) {
        struct handshake_energy en;
        md_halves(w, &w->el, &w->er);
        handshake_energy(&c->hs, &en);
        w->etr = en.mpm_kinetic + en.mpm_strain;
    }
    if (!run_due(step, c->steps, c->profile_every))
        return 0;
    timer_start(&run->timers, TIMER_OUTPUT);
    int rc = hs_case_profile(c, run, NULL, NULL, e);
    timer_stop(&run->timers, TIMER_OUTPUT);
    return rc;
}

static const char *const energy_cols[] = {"md_left_eV", "md_right_eV", "mpm_eV"};

static int packet_begin(void *state, struct sim *s, struct err *e)
{
    struct packet_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    int rc = hs_case_output_begin(c, s->run, energy_cols, 3, e);
    if (rc)
        return rc;
    run_log(s->run,
            "handshake_packet: %ld atoms, %ld material points, sigma %g a, packet energy %.6g "
            "eV, measured at %.4g ps",
            hs->counts[HS_CORE] + hs->counts[HS_I], hs->npoints, w->sigma, w->e_init,
            w->measure_time);
    return s->restarted_from < 0 ? packet_sample(w, s->run, 0, e) : 0;
}

static int packet_after_step(void *state, struct sim *s, struct err *e)
{
    return packet_sample(state, s->run, s->step, e);
}

static int packet_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct packet_case *w = state;
    int rc = 0;
    if (due & SIM_DUE_THERMO) {
        double l, r;
        md_halves(w, &l, &r);
        struct handshake_energy en;
        handshake_energy(&w->c.hs, &en);
        double row[3] = {l, r, en.mpm_kinetic + en.mpm_strain};
        rc = hs_case_thermo(&w->c, s->run, row, 3, e);
    }
    if (!rc && (due & SIM_DUE_SNAPSHOT))
        rc = hs_case_snapshot(&w->c, s->run, e);
    return rc;
}

static int packet_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct packet_case *w = state;
    double el = w->el, er = w->er, etr = w->etr;
    struct result *res = &s->run->result;
    result_metric(res, "sigma", w->sigma, "a");
    result_metric(res, "packet_energy", w->e_init, "eV");
    result_metric(res, "measure_time", w->measure_time, "ps");
    result_metric(res, "reference_energy", er, "eV");
    result_metric(res, "reflected_energy", el, "eV");
    result_metric(res, "transmitted_energy", etr, "eV");
    result_metric(res, "transmitted_fraction", er > 0 ? etr / er : NAN, "1");
    result_metric(res, "reflected_fraction", er > 0 ? el / er : NAN, "1");
    result_metric(res, "lost_fraction", er > 0 ? 1 - (etr + el) / er : NAN, "1");
    result_metric(res, "reference_fraction_of_packet", w->e_init > 0 ? er / w->e_init : NAN, "1");
    return hs_case_output_end(&w->c, s->run, e);
}

static int packet_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct packet_case *w = state;
    double m[3] = {w->el, w->er, w->etr};
    int rc = hs_case_checkpoint_write(&w->c, ck);
    if (!rc) rc = ckpt_put_doubles(ck, "measured_energies", m, 3);
    return rc;
}

static int packet_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct packet_case *w = state;
    double m[3];
    int rc = hs_case_checkpoint_read(&w->c, ck, e);
    if (!rc) rc = ckpt_get_doubles(ck, "measured_energies", m, 3);
    if (!rc) {
        w->el = m[0];
        w->er = m[1];
        w->etr = m[2];
    }
    return rc;
}

static const struct sim_case_ops packet_ops = {
    .begin = packet_begin,
    .after_step = packet_after_step,
    .output = packet_output,
    .report = packet_report,
    .checkpoint_write = packet_checkpoint_write,
    .checkpoint_read = packet_checkpoint_read,
};

static int packet_run(void *state, struct run *run, struct err *e)
{
    struct packet_case *w = state;
    w->smeas = (long)llround(w->measure_time / w->c.dt);
    return hs_case_run(&w->c, run, &packet_ops, w, e);
}

const struct case_type handshake_packet_case_type = {
    "handshake_packet",
    "MPM/MD handshake: Gaussian wave packets from the MD into the MPM (Guo & Yang 2005, Fig. 9)",
    packet_read, packet_run, hs_case_destroy, hs_case_particles, hs_case_steps,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
