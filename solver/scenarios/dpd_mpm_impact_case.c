/*
 * dpd_mpm_impact_case: the flyer/target impact of Chen et al. 2014 with the
 * DPD particles carried by the MPM grid (couple/dpd_mpm.h):
 *
 *   type: dpd_grid_impact   the DPD/MPM-grid model (Sec. 4.1.1, Figs. 2b, 3, 4):
 *                           the whole target DPD, its pair forces mapped to the
 *                           grid nodes (Eq. (s3b)), moved by the MUSL update
 *   type: dpd_mpm_impact    the concurrent DPD/MPM model (Sec. 4.2, Figs. 7, 8):
 *                           the target split into DPD particles and material
 *                           points of the same size on one grid (Eq. (3.1))
 *
 * Sections: system, dpd (dpd_setup.h; default variant dpde), impact
 * (dpd_impact_setup.h: the same flyer, regions, arrival criterion, reference
 * run and profiles as the DPD-only `dpd_impact`), grid (dpd_mpm_setup.h),
 * analysis.structure (dpd_structure.h: CNA of the flyer run's DPD particles
 * at the coarse lattice constant, metrics cna_fcc, cna_hcp, cna_other, ...,
 * field `structure` in the snapshots),
 * and for dpd_mpm_impact:
 *
 *   concurrent:
 *     dpd: [-20, 108.45]     Å from the impact face, [lo, hi): DPD particles (required)
 *     mpm: [108.45, 240]     Å from the impact face, [lo, hi): material points (required);
 *                            the ranges must not overlap and must hold every particle
 *                            of the target (by its position at the start)
 *     material_state: lattice  the state whose density, point volume and cubic elastic
 *                            constants the material points get (cg_material_state.h):
 *                            lattice (the zero-pressure coarse-grained crystal at the
 *                            target's temperature), bar (the bar's volume per particle)
 *                            or parameter (the parameter file's lattice constant)
 *     lattice_constant: 0    Å: that state at this lattice constant instead (0: by
 *                            material_state)
 *     partner_embedding: frozen   frozen: each partner's F'(rho) stays at its start
 *                            value, so the interface forces are conservative
 *                            (dpd_conservative.c); live: F'(rho) of the partner's
 *                            current density (not energy-conserving: the runs
 *                            before 2026-11-25)
 *     partner_range: 0       Å: material points this close to a DPD particle become its
 *                            passive partners (0: two DPD cutoffs plus the skin)
 *     monitor: 60.0          Å from the face: centre of the slab (DPD side) where the
 *                            incident and reflected waves are measured
 *     monitor_thickness: 6.0 Å
 *     velocity_window: 0.1   ps: a slab's velocity is the central difference of its
 *                            displacement over +- this
 *     compare: true          also run the same target all DPD on the grid (with its own
 *                            reference run): the reflected wave is the difference
 *
 * The material points sit where the particles they replace were, at rest,
 * unstressed, each with the particle's mass and the volume a^3/4 of the
 * state of concurrent.material_state; their law is cubic_elastic with C11,
 * C12, C44 of the coarse-grained crystal at that same state -- computed,
 * never tuned.
 *
 * Measurements.  As in dpd_impact, a region's signal is its mean
 * displacement along the axis (DPD particles and material points, selected
 * by where they were at the start) in the flyer run minus that in the
 * reference run without the flyer: the displacement the impact caused.  The
 * wave has arrived when the signal first reaches impact.arrival_threshold
 * (analysis/wave_arrival.h); wave_speed_threshold = region separation /
 * difference of the arrival times.  wave_speed is the threshold-free front
 * fit over probe slabs between the regions (scenarios/impact_front.h; DPD
 * particles and material points alike).  Concurrent model with `compare`: the monitor slab's
 * impact-caused displacement in the concurrent run and in the all-DPD run
 * agree until a wave from the interface reaches the monitor; the
 * difference of their velocities (central differences over
 * +-velocity_window) is the reflected wave.  incident_amplitude = the
 * largest all-DPD velocity before any wave from the interface can reach
 * the monitor, tr = (2 x_i - x_m) / c_L (c_L = sqrt(C11/rho), the fastest
 * wave), reflected_amplitude = the largest |difference| before a wave from
 * the far end can, tw = (2 L - x_m) / c_L; reflection_ratio is their
 * quotient -- the reflection coefficient of the particle velocity.
 * transmission_ratio: the largest velocity of region 2 (beyond the
 * interface in the paper's layout) in the concurrent over the all-DPD run,
 * before tw.
 *
 * Snapshots (fields.h5): the DPD particles of the flyer run as in dpd_impact
 * (collection "particles"; partners, the material points' copies, have ids
 * from 2^40 on), and for the concurrent model the material points
 * (collection "points": position, displacement, velocity, stress in GPa,
 * id).
 *
 * On the engine (engine/sim.h): each run -- flyer, reference, all-DPD flyer
 * and reference -- is an instance of the dpd_mpm model
 * (engine/model_dpd_mpm.c); the sampling, the energy extremes and the
 * structure analysis are the case's after_step hook, and they go into the
 * checkpoints (output.checkpoint_every, run --restart).
 *
 * Under mpirun both types run on bricks (docs/dpd_mpm.md "Under MPI";
 * impact_bricks): each run's DPD particles on its own halo over the same
 * bricks, its grid whole on every rank with the node sums over the ranks
 * (couple/dpd_mpm.c), the free flyer's force a sum over the ranks; the
 * region means, profiles, front probes, CNA counts and internal
 * temperature are sums, the final state is written by rank 0 a window at a time.  The
 * concurrent model's partners are made before the split (add_partners)
 * and are DPD particles of the bricks; its material points stay whole on
 * every rank (the coupling adds their share of the nodes once), so the
 * means, profiles and probes add the points' share once, after the sums
 * over the ranks; rank 0 writes their snapshots.  result.json's parallel
 * record counts the partners that crossed a brick face during the steps
 * (partner_migrations, partner_migrations_reference: dpd_mpm_partner_moves).
 *
 * Metrics (besides dpd_impact's wave_speed and its companions,
 * wave_speed_threshold, arrival_time_1/2,
 * region_particles_1/2, displacement_max_1/2, flyer_velocity_final,
 * target_particles, flyer_particles, target_length, momentum_change,
 * temperature): cell (Å), energy_drift and energy_deviation_max (relative,
 * the centred energy of dpd_mpm.h), impact_energy (eV, the flyer's kinetic
 * energy at the start), energy_deviation_max_abs (eV) and
 * energy_error_impact_fraction (over the impact energy), heat_dr and heat_grid (eV given to the
 * internal energies by the D + R forces and by the grid's smoothing),
 * internal_temperature (K, mean u / (C_v kB)), grid_nodes; concurrent:
 * material_points, partners, c11, c12, c44 (GPa), density (g/cm^3),
 * longitudinal_speed (m/s), incident_amplitude, reflected_amplitude (Å/ps),
 * reflection_ratio, transmission_ratio, reflection_window (ps).  Series: time_ps,
 * displacement_region_1/2, profile_x and profile_t<T>ps, arrival_thresholds
 * and wave_speed_scan, etotal (centred, eV); concurrent + compare:
 * monitor_concurrent, monitor_homogeneous (Å), monitor_velocity_concurrent,
 * monitor_velocity_homogeneous, reflected_velocity (Å/ps).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/displacement.h"
#include "analysis/wave_arrival.h"
#include "core/halo.h"
#include "core/units.h"
#include "core/velocity.h"
#include "dpd/cg_lattice.h"
#include "engine/models.h"
#include "scenarios/dpd_bar.h"
#include "scenarios/cg_material_state.h"
#include "scenarios/dpd_impact_setup.h"
#include "scenarios/impact_front.h"
#include "scenarios/dpd_mpm_setup.h"
#include "output/decomp_record.h"
#include "output/dpd_output.h"
#include "output/final_state.h"
#include "scenarios/dpd_setup.h"
#include "scenarios/dpd_structure.h"
#include "input/md_system.h"

#define PARTNER_BIT (1u << 6)
#define PARTNER_ID0 ((int64_t)1 << 40)
#define MAX_RUNS 4

/* One simulation: the DPD model and the grid (and material points). */
struct coupled {
    struct dpd d;
    struct dpd_mpm c;
    int xref;
    int has_d, has_c;
};

