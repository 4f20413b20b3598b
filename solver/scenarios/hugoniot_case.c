/*
 * hugoniot_case: the shock Hugoniot of a crystal (`type: hugoniot`), Guo &
 * Yang 2005, section 3.1 and Fig. 10: shock velocity against particle
 * velocity for copper with the Mishin EAM, compared with Mitchell & Nellis.
 *
 *   hugoniot:
 *     lattice: fcc             fcc | bcc
 *     element: Cu
 *     a: 3.615                 Å at 0 K: the starting guess
 *     temperature: 300         K
 *     zero_pressure: true      first find the lattice constant of zero
 *                              pressure at the temperature (thermal_crystal.h)
 *     cells: [100, 8, 8]       cubic cells; the shock runs along x = [100],
 *                              y and z are periodic
 *     piston_cells: 2          thickness of the rigid piston at the low-x end
 *     particle_velocities: [1.0, 2.0]   km/s: one shock per value
 *     fit_range: [1.5, 3.0]    km/s: the points used for Us = c0 + s up
 *     reference_c0: 3.94       km/s: the experimental line the deviations
 *     reference_s: 1.49              are reported against (Mitchell & Nellis 1981)
 *     equilibrate: 2.0         ps of Langevin at the temperature (periodic in x)
 *     damping_time: 0.1        ps
 *     sample_every: 0.05       ps between front detections
 *     bin: 0                   Å, slab width of the profiles (0: a)
 *     fit_start: 0.25          the front is fitted once past this fraction of
 *     stop_at: 0.85            the sample, and the run stops at this one
 *     max_time: 30             ps
 *   potential: {...}
 *   md: {timestep: 0.001, skin: 1.0}
 *   analysis: {structure: {...}}   classes behind the front (default adaptive:
 *                                  a fixed cutoff calls fcc squeezed by 15 %
 *                                  along [100] bcc, see structure.h)
 *   output: {...}
 *
 * Method.  The crystal is thermalised periodic in all three directions,
 * then cut open along x (free ends).  A rigid piston -- the first
 * piston_cells of atoms, all moving at exactly up along +x -- drives a
 * shock into the rest, which is at rest on average (Holian's "piston"; a
 * momentum mirror is the same shock seen from the shocked material).
 * Every sample_every the mean x velocity in slabs of width `bin` is
 * formed and the front located where it reaches up/2, scanning from the
 * undisturbed end (analysis/shock_front.h); the leading edge where it
 * reaches 0.15 up.  Us is the slope of the front position against time
 * while the front crosses fit_start..stop_at of the sample.  Behind the
 * front (the middle 70 % between piston face and front) the pressure
 * tensor comes from the per-atom virial plus the kinetic term about the
 * mean velocity, averaged over the samples after the front passed half
 * the sample; Rankine-Hugoniot predicts Pxx = rho0 Us up (eos.h).  The
 * shear stress tau = (Pxx - (Pyy + Pzz) / 2) / 2 shows whether the
 * shocked crystal has yielded: a perfect crystal at low up can stay
 * elastic, keep its shear stress, and run faster than the experimental
 * (plastic) Hugoniot.
 *
 * Outputs: per velocity (series, in the order given) up_piston_km_s,
 * up_measured_km_s, us_km_s, us_err_km_s, us_leading_km_s, us_reference_km_s,
 * us_deviation, pxx_GPa, pyy_GPa, pzz_GPa, shear_GPa, p_rh_GPa,
 * p_rh_deviation, compression, compression_rh, temperature_K,
 * fcc_fraction, hcp_fraction, bcc_fraction, other_fraction (structure
 * classes in the middle of the shocked region at the end), run_time_ps; metrics c0, s (with errors) from the fit,
 * us_deviation_max and p_rh_deviation_max over the fit range, the lattice
 * constant and density at the temperature, and with a single velocity the
 * values of that velocity.  The front trajectories (front_time_ps_K,
 * front_x_A_K for velocity K, in the order given) are series in
 * result.json and fields.h5, which also has a snapshot at the end of every
 * shock with the fields structure and shocked.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/eos.h"
#include "analysis/shock_front.h"
#include "analysis/structure.h"
#include "core/units.h"
#include "engine/models.h"
#include "md/md_settings.h"
#include "scenarios/case_type.h"
#include "output/md_output.h"
#include "input/md_system.h"
#include "md/md_timestep.h"
#include "scenarios/thermal_crystal.h"

#define GROUP_PISTON (1u << 1)

enum {
    H_UP, H_UPM, H_US, H_USERR, H_USLEAD, H_USREF, H_USDEV, H_PXX, H_PYY, H_PZZ, H_SHEAR, H_PRH,
    H_PRHDEV, H_COMP, H_COMPRH, H_TEMP, H_FCC, H_HCP, H_BCC, H_OTHER, H_TIME, H_NCOL
};
static const char *const hcols[H_NCOL] = {
    "up_piston_km_s", "up_measured_km_s", "us_km_s", "us_err_km_s", "us_leading_km_s",
    "us_reference_km_s", "us_deviation", "pxx_GPa", "pyy_GPa", "pzz_GPa", "shear_GPa", "p_rh_GPa",
    "p_rh_deviation", "compression", "compression_rh", "temperature_K", "fcc_fraction",
    "hcp_fraction", "bcc_fraction", "other_fraction", "run_time_ps"};
/* metric names when the case has one velocity */
static const char *const hmetrics[H_NCOL] = {
    "up_piston", "up_measured", "us", "us_err", "us_leading", "us_reference", "us_deviation", "pxx",
    "pyy", "pzz", "shear", "p_rh", "p_rh_deviation", "compression", "compression_rh",
    "temperature_behind", "fcc_fraction", "hcp_fraction", "bcc_fraction", "other_fraction",
    "run_time"};
