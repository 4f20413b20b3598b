/* dpd: set-up, neighbour management, the split step and observables. */
#include "dpd/dpd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/domain.h"
#include "core/ghost.h"
#include "core/halo.h"
#include "core/units.h"
#include "dpd/cg_lattice.h"
#include "dpd/dpd_pair.h"

const char *const dpd_variant_names[] = {"dpd", "dpde", NULL};

static void tstart(struct dpd *d, enum timer_id id)
{
    if (d->timers)
        timer_start(d->timers, id);
}
static void tstop(struct dpd *d, enum timer_id id)
{
    if (d->timers)
        timer_stop(d->timers, id);
}

static double list_cutoff(const struct dpd *d)
{
    return fmax(d->prm.sc.rc, d->set.cutoff);
}

/* Order every particle's neighbours by (id, periodic image counted on
 * unwrapped positions): the sweep's order of a particle's pairs then
 * depends on who its neighbours are, not on storage or ghost indices or on
 * when particles were wrapped (insertion sort: lists are short). */
static void neighbour_key(const struct particles *p, int i, int j, int64_t key[4])
{
    int o = p->origin[j];
    key[0] = p->id[o];
    for (int k = 0; k < 3; k++)
        key[1 + k] = p->gshift[3 * j + k] - p->image[3 * o + k] + p->image[3 * i + k];
}

static int key_less(const int64_t a[4], const int64_t b[4])
{
    for (int k = 0; k < 4; k++)
        if (a[k] != b[k])
            return a[k] < b[k];
    return 0;
}

static void canonical_order(const struct particles *p, struct nlist *nl)
{
    for (int i = 0; i < nl->n; i++) {
        int *a = nl->neigh + nl->offset[i], n = nl->offset[i + 1] - nl->offset[i];
        for (int k = 1; k < n; k++) {
            int j = a[k], q = k;
            int64_t kj[4], km[4];
            neighbour_key(p, i, j, kj);
            while (q > 0) {
                neighbour_key(p, i, a[q - 1], km);
                if (!key_less(kj, km))
                    break;
                a[q] = a[q - 1];
                q--;
            }
            a[q] = j;
        }
    }
}

static int cmp_order_key(const void *a, const void *b);

/* perm: the owned particles in (cls, id) order (cls NULL: id alone). */
static int order_perm(const struct particles *p, const int *cls, int *perm, struct err *e)
{
    int n = p->n_owned;
    int64_t (*key)[3] = malloc((size_t)(n ? n : 1) * sizeof *key);
    if (!key)
        return err_nomem(e, "particle order");
    for (int i = 0; i < n; i++) {
        key[i][0] = cls ? cls[i] : 0;
        key[i][1] = p->id[i];
        key[i][2] = i;
    }
    qsort(key, (size_t)n, sizeof *key, cmp_order_key);
    for (int i = 0; i < n; i++)
        perm[i] = (int)key[i][2];
    free(key);
    return 0;
}

/* The classes of dpd_fix_class_order. */
static int particle_class(const struct dpd *d, int i)
{
    if (dpd_body_of(d, i) >= 0)
        return 2;
    return (d->p->mask[i] & d->class_mask) ? 1 : 0;
}

/* domain_order_fn: the owned particles back in (class, id) order after a
 * migration between bricks. */
static int class_perm(void *ctx, const struct particles *p, int *perm, struct err *e)
{
    const struct dpd *d = ctx;
    int n = p->n_owned;
    int *cls = malloc((size_t)(n ? n : 1) * sizeof *cls);
    if (!cls)
        return err_nomem(e, "particle order");
    for (int i = 0; i < n; i++)
        cls[i] = particle_class(d, i);
    int rc = order_perm(p, cls, perm, e);
    free(cls);
    return rc;
}

double dpd_ghost_range(const struct dpd *d)
{
    double range = list_cutoff(d) + d->skin;
    /* the cell sweep's anchors reach half a cell past the brick */
    if (d->set.sweep_cells || (d->p->halo && !d->moved_elsewhere))
        range = fmax(range, dpd_sweep_cells_range(&d->box, d->set.cutoff, d->skin));
    return range;
}

