/*
 * dpd_impact_case: a rigid flyer hits a DPD target bar (`type:
 * dpd_impact`), Chen et al. 2014 Sec. 4.1.1, DPD-only model: target 216 x
 * 72.3 x 72.3 Å (30a x 10a x 10a, a = 7.23 Å), non-periodic, a rigid 15 Å
 * flyer at 5 Å/ps, reference regions 6 Å thick centred 100 Å and 150 Å
 * from the impact face; the wave speed from the difference of the times at
 * which the two regions first move (analysis/wave_arrival.h).
 *
 *   system:   the target (md_system.h): read_data of the equilibrated bar
 *             (a `dpd` case with output.final_state), or a lattice
 *   dpd:      dpd_setup.h (default variant dpde, the paper's DPD-only model)
 *   impact:
 *     axis: x                   propagation axis; the flyer comes from below
 *     flyer_thickness: 15.0     Å: (100) planes of the flyer, round(15 / (a/2)) = 4
 *     flyer_velocity: 5.0       Å/ps toward the target
 *     flyer_motion: free        free: a rigid body that the target slows down;
 *                               prescribed: a piston at constant velocity
 *     lattice_constant: 0       Å of the flyer (0: the parameter file's)
 *     gap: 0.0                  Å added to one plane spacing between flyer and target
 *     regions: [100.0, 150.0]   Å: centres of the reference regions from the impact face
 *     region_thickness: 6.0     Å
 *     arrival_threshold: 0.01   Å: the wave has arrived at a region when the mean
 *                               displacement of its particles along the axis that
 *                               the impact caused first reaches this (linear
 *                               interpolation between samples); without a reference
 *                               run use about 0.2 Å, above the thermal wander
 *     reference: true           also run the target without the flyer from the same
 *                               state with the same random numbers, and measure the
 *                               displacement the impact causes as the difference
 *                               between the two runs (see below)
 *     sample_every: 1           steps between displacement samples
 *     profile_times: []         ps: displacement profiles along the bar at these times
 *     profile_bin: 0            Å: profile bin width (0: the plane spacing a/2)
 *
 * The impact face is the mean position of the target's first (100) plane at
 * the start; regions and profile bins are Lagrangian (selected by where the
 * material was then).
 *
 * Why a reference run: at 298 K the mean displacement of a 6 Å slab of a
 * 72 Å bar wanders by a few hundredths of an Å (its centre-of-mass velocity
 * alone is sqrt(kB T / M_slab), about 0.04 Å/ps), and the front of the wave
 * rises over a picosecond, so the time a raw signal crosses a threshold
 * depends on the noise.  The unperturbed run sees the same forces and --
 * the random numbers being keyed on pair ids and step -- the same random
 * kicks, so ahead of the wave both runs agree (to round-off amplified by
 * the dynamics, 1e-6 Å over ten picoseconds here) and their difference is
 * the disturbance the impact alone has caused.  The arrival then marks
 * where that disturbance first becomes significant, at any threshold.
 * The threshold scan (series arrival_thresholds, wave_speed_scan) shows
 * how the speed depends on it: small thresholds follow the leading edge,
 * large ones the main pulse.
 *
 * Under mpirun the impact runs on bricks (docs/dpd.md, docs/parallel.md):
 * every rank builds its brick's part of the target and of the flyer (the
 * bar's faces measured over every rank), the flyer run on the DPD halo and
 * the reference run on a second halo over the same bricks; both sweep in cell-colour order
 * (dpd.sweep: cells), the flyer's pairs apart in one global order on
 * every rank (dpd/dpd_sweep_bodies.h), so the flyer's velocity is the same
 * on every rank.  The region means, profiles, front probes and CNA counts
 * are sums over the ranks; the final state is written by rank 0 a window at a time.
 *
 * Metrics: wave_speed and its companions (m/s; the threshold-free front
 * fit over probe slabs between the regions, scenarios/impact_front.h:
 * null when its spread over the criteria exceeds 3 %), wave_speed_threshold
 * (m/s, the fixed arrival_threshold above), arrival_time_1/2 (ps, at that
 * threshold), region_particles_1/2,
 * displacement_max_1/2 (Å), flyer_velocity_final (Å/ps), target_particles,
 * flyer_particles, energy_drift and energy_deviation_max (relative change
 * of pe + ke + internal energy: conserved by DPDE with a free flyer),
 * impact_energy (eV, the flyer's kinetic energy at the start),
 * energy_deviation_max_abs (eV) and energy_error_impact_fraction (the
 * largest energy change over the impact energy),
 * momentum_change (amu Å/ps: zero with a free flyer), and the common
 * neighbour analysis of the target at the coarse lattice constant
 * (section analysis.structure, metrics cna_fcc, cna_hcp, cna_other, ...,
 * per-particle field `structure` in the snapshots: dpd_structure.h).
 * Series: time_ps, displacement_region_1/2 (Å; differences to the reference
 * run when there is one, raw_displacement_region_1/2 the flyer run's own),
 * etotal (eV), arrival_thresholds (Å) and wave_speed_scan (m/s), and per
 * profile time T: profile_x (Å from the face, bin centres), profile_tT (Å).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/displacement.h"
#include "analysis/wave_arrival.h"
#include "dpd/cg_lattice.h"
#include "core/halo.h"
#include "core/lattice.h"
#include "core/units.h"
#include "engine/models.h"
#include "output/final_state.h"
#include "output/decomp_record.h"
#include "scenarios/dpd_bar.h"
#include "core/velocity.h"
#include "scenarios/dpd_impact_setup.h"
#include "scenarios/impact_front.h"
#include "output/dpd_output.h"
#include "scenarios/dpd_setup.h"
#include "scenarios/dpd_structure.h"
#include "input/md_system.h"

#define FLYER_BIT DPD_FLYER_BIT

struct impact_case {
    struct dpd d;
    struct dpd ref;            /* the target without the flyer (has_ref) */
    int has_ref, xref_ref;
    struct halo *halo, *halo_ref;   /* bricks of the two runs (owned), or NULL */
    long steps;
    int axis;
    double regions[2], half;   /* Å from the face; half thickness */
    double threshold;          /* Å */
    long sample_every;
    double *profile_times;     /* ps */
    size_t nprofiles;
    double profile_bin;        /* Å */
    double face, length;       /* Å */
    int xref;                  /* displacement reference field */
    long n_target, n_flyer;
    struct dpd_structure st;   /* CNA of the flyer run (Fig. 4) */
    struct dpd_model model[2]; /* the flyer run and the reference run on the engine */
    struct dpd_bar bar;        /* the target at the start (lateral extent of the probes) */
    double c11, c12, rho;      /* eV/Å^3, amu/Å^3: the material (reference speeds) */
    struct impact_front front; /* probes of the threshold-free wave speed */
    /* the run's accumulators (checkpointed) */
    struct dpd_output out;
    long nsamp, ns;            /* samples: room for, taken */
    double *ts, *s1, *s2, *es, *r1, *r2;   /* time, region displacements, energy, raw */
    long count[2];             /* particles in the regions at the last sample */
    int nbins;
    double *prof;              /* nprofiles x nbins, NaN until taken */
    double *pref;              /* scratch: the reference run's profile */
    double *pcnt;              /* scratch: a profile's particles per bin */
    long *pstep;               /* step of each profile time */
    double P0[3];              /* momentum at the start */
    double demax;              /* largest |etotal - etotal(0)| so far */
    double impact_energy;      /* eV: the flyer's kinetic energy at the start */
    double *restored_rows;     /* thermo rows read from a checkpoint */
    long nrestored;
};