static const char *const hunits[H_NCOL] = {
    "km/s", "km/s", "km/s", "km/s", "km/s", "km/s", "1", "GPa", "GPa", "GPa", "GPa", "GPa", "1", "1",
    "1", "K", "1", "1", "1", "1", "ps"};

struct hugoniot {
    struct potential *pot;
    struct thermal_spec th;
    struct structure_params sp;
    double a, piston_cells, bin, sample_every, fit_start, stop_at, max_time;
    double fit_lo, fit_hi, ref_c0, ref_s;
    int zero_pressure;
    double *up;
    size_t nup;
    long steps_done;
    long natoms;
    double (*res)[H_NCOL];
};

static const char *const hlattices[] = {"fcc", "bcc", NULL};

static void hugoniot_destroy(void *state);

static int hugoniot_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct cfg_obj ho, ao, so, po;
    struct md_settings ms;
    int rc, lat, zp;
    const char *element;
    double a, T, piston, bin, every, fstart, stop, tmax, teq, tau, c0, sref, dt, skin;
    static const long cells_def[3] = {100, 8, 8};
    static const double fit_def[2] = {1.5, 3.0};
    long cells[3], max_particles;
    double fit[2], *up = NULL;
    size_t nup = 0;
    if ((rc = cfg_section_required(root, "hugoniot", &ho)) ||
        (rc = cfg_enum(&ho, "lattice", "fcc", hlattices, &lat)) ||
        (rc = cfg_string(&ho, "element", NULL, &element)) ||
        (rc = cfg_real(&ho, "a", CFG_REQUIRED, CFG_GT(0), &a)) ||
        (rc = cfg_real(&ho, "temperature", 300.0, CFG_GE(0), &T)) ||
        (rc = cfg_bool(&ho, "zero_pressure", 1, &zp)) ||
        (rc = cfg_ints(&ho, "cells", 3, cells_def, CFG_RANGE(1, 100000), cells)) ||
        (rc = cfg_real(&ho, "piston_cells", 2.0, CFG_GT(0), &piston)) ||
        (rc = cfg_real_list(&ho, "particle_velocities", 1, CFG_GT(0), &up, &nup)) ||
        (rc = cfg_reals(&ho, "fit_range", 2, fit_def, CFG_GE(0), fit)) ||
        (rc = cfg_real(&ho, "reference_c0", 3.94, CFG_GT(0), &c0)) ||
        (rc = cfg_real(&ho, "reference_s", 1.49, CFG_ANY, &sref)) ||
        (rc = cfg_real(&ho, "equilibrate", 2.0, CFG_GE(0), &teq)) ||
        (rc = cfg_real(&ho, "damping_time", 0.1, CFG_GT(0), &tau)) ||
        (rc = cfg_real(&ho, "sample_every", 0.05, CFG_GT(0), &every)) ||
        (rc = cfg_real(&ho, "bin", 0.0, CFG_GE(0), &bin)) ||
        (rc = cfg_real(&ho, "fit_start", 0.25, CFG_RANGE(0, 0.9), &fstart)) ||
        (rc = cfg_real(&ho, "stop_at", 0.85, CFG_RANGE(0.1, 0.98), &stop)) ||
        (rc = cfg_real(&ho, "max_time", 30.0, CFG_GT(0), &tmax)) ||
        (rc = md_read_max_particles(&ho, &max_particles)))
        goto fail;
    /* before anything is built, also for resolve */
    char what[128];
    snprintf(what, sizeof what, "%ld x %ld x %ld cells of %d atoms are", cells[0], cells[1],
             cells[2], lat == 0 ? 4 : 2);
    if ((rc = md_check_count(&ho, "cells", (double)cells[0] * (double)cells[1] *
                                               (double)cells[2] * (lat == 0 ? 4 : 2),
                             max_particles, what)) ||
        (rc = cfg_close(&ho)))
        goto fail;
    if (!(stop > fstart + 0.1)) {
        rc = cfg_error_at(root->cfg, "hugoniot.stop_at",
                          "stop_at (%g) must exceed fit_start (%g) by at least 0.1", stop, fstart);
        goto fail;
    }
    if (!(fit[1] >= fit[0])) {
        rc = cfg_error_at(root->cfg, "hugoniot.fit_range", "fit_range [%g, %g] is reversed",
                          fit[0], fit[1]);
        goto fail;
    }
    if ((rc = md_settings_read(root, MD_KEY_TIMESTEP | MD_KEY_SKIN, &md_settings_defaults, &ms)))
        goto fail;
    dt = ms.timestep;
    skin = ms.skin;
    struct structure_params def = {lat == 0 ? STRUCT_REF_FCC : STRUCT_REF_BCC, CNA_ADAPTIVE, a, 0, 0,
                                   0, 0.15, 1};
    struct structure_params sp;
    if ((rc = cfg_section(root, "analysis", &ao)) || (rc = cfg_section(&ao, "structure", &so)) ||
        (rc = structure_params_read(&so, &def, &sp)) || (rc = cfg_close(&so)) ||
        (rc = cfg_close(&ao)))
        goto fail;
    /* the piston must leave a sample, and the sample must be wider than
     * two cutoffs across (checked again against the potential below) */
    if (piston >= 0.5 * cells[0]) {
        rc = cfg_error_at(root->cfg, "hugoniot.piston_cells",
                          "a piston of %g cells leaves too little of the %ld-cell sample", piston,
                          cells[0]);
        goto fail;
    }
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot)))
        goto fail;
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        free(up);
        return 0;
    }
    for (int d = 1; d < 3; d++)
        if (cells[d] * a < 2.0 * (pot->cutoff + skin)) {
            rc = cfg_error_at(root->cfg, "hugoniot.cells",
                              "the cross-section (%ld cells = %.1f Å along %c) must be at least two "
                              "cutoffs plus skins (%.1f Å) wide", cells[d], cells[d] * a, "xyz"[d],
                              2.0 * (pot->cutoff + skin));
            potential_destroy(&pot);
            goto fail;
        }
    struct hugoniot *h = calloc(1, sizeof *h);
    if (!h) {
        potential_destroy(&pot);
        rc = err_nomem(root->cfg->err, "hugoniot case");
        goto fail;
    }
    h->pot = pot;
    h->th = (struct thermal_spec){lat == 0 ? LATTICE_FCC : LATTICE_BCC, NULL, {6, 6, 6}, T, dt,
                                  skin, tau, 1.0, 1.0, common->seed, common->nthreads};
    h->th.element = element;   /* borrowed from the document, which outlives the case */
    memcpy(h->th.cells, cells, sizeof cells);
    h->sp = sp;
    h->a = a;
    h->zero_pressure = zp;
    h->piston_cells = piston;
    h->bin = bin > 0 ? bin : a;
    h->sample_every = every;
    h->fit_start = fstart;
    h->stop_at = stop;
    h->max_time = tmax;
    h->fit_lo = fit[0];
    h->fit_hi = fit[1];
    h->ref_c0 = c0;
    h->ref_s = sref;
    h->th.t_eq = teq;
    h->up = up;
    h->nup = nup;
    h->res = calloc(nup, sizeof *h->res);
    h->natoms = cells[0] * cells[1] * cells[2] * (lat == 0 ? 4 : 2);
    if (!h->res) {
        potential_destroy(&h->pot);
        free(h);
        rc = err_nomem(root->cfg->err, "hugoniot case");
        goto fail;
    }
    /* the fastest piston must not outrun the time step */
    double umax = 0;
    for (size_t k = 0; k < nup; k++)
        umax = fmax(umax, up[k] * 10.0);
    struct lattice l = {h->th.style, a, {0, 0, 0}, {{0}}};
    if (umax * dt > 0.1 * lattice_nn_distance(&l)) {
        double lim = 0.1 * lattice_nn_distance(&l) / umax;
        free(h->res);
        potential_destroy(&h->pot);
        free(h);
        rc = cfg_error_at(root->cfg, "md.timestep",
                          "time step %g ps moves the %.3g km/s piston %.3g Å per step, more than "
                          "0.1 of the nearest-neighbour distance; use a time step of at most %.3g ps",
                          dt, umax / 10.0, umax * dt, lim);
        goto fail;
    }
    /* the stability bound of the time step, on a small crystal */
    struct thermal_spec small = h->th;
    small.cells[0] = small.cells[1] = small.cells[2] = 3;
    small.temperature = 0;
    struct md md;
    rc = thermal_crystal_md(&md, h->pot, &small, a, NULL, root->cfg->err);
    if (!rc)
        rc = md_check_timestep(&md, root->cfg, "md.timestep");
    md.pot = NULL;
    md_free(&md);
    if (rc) {
        hugoniot_destroy(h);
        return rc;
    }
    *state = h;
    return 0;