/* The material points of the concurrent model (shared by its runs). */
struct points {
    long n;
    double *x;
    int64_t *id;
    double mass, volume, rho, c11, c12, c44, range;
    struct cg_material_state state;   /* where rho, volume and C come from */
};

struct conc_keys {
    double dpd[2], mpm[2], a, range, monitor, mhalf, vwin;
    int compare;
    int live_embedding;   /* partner_embedding: live (1) or frozen (0) */
    int state;            /* material_state: enum cg_state_source */
};

struct samples {
    double *t, *s1, *s2, *es, *mc, *mh, *h2;
    long n, cap;
};

static int samples_alloc(struct samples *s, long cap, struct err *e)
{
    memset(s, 0, sizeof *s);
    s->cap = cap;
    double **a[] = {&s->t, &s->s1, &s->s2, &s->es, &s->mc, &s->mh, &s->h2};
    for (size_t k = 0; k < sizeof a / sizeof a[0]; k++)
        if (!(*a[k] = calloc((size_t)cap, sizeof(double))))
            return err_nomem(e, "impact samples");
    return 0;
}

static void samples_free(struct samples *s)
{
    free(s->t);
    free(s->s1);
    free(s->s2);
    free(s->es);
    free(s->mc);
    free(s->mh);
    free(s->h2);
}

struct impact_case {
    int concurrent;
    struct coupled r[MAX_RUNS];   /* flyer, reference, all-DPD flyer, all-DPD reference */
    struct halo *halo[MAX_RUNS];  /* bricks of each run (owned; dpd_grid_impact under
                                     mpirun), or NULL */
    int nruns, has_ref, has_hom;
    long steps;
    struct dpd_impact_keys k;
    struct conc_keys ck;
    struct points pts;
    double face, length, cell;
    struct dpd_bar bar;           /* the target at the start (lateral extent of the probes) */
    double c11, c12, rho;         /* eV/Å^3, amu/Å^3: the DPD material (reference speeds) */
    struct impact_front front;    /* probes of the threshold-free wave speed */
    long n_target, n_flyer, nodes;
    long npartners[MAX_RUNS];     /* partners of each run (on bricks over the ranks) */
    struct dpd_structure st;      /* CNA of the flyer run's DPD particles (Fig. 4) */
    /* on the engine: one model instance per run */
    struct dpd_mpm_model model[MAX_RUNS];
    /* the run's accumulators (checkpointed) */
    struct dpd_output out;
    int out_open;
    struct samples S;             /* region signals every sample_every steps */
    double *prof, *pref;          /* profiles at the profile times (nptimes x nbins) */
    double *cnt;                  /* scratch: a profile's particles per bin */
    int nbins;
    double bin;
    double P0[3];                 /* total momentum at step 0 */
    double e0, demax, et;         /* centred energy after step 1, largest change, last */
    double *restored_rows;        /* thermo rows read from a checkpoint */
    long nrestored;
};

static int read_concurrent(struct cfg_obj *root, struct conc_keys *k)
{
    static const char *const embeddings[] = {"frozen", "live", NULL};
    static const char *const states[] = {"lattice", "bar", "parameter", NULL};
    struct cfg_obj o;
    int rc;
    if ((rc = cfg_section_required(root, "concurrent", &o)) ||
        (rc = cfg_reals(&o, "dpd", 2, NULL, CFG_ANY, k->dpd)) ||
        (rc = cfg_reals(&o, "mpm", 2, NULL, CFG_ANY, k->mpm)) ||
        (rc = cfg_real(&o, "lattice_constant", 0.0, CFG_GE(0), &k->a)) ||
        (rc = cfg_real(&o, "partner_range", 0.0, CFG_GE(0), &k->range)) ||
        (rc = cfg_real(&o, "monitor", 60.0, CFG_ANY, &k->monitor)) ||
        (rc = cfg_real(&o, "monitor_thickness", 6.0, CFG_GT(0), &k->mhalf)) ||
        (rc = cfg_real(&o, "velocity_window", 0.1, CFG_GT(0), &k->vwin)) ||
        (rc = cfg_bool(&o, "compare", 1, &k->compare)) ||
        (rc = cfg_enum(&o, "partner_embedding", "frozen", embeddings, &k->live_embedding)) ||
        (rc = cfg_enum(&o, "material_state", "lattice", states, &k->state)) ||
        (rc = cfg_close(&o)))
        return rc;
    k->mhalf *= 0.5;
    char kp[CFG_PATH_MAX];
    for (int q = 0; q < 2; q++) {
        const double *r = q ? k->mpm : k->dpd;
        if (!(r[1] > r[0])) {
            snprintf(kp, sizeof kp, "%s.%s", o.path, q ? "mpm" : "dpd");
            return cfg_error_at(o.cfg, kp, "empty range [%g, %g): give [lo, hi) with hi > lo",
                                r[0], r[1]);
        }
    }
    if (k->dpd[0] < k->mpm[1] && k->mpm[0] < k->dpd[1]) {
        snprintf(kp, sizeof kp, "%s.mpm", o.path);
        return cfg_error_at(o.cfg, kp,
                            "the MPM range [%g, %g) overlaps the DPD range [%g, %g): a particle "
                            "is either a DPD particle or a material point",
                            k->mpm[0], k->mpm[1], k->dpd[0], k->dpd[1]);
    }
    return 0;
}

/* --- building ---------------------------------------------------------------- */

static void coupled_free(struct coupled *m)
{
    if (m->has_c)
        dpd_mpm_free(&m->c);
    if (m->has_d)
        dpd_free(&m->d);
    memset(m, 0, sizeof *m);
}

/* One run over the DPD particles p (taken; with their partners already
 * added, add_partners), with the flyer's particles (mask DPD_FLYER_BIT)
 * made a rigid body when `flyer` (on bricks on every rank, also those that
 * hold none of them), and the material points `pts` (NULL: none). */
static int coupled_build(struct coupled *m, struct particles *p, int flyer,
                         const struct points *pts, const struct impact_case *ic,
                         const struct dpd_input *in, const struct box *box,
                         const struct case_common *common, const struct dpd_mpm_grid *g,
                         struct err *e)
{
    memset(m, 0, sizeof *m);
    int rc = 0;
    m->has_d = 1;
    if ((rc = dpd_build(in, p, box, common, e, &m->d)))
        return rc;
    m->d.passive_mask = PARTNER_BIT;
    /* conservative interface forces (dpd_conservative.c) unless asked for
     * the partners' live embedding */
    m->d.freeze_passive_fp = pts && pts->n > 0 && !ic->ck.live_embedding;
    if (flyer) {
        double v[3] = {0, 0, 0};
        v[ic->k.axis] = ic->k.velocity;
        rc = dpd_add_body(&m->d, DPD_FLYER_BIT,
                          ic->k.motion == 0 ? DPD_BODY_FREE : DPD_BODY_PRESCRIBED, v, e);
    }
    if (!rc)
        rc = dpd_mpm_order(&m->d, PARTNER_BIT, e);
    if (!rc && (m->xref = displacement_begin(m->d.p, &m->d.box, e)) < 0)
        rc = ERR_RUNTIME;
    if (rc)
        return rc;
    m->has_c = 1;
    if ((rc = dpd_mpm_init(&m->c, &m->d, g, PARTNER_BIT, PARTNER_ID0, e)))
        return rc;
    if (pts && pts->n > 0) {
        struct mpm_material *mat =
            mpm_material_cubic_elastic("coarse-grained", pts->rho, pts->c11, pts->c12, pts->c44);
        if (!mat)
            return err_nomem(e, "material");
        rc = dpd_mpm_add_points(&m->c, mat, pts->n, pts->x, NULL, pts->mass, pts->volume, pts->id,
                                e);
    }
    return rc ? rc : dpd_mpm_prepare(&m->c, e);
}