static void impact_free_halos(struct impact_case *c)
{
    struct halo **h[2] = {&c->halo, &c->halo_ref};
    for (int q = 0; q < 2; q++) {
        if (*h[q])
            halo_free(*h[q]);
        free(*h[q]);
        *h[q] = NULL;
    }
}

static int impact_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    struct dpd_input in;
    struct dpd_impact_keys k;
    struct dpd_structure st;
    struct halo *halo = NULL;
    /* the dpd section first: its ranges size the bricks, and under mpirun
     * each rank builds (a lattice) or receives (a file rank 0 read) only
     * its brick's target particles */
    int rc = dpd_section_read(root, DPD_ENERGY, &in);
    struct dpd_split_plan plan = {&in, common, root->cfg, 0};
    struct md_system_split split = {dpd_split_plan_bricks, &plan, 0, common->par, 0};
    if (!rc)
        rc = md_system_read_split(root, common->seed, root->cfg->shallow ? NULL : &split, &p,
                                  &box, &info, &halo);
    memset(&k, 0, sizeof k);
    if (!rc)
        rc = dpd_impact_keys_read(root, &k);
    if (!rc)
        rc = dpd_structure_read(root, &st);
    if (!rc && box.bc[k.axis] == BOUNDARY_PERIODIC)
        rc = cfg_error_at(root->cfg, "system.boundary",
                          "the impact axis %c must not be periodic (the flyer comes from outside)",
                          "xyz"[k.axis]);
    struct err *e = root->cfg->err;
    struct impact_case *c = NULL;
    if (!rc && !root->cfg->shallow && !(c = calloc(1, sizeof *c)))
        rc = err_nomem(e, "impact case");
    if (c) {
        c->halo = halo;
        halo = NULL;
    }
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        free(k.ptimes);
        if (halo) {
            halo_free(halo);
            free(halo);
        }
        if (c)
            impact_free_halos(c);
        free(c);
        return rc;
    }
    double a = k.a > 0 ? k.a : in.prm.lattice_constant;
    struct dpd_bar bar;
    long nflyer = 0;
    struct particles *pref = NULL;
    if (c->halo) {
        p->halo = c->halo;
        p->par = NULL;   /* no replicated sums: each rank owns its brick */
    }
    double ntarget = (double)p->n_owned;
    if (c->halo)
        halo_sum(c->halo, &ntarget, 1);
    c->n_target = (long)ntarget;
    /* the k-th Maxwell draw to the k-th id of all ranks: the serial
     * velocities (to round-off on bricks, bitwise serially) */
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = in.prm.mass;
    if (in.t_init > 0)
        rc = velocity_maxwell_split(p, in.t_init, common->seed, 1u, c->halo, e);
    if (!rc && k.reference && !(pref = dpd_particles_clone(p, e)))
        rc = ERR_RUNTIME;
    /* the bar's faces and the flyer's stacking over every rank's particles;
     * each rank adds the flyer sites of its brick */
    if (!rc) {
        dpd_bar_measure_over(p, 0, 0.5 * a, c->halo, &bar);
        rc = dpd_impact_add_flyer_over(p, &bar, &k, a, c->halo, &nflyer, e);
    }
    /* every rank keeps what it built; a particle a displacement moved just
     * out of its brick migrates at the first list build.  The reference
     * run's halo cuts the same bricks. */
    if (c->halo)
        rc = halo_adopt(c->halo, p, rc, e);
    if (!rc && c->halo && pref) {
        c->halo_ref = calloc(1, sizeof *c->halo_ref);
        rc = c->halo_ref ? halo_init_like(c->halo_ref, c->halo, e)
                         : err_nomem(e, "reference run bricks");
        if (!rc) {
            pref->halo = c->halo_ref;
            pref->par = NULL;
        }
        rc = halo_adopt(c->halo_ref ? c->halo_ref : c->halo, pref, rc, e);
    }
    if (rc) {
        particles_destroy(&p);
        particles_destroy(&pref);
        free(k.ptimes);
        impact_free_halos(c);
        free(c);
        return rc;
    }
    c->n_flyer = nflyer;
    rc = dpd_build(&in, p, &box, common, e, &c->d);
    double v[3] = {0, 0, 0};
    v[k.axis] = k.velocity;
    if (!rc)
        rc = dpd_add_body(&c->d, FLYER_BIT, k.motion == 0 ? DPD_BODY_FREE : DPD_BODY_PRESCRIBED,
                          v, e);
    if (!rc)
        c->impact_energy = 0.5 * c->d.body[0].mass * k.velocity * k.velocity * UNITS_MVV2E;
    if (!rc) {
        c->xref = displacement_begin(c->d.p, &c->d.box, e);
        if (c->xref < 0)
            rc = ERR_RUNTIME;
    }
    if (pref) {
        /* Same seed: the same random kick for every target pair.  Same
         * storage order (no spatial sorting: the target particles keep their
         * indices, the flyer's come after them) and canonical neighbour
         * lists: the pair sweep meets every target particle's pairs in the
         * same order in both runs, so ahead of the wave they stay equal.
         * The cell-colour sweep (bricks, dpd.sweep: cells) orders the pairs
         * by cells fixed in space along the free axes, also the same in
         * both runs (dpd_sweep_cells.c). */
        if (!rc) {
            c->has_ref = 1;
            rc = dpd_build(&in, pref, &box, common, e, &c->ref);
        } else {
            particles_destroy(&pref);
        }
        for (int r = 0; !rc && r < 2; r++)
            rc = dpd_fix_order(r ? &c->ref : &c->d, NULL, e);
        if (!rc) {
            c->xref_ref = displacement_begin(c->ref.p, &c->ref.box, e);
            if (c->xref_ref < 0)
                rc = ERR_RUNTIME;
        }
    }
    c->st = st;
    if (!rc)
        rc = dpd_structure_attach(&c->st, &c->d, in.prm.sc.a, FLYER_BIT, common->nthreads, e);
    if (rc) {
        dpd_structure_free(&c->st);
        dpd_free(&c->d);
        if (c->has_ref)
            dpd_free(&c->ref);
        impact_free_halos(c);
        free(k.ptimes);
        free(c);
        return rc;
    }
    c->steps = in.steps;
    c->axis = k.axis;
    c->regions[0] = k.regions[0];
    c->regions[1] = k.regions[1];
    c->half = k.half;
    c->threshold = k.threshold;
    c->sample_every = k.sample_every;
    c->profile_times = k.ptimes;
    c->nprofiles = k.nptimes;
    c->profile_bin = k.bin > 0 ? k.bin : 0.5 * a;
    c->face = bar.face_lo[k.axis];
    c->length = bar.extent[k.axis];
    c->bar = bar;
    {
        double c44;
        cg_lattice_elastic(&in.prm.sc, in.prm.lattice_constant, &c->c11, &c->c12, &c44);
        c->rho = 4 * in.prm.mass / pow(in.prm.lattice_constant, 3);
    }
    for (int r = 0; r < 2; r++)
        if (c->regions[r] + c->half > c->length)
            rc = cfg_error_at(root->cfg, "impact.regions",
                              "region %d (%g +- %g Å from the face) reaches past the target's "
                              "far face at %g Å",
                              r + 1, c->regions[r], c->half, c->length);
    if (rc) {
        dpd_free(&c->d);
        if (c->has_ref)
            dpd_free(&c->ref);
        dpd_structure_free(&c->st);
        impact_free_halos(c);
        free(c->profile_times);
        free(c);
        return rc;
    }
    *state = c;
    return 0;
}