fail:
    free(up);
    return rc;
}

/* Copy of the owned particles (positions wrapped into the box). */
static struct particles *clone_particles(const struct particles *src, const struct box *b,
                                         struct err *e)
{
    struct particles *p = particles_create(src->n_owned + 16);
    if (!p) {
        err_nomem(e, "particles");
        return NULL;
    }
    p->ntypes = src->ntypes;
    memcpy(p->mass, src->mass, sizeof p->mass);
    memcpy(p->type_name, src->type_name, sizeof p->type_name);
    for (int i = 0; i < src->n_owned; i++) {
        double x[3];
        for (int d = 0; d < 3; d++) {
            double len = box_length(b, d), v = src->x[3 * i + d];
            v -= floor((v - b->lo[d]) / len) * len;
            x[d] = v;
        }
        if (particles_add(p, x, src->v + 3 * i, src->type[i], src->id[i]) < 0) {
            particles_destroy(&p);
            err_nomem(e, "particles");
            return NULL;
        }
    }
    return p;
}

/* Stress and state behind the front: atoms with x in [x1, x2]. */
struct region_state {
    double P[6];         /* eV/Å^3 */
    double u;            /* mean x velocity, Å/ps */
    double rho;          /* amu/Å^3 */
    double T;            /* K */
    long n;
};