/* Wrap, (sort), ghosts, list. */
static int rebuild(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    double range = dpd_ghost_range(d);
    /* shifted cuts (parallel.balance), as for MD (md.c) */
    if (p->halo) {
        int brc = halo_balance_step(p->halo, &d->box, p, range, d->step, e);
        if (brc)
            return brc;
    }
    int rc = d->class_order && p->halo
                 ? domain_rebuild_ordered(p, &d->box, range, class_perm, d, d->timers, e)
                 : domain_rebuild(p, &d->box, range,
                                  d->sort_every > 0 && d->nrebuilds % d->sort_every == 0,
                                  d->timers, e);
    if (!rc)
        rc = nlist_build(d->nl, p, e);
    if (!rc && d->canonical_lists)
        canonical_order(p, d->nl);
    d->nrebuilds++;
    return rc;
}

/* Bring ghosts and the list up to date with the current positions. */
int dpd_refresh_neighbours(struct dpd *d, struct err *e)
{
    tstart(d, TIMER_NEIGHBOR);
    int rc = 0;
    int need = d->rebuild_next || nlist_needs_rebuild(d->nl, d->p);
    if (d->p->halo)   /* every rank rebuilds when one needs it */
        need = halo_any(d->p->halo, need);
    if (need) {
        d->rebuild_next = 0;
        rc = rebuild(d, e);
        tstop(d, TIMER_NEIGHBOR);
    } else {
        tstop(d, TIMER_NEIGHBOR);
        tstart(d, TIMER_COMM);
        ghost_update_positions(d->p, &d->box);
        tstop(d, TIMER_COMM);
    }
    return rc;
}

int dpd_compute_forces(struct dpd *d, struct err *e)
{
    int rc = dpd_refresh_neighbours(d, e);
    if (rc)
        return rc;
    tstart(d, TIMER_FORCE);
    rc = dpd_conservative(d, e);
    tstop(d, TIMER_FORCE);
    return rc;
}

int dpd_init(struct dpd *d, struct particles *p, const struct box *box,
             const struct cg_params *prm, const struct dpd_settings *set, double dt, double skin,
             int nthreads, uint64_t seed, struct err *e)
{
    memset(d, 0, sizeof *d);
    d->p = p;
    d->box = *box;
    d->prm = *prm;
    d->set = *set;
    d->dt = dt;
    d->skin = skin;
    d->nthreads = nthreads < 1 ? 1 : nthreads;
    d->seed = seed;
    d->sort_every = 20;
    d->ufield = -1;
    d->thermo.style = THERMOSTAT_NONE;
    d->thermo.group_mask = 1u;
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = prm->mass;
    for (int dim = 0; dim < 3; dim++)
        if (box->bc[dim] == BOUNDARY_PERIODIC && box_length(box, dim) <= 0)
            return err_set(e, ERR_INPUT, "periodic box length along %c must be positive",
                           "xyz"[dim]);
    if (set->variant == DPD_ENERGY) {
        d->ufield = particles_add_field(p, "u_internal", 1, 0, e);
        if (d->ufield < 0)
            return ERR_RUNTIME;
        /* u_i = C_v kB T0: every particle starts at the reference temperature */
        double *u = particles_field(p, d->ufield);
        for (int i = 0; i < p->n_owned; i++)
            u[i] = set->heat_capacity * UNITS_KB * set->temperature;
    }
    d->nl = nlist_create(NLIST_HALF, list_cutoff(d), skin);
    if (!d->nl)
        return err_nomem(e, "neighbor list");
    return dpd_compute_forces(d, e);
}

void dpd_free(struct dpd *d)
{
    particles_destroy(&d->p);
    nlist_destroy(&d->nl);
    free(d->rho);
    free(d->fp_frozen);
    free(d->fp);
    free(d->pair_dr);
    free(d->inner);
    free(d->ninner);
    free(d->r2buf);
    thread_accum_free(&d->acc_rho);
    thread_accum_free(&d->acc_f);
    thread_accum_free(&d->acc_pe);
    thread_accum_free(&d->acc_vir);
    memset(d, 0, sizeof *d);
}

int dpd_add_body(struct dpd *d, uint32_t mask, enum dpd_body_kind kind, const double v[3],
                 struct err *e)
{
    if (d->nbodies >= DPD_MAX_BODIES)
        return err_set(e, ERR_INPUT, "at most %d rigid bodies", DPD_MAX_BODIES);
    for (int b = 0; b < d->nbodies; b++)
        if (d->body[b].mask & mask)
            return err_set(e, ERR_INPUT, "rigid bodies %d and %d share group bits", b,
                           d->nbodies);
    struct dpd_body *body = &d->body[d->nbodies];
    memset(body, 0, sizeof *body);
    body->mask = mask;
    body->kind = kind;
    memcpy(body->v, v, sizeof body->v);
    struct particles *p = d->p;
    for (int i = 0; i < p->n_owned; i++)
        if (p->mask[i] & mask) {
            body->n++;
            body->mass += p->mass[p->type[i]];
            memcpy(p->v + 3 * i, v, 3 * sizeof(double));
        }
    if (p->halo) {   /* a body spanning bricks: its particles on every rank */
        double nm[2] = {body->n, body->mass};
        halo_sum(p->halo, nm, 2);
        body->n = (int)nm[0];
        body->mass = nm[1];
    }
    if (body->n == 0)
        return err_set(e, ERR_INPUT, "rigid body %d has no particles", d->nbodies);
    d->nbodies++;
    return 0;
}