/* The mean displacement of a slab of run d (dpd_slab_mean), on bricks
 * over every rank's particles. */
static double slab_mean(const struct dpd *d, int field, int axis, double lo, double hi,
                        uint32_t exclude, long *count)
{
    long n = 0;
    double m = displacement_slab_mean(d->p, &d->box, field, axis, lo, hi, exclude, &n);
    if (d->p->halo) {   /* each rank's sum and count */
        double s[2] = {n ? m * (double)n : 0.0, (double)n};
        halo_sum(d->p->halo, s, 2);
        n = lround(s[1]);
        m = n ? s[0] / s[1] : NAN;
    }
    if (count)
        *count = n;
    return m;
}

/* Mean displacement of reference region r in the flyer run (*raw) and, with
 * a reference run, less that of the same material without the flyer. */
static double region_disp(const struct impact_case *c, int r, long *count, double *raw)
{
    double lo = c->face + c->regions[r] - c->half, hi = c->face + c->regions[r] + c->half;
    *raw = slab_mean(&c->d, c->xref, c->axis, lo, hi, FLYER_BIT, count);
    if (!c->has_ref)
        return *raw;
    return *raw - slab_mean(&c->ref, c->xref_ref, c->axis, lo, hi, 0, NULL);
}

/* The displacement profile of run d into out (nbins), on bricks over
 * every rank's particles; cnt: nbins of scratch. */