static void region_measure(const struct md *md, double x1, double x2, double area,
                           struct region_state *r)
{
    const struct particles *p = md->p;
    double m = 0, mv[3] = {0}, K[6] = {0}, W[6] = {0};
    long n = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double x = p->x[3 * i];
        if (x < x1 || x > x2 || (p->mask[i] & GROUP_PISTON))
            continue;
        double mi = p->mass[p->type[i]];
        m += mi;
        for (int d = 0; d < 3; d++)
            mv[d] += mi * p->v[3 * i + d];
        n++;
    }
    memset(r, 0, sizeof *r);
    if (n == 0)
        return;
    double vm[3] = {mv[0] / m, mv[1] / m, mv[2] / m};
    for (int i = 0; i < p->n_owned; i++) {
        double x = p->x[3 * i];
        if (x < x1 || x > x2 || (p->mask[i] & GROUP_PISTON))
            continue;
        double mi = p->mass[p->type[i]] * UNITS_MVV2E;
        double dv[3] = {p->v[3 * i] - vm[0], p->v[3 * i + 1] - vm[1], p->v[3 * i + 2] - vm[2]};
        K[0] += mi * dv[0] * dv[0];
        K[1] += mi * dv[1] * dv[1];
        K[2] += mi * dv[2] * dv[2];
        K[3] += mi * dv[0] * dv[1];
        K[4] += mi * dv[0] * dv[2];
        K[5] += mi * dv[1] * dv[2];
        for (int c = 0; c < 6; c++)
            W[c] += p->virial[6 * i + c];
    }
    double V = (x2 - x1) * area;
    for (int c = 0; c < 6; c++)
        r->P[c] = (K[c] + W[c]) / V;
    r->u = vm[0];
    r->rho = m / V;
    r->T = (K[0] + K[1] + K[2]) / (3.0 * n * UNITS_KB);
    r->n = n;
}

struct shock_out {
    double us, us_err, us_lead, upm, P[6], rho, T, fcc, hcp, bcc, other, time;
    long npts;
};

/* One shock's sampling, every `every` steps: the velocity profile, the
 * front and leading-edge positions, the state between piston and front. */
struct shock_sampler {
    struct hugoniot *h;
    struct md *md;
    struct run *run;
    double up, u, x0, L, xp0, area;
    int nbins;
    double *mean;
    long *count;
    double *ts, *xf, *xl;
    long cap, min_count, global_step0;
    long nsamp, nmeas;
    double Pacc[6], racc, Tacc, uacc;
    long every;
};