/* Split the target into DPD particles (kept in p) and material points by
 * position along the axis from the face. */
static int split_target(struct cfg_obj *root, struct particles *p, const struct impact_case *ic,
                        struct points *pts)
{
    struct err *e = root->cfg->err;
    const int ax = ic->k.axis;
    unsigned char *keep = malloc((size_t)(p->n_owned ? p->n_owned : 1));
    pts->x = malloc((size_t)3 * (p->n_owned ? p->n_owned : 1) * sizeof *pts->x);
    pts->id = malloc((size_t)(p->n_owned ? p->n_owned : 1) * sizeof *pts->id);
    if (!keep || !pts->x || !pts->id) {
        free(keep);
        return err_nomem(e, "material points");
    }
    pts->n = 0;
    int rc = 0;
    for (int i = 0; i < p->n_owned && !rc; i++) {
        double s = p->x[3 * i + ax] - ic->face;
        int in_dpd = s >= ic->ck.dpd[0] && s < ic->ck.dpd[1];
        int in_mpm = s >= ic->ck.mpm[0] && s < ic->ck.mpm[1];
        keep[i] = (unsigned char)in_dpd;
        if (in_mpm) {
            memcpy(pts->x + 3 * pts->n, p->x + 3 * i, 3 * sizeof(double));
            pts->id[pts->n++] = p->id[i];
        } else if (!in_dpd) {
            rc = cfg_error_at(root->cfg, "concurrent",
                              "particle %lld at %.3f Å from the impact face lies in neither "
                              "concurrent.dpd [%g, %g) nor concurrent.mpm [%g, %g)",
                              (long long)p->id[i], s, ic->ck.dpd[0], ic->ck.dpd[1], ic->ck.mpm[0],
                              ic->ck.mpm[1]);
        }
    }
    if (!rc && pts->n == 0)
        rc = cfg_error_at(root->cfg, "concurrent.mpm",
                          "no particle of the target lies in the MPM range [%g, %g) Å from the "
                          "impact face",
                          ic->ck.mpm[0], ic->ck.mpm[1]);
    long n_dpd = 0;
    for (int i = 0; i < p->n_owned; i++)
        n_dpd += keep[i];
    if (!rc && n_dpd == 0)
        rc = cfg_error_at(root->cfg, "concurrent.dpd",
                          "no particle of the target lies in the DPD range [%g, %g) Å from the "
                          "impact face: the concurrent model needs DPD particles where the "
                          "DPD flyer strikes (Sec. 4.2)",
                          ic->ck.dpd[0], ic->ck.dpd[1]);
    if (!rc)
        particles_compact(p, keep);
    free(keep);
    return rc;
}

/* The material points hold together only through the grid nodes they share:
 * with linear shape functions a point's stress reaches the 8 nodes of its
 * own cell and nothing else (Eq. (s3a)), so two neighbouring
 * points interact only when their separation along each axis is at most a
 * cell edge.  For the fcc coarse-grained lattice the nearest neighbours are
 * a/2 apart along each axis, so the edge must be at least a/2, which is
 * V_point / h^3 <= 2: at least half a material point per cell.  Finer grids
 * leave the points unconnected (the MPM part neither moves nor transmits the
 * wave, and the run would end "ok" with no wave speed). */
#define CONCURRENT_MIN_POINTS_PER_CELL 0.5

static int check_points_per_cell(struct cfg_obj *root, double cell, const struct points *pts)
{
    double ppc = cell * cell * cell / pts->volume;
    if (ppc >= CONCURRENT_MIN_POINTS_PER_CELL)
        return 0;
    return cfg_error_at(root->cfg, "grid.cell",
                        "cell edge %g Å gives %.3g material points per cell (volume %.4g Å^3 "
                        "per point); the concurrent model needs at least %g, i.e. a cell edge "
                        "of at least %.3g Å, so that neighbouring points share grid nodes",
                        cell, ppc, pts->volume, CONCURRENT_MIN_POINTS_PER_CELL,
                        cbrt(CONCURRENT_MIN_POINTS_PER_CELL * pts->volume));
}

static void impact_destroy(void *state);

/* The passive partners of the material points `pts` (NULL: none) near the
 * DPD particles of p: before p is split over bricks, so that a point near
 * a DPD particle of another brick gets its partner too. */
static int add_partners(struct particles *p, const struct points *pts, struct err *e)
{
    long added = 0;
    if (!pts || pts->n == 0)
        return 0;
    return dpd_mpm_partners_create(p, p->n_owned, pts->n, pts->x, pts->id, pts->range,
                                   PARTNER_BIT, PARTNER_ID0, &added, e);
}

/* Under mpirun (docs/dpd_mpm.md "Under MPI"): the flyer run's particles p
 * keep their brick's share of the DPD halo (no sweep's reach: the grid
 * model has no Shardlow sweep), every other run its own of a halo over
 * the same bricks, so that a run and its reference run hold the same
 * material on each rank.  dpd_grid_impact: each rank built only its
 * brick's particles, on the bricks impact_read planned.  dpd_mpm_impact:
 * every rank built all particles (with the partners) and keeps its
 * brick's (dpd_bricks), planned here on the DPD part's extent.  The
 * grid, and for dpd_mpm_impact the material points, stay whole on every
 * rank.  No-op serially and replicated. */
static int impact_bricks(struct impact_case *c, int r, struct particles *p,
                         const struct dpd_input *in, const struct box *box,
                         const struct case_common *common, struct cfg *cfg)
{
    if (!c->concurrent) {
        /* each rank built its brick's target (md_system_read_split, whose
         * plan gave c->halo[0]; none serially or replicated) and flyer:
         * every run keeps it, on its own halo over the same bricks (a
         * particle a displacement moved just out of its brick migrates at
         * the first list build) */
        if (!c->halo[0])
            return 0;
        struct err *e = cfg->err;
        int rc = 0;
        if (r > 0) {
            if (!(c->halo[r] = calloc(1, sizeof *c->halo[r])))
                rc = err_nomem(e, "reference run bricks");
            else
                rc = halo_init_like(c->halo[r], c->halo[0], e);
        }
        struct halo *h = c->halo[r] ? c->halo[r] : c->halo[0];
        p->halo = h;
        p->par = NULL;   /* no replicated sums: each rank owns its brick */
        return halo_adopt(h, p, rc, e);
    }
    if (r == 0) {
        /* The DPD halo holds only the DPD part (for dpd_mpm_impact with
         * the partners, not the material points), and the reference run
         * holds it without the flyer: the bricks are planned on that
         * extent (dpd_bricks_plan_box), so that `auto` takes bricks only
         * where they stay thicker than the interaction range in every run
         * (a note and replicated data otherwise). */
        struct box plan;
        dpd_bricks_plan_box(box, p, DPD_FLYER_BIT, in->skin, &plan);
        return dpd_bricks(in, &plan, p, common, cfg, 0, &c->halo[0]);
    }
    if (!c->halo[0])
        return 0;
    struct err *e = cfg->err;
    if (!(c->halo[r] = calloc(1, sizeof *c->halo[r])))
        return err_nomem(e, "reference run bricks");
    int rc = halo_init_like(c->halo[r], c->halo[0], e);
    if (rc)
        return rc;
    p->halo = c->halo[r];
    p->par = NULL;   /* no replicated sums: each rank owns its brick */
    return halo_distribute(c->halo[r], p, e);
}