static void profile(const struct impact_case *c, const struct dpd *d, int field,
                    uint32_t exclude, double *out, double *cnt)
{
    displacement_profile_sums(d->p, &d->box, field, c->axis, c->face, c->profile_bin, c->nbins,
                              exclude, out, cnt);
    if (d->p->halo) {
        halo_sum(d->p->halo, out, c->nbins);
        halo_sum(d->p->halo, cnt, c->nbins);
    }
    for (int b = 0; b < c->nbins; b++)
        out[b] = cnt[b] > 0 ? out[b] / cnt[b] : NAN;
}

/* Samples of step `step`: region displacements and energy every
 * sample_every steps and at the end, profiles at their times. */
static void impact_sample(struct impact_case *c, struct run *run, long step)
{
    struct dpd *d = &c->d;
    timer_start(&run->timers, TIMER_ANALYSIS);
    if (step % c->sample_every == 0 || step == c->steps) {
        long ns = c->ns;
        c->ts[ns] = d->time;
        c->s1[ns] = region_disp(c, 0, &c->count[0], &c->r1[ns]);
        c->s2[ns] = region_disp(c, 1, &c->count[1], &c->r2[ns]);
        c->es[ns] = dpd_total_energy(d);
        c->ns++;
        struct impact_front *f = &c->front;
        impact_front_clear(f);
        impact_front_add(f, 0, d->p->fields[c->xref].data, d->p->v, d->p->mask, FLYER_BIT,
                         d->p->n_owned);
        if (c->has_ref)
            impact_front_add(f, 1, c->ref.p->fields[c->xref_ref].data, c->ref.p->v,
                             c->ref.p->mask, 0, c->ref.p->n_owned);
        if (c->halo)
            impact_front_sum_ranks(f, c->halo);
        impact_front_end(f, d->time, c->has_ref);
    }
    for (size_t q = 0; q < c->nprofiles; q++) {
        if (c->pstep[q] != step)
            continue;
        double *pq = c->prof + q * c->nbins;
        profile(c, d, c->xref, FLYER_BIT, pq, c->pcnt);
        if (c->has_ref) {
            profile(c, &c->ref, c->xref_ref, 0, c->pref, c->pcnt);
            for (int b = 0; b < c->nbins; b++)
                pq[b] -= c->pref[b];
        }
    }
    timer_stop(&run->timers, TIMER_ANALYSIS);
}