static int shock_after_step(void *state, struct sim *sim, struct err *e)
{
    struct shock_sampler *sm = state;
    struct hugoniot *h = sm->h;
    struct md *md = sm->md;
    long s = sim->step;
    if (s % sm->every)
        return 0;
    double ke = md_kinetic_energy(md);
    shock_profile(md->p->x, 3, md->p->v, 3, md->p->n_owned, sm->x0, h->bin, sm->nbins, sm->mean,
                  sm->count);
    double front, lead;
    if (shock_front_locate(sm->mean, sm->count, sm->nbins, sm->x0, h->bin, 0.5 * sm->u, +1,
                           sm->min_count, &front) != 0)
        return 0;   /* not formed yet */
    if (shock_front_locate(sm->mean, sm->count, sm->nbins, sm->x0, h->bin, 0.15 * sm->u, +1,
                           sm->min_count, &lead) != 0)
        lead = front;
    sm->ts[sm->nsamp] = md->time;
    sm->xf[sm->nsamp] = front;
    sm->xl[sm->nsamp] = lead;
    sm->nsamp++;
    double xpist = sm->xp0 + sm->u * md->time;
    double row[8] = {sm->up, (double)(sm->global_step0 + s), md->time, front, lead,
                     md->last.energy, ke, md_temperature(md)};
    run_thermo_row(sm->run, row, 8);
    double frac = (front - sm->xp0) / (sm->x0 + sm->L - sm->xp0);
    if (frac > 0.5) {
        /* the middle 70 % between piston face and front */
        double gap = front - xpist;
        struct region_state r;
        region_measure(md, xpist + 0.15 * gap, front - 0.15 * gap, sm->area, &r);
        if (r.n > 0) {
            for (int c = 0; c < 6; c++)
                sm->Pacc[c] += r.P[c];
            sm->racc += r.rho;
            sm->Tacc += r.T;
            sm->uacc += r.u;
            sm->nmeas++;
        }
    }
    if (frac > h->stop_at || sm->nsamp >= sm->cap)
        sim->stop = 1;
    (void)e;
    return 0;
}