static int impact_read(struct cfg_obj *root, const struct case_common *common, void **state,
                       int concurrent)
{
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    struct dpd_input in;
    struct dpd_mpm_grid_keys gk;
    struct impact_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "impact case");
    c->concurrent = concurrent;
    /* both types run on bricks (impact_bricks).  dpd_grid_impact builds
     * (a lattice) or receives (a file rank 0 read) only each rank's
     * brick of the target, the bricks planned on the target's extent
     * less the skin; the dpd section first, its ranges size the bricks.
     * The concurrent model builds the whole target on every rank: its
     * DPD part, which the bricks hold, is known only once the target is
     * split at the face (split_target), and its material points stay
     * whole on every rank. */
    int rc = dpd_section_read(root, DPD_ENERGY, &in);
    struct halo *mine = NULL;
    if (!rc && concurrent) {
        rc = md_system_read(root, common->seed, &p, &box, &info);
    } else if (!rc) {
        struct dpd_split_plan plan = {&in, common, root->cfg, 1};
        struct md_system_split sp = {dpd_split_plan_bricks, &plan, 0, common->par, 1};
        rc = md_system_read_split(root, common->seed, root->cfg->shallow ? NULL : &sp, &p, &box,
                                  &info, &mine);
    }
    c->halo[0] = mine;   /* the flyer run's, owned by the case */
    if (mine) {
        p->halo = mine;
        p->par = NULL;   /* no replicated sums: each rank owns its brick */
    }
    if (!rc)
        rc = dpd_impact_keys_read(root, &c->k);
    if (!rc)
        rc = dpd_mpm_grid_read(root, root->cfg->shallow ? 0.0 : fmax(in.prm.sc.rc, in.set.cutoff),
                               &gk);
    if (!rc && concurrent)
        rc = read_concurrent(root, &c->ck);
    if (!rc)
        rc = dpd_structure_read(root, &c->st);
    if (!rc && box.bc[c->k.axis] == BOUNDARY_PERIODIC)
        rc = cfg_error_at(root->cfg, "system.boundary",
                          "the impact axis %c must not be periodic (the flyer comes from outside)",
                          "xyz"[c->k.axis]);
    if (!rc && in.thermo.style != THERMOSTAT_NONE)
        rc = cfg_error_at(root->cfg, "dpd.thermostat.style",
                          "the grid-carried models take no thermostat: equilibrate with the "
                          "DPD-only `dpd` case type and read its final state (Chen 2014 "
                          "embeds the equilibrated state in the grid)");
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        impact_destroy(c);
        return rc;
    }
    struct err *e = root->cfg->err;
    const int ax = c->k.axis;
    double a = c->k.a > 0 ? c->k.a : in.prm.lattice_constant;
    struct dpd_bar bar;
    struct particles *hom = NULL;
    /* the k-th Maxwell draw to the k-th id of all ranks: the serial
     * velocities (to round-off on bricks, bitwise serially); the bar's
     * faces over every rank's particles */
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = in.prm.mass;
    if (in.t_init > 0)
        rc = velocity_maxwell_split(p, in.t_init, common->seed, 1u, mine, e);
    dpd_bar_measure_over(p, 0, 0.5 * a, mine, &bar);
    c->face = bar.face_lo[ax];
    c->length = bar.extent[ax];
    c->bar = bar;
    {
        double c44;
        cg_lattice_elastic(&in.prm.sc, in.prm.lattice_constant, &c->c11, &c->c12, &c44);
        c->rho = 4 * in.prm.mass / pow(in.prm.lattice_constant, 3);
    }
    double ntarget = (double)p->n_owned;
    if (mine)
        halo_sum(mine, &ntarget, 1);
    c->n_target = lround(ntarget);
    c->steps = in.steps;
    c->cell = gk.cell;
    for (int r = 0; r < 2 && !rc; r++)
        if (c->k.regions[r] + c->k.half > c->length)
            rc = cfg_error_at(root->cfg, "impact.regions",
                              "region %d (%g +- %g Å from the face) reaches past the target's "
                              "far face at %g Å",
                              r + 1, c->k.regions[r], c->k.half, c->length);
    /* one grid for every run: over the target, with room for where the
     * impact pushes it over the run */
    struct dpd_mpm_grid g;
    double mlo[3], mhi[3];
    for (int d = 0; d < 3; d++) {
        mlo[d] = mhi[d] = gk.margin > 0 ? gk.margin : 2 * gk.cell + 0.5 * a;
        if (d == ax && gk.margin <= 0)
            mhi[d] += fabs(c->k.velocity) * in.dt * (double)in.steps;
    }
    dpd_mpm_grid_place(p, 0, mlo, mhi, &gk, &g);
    if (!rc && concurrent) {
        c->has_hom = c->ck.compare;
        if (c->has_hom && !(hom = dpd_particles_clone(p, e)))
            rc = ERR_RUNTIME;
        struct points *pts = &c->pts;
        /* density, point volume and elastic constants of one state
         * (cg_material_state.h); the run's temperature is the target's */
        double ke2 = 0;
        for (int i = 0; i < p->n_owned; i++)
            ke2 += p->v[3 * i] * p->v[3 * i] + p->v[3 * i + 1] * p->v[3 * i + 1] +
                   p->v[3 * i + 2] * p->v[3 * i + 2];
        double T = p->n_owned ? in.prm.mass * ke2 * UNITS_MVV2E / (3.0 * p->n_owned * UNITS_KB)
                              : 0.0;
        double vbar = bar.extent[0] * bar.extent[1] * bar.extent[2] / (double)c->n_target;
        int src = c->ck.a > 0 ? CG_STATE_GIVEN : c->ck.state;
        if (!rc && (rc = cg_material_state_get(&in.prm, src, c->ck.a, T, vbar, &pts->state, e)))
            rc = cfg_error_at(root->cfg, "concurrent.material_state", "%s", e->msg);
        pts->c11 = pts->state.c11;
        pts->c12 = pts->state.c12;
        pts->c44 = pts->state.c44;
        pts->mass = in.prm.mass;
        pts->volume = pts->state.volume;
        pts->rho = pts->state.rho;
        pts->range = c->ck.range > 0 ? c->ck.range : 2 * fmax(in.prm.sc.rc, in.set.cutoff) + in.skin;
        if (!rc)
            rc = check_points_per_cell(root, gk.cell, pts);
        if (!rc)
            rc = split_target(root, p, c, pts);
        if (!rc && c->ck.monitor - c->ck.mhalf < c->ck.dpd[0])
            rc = cfg_error_at(root->cfg, "concurrent.monitor",
                              "the monitor slab must lie in the DPD part [%g, %g)", c->ck.dpd[0],
                              c->ck.dpd[1]);
    }
    /* the runs: flyer (+ reference) (+ all-DPD flyer and reference) */
    struct particles *src[MAX_RUNS] = {NULL, NULL, NULL, NULL};
    const struct points *use[MAX_RUNS] = {concurrent ? &c->pts : NULL,
                                          concurrent ? &c->pts : NULL, NULL, NULL};
    int flyer[MAX_RUNS] = {1, 0, 1, 0};
    c->has_ref = c->k.reference;
    int want[MAX_RUNS] = {1, c->has_ref, c->has_hom, c->has_hom && c->has_ref};
    for (int r = 0; r < MAX_RUNS && !rc; r++) {
        if (!want[r])
            continue;
        src[r] = dpd_particles_clone(r < 2 ? p : hom, e);
        if (!src[r]) {
            rc = ERR_RUNTIME;
            break;
        }
        long nf = 0;
        if (flyer[r])   /* each rank the flyer sites of its brick */
            rc = dpd_impact_add_flyer_over(src[r], &bar, &c->k, a, mine, &nf, e);
        if (r == 0)
            c->n_flyer = nf;
        if (!rc)
            rc = add_partners(src[r], use[r], e);
        if (!rc)
            rc = impact_bricks(c, r, src[r], &in, &box, common, root->cfg);
        if (!rc) {
            rc = coupled_build(&c->r[r], src[r], flyer[r], use[r], c, &in, &box, common, &g, e);
            src[r] = NULL;
            c->nruns = r + 1;
        }
        if (rc == ERR_INPUT && strstr(e->msg, "time step")) {
            char msg[sizeof e->msg];
            snprintf(msg, sizeof msg, "%s", e->msg);
            rc = cfg_error_at(root->cfg, "dpd.timestep", "%s", msg);
        }
    }
    for (int r = 0; r < MAX_RUNS; r++)
        particles_destroy(&src[r]);
    particles_destroy(&p);
    particles_destroy(&hom);
    if (!rc)
        rc = dpd_structure_attach(&c->st, &c->r[0].d, in.prm.sc.a, DPD_FLYER_BIT | PARTNER_BIT,
                                  common->nthreads, e);
    if (rc) {
        impact_destroy(c);
        return rc;
    }
    c->nodes = c->r[0].c.m.grid.nnodes;
    for (int r = 0; r < c->nruns; r++) {   /* bricks: each rank holds its brick's partners */
        double np = (double)c->r[r].c.npartner;
        if (c->halo[r])
            halo_sum(c->halo[r], &np, 1);
        c->npartners[r] = lround(np);
    }
    *state = c;
    return 0;
}