/* --- the run on the engine (engine/sim.h) --------------------------------- */

static int impact_begin(void *state, struct sim *s, struct err *e)
{
    struct impact_case *c = state;
    struct dpd *d = &c->d;
    int rc = dpd_output_begin(&c->out, s->run, e);
    if (!rc && s->restarted_from >= 0)
        rc = dpd_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    if (rc || s->restarted_from >= 0)
        return rc;
    /* step 0: the state the conservation metrics and the structure start from */
    dpd_momentum(d, c->P0);
    if ((rc = dpd_structure_classify(&c->st, d, e)))
        return rc;
    impact_sample(c, s->run, 0);
    return 0;
}

static int impact_after_step(void *state, struct sim *s, struct err *e)
{
    (void)e;
    struct impact_case *c = state;
    c->demax = fmax(c->demax, fabs(dpd_total_energy(&c->d) - s->e0[0].total));
    impact_sample(c, s->run, s->step);
    return 0;
}

static int impact_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct impact_case *c = state;
    (void)due;   /* dpd_output_step reads the same schedule */
    int rc = dpd_structure_before_output(&c->st, s->run, &c->d, c->steps, e);
    if (rc)
        return rc;
    rc = dpd_output_step(&c->out, s->run, &c->d, c->steps);
    return rc ? err_set(e, ERR_RUNTIME, "%s: cannot write the outputs of step %ld",
                        s->run->opt.out_dir, s->step)
              : 0;
}