static int run_shock(struct hugoniot *h, const struct particles *tmpl, const struct box *tbox,
                     double up, int k, struct run *run, long *global_step, struct shock_out *o,
                     struct err *e)
{
    memset(o, 0, sizeof *o);
    struct particles *p = clone_particles(tmpl, tbox, e);
    if (!p)
        return ERR_RUNTIME;
    double x0 = tbox->lo[0], L = box_length(tbox, 0);
    double xp0 = x0 + h->piston_cells * h->a;   /* piston face */
    double u = up * 10.0;                        /* Å/ps */
    /* piston: rigid, exactly u; the sample: at rest on average */
    double m = 0, mv[3] = {0};
    for (int i = 0; i < p->n_owned; i++) {
        if (p->x[3 * i] < xp0) {
            p->mask[i] |= GROUP_PISTON;
            p->v[3 * i] = u;
            p->v[3 * i + 1] = p->v[3 * i + 2] = 0;
        } else {
            double mi = p->mass[p->type[i]];
            m += mi;
            for (int d = 0; d < 3; d++)
                mv[d] += mi * p->v[3 * i + d];
        }
    }
    for (int i = 0; i < p->n_owned; i++)
        if (!(p->mask[i] & GROUP_PISTON))
            for (int d = 0; d < 3; d++)
                p->v[3 * i + d] -= mv[d] / m;
    int f_struct = particles_add_field(p, "structure", 1, 0, e);
    int f_shock = particles_add_field(p, "shocked", 1, 0, e);
    if (f_struct < 0 || f_shock < 0) {
        particles_destroy(&p);
        return ERR_RUNTIME;
    }
    struct box b = *tbox;
    b.bc[0] = BOUNDARY_FREE;
    struct md md;
    int rc = md_init(&md, p, &b, h->pot, h->th.dt, h->th.skin, h->th.nthreads, e);
    md.rigid_mask = GROUP_PISTON;
    md.seed = h->th.seed;
    md.timers = &run->timers;
    double area = box_length(tbox, 1) * box_length(tbox, 2);
    int nbins = (int)ceil((L + 10 * h->bin) / h->bin);
    double *mean = malloc((size_t)nbins * sizeof *mean);
    long *count = malloc((size_t)nbins * sizeof *count);
    long cap = (long)(h->max_time / h->sample_every) + 8;
    double *ts = malloc((size_t)cap * sizeof *ts), *xf = malloc((size_t)cap * sizeof *xf),
           *xl = malloc((size_t)cap * sizeof *xl);
    if (!rc && (!mean || !count || !ts || !xf || !xl))
        rc = err_nomem(e, "shock profiles");
    long every = (long)llround(h->sample_every / h->th.dt);
    if (every < 1)
        every = 1;
    /* profile: mean vx in slabs from the original left end */
    long min_count = (long)(0.5 * area / (h->a * h->a) * (h->bin / h->a) * 2);
    if (min_count < 4)
        min_count = 4;
    long nsteps_max = (long)llround(h->max_time / h->th.dt);
    /* the shock runs until its front has crossed stop_at of the sample (the
     * case's stop condition) or max_time */
    struct shock_sampler sm = {
        .h = h, .md = &md, .run = run, .up = up, .u = u, .x0 = x0, .L = L, .xp0 = xp0,
        .area = area, .nbins = nbins, .mean = mean, .count = count, .ts = ts, .xf = xf, .xl = xl,
        .cap = cap, .min_count = min_count, .global_step0 = *global_step, .every = every,
    };
    static const struct sim_case_ops hooks = {.after_step = shock_after_step};
    struct md_model model = {.md = &md, .peratom_every = every};
    struct sim sim;
    sim_init_subrun(&sim, NULL, nsteps_max, h->th.dt);
    sim.case_ops = &hooks;
    sim.case_state = &sm;
    if (!rc)
        rc = sim_add_model(&sim, &sim_model_md, &model, e);
    if (!rc)
        rc = sim_run(&sim, NULL, e);
    int stopped = sim.stop;
    long nsamp = sm.nsamp, nmeas = sm.nmeas;
    double *Pacc = sm.Pacc, racc = sm.racc, Tacc = sm.Tacc, uacc = sm.uacc;
    o->time = md.time;
    *global_step += md.step;
    h->steps_done += md.step;
    if (!rc && !stopped)
        rc = err_set(e, ERR_RUNTIME,
                     "the %g km/s shock did not cross %g of the sample within max_time = %g ps "
                     "(front detections: %ld)", up, h->stop_at, h->max_time, nsamp);
    /* Us from the front positions between fit_start and stop_at */
    if (!rc) {
        long a0 = -1;
        for (long q = 0; q < nsamp && a0 < 0; q++)
            if ((xf[q] - xp0) / (x0 + L - xp0) >= h->fit_start)
                a0 = q;
        long npts = a0 >= 0 ? nsamp - a0 : 0;
        o->npts = npts;
        if (npts < 3 || nmeas == 0)
            rc = err_set(e, ERR_RUNTIME, "the %g km/s shock gave %ld front positions to fit and %ld "
                         "stress samples; lengthen the sample or sample more often", up, npts, nmeas);
        else {
            double icpt, dummy;
            rc = shock_speed_fit(ts + a0, xf + a0, (int)npts, &o->us, &o->us_err, &icpt, e);
            if (!rc)
                rc = shock_speed_fit(ts + a0, xl + a0, (int)npts, &o->us_lead, &dummy, &icpt, e);
        }
    }
    if (!rc) {
        for (int c = 0; c < 6; c++)
            o->P[c] = Pacc[c] / nmeas;
        o->rho = racc / nmeas;
        o->T = Tacc / nmeas;
        o->upm = uacc / nmeas;
        /* structure behind the front, as fields for the final snapshot */
        int *cls = malloc((size_t)md.p->n_owned * sizeof *cls);
        struct frame fr = {0};
        struct structure_params sp = h->sp;
        sp.nthreads = h->th.nthreads;
        if (!cls)
            rc = err_nomem(e, "structure classes");
        if (!rc)
            rc = structure_classify_particles(&sp, md.p, &md.box, &fr, cls, e);
        double front = xf[nsamp - 1], xpist = xp0 + u * md.time, gap = front - xpist;
        long nin = 0, nfcc = 0, nhcp = 0, nbcc = 0;
        double *fs = particles_field(md.p, f_struct), *fsh = particles_field(md.p, f_shock);
        for (int i = 0; !rc && i < md.p->n_owned; i++) {
            double x = md.p->x[3 * i];
            fs[i] = cls[i];
            fsh[i] = x < front && !(md.p->mask[i] & GROUP_PISTON);
            if (x > xpist + 0.15 * gap && x < front - 0.15 * gap) {
                nin++;
                nfcc += cls[i] == STRUCT_FCC;
                nhcp += cls[i] == STRUCT_HCP;
                nbcc += cls[i] == STRUCT_BCC;
            }
        }
        o->fcc = nin > 0 ? (double)nfcc / nin : 0.0;
        o->hcp = nin > 0 ? (double)nhcp / nin : 0.0;
        o->bcc = nin > 0 ? (double)nbcc / nin : 0.0;
        o->other = nin > 0 ? 1.0 - o->fcc - o->hcp - o->bcc : 0.0;
        frame_free(&fr);
        free(cls);
    }
    if (nsamp > 0) {
        char n1[64], n2[64];
        snprintf(n1, sizeof n1, "front_time_ps_%d", k);
        snprintf(n2, sizeof n2, "front_x_A_%d", k);
        result_series(&run->result, n1, ts, (int)nsamp, "ps");
        result_series(&run->result, n2, xf, (int)nsamp, "Å");
    }
    if (run->h5_open && nsamp > 0) {
        char n1[64], n2[64];
        snprintf(n1, sizeof n1, "front_time_ps_%d", k);
        snprintf(n2, sizeof n2, "front_x_A_%d", k);
        int r1 = h5out_write_series(&run->h5, n1, ts, nsamp, "ps", e);
        if (!r1)
            r1 = h5out_write_series(&run->h5, n2, xf, nsamp, "Å", e);
        if (!rc)
            rc = r1;
        /* the end state: step labels continue across the shocks */
        struct md_output mo;
        memset(&mo, 0, sizeof mo);
        long keep = md.step;
        md.step = *global_step;
        md.peratom = 1;
        if (!rc && !(rc = md_compute_forces(&md, e)))
            rc = md_output_snapshot(&mo, run, &md) ? ERR_RUNTIME : 0;
        md.step = keep;
        free(mo.stress);
        free(mo.ibuf);
    }
    free(mean);
    free(count);
    free(ts);
    free(xf);
    free(xl);
    md.pot = NULL;   /* the case keeps the potential for the next shock */
    md_free(&md);
    return rc;
}