static int grid_impact_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    return impact_read(root, common, state, 0);
}

static int concurrent_impact_read(struct cfg_obj *root, const struct case_common *common,
                                  void **state)
{
    return impact_read(root, common, state, 1);
}

/* --- measuring ------------------------------------------------------------------ */

/* Mean displacement along the axis of the material (carried DPD particles
 * and material points) whose start position along the axis lies in
 * [lo, hi); *count its number. */
static double slab_mean(const struct coupled *m, int ax, double lo, double hi, long *count)
{
    long nd = 0;
    double md = displacement_slab_mean(m->d.p, &m->d.box, m->xref, ax, lo, hi,
                                       DPD_FLYER_BIT | PARTNER_BIT, &nd);
    double s[2] = {nd ? md * nd : 0.0, (double)nd};   /* sum, count */
    if (m->d.p->halo)   /* bricks: each rank's particles; the points (whole on
                           every rank) are added once, after the sum */
        halo_sum(m->d.p->halo, s, 2);
    const struct mpm_points *pts = &m->c.m.pts;
    for (long k = 0; k < pts->n; k++) {
        double r = pts->x0[3 * k + ax];
        if (r < lo || r >= hi)
            continue;
        s[0] += pts->x[3 * k + ax] - r;
        s[1] += 1;
    }
    long n = lround(s[1]);
    if (count)
        *count = n;
    return n ? s[0] / s[1] : NAN;
}

/* Displacement profile of both kinds of material in bins of width w from
 * origin: out[k] (NAN for empty bins). */
static void profile(const struct coupled *m, int ax, double origin, double w, int nbins,
                    double *out, double *cnt)
{
    /* the carried DPD particles: neither the flyer nor partners */
    displacement_profile_sums(m->d.p, &m->d.box, m->xref, ax, origin, w, nbins,
                              DPD_FLYER_BIT | PARTNER_BIT, out, cnt);
    if (m->d.p->halo) {   /* bricks: each rank's particles; then the points once */
        halo_sum(m->d.p->halo, out, nbins);
        halo_sum(m->d.p->halo, cnt, nbins);
    }
    const struct mpm_points *pts = &m->c.m.pts;
    for (long q = 0; q < pts->n; q++) {
        int k = (int)floor((pts->x0[3 * q + ax] - origin) / w);
        if (k < 0 || k >= nbins)
            continue;
        out[k] += pts->x[3 * q + ax] - pts->x0[3 * q + ax];
        cnt[k] += 1;
    }
    for (int k = 0; k < nbins; k++)
        out[k] = cnt[k] > 0 ? out[k] / cnt[k] : NAN;
}

/* Impact-caused mean displacement of [lo, hi) from the face: flyer run a
 * less reference run b (or the raw signal without one). */
static double signal(const struct impact_case *c, int a, int b, double lo, double hi, long *count)
{
    double s = slab_mean(&c->r[a], c->k.axis, c->face + lo, c->face + hi, count);
    if (b >= 0 && b < c->nruns && c->r[b].has_c)
        s -= slab_mean(&c->r[b], c->k.axis, c->face + lo, c->face + hi, NULL);
    return s;
}

static double internal_temperature(const struct coupled *m)
{
    const struct dpd *d = &m->d;
    if (d->ufield < 0)
        return NAN;
    const double *u = d->p->fields[d->ufield].data;
    double s[2] = {0, (double)m->c.ncarried};   /* sum, count */
    for (long i = 0; i < m->c.ncarried; i++)
        s[0] += u[i];
    if (d->p->halo)   /* bricks: each rank's carried particles */
        halo_sum(d->p->halo, s, 2);
    if (!(s[1] > 0))
        return NAN;
    return s[0] / s[1] / (d->set.heat_capacity * UNITS_KB);
}

/* --- the run ----------------------------------------------------------------- */

/* The material points of the flyer run (collection "points" beside the DPD
 * "particles" of dpd_output): position, displacement, velocity (Å, Å/ps),
 * stress (GPa, xx yy zz xy xz yz), id. */
static int points_snapshot(struct run *run, const struct coupled *m, struct err *e)
{
    const struct mpm_points *p = &m->c.m.pts;
    long n = p->n;
    if (!run->h5_open || n == 0)
        return 0;
    double *buf = malloc((size_t)6 * n * sizeof *buf);
    int64_t *ids = malloc((size_t)n * sizeof *ids);
    int rc = 0;
    hid_t g = H5I_INVALID_HID;
    if (!buf || !ids)
        rc = err_nomem(e, "points snapshot");
    else if ((g = h5out_begin_snapshot(&run->h5, "points", m->d.step, m->d.time, n, e)) < 0)
        rc = ERR_RUNTIME;
    if (!rc)
        rc = h5out_write_doubles(&run->h5, g, "position", p->x, n, 3, "Å", e);
    if (!rc) {
        for (long k = 0; k < 3 * n; k++)
            buf[k] = p->x[k] - p->x0[k];
        rc = h5out_write_doubles(&run->h5, g, "displacement", buf, n, 3, "Å", e);
    }
    if (!rc)
        rc = h5out_write_doubles(&run->h5, g, "velocity", p->v, n, 3, "Å/ps", e);
    if (!rc) {
        for (long k = 0; k < 6 * n; k++)
            buf[k] = p->stress[k] * UNITS_EVA3_TO_GPA;
        rc = h5out_write_doubles(&run->h5, g, "stress", buf, n, 6, "GPa", e);
    }
    if (!rc) {
        for (long k = 0; k < n; k++)
            ids[k] = p->id[k];
        rc = h5out_write_ints(&run->h5, g, "id", ids, n, "1", e);
    }
    if (g >= 0)
        h5out_end_snapshot(&run->h5, g);
    free(buf);
    free(ids);
    return rc;
}

/* Velocity of a slab from its displacement samples: central differences
 * over +-w ps (NAN where the window leaves the run). */
static void slab_velocity(const double *t, const double *u, long n, double w, double *v)
{
    long j0 = 0, j1 = 0;
    for (long q = 0; q < n; q++) {
        v[q] = NAN;
        while (j0 < q && t[j0] < t[q] - w)
            j0++;
        if (j1 < q)
            j1 = q;
        while (j1 + 1 < n && t[j1 + 1] <= t[q] + w)
            j1++;
        if (t[q] - t[0] >= w - 1e-12 && t[n - 1] - t[q] >= w - 1e-12 && t[j1] > t[j0])
            v[q] = (u[j1] - u[j0]) / (t[j1] - t[j0]);
    }
}