/* Sum of the conservative forces on each body (owned particles; on
 * bricks summed over the ranks, so a free body moves alike on every rank). */
static void body_forces(struct dpd *d, double F[DPD_MAX_BODIES][3])
{
    memset(F, 0, sizeof(double) * 3 * DPD_MAX_BODIES);
    if (d->nbodies == 0)
        return;
    const struct particles *p = d->p;
    for (int i = 0; i < p->n_owned; i++) {
        int b = dpd_body_of(d, i);
        if (b >= 0)
            for (int c = 0; c < 3; c++)
                F[b][c] += p->f[3 * i + c];
    }
    if (p->halo)
        halo_sum(p->halo, &F[0][0], 3 * DPD_MAX_BODIES);
}

/* Velocity-Verlet half kick of free particles and free bodies. */
static void half_kick(struct dpd *d, const double F[DPD_MAX_BODIES][3])
{
    struct particles *p = d->p;
    const double h = 0.5 * d->dt * UNITS_FTM2V;
    for (int i = 0; i < p->n_owned; i++) {
        if (d->nbodies && dpd_body_of(d, i) >= 0)
            continue;
        double s = h / p->mass[p->type[i]];
        for (int c = 0; c < 3; c++)
            p->v[3 * i + c] += s * p->f[3 * i + c];
    }
    for (int b = 0; b < d->nbodies; b++)
        if (d->body[b].kind == DPD_BODY_FREE)
            for (int c = 0; c < 3; c++)
                d->body[b].v[c] += h * F[b][c] / d->body[b].mass;
}

/* Body particles take their body's velocity. */
static void sync_bodies(struct dpd *d)
{
    if (d->nbodies == 0)
        return;
    struct particles *p = d->p;
    for (int i = 0; i < p->n_owned; i++) {
        int b = dpd_body_of(d, i);
        if (b >= 0)
            memcpy(p->v + 3 * i, d->body[b].v, 3 * sizeof(double));
    }
}