static int hugoniot_run(void *state, struct run *run, struct err *e)
{
    struct hugoniot *h = state;
    double a_T = h->a, p_left = 0;
    int rc = 0;
    static const char *const tcols[8] = {"up_km_s", "step", "time_ps", "front_A", "leading_A",
                                         "pe_eV", "ke_eV", "temp_K"};
    if (run_thermo_header(run, tcols, 8) != 0)
        return err_set(e, ERR_RUNTIME, "%s", run->write_err.msg);
    timer_start(&run->timers, TIMER_LOOP);
    if (h->zero_pressure && h->th.temperature > 0) {
        struct thermal_spec small = h->th;
        small.cells[0] = small.cells[1] = small.cells[2] = 5;
        small.t_eq = 1.0;
        small.t_avg = 1.0;
        rc = thermal_lattice_constant(h->pot, &small, h->a, 0.02 / UNITS_EVA3_TO_GPA, &a_T,
                                      &p_left, e);
        if (rc)
            goto done;
        run_log(run, "lattice constant at %g K: %.5f Å (pressure left %.3f GPa)",
                h->th.temperature, a_T, p_left * UNITS_EVA3_TO_GPA);
    }
    h->a = a_T;
    /* thermalise the sample, periodic in all directions */
    struct md eq;
    rc = thermal_crystal_md(&eq, h->pot, &h->th, a_T, NULL, e);
    double P[6], T;
    if (!rc && h->th.t_eq > 0)
        rc = thermal_average(&eq, h->th.t_eq, fmin(0.5, h->th.t_eq), P, &T, e);
    struct particles *tmpl = NULL;
    struct box tbox = eq.box;
    if (!rc) {
        tmpl = clone_particles(eq.p, &eq.box, e);
        if (!tmpl)
            rc = ERR_RUNTIME;
    }
    h->natoms = eq.p ? eq.p->n_owned : 0;
    long global = eq.step;
    h->steps_done += eq.step;
    eq.pot = NULL;
    md_free(&eq);
    if (rc)
        goto done;
    double rho0 = 0;
    for (int i = 0; i < tmpl->n_owned; i++)
        rho0 += tmpl->mass[tmpl->type[i]];
    rho0 /= box_volume(&tbox);
    run_log(run, "sample %d atoms, %.1f x %.1f x %.1f Å, rho0 = %.4f g/cm^3", tmpl->n_owned,
            box_length(&tbox, 0), box_length(&tbox, 1), box_length(&tbox, 2),
            rho0 * UNITS_AMU_A3_TO_KG_M3 * 1e-3);
    for (size_t k = 0; k < h->nup && !rc; k++) {
        struct shock_out o;
        rc = run_shock(h, tmpl, &tbox, h->up[k], (int)k, run, &global, &o, e);
        if (rc)
            break;
        double *r = h->res[k];
        const double g = UNITS_EVA3_TO_GPA;
        r[H_UP] = h->up[k];
        r[H_UPM] = o.upm / 10.0;
        r[H_US] = o.us / 10.0;
        r[H_USERR] = o.us_err / 10.0;
        r[H_USLEAD] = o.us_lead / 10.0;
        r[H_USREF] = h->ref_c0 + h->ref_s * h->up[k];
        r[H_USDEV] = r[H_US] / r[H_USREF] - 1.0;
        r[H_PXX] = o.P[0] * g;
        r[H_PYY] = o.P[1] * g;
        r[H_PZZ] = o.P[2] * g;
        r[H_SHEAR] = 0.5 * (o.P[0] - 0.5 * (o.P[1] + o.P[2])) * g;
        /* Rankine-Hugoniot momentum condition with the measured Us and the
         * piston velocity (P0 ~ 0 after the zero-pressure search) */
        r[H_PRH] = eos_rh_pressure(rho0, o.us, h->up[k] * 10.0) * g + p_left * g;
        r[H_PRHDEV] = r[H_PXX] / r[H_PRH] - 1.0;
        r[H_COMP] = o.rho / rho0;
        r[H_COMPRH] = eos_rh_compression(o.us, h->up[k] * 10.0);
        r[H_TEMP] = o.T;
        r[H_FCC] = o.fcc;
        r[H_HCP] = o.hcp;
        r[H_BCC] = o.bcc;
        r[H_OTHER] = o.other;
        r[H_TIME] = o.time;
        run_log(run, "up %.3f km/s: Us %.3f +- %.3f km/s (leading edge %.3f; line %.3f, %+.1f %%), "
                     "Pxx %.2f GPa vs rho0 Us up %.2f GPa (%+.1f %%), shear %.2f GPa, rho/rho0 "
                     "%.4f (RH %.4f), T %.0f K; behind the front %.0f %% fcc, %.0f %% hcp, %.0f %% "
                     "bcc, %.0f %% other",
                h->up[k], r[H_US], r[H_USERR], r[H_USLEAD], r[H_USREF], 100 * r[H_USDEV], r[H_PXX],
                r[H_PRH], 100 * r[H_PRHDEV], r[H_SHEAR], r[H_COMP], r[H_COMPRH], r[H_TEMP],
                100 * r[H_FCC], 100 * r[H_HCP], 100 * r[H_BCC], 100 * r[H_OTHER]);
    }
    particles_destroy(&tmpl);
    if (rc)
        goto done;
    struct result *res = &run->result;
    double col[256];
    size_t nu = h->nup < 256 ? h->nup : 256;
    for (int c = 0; c < H_NCOL; c++) {
        for (size_t k = 0; k < nu; k++)
            col[k] = h->res[k][c];
        result_series(res, hcols[c], col, (int)nu, hunits[c]);
        if (run->h5_open && (rc = h5out_write_series(&run->h5, hcols[c], col, (long)nu, hunits[c], e)))
            goto done;
    }
    result_metric(res, "lattice_constant_T", a_T, "Å");
    result_metric(res, "density_T", rho0 * UNITS_AMU_A3_TO_KG_M3 * 1e-3, "g/cm^3");
    result_metric(res, "sample_atoms", (double)h->natoms, "1");
    double dev_us = 0, dev_p = 0;
    int inrange = 0;
    for (size_t k = 0; k < nu; k++)
        if (h->up[k] >= h->fit_lo && h->up[k] <= h->fit_hi) {
            dev_us = fmax(dev_us, fabs(h->res[k][H_USDEV]));
            inrange++;
        }
    for (size_t k = 0; k < nu; k++)
        dev_p = fmax(dev_p, fabs(h->res[k][H_PRHDEV]));
    result_metric(res, "p_rh_deviation_max", dev_p, "1");
    if (inrange > 0)
        result_metric(res, "us_deviation_max", dev_us, "1");
    if (nu == 1)
        for (int c = 0; c < H_NCOL; c++)
            result_metric(res, hmetrics[c], h->res[0][c], hunits[c]);
    if (nu >= 2) {
        double up[256], us[256], c0, s, c0e, se;
        int used;
        for (size_t k = 0; k < nu; k++) {
            up[k] = h->res[k][H_UP];
            us[k] = h->res[k][H_US];
        }
        struct err fe = {0};
        if (eos_fit_us_up(up, us, (int)nu, h->fit_lo, h->fit_hi, &c0, &s, &c0e, &se, &used, &fe) == 0) {
            result_metric(res, "c0", c0, "km/s");
            result_metric(res, "s", s, "1");
            result_metric(res, "c0_err", c0e, "km/s");
            result_metric(res, "s_err", se, "1");
            result_metric(res, "fit_points", used, "1");
            run_log(run, "Us = c0 + s up over %g..%g km/s (%d points): c0 = %.3f +- %.3f km/s, s = "
                         "%.3f +- %.3f (reference %.2f, %.2f)",
                    h->fit_lo, h->fit_hi, used, c0, c0e, s, se, h->ref_c0, h->ref_s);
        } else {
            run_log(run, "no Us-up fit: %s", fe.msg);
        }
    }
done:
    timer_stop(&run->timers, TIMER_LOOP);
    run->steps_run = h->steps_done;
    return rc;
}

static void hugoniot_destroy(void *state)
{
    struct hugoniot *h = state;
    if (!h)
        return;
    potential_destroy(&h->pot);
    free(h->up);
    free(h->res);
    free(h);
}

static long hugoniot_particles(const void *state)
{
    const struct hugoniot *h = state;
    return h ? h->natoms : 0;
}

const struct case_type hugoniot_case_type = {
    "hugoniot", "shock Hugoniot of a crystal: Us(up) by piston-driven shocks, Rankine-Hugoniot check",
    hugoniot_read, hugoniot_run, hugoniot_destroy, hugoniot_particles, NULL,
    .checkpoints = 0,
};