static int impact_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct impact_case *c = state;
    struct dpd *d = &c->d;
    struct run *run = s->run;
    int rc = run_rc ? 0 : dpd_structure_finish(&c->st, run, d, e);
    const long ns = c->ns;
    const int nbins = c->nbins;
    const double *ts = c->ts, *s1 = c->s1, *s2 = c->s2;
    double e0 = s->e0[0].total;
    struct result *res = &run->result;
    /* the legacy criterion: a fixed displacement threshold (wave_speed_threshold) */
    double t1 = wave_arrival_time(ts, s1, ns, c->threshold);
    double t2 = wave_arrival_time(ts, s2, ns, c->threshold);
    double speed = wave_speed(c->regions[1] - c->regions[0], t1, t2);   /* Å/ps */
    double front_speed;
    impact_front_report(&c->front, res, c->c11, c->c12, c->rho, &front_speed);
    double m1 = -INFINITY, m2 = -INFINITY;
    for (long q = 0; q < ns; q++) {
        m1 = fmax(m1, s1[q]);
        m2 = fmax(m2, s2[q]);
    }
    double P1[3], et = dpd_total_energy(d);
    const double *P0 = c->P0;
    dpd_momentum(d, P1);
    double dP = sqrt((P1[0] - P0[0]) * (P1[0] - P0[0]) + (P1[1] - P0[1]) * (P1[1] - P0[1]) +
                     (P1[2] - P0[2]) * (P1[2] - P0[2]));
    result_metric(res, "wave_speed_threshold", speed * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "arrival_time_1", t1, "ps");
    result_metric(res, "arrival_time_2", t2, "ps");
    result_metric(res, "region_particles_1", (double)c->count[0], "1");
    result_metric(res, "region_particles_2", (double)c->count[1], "1");
    result_metric(res, "displacement_max_1", m1, "Å");
    result_metric(res, "displacement_max_2", m2, "Å");
    result_metric(res, "flyer_velocity_final", d->body[0].v[c->axis], "Å/ps");
    result_metric(res, "target_particles", (double)c->n_target, "1");
    result_metric(res, "flyer_particles", (double)c->n_flyer, "1");
    result_metric(res, "target_length", c->length, "Å");
    result_metric(res, "energy_drift", (et - e0) / fabs(e0), "1");
    result_metric(res, "energy_deviation_max", c->demax / fabs(e0), "1");
    /* the same excursion against the impact energy: relative to the total
     * energy (cohesive, -1e5 eV) it looks small when it is not */
    result_metric(res, "impact_energy", c->impact_energy, "eV");
    result_metric(res, "energy_deviation_max_abs", c->demax, "eV");
    result_metric(res, "energy_error_impact_fraction",
                  c->impact_energy > 0 ? c->demax / c->impact_energy : NAN, "1");
    result_metric(res, "momentum_change", dP, "amu Å/ps");
    result_metric(res, "temperature", dpd_temperature(d), "K");
    result_series(res, "time_ps", ts, (int)ns, "ps");
    result_series(res, "displacement_region_1", s1, (int)ns, "Å");
    result_series(res, "displacement_region_2", s2, (int)ns, "Å");
    if (c->has_ref) {
        result_series(res, "raw_displacement_region_1", c->r1, (int)ns, "Å");
        result_series(res, "raw_displacement_region_2", c->r2, (int)ns, "Å");
    }
    {
        /* how the speed depends on the arrival threshold */
        static const double th[] = {0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0};
        const int nth = (int)(sizeof th / sizeof th[0]);
        double vs[sizeof th / sizeof th[0]];
        for (int q = 0; q < nth; q++)
            vs[q] = wave_speed(c->regions[1] - c->regions[0], wave_arrival_time(ts, s1, ns, th[q]),
                               wave_arrival_time(ts, s2, ns, th[q])) *
                    UNITS_APS_TO_MS;
        result_series(res, "arrival_thresholds", th, nth, "Å");
        result_series(res, "wave_speed_scan", vs, nth, "m/s");
    }
    result_series(res, "etotal", c->es, (int)ns, "eV");
    if (c->nprofiles) {
        double *xc = malloc((size_t)nbins * sizeof *xc);
        if (xc) {
            for (int b = 0; b < nbins; b++)
                xc[b] = (b + 0.5) * c->profile_bin;
            result_series(res, "profile_x", xc, nbins, "Å");
            free(xc);
        }
        for (size_t q = 0; q < c->nprofiles; q++) {
            char name[64];
            snprintf(name, sizeof name, "profile_t%gps", c->profile_times[q]);
            result_series(res, name, c->prof + q * nbins, nbins, "Å");
        }
    }
    run_log(run, "wave front fit: %.0f m/s (flagged when null); fixed threshold %g Å: region 1 "
            "at %.4f ps, region 2 at %.4f ps -> %.0f m/s",
            front_speed * UNITS_APS_TO_MS, c->threshold, t1, t2, speed * UNITS_APS_TO_MS);
    if (c->halo)
        decomp_record_write(run, c->halo, d->p);
    int rc2 = dpd_output_end(&c->out, run, e);
    if (!run_rc && !rc && !rc2) {
        rc2 = final_state_write(run, c->halo, d->p, &d->box, d->step, d->time, e);
    }
    return rc ? rc : rc2;
}