int dpd_step_sweep_drift(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    int rc = 0;
    /* a checkpoint asked for ghosts and list rebuilt from the stored state:
     * the sweep below walks the list */
    if (d->rebuild_next && (rc = dpd_refresh_neighbours(d, e)))
        return rc;
    /* 1. dissipative + random, pair by pair (positions at t, forces f(t) kept) */
    memset(d->body_impulse, 0, sizeof d->body_impulse);
    if (d->set.gamma > 0) {
        tstart(d, TIMER_DPD_SWEEP);
        rc = d->set.sweep_cells || d->p->halo ? dpd_sweep_cells(d, e) : dpd_sweep(d, e);
        sync_bodies(d);
        tstop(d, TIMER_DPD_SWEEP);
        if (rc)
            return rc;
    }
    /* 2. velocity Verlet with the conservative forces: half kick, drift */
    double F[DPD_MAX_BODIES][3];
    tstart(d, TIMER_INTEGRATE);
    body_forces(d, F);
    half_kick(d, F);
    sync_bodies(d);
    for (int i = 0; i < p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            p->x[3 * i + c] += d->dt * p->v[3 * i + c];
    tstop(d, TIMER_INTEGRATE);
    return 0;
}

int dpd_step_forces(struct dpd *d, struct err *e) { return dpd_compute_forces(d, e); }

void dpd_step_kick(struct dpd *d)
{
    struct particles *p = d->p;
    double F[DPD_MAX_BODIES][3];
    tstart(d, TIMER_INTEGRATE);
    body_forces(d, F);
    half_kick(d, F);
    /* 3. optional Berendsen rescaling of the free particles */
    if (d->thermo.style == THERMOSTAT_BERENDSEN)
        thermostat_berendsen_rescale(&d->thermo, p, d->dt, dpd_temperature(d));
    sync_bodies(d);
    /* the sweep's impulse (kept in d->body_impulse since stage 1) as a force */
    for (int b = 0; b < d->nbodies; b++)
        for (int c = 0; c < 3; c++)
            d->body[b].force[c] = F[b][c] + d->body_impulse[b][c] * UNITS_MVV2E / d->dt;
    tstop(d, TIMER_INTEGRATE);
    d->step++;
    d->time += d->dt;
}

int dpd_step(struct dpd *d, struct err *e)
{
    int rc = dpd_step_sweep_drift(d, e);
    if (!rc)
        rc = dpd_step_forces(d, e);
    if (rc)
        return rc;
    dpd_step_kick(d);
    return 0;
}

double dpd_kinetic_energy(const struct dpd *d)
{
    const struct particles *p = d->p;
    double ke = 0;
    for (int i = 0; i < p->n_owned; i++) {
        const double *v = p->v + 3 * i;
        ke += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    if (p->halo)
        halo_sum(p->halo, &ke, 1);
    return 0.5 * ke * UNITS_MVV2E;
}

double dpd_temperature(const struct dpd *d)
{
    const struct particles *p = d->p;
    double ke = 0;
    long n = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (d->nbodies && dpd_body_of(d, i) >= 0)
            continue;
        const double *v = p->v + 3 * i;
        ke += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        n++;
    }
    if (p->halo) {
        double s[2] = {ke, (double)n};
        halo_sum(p->halo, s, 2);
        ke = s[0];
        n = (long)s[1];
    }
    double dof = n > 1 ? 3.0 * n - 3.0 : 3.0 * n;
    return dof > 0 ? ke * UNITS_MVV2E / (dof * UNITS_KB) : 0.0;
}

double dpd_internal_energy(const struct dpd *d)
{
    if (d->ufield < 0)
        return 0;
    const double *u = d->p->fields[d->ufield].data;
    double s = 0;
    for (int i = 0; i < d->p->n_owned; i++)
        s += u[i];
    if (d->p->halo)
        halo_sum(d->p->halo, &s, 1);
    return s;
}

void dpd_momentum(const struct dpd *d, double P[3])
{
    const struct particles *p = d->p;
    P[0] = P[1] = P[2] = 0;
    for (int i = 0; i < p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            P[c] += p->mass[p->type[i]] * p->v[3 * i + c];
    if (p->halo)
        halo_sum(p->halo, P, 3);
}

void dpd_pressure_tensor(const struct dpd *d, double P[6])
{
    double k[6];
    particles_kinetic_tensor(d->p, k);
    if (d->p->halo)
        halo_sum(d->p->halo, k, 6);
    double V = box_volume(&d->box);
    for (int c = 0; c < 6; c++)
        P[c] = (k[c] + d->virial[c]) / V;
}

double dpd_timestep_limit(const struct cg_params *prm)
{
    double k = cg_lattice_einstein_k(&prm->sc, prm->lattice_constant);
    if (!(k > 0))
        return INFINITY;
    double wE = sqrt(k * UNITS_FTM2V / prm->mass);
    return sqrt(2.0) / wE;
}

long dpd_nparticles(const struct dpd *d)
{
    return d->p->halo ? d->p->halo->natoms : d->p->n_owned;
}

static int cmp_order_key(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    for (int k = 0; k < 2; k++)
        if (x[k] != y[k])
            return (x[k] > y[k]) - (x[k] < y[k]);
    return 0;
}

int dpd_fix_order(struct dpd *d, const int *cls, struct err *e)
{
    struct particles *p = d->p;
    int n = p->n_owned;
    int *perm = malloc((size_t)(n ? n : 1) * sizeof *perm);
    int rc = perm ? order_perm(p, cls, perm, e) : err_nomem(e, "particle order");
    if (!rc) {
        particles_clear_ghosts(p);
        rc = particles_permute(p, perm, e);
    }
    free(perm);
    if (rc)
        return rc;
    d->sort_every = 0;
    d->canonical_lists = 1;
    d->nl->nbuilds = 0;   /* rebuild ghosts and list from the new order */
    return dpd_compute_forces(d, e);
}

int dpd_fix_class_order(struct dpd *d, uint32_t mid_mask, struct err *e)
{
    int n = d->p->n_owned;
    int *cls = malloc((size_t)(n ? n : 1) * sizeof *cls);
    if (!cls)
        return err_nomem(e, "particle order");
    d->class_mask = mid_mask;
    d->class_order = 1;   /* also for the rebuild of dpd_fix_order */
    d->moved_elsewhere = 1;
    for (int i = 0; i < n; i++)
        cls[i] = particle_class(d, i);
    int rc = dpd_fix_order(d, cls, e);
    free(cls);
    return rc;
}