static void impact_metrics(struct impact_case *c, struct run *run, const struct samples *S,
                           double demax, double e0, double et, const double P0[3])
{
    struct result *res = &run->result;
    struct coupled *m = &c->r[0];
    double dist = c->k.regions[1] - c->k.regions[0];
    /* the legacy criterion: a fixed displacement threshold (wave_speed_threshold) */
    double t1 = wave_arrival_time(S->t, S->s1, S->n, c->k.threshold);
    double t2 = wave_arrival_time(S->t, S->s2, S->n, c->k.threshold);
    double speed = wave_speed(dist, t1, t2);
    double front_speed;
    /* reference speeds: the material points' constants in the concurrent
     * model (the probes beyond the interface are points), else the DPD
     * crystal's */
    if (c->concurrent)
        impact_front_report(&c->front, res, c->pts.c11, c->pts.c12, c->pts.rho, &front_speed);
    else
        impact_front_report(&c->front, res, c->c11, c->c12, c->rho, &front_speed);
    double m1 = -INFINITY, m2 = -INFINITY;
    for (long q = 0; q < S->n; q++) {
        m1 = fmax(m1, S->s1[q]);
        m2 = fmax(m2, S->s2[q]);
    }
    double P1[3];
    dpd_mpm_momentum(&m->c, P1);
    double dP = sqrt((P1[0] - P0[0]) * (P1[0] - P0[0]) + (P1[1] - P0[1]) * (P1[1] - P0[1]) +
                     (P1[2] - P0[2]) * (P1[2] - P0[2]));
    long n1 = 0, n2 = 0;
    signal(c, 0, -1, c->k.regions[0] - c->k.half, c->k.regions[0] + c->k.half, &n1);
    signal(c, 0, -1, c->k.regions[1] - c->k.half, c->k.regions[1] + c->k.half, &n2);
    result_metric(res, "wave_speed_threshold", speed * UNITS_APS_TO_MS, "m/s");
    result_metric(res, "arrival_time_1", t1, "ps");
    result_metric(res, "arrival_time_2", t2, "ps");
    result_metric(res, "region_particles_1", (double)n1, "1");
    result_metric(res, "region_particles_2", (double)n2, "1");
    result_metric(res, "displacement_max_1", m1, "Å");
    result_metric(res, "displacement_max_2", m2, "Å");
    result_metric(res, "flyer_velocity_final", m->d.nbodies ? m->d.body[0].v[c->k.axis] : NAN,
                  "Å/ps");
    result_metric(res, "target_particles", (double)c->n_target, "1");
    result_metric(res, "flyer_particles", (double)c->n_flyer, "1");
    result_metric(res, "target_length", c->length, "Å");
    result_metric(res, "cell", c->cell, "Å");
    result_metric(res, "grid_nodes", (double)c->nodes, "1");
    result_metric(res, "energy_drift", (et - e0) / fabs(e0), "1");
    result_metric(res, "energy_deviation_max", demax / fabs(e0), "1");
    /* the same excursion against the impact energy: relative to the total
     * energy (cohesive, -1e5 eV) it looks small when it is not */
    double ke0 = m->d.nbodies ? 0.5 * m->d.body[0].mass * c->k.velocity * c->k.velocity *
                                    UNITS_MVV2E
                              : NAN;
    result_metric(res, "impact_energy", ke0, "eV");
    result_metric(res, "energy_deviation_max_abs", demax, "eV");
    result_metric(res, "energy_error_impact_fraction", ke0 > 0 ? demax / ke0 : NAN, "1");
    result_metric(res, "heat_dr", m->c.heat, "eV");
    result_metric(res, "heat_grid", m->c.subgrid_heat, "eV");
    result_metric(res, "momentum_change", dP, "amu Å/ps");
    result_metric(res, "temperature", dpd_temperature(&m->d), "K");
    result_metric(res, "internal_temperature", internal_temperature(m), "K");
    result_series(res, "time_ps", S->t, (int)S->n, "ps");
    result_series(res, "displacement_region_1", S->s1, (int)S->n, "Å");
    result_series(res, "displacement_region_2", S->s2, (int)S->n, "Å");
    result_series(res, "etotal", S->es, (int)S->n, "eV");
    {
        static const double th[] = {0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0};
        const int nth = (int)(sizeof th / sizeof th[0]);
        double vs[sizeof th / sizeof th[0]];
        for (int q = 0; q < nth; q++)
            vs[q] = wave_speed(dist, wave_arrival_time(S->t, S->s1, S->n, th[q]),
                               wave_arrival_time(S->t, S->s2, S->n, th[q])) *
                    UNITS_APS_TO_MS;
        result_series(res, "arrival_thresholds", th, nth, "Å");
        result_series(res, "wave_speed_scan", vs, nth, "m/s");
    }
    run_log(run, "wave front fit: %.0f m/s (flagged when null); fixed threshold %g Å: region 1 "
            "at %.4f ps, region 2 at %.4f ps -> %.0f m/s",
            front_speed * UNITS_APS_TO_MS, c->k.threshold, t1, t2, speed * UNITS_APS_TO_MS);
    if (!c->concurrent)
        return;
    const struct points *pts = &c->pts;
    double cl = sqrt(pts->c11 / pts->rho * UNITS_FTM2V);   /* Å/ps */
    result_metric(res, "material_points", (double)m->c.m.pts.n, "1");
    result_metric(res, "partners", (double)c->npartners[0], "1");
    result_metric(res, "c11", pts->c11 * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(res, "c12", pts->c12 * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(res, "c44", pts->c44 * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(res, "density", pts->rho * UNITS_AMU_A3_TO_KG_M3 * 1e-3, "g/cm^3");
    result_metric(res, "material_lattice_constant", pts->state.a, "Å");
    result_metric(res, "material_temperature", pts->state.T, "K");
    result_metric_source(res, "density", pts->state.note);
    result_metric_source(res, "c11", pts->state.note);
    result_metric_source(res, "material_lattice_constant", pts->state.note);
    if (!c->has_hom)
        return;
    /* the first wave from the interface reaches the monitor at tr, the
     * first one from the far end at tw (at the fastest, longitudinal speed) */
    double xi = c->ck.dpd[1] < c->ck.mpm[1] ? c->ck.dpd[1] : c->ck.mpm[1];
    double tr = (2 * xi - c->ck.monitor) / cl, tw = (2 * c->length - c->ck.monitor) / cl;
    long n = S->n;
    size_t sz = (size_t)(n ? n : 1) * sizeof(double);
    double *vc = malloc(sz), *vh = malloc(sz), *rv = malloc(sz), *v2c = malloc(sz),
           *v2h = malloc(sz);
    if (vc && vh && rv && v2c && v2h) {
        slab_velocity(S->t, S->mc, n, c->ck.vwin, vc);
        slab_velocity(S->t, S->mh, n, c->ck.vwin, vh);
        slab_velocity(S->t, S->s2, n, c->ck.vwin, v2c);
        slab_velocity(S->t, S->h2, n, c->ck.vwin, v2h);
        double inc = 0, refl = 0, tc = 0, th = 0;
        for (long q = 0; q < n; q++) {
            rv[q] = vc[q] - vh[q];
            if (!isfinite(rv[q]) || S->t[q] > tw)
                continue;
            if (S->t[q] <= tr)
                inc = fmax(inc, vh[q]);
            refl = fmax(refl, fabs(rv[q]));
            tc = fmax(tc, v2c[q]);
            th = fmax(th, v2h[q]);
        }
        result_metric(res, "reflection_window", tw, "ps");
        result_metric(res, "incident_amplitude", inc, "Å/ps");
        result_metric(res, "reflected_amplitude", refl, "Å/ps");
        result_metric(res, "reflection_ratio", inc > 0 ? refl / inc : NAN, "1");
        result_metric(res, "transmission_ratio", th > 0 ? tc / th : NAN, "1");
        result_series(res, "monitor_concurrent", S->mc, (int)n, "Å");
        result_series(res, "monitor_homogeneous", S->mh, (int)n, "Å");
        result_series(res, "monitor_velocity_concurrent", vc, (int)n, "Å/ps");
        result_series(res, "monitor_velocity_homogeneous", vh, (int)n, "Å/ps");
        result_series(res, "reflected_velocity", rv, (int)n, "Å/ps");
        run_log(run,
                "interface: incident %.3f Å/ps (up to %.2f ps), reflected %.3f Å/ps (ratio %.3f) "
                "up to %.2f ps; region 2 peak velocity %.3f of the all-DPD one",
                inc, tr, refl, inc > 0 ? refl / inc : NAN, tw, th > 0 ? tc / th : NAN);
    }
    free(vc);
    free(vh);
    free(rv);
    free(v2c);
    free(v2h);
}

/* The velocities of the front probes (flyer run less reference run). */
static void front_sample(struct impact_case *c, double t)
{
    struct impact_front *f = &c->front;
    impact_front_clear(f);
    for (int r = 0; r < 2; r++) {
        const struct coupled *m = &c->r[r];
        if (r >= c->nruns || !m->has_c)
            continue;
        const struct particles *p = m->d.p;
        impact_front_add(f, r, p->fields[m->xref].data, p->v, p->mask,
                         DPD_FLYER_BIT | PARTNER_BIT, p->n_owned);
        const struct mpm_points *pts = &m->c.m.pts;
        if (!c->halo[0])
            impact_front_add(f, r, pts->x0, pts->v, NULL, 0, pts->n);
    }
    if (c->halo[0]) {   /* bricks: each rank added its own particles; the
                           points (whole on every rank) are added once after */
        impact_front_sum_ranks(f, c->halo[0]);
        for (int r = 0; r < 2 && r < c->nruns; r++) {
            const struct mpm_points *pts = &c->r[r].c.m.pts;
            if (c->r[r].has_c)
                impact_front_add(f, r, pts->x0, pts->v, NULL, 0, pts->n);
        }
    }
    impact_front_end(f, t, c->has_ref);
}

/* The regions' signals at this step (every sample_every steps and the
 * last), and the displacement profiles at the profile times. */
static void impact_sample(struct impact_case *c, struct run *run, long step)
{
    struct coupled *m = &c->r[0];
    const struct dpd *d = &m->d;
    struct samples *S = &c->S;
    const double lo1 = c->k.regions[0] - c->k.half, hi1 = c->k.regions[0] + c->k.half;
    const double lo2 = c->k.regions[1] - c->k.half, hi2 = c->k.regions[1] + c->k.half;
    const double mlo = c->ck.monitor - c->ck.mhalf, mhi = c->ck.monitor + c->ck.mhalf;
    timer_start(&run->timers, TIMER_ANALYSIS);
    if (step % c->k.sample_every == 0 || step == c->steps) {
        long q = S->n++;
        S->t[q] = d->time;
        S->s1[q] = signal(c, 0, 1, lo1, hi1, NULL);
        S->s2[q] = signal(c, 0, 1, lo2, hi2, NULL);
        S->es[q] = step > 0 ? c->et : NAN;
        if (c->has_hom) {
            S->mc[q] = signal(c, 0, 1, mlo, mhi, NULL);
            S->mh[q] = signal(c, 2, 3, mlo, mhi, NULL);
            S->h2[q] = signal(c, 2, 3, lo2, hi2, NULL);
        }
        front_sample(c, d->time);
    }
    for (size_t q = 0; q < c->k.nptimes; q++) {
        if (lround(c->k.ptimes[q] / d->dt) != step)
            continue;
        double *pq = c->prof + q * c->nbins;
        profile(m, c->k.axis, c->face, c->bin, c->nbins, pq, c->cnt);
        if (c->has_ref) {
            profile(&c->r[1], c->k.axis, c->face, c->bin, c->nbins, c->pref, c->cnt);
            for (int b = 0; b < c->nbins; b++)
                pq[b] -= c->pref[b];
        }
    }
    timer_stop(&run->timers, TIMER_ANALYSIS);
}

/* --- the run on the engine (engine/sim.h) ------------------------------------ */

static int impact_begin(void *state, struct sim *s, struct err *e)
{
    struct impact_case *c = state;
    struct coupled *m = &c->r[0];
    int rc = dpd_output_begin(&c->out, s->run, e);
    c->out_open = !rc;
    if (!rc && s->restarted_from >= 0)
        rc = dpd_output_resume(&c->out, s->run, c->restored_rows, c->nrestored, e);
    free(c->restored_rows);
    c->restored_rows = NULL;
    if (rc || s->restarted_from >= 0)
        return rc;
    /* step 0 */
    dpd_mpm_momentum(&m->c, c->P0);
    if ((rc = dpd_structure_classify(&c->st, &m->d, e)))
        return rc;
    impact_sample(c, s->run, 0);
    return 0;
}

static int impact_after_step(void *state, struct sim *s, struct err *e)
{
    struct impact_case *c = state;
    struct coupled *m = &c->r[0];
    struct dpd_mpm_energy en;
    dpd_mpm_energy(&m->c, &en);
    c->et = en.centred;
    if (s->step == 1)
        c->e0 = c->et;
    c->demax = fmax(c->demax, fabs(c->et - c->e0));
    int rc = dpd_structure_before_output(&c->st, s->run, &m->d, c->steps, e);
    if (!rc)
        impact_sample(c, s->run, s->step);
    return rc;
}

static int impact_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct impact_case *c = state;
    struct coupled *m = &c->r[0];
    /* dpd_output_step reads the same schedule */
    if (dpd_output_step(&c->out, s->run, &m->d, c->steps))
        return err_set(e, ERR_RUNTIME, "%s: cannot write the outputs of step %ld",
                       s->run->opt.out_dir, s->step);
    return (due & SIM_DUE_SNAPSHOT) ? points_snapshot(s->run, m, e) : 0;
}

static int impact_report(void *state, struct sim *s, int rc, struct err *e)
{
    struct impact_case *c = state;
    struct coupled *m = &c->r[0];
    struct run *run = s->run;
    struct dpd *d = &m->d;
    /* a run that stopped on a non-finite energy reports that energy */
    if (rc == ERR_DIVERGED && s->diverged[0]) {
        struct dpd_mpm_energy en;
        dpd_mpm_energy(&m->c, &en);
        c->et = en.centred;
    }
    if (!rc)
        rc = dpd_structure_finish(&c->st, run, d, e);
    if (!rc || rc == ERR_DIVERGED) {
        impact_metrics(c, run, &c->S, c->demax, c->e0, c->et, c->P0);
        if (c->k.nptimes) {
            double *xc = malloc((size_t)c->nbins * sizeof *xc);
            if (xc) {
                for (int b = 0; b < c->nbins; b++)
                    xc[b] = (b + 0.5) * c->bin;
                result_series(&run->result, "profile_x", xc, c->nbins, "Å");
                free(xc);
            }
            for (size_t q = 0; q < c->k.nptimes; q++) {
                char name[64];
                snprintf(name, sizeof name, "profile_t%gps", c->k.ptimes[q]);
                result_series(&run->result, name, c->prof + q * c->nbins, c->nbins, "Å");
            }
        }
    }
    if (!c->out_open)
        return rc;
    c->out_open = 0;
    int rc2 = dpd_output_end(&c->out, run, e);
    if (c->halo[0]) {
        decomp_record_write(run, c->halo[0], d->p);
        /* the partners that crossed a brick face during the steps, in the
         * flyer run and its reference run (a diagnostic: the lookup of
         * their points by id after a migration ran; collective) */
        static const char *const key[2] = {"partner_migrations", "partner_migrations_reference"};
        json_t *par = json_object_get(run->result.root, "parallel");
        for (int r = 0; c->concurrent && r < 2 && c->r[r].has_c; r++) {
            long moves = dpd_mpm_partner_moves(&c->r[r].c);
            if (par)
                json_object_set_new(par, key[r], json_integer((json_int_t)moves));
        }
    }
    if (!rc && !rc2)   /* bricks: rank 0 writes, a window at a time */
        rc2 = final_state_write(run, c->halo[0], d->p, &d->box, d->step, d->time, e);
    return rc ? rc : rc2;
}

static int impact_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct impact_case *c = state;
    const struct samples *S = &c->S;
    (void)e;
    int rc = ckpt_put_doubles(ck, "momentum_start", c->P0, 3);
    if (!rc) rc = ckpt_put_double(ck, "energy_start", c->e0);
    if (!rc) rc = ckpt_put_double(ck, "energy_deviation_max", c->demax);
    if (!rc) rc = ckpt_put_double(ck, "energy_last", c->et);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_time", S->t, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_region_1", S->s1, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_region_2", S->s2, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_energy", S->es, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_monitor_concurrent", S->mc, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_monitor_homogeneous", S->mh, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "sample_region_2_homogeneous", S->h2, S->n);
    if (!rc) rc = ckpt_put_doubles(ck, "profiles", c->prof, (long)c->k.nptimes * c->nbins);
    if (!rc) rc = impact_front_checkpoint_write(&c->front, ck);
    if (!rc) rc = dpd_structure_checkpoint_write(&c->st, ck);
    if (!rc) rc = dpd_output_checkpoint_write(&c->out, ck);
    return rc;
}