static int impact_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    (void)e;
    struct impact_case *c = state;
    const long ns = c->ns;
    int rc = ckpt_put_doubles(ck, "time", c->ts, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "displacement_1", c->s1, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "displacement_2", c->s2, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "raw_displacement_1", c->r1, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "raw_displacement_2", c->r2, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "etotal", c->es, ns);
    if (!rc) rc = ckpt_put_doubles(ck, "profiles", c->prof, (long)c->nprofiles * c->nbins);
    if (!rc) rc = ckpt_put_doubles(ck, "momentum_start", c->P0, 3);
    if (!rc) rc = ckpt_put_double(ck, "energy_deviation_max", c->demax);
    if (!rc) rc = ckpt_put_i64(ck, "region_particles", (const int64_t[2]){c->count[0], c->count[1]}, 2);
    if (!rc) rc = impact_front_checkpoint_write(&c->front, ck);
    if (!rc) rc = dpd_structure_checkpoint_write(&c->st, ck);
    if (!rc) rc = dpd_output_checkpoint_write(&c->out, ck);
    return rc;
}

static int impact_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct impact_case *c = state;
    long ns = ckpt_len(ck, "time");
    int rc = ns < 0 ? ERR_INPUT : 0;
    if (!rc && ns > c->nsamp)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld samples, at most %ld fit", ck->path,
                     ns, c->nsamp);
    int64_t count[2];
    if (!rc) rc = ckpt_get_doubles(ck, "time", c->ts, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "displacement_1", c->s1, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "displacement_2", c->s2, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "raw_displacement_1", c->r1, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "raw_displacement_2", c->r2, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "etotal", c->es, ns);
    if (!rc) rc = ckpt_get_doubles(ck, "profiles", c->prof, (long)c->nprofiles * c->nbins);
    if (!rc) rc = ckpt_get_doubles(ck, "momentum_start", c->P0, 3);
    if (!rc) rc = ckpt_get_double(ck, "energy_deviation_max", &c->demax);
    if (!rc) rc = ckpt_get_i64(ck, "region_particles", count, 2);
    if (!rc) {
        c->ns = ns;
        c->count[0] = (long)count[0];
        c->count[1] = (long)count[1];
        rc = dpd_structure_checkpoint_read(&c->st, ck);
    }
    if (!rc) rc = impact_front_checkpoint_read(&c->front, ck, e);
    if (!rc) rc = dpd_output_checkpoint_read(ck, &c->restored_rows, &c->nrestored, e);
    return rc;
}