static int impact_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct impact_case *c = state;
    struct samples *S = &c->S;
    int rc = ckpt_get_doubles(ck, "momentum_start", c->P0, 3);
    if (!rc) rc = ckpt_get_double(ck, "energy_start", &c->e0);
    if (!rc) rc = ckpt_get_double(ck, "energy_deviation_max", &c->demax);
    if (!rc) rc = ckpt_get_double(ck, "energy_last", &c->et);
    long n = rc ? -1 : ckpt_len(ck, "sample_time");
    if (!rc && (n < 0 || n > S->cap))
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld samples, at most %ld fit", ck->path,
                     n, S->cap);
    if (!rc) {
        S->n = n;
        rc = ckpt_get_doubles(ck, "sample_time", S->t, n);
    }
    if (!rc) rc = ckpt_get_doubles(ck, "sample_region_1", S->s1, n);
    if (!rc) rc = ckpt_get_doubles(ck, "sample_region_2", S->s2, n);
    if (!rc) rc = ckpt_get_doubles(ck, "sample_energy", S->es, n);
    if (!rc) rc = ckpt_get_doubles(ck, "sample_monitor_concurrent", S->mc, n);
    if (!rc) rc = ckpt_get_doubles(ck, "sample_monitor_homogeneous", S->mh, n);
    if (!rc) rc = ckpt_get_doubles(ck, "sample_region_2_homogeneous", S->h2, n);
    if (!rc) rc = ckpt_get_doubles(ck, "profiles", c->prof, (long)c->k.nptimes * c->nbins);
    if (!rc) rc = impact_front_checkpoint_read(&c->front, ck, e);
    if (!rc) rc = dpd_structure_checkpoint_read(&c->st, ck);
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

/* Checkpoint groups of the runs (model/<name>). */
static const char *const run_names[MAX_RUNS] = {"dpd_mpm", "dpd_mpm_reference", "dpd_mpm_all_dpd",
                                                "dpd_mpm_all_dpd_reference"};

static int impact_run(void *state, struct run *run, struct err *e)
{
    struct impact_case *c = state;
    struct coupled *m = &c->r[0];
    struct dpd *d = &m->d;
    d->timers = &run->timers;
    m->c.m.timers = &run->timers;
    long nsamp = c->steps / c->k.sample_every + 2;
    c->bin = c->k.bin > 0 ? c->k.bin : 0.5 * d->prm.lattice_constant;
    c->nbins = (int)ceil(c->length / c->bin);
    size_t np = c->k.nptimes;
    c->prof = calloc((np ? np : 1) * (size_t)c->nbins, sizeof *c->prof);
    c->pref = calloc((size_t)c->nbins, sizeof *c->pref);
    c->cnt = calloc((size_t)c->nbins, sizeof *c->cnt);
    int rc = samples_alloc(&c->S, nsamp, e);
    if (rc || !c->prof || !c->pref || !c->cnt)
        return rc ? rc : err_nomem(e, "profiles");
    double lat_lo[3];
    for (int k = 0; k < 3; k++)
        lat_lo[k] = c->bar.face_lo[k] - 0.5 * c->bar.plane;
    if ((rc = impact_front_init(&c->front, c->k.axis, c->face, c->length, c->k.regions,
                                c->k.half, c->bar.plane, lat_lo, c->bar.extent, nsamp, e)))
        return rc;
    for (size_t q = 0; q < np * (size_t)c->nbins; q++)
        c->prof[q] = NAN;
    c->e0 = c->et = NAN;
    c->demax = 0;
    struct sim s;
    sim_init(&s, run, c->steps, d->dt);
    s.case_ops = &impact_ops;
    s.case_state = c;
    for (int r = 0; r < c->nruns && !rc; r++) {
        if (!c->r[r].has_c)
            continue;
        /* the flyer run's particles are the ones written */
        c->model[r] = (struct dpd_mpm_model){.c = &c->r[r].c, .snapshots = r == 0};
        rc = sim_add_model_named(&s, &sim_model_dpd_mpm, &c->model[r], run_names[r], e);
    }
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void impact_destroy(void *state)
{
    struct impact_case *c = state;
    if (!c)
        return;
    for (int r = 0; r < MAX_RUNS; r++)
        coupled_free(&c->r[r]);
    for (int r = 0; r < MAX_RUNS; r++) {   /* after the runs whose particles use them */
        if (c->halo[r])
            halo_free(c->halo[r]);
        free(c->halo[r]);
    }
    free(c->pts.x);
    free(c->pts.id);
    free(c->k.ptimes);
    dpd_structure_free(&c->st);
    samples_free(&c->S);
    impact_front_free(&c->front);
    free(c->prof);
    free(c->pref);
    free(c->cnt);
    free(c->restored_rows);
    free(c);
}

/* Particles advanced per step, over every run: DPD particles (not the
 * partners; on bricks over every rank) and material points. */
static long impact_particles(const void *state)
{
    const struct impact_case *c = state;
    long n = 0;
    for (int r = 0; r < c->nruns; r++)
        if (c->r[r].has_c)
            n += dpd_nparticles(&c->r[r].d) - c->npartners[r] + c->r[r].c.m.pts.n;
    return n;
}

static long impact_steps(const void *state)
{
    const struct impact_case *c = state;
    return c->steps;
}

const struct case_type dpd_grid_impact_case_type = {
    "dpd_grid_impact",
    "DPD/MPM-grid flyer/target impact: DPD forces on the MPM grid, wave arrival, wave speed",
    grid_impact_read, impact_run, impact_destroy, impact_particles, impact_steps,
    .checkpoints = 1,
    .decomposes = 1,
};

const struct case_type dpd_mpm_impact_case_type = {
    "dpd_mpm_impact",
    "concurrent DPD/MPM flyer/target impact: wave across the interface, reflection",
    concurrent_impact_read, impact_run, impact_destroy, impact_particles, impact_steps,
    .checkpoints = 1,
    .decomposes = 1,
};