static const struct sim_case_ops impact_ops = {
    .begin = impact_begin,
    .after_step = impact_after_step,
    .output = impact_output,
    .report = impact_report,
    .checkpoint_write = impact_checkpoint_write,
    .checkpoint_read = impact_checkpoint_read,
};

static int impact_run(void *state, struct run *run, struct err *e)
{
    struct impact_case *c = state;
    struct dpd *d = &c->d;
    d->timers = &run->timers;
    long nsamp = c->nsamp = c->steps / c->sample_every + 2;
    int nbins = c->nbins = (int)ceil(c->length / c->profile_bin);
    size_t np = c->nprofiles ? c->nprofiles : 1;
    c->ts = malloc((size_t)nsamp * sizeof *c->ts);
    c->s1 = malloc((size_t)nsamp * sizeof *c->s1);
    c->s2 = malloc((size_t)nsamp * sizeof *c->s2);
    c->es = malloc((size_t)nsamp * sizeof *c->es);
    c->r1 = malloc((size_t)nsamp * sizeof *c->r1);
    c->r2 = malloc((size_t)nsamp * sizeof *c->r2);
    c->prof = calloc(np * (size_t)nbins, sizeof *c->prof);
    c->pref = calloc((size_t)nbins, sizeof *c->pref);
    c->pcnt = calloc((size_t)nbins, sizeof *c->pcnt);
    c->pstep = malloc(np * sizeof *c->pstep);
    if (!c->ts || !c->s1 || !c->s2 || !c->es || !c->r1 || !c->r2 || !c->prof || !c->pref || !c->pcnt ||
        !c->pstep)
        return err_nomem(e, "impact samples");
    double lat_lo[3];
    for (int k = 0; k < 3; k++)
        lat_lo[k] = c->bar.face_lo[k] - 0.5 * c->bar.plane;
    int rcf = impact_front_init(&c->front, c->axis, c->face, c->length, c->regions, c->half,
                                c->bar.plane, lat_lo, c->bar.extent, nsamp, e);
    if (rcf)
        return rcf;
    for (size_t q = 0; q < c->nprofiles; q++) {
        c->pstep[q] = lround(c->profile_times[q] / d->dt);
        for (int b = 0; b < nbins; b++)
            c->prof[q * nbins + b] = NAN;
    }
    /* the reference run keeps no per-particle energies (it is not written) */
    c->model[0] = (struct dpd_model){.d = d, .snapshots = 1};
    c->model[1] = (struct dpd_model){.d = &c->ref, .snapshots = 0};
    struct sim s;
    sim_init(&s, run, c->steps, d->dt);
    s.case_ops = &impact_ops;
    s.case_state = c;
    int rc = sim_add_model(&s, &sim_model_dpd, &c->model[0], e);
    if (!rc && c->has_ref)
        rc = sim_add_model(&s, &sim_model_dpd_ref, &c->model[1], e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void impact_destroy(void *state)
{
    struct impact_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    if (c->has_ref)
        dpd_free(&c->ref);
    dpd_structure_free(&c->st);
    impact_free_halos(c);
    free(c->profile_times);
    free(c->ts);
    free(c->s1);
    free(c->s2);
    free(c->es);
    free(c->r1);
    free(c->r2);
    free(c->prof);
    free(c->pref);
    free(c->pcnt);
    free(c->pstep);
    impact_front_free(&c->front);
    free(c->restored_rows);
    free(c);
}

/* Particles integrated per step: the flyer run and the reference run. */
static long impact_particles(const void *state)
{
    const struct impact_case *c = state;
    long n = c->d.p ? dpd_nparticles(&c->d) : 0;
    if (c->has_ref && c->ref.p)
        n += dpd_nparticles(&c->ref);
    return n;
}

static long impact_steps(const void *state)
{
    const struct impact_case *c = state;
    return c->steps;
}

const struct case_type dpd_impact_case_type = {
    "dpd_impact", "DPD flyer/target impact: wave arrival at reference regions, wave speed",
    impact_read, impact_run, impact_destroy, impact_particles, impact_steps,
    .checkpoints = 1,
    .decomposes = 1,
};
