/* md: velocity Verlet, neighbour and ghost management, observables. */
#include "md/md.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/domain.h"
#include "core/ghost.h"
#include "core/halo.h"
#include "core/parallel.h"
#include "core/units.h"

static void tstart(struct md *md, enum timer_id id)
{
    if (md->timers)
        timer_start(md->timers, id);
}
static void tstop(struct md *md, enum timer_id id)
{
    if (md->timers)
        timer_stop(md->timers, id);
}

/* Wrap, (sort), ghosts, list. */
static int rebuild(struct md *md, struct err *e)
{
    struct particles *p = md->p;
    double range = md->pot->cutoff + md->skin;
    /* dynamic balance: a build is where atoms migrate anyway (LAMMPS' fix
     * balance checks at its re-neighbouring steps too) */
    int rc = md->halo ? halo_balance_step(md->halo, &md->box, p, range, md->step, e) : 0;
    if (rc)
        return rc;
    rc = domain_rebuild(p, &md->box, range, md->sort_every > 0 && md->nrebuilds % md->sort_every == 0,
                            md->timers, e);
    if (rc)
        return rc;
    parallel_range(p->par, p->n_owned, &md->nl->ilo, &md->nl->ihi);
    rc = nlist_build(md->nl, p, e);
    md->nrebuilds++;
    return rc;
}

int md_compute_forces(struct md *md, struct err *e)
{
    struct particles *p = md->p;
    int rc;
    tstart(md, TIMER_NEIGHBOR);
    if (md->sync_rc) {
        tstop(md, TIMER_NEIGHBOR);
        return err_set(e, md->sync_rc, "redistributing the atoms over the bricks after a "
                                       "checkpoint failed");
    }
    int need = md->rebuild_next || nlist_needs_rebuild(md->nl, p);
    if (md->halo)   /* every rank rebuilds when one needs it */
        need = halo_any(md->halo, need);
    md->rebuild_next = 0;
    if (need) {
        rc = rebuild(md, e);
        tstop(md, TIMER_NEIGHBOR);
        if (rc)
            return rc;
    } else {
        tstop(md, TIMER_NEIGHBOR);
        tstart(md, TIMER_COMM);
        ghost_update_positions(p, &md->box);
        tstop(md, TIMER_COMM);
    }
    tstart(md, TIMER_FORCE);
    md->pot->nthreads = md->nthreads;
    rc = md->pot->ops->compute(md->pot, p, md->nl, md->peratom ? POT_PERATOM : 0, &md->last, e);
    tstop(md, TIMER_FORCE);
    if (rc)
        return rc;
    tstart(md, TIMER_COMM);
    ghost_reverse_add(p, p->f, 3);
    if (md->peratom) {
        ghost_reverse_add(p, p->pe, 1);
        ghost_reverse_add(p, p->virial, 6);
    }
    if (p->par || md->halo) {   /* energy and virial of this rank's slice or brick -> totals */
        double ev[7] = {md->last.energy};
        for (int c = 0; c < 6; c++)
            ev[1 + c] = md->last.virial[c];
        if (md->halo)
            halo_sum(md->halo, ev, 7);
        else
            parallel_sum(p->par, ev, 7);
        md->last.energy = ev[0];
        for (int c = 0; c < 6; c++)
            md->last.virial[c] = ev[1 + c];
    }
    tstop(md, TIMER_COMM);
    return 0;
}

int md_range_ok(const struct potential *pot, const struct box *b, long n, double skin,
                double max_ghosts, const char *limit, char *why, size_t len)
{
    double range = pot->cutoff + skin;
    double ghosts = ghost_estimate(b, n, range);
    double vol = box_volume(b);
    double dens = vol > 0 ? (double)n / vol : 0;
    double total = (double)n + ghosts;
    double per_atom = fmin(total, dens * 4.0 / 3.0 * M_PI * range * range * range);
    if (pot->list_kind == NLIST_HALF)   /* each pair once */
        per_atom *= 0.5;
    double entries = total * per_atom;
    char from[700] = "";
    if (pot->cutoff_source[0])
        snprintf(from, sizeof from, " (from %s)", pot->cutoff_source);
    if (!(ghosts <= max_ghosts)) {
        snprintf(why, len, "cutoff %g Å%s plus skin %g Å against the %g x %g x %g Å box "
                 "(%s %s %s) needs about %.3g ghost atoms (periodic images), more than %s = %.0f",
                 pot->cutoff, from, skin, box_length(b, 0), box_length(b, 1), box_length(b, 2),
                 boundary_names[b->bc[0]], boundary_names[b->bc[1]], boundary_names[b->bc[2]],
                 ghosts, limit, max_ghosts);
        return -1;
    }
    if (!(entries <= INT_MAX)) {
        snprintf(why, len, "cutoff %g Å%s plus skin %g Å: the neighbour list of %ld atoms would "
                 "hold about %.3g entries, more than its int offsets count (%d)", pot->cutoff,
                 from, skin, n, entries, INT_MAX);
        return -1;
    }
    return 0;
}

int md_init(struct md *md, struct particles *p, const struct box *box, struct potential *pot,
            double dt, double skin, int nthreads, struct err *e)
{
    memset(md, 0, sizeof *md);
    md->halo = p->halo;   /* md_adopt's (NULL otherwise) */
    md->p = p;
    md->box = *box;
    md->pot = pot;
    md->dt = dt;
    md->skin = skin;
    md->nthreads = nthreads < 1 ? 1 : nthreads;
    md->sort_every = 20;
    md->thermo.style = THERMOSTAT_NONE;
    md->thermo.group_mask = 1u;
    md->nl = nlist_create(pot->list_kind, pot->cutoff, skin);
    if (md->halo)   /* a half list never holds a ghost below the brick (core/halo.h) */
        md->halo->half_shell = pot->list_kind == NLIST_HALF;
    if (!md->nl)
        return err_nomem(e, "neighbor list");
    for (int d = 0; d < 3; d++)
        if (box->bc[d] == BOUNDARY_PERIODIC && box_length(box, d) <= 0)
            return err_set(e, ERR_INPUT, "periodic box length along %c must be positive",
                           "xyz"[d]);
    char why[1024];
    if (md_range_ok(pot, box, p->n_owned, skin, INT_MAX / 2 - (double)p->n_owned,
                    "what int particle indices hold", why, sizeof why) != 0)
        return err_set(e, ERR_INPUT, "%s", why);
    int rc = potential_bind(pot, p, e);
    if (rc)
        return rc;
    return md_compute_forces(md, e);
}

void md_free(struct md *md)
{
    particles_destroy(&md->p);
    potential_destroy(&md->pot);
    nlist_destroy(&md->nl);
    if (md->halo)
        halo_free(md->halo);
    free(md->halo);
    md->halo = NULL;
}

long md_natoms(const struct md *md)
{
    return md->halo ? md->halo->natoms : md->p->n_owned;
}

void md_adopt(struct md *md, struct particles *p, struct halo *h)
{
    memset(md, 0, sizeof *md);
    md->halo = h;
    p->halo = h;
    p->par = NULL;   /* no replicated sums: each rank owns its brick */
}

int md_decomposed_sync(struct md *md, int after_read, struct err *e)
{
    struct particles *p = md->p;
    particles_clear_ghosts(p);
    int rc = 0;
    if (after_read) {   /* every rank read every atom: keep the brick's */
        decomp_set_box(&md->halo->dc, &md->box);
        rc = halo_distribute(md->halo, p, e);
    }
    /* no shrink-wrap: the box stays the one of the last list build, as in
     * a run without checkpoints */
    if (!rc)
        rc = halo_remap(md->halo, &md->box, p, 0, e);
    /* dynamic balance: the continuing and the restarted run both cut at
     * the stored atoms (the restarted one would otherwise go on with the
     * set-up's cuts) */
    if (!rc)
        rc = halo_balance_sync(md->halo, p, md->pot->cutoff + md->skin, md->step, e);
    if (!rc)
        rc = halo_migrate(md->halo, p, e);
    if (!rc)
        rc = halo_sort_by_id(p, e);
    md->rebuild_next = 1;
    return rc;
}

void md_step_drift(struct md *md)
{
    struct particles *p = md->p;
    const double dt = md->dt;
    const uint32_t hold = md->frozen_mask | md->rigid_mask;
    tstart(md, TIMER_INTEGRATE);
    for (int i = 0; i < p->n_owned; i++) {
        double dtfm = 0.5 * dt * UNITS_FTM2V / p->mass[p->type[i]];
        if (p->mask[i] & md->frozen_mask)
            continue;
        if (!(p->mask[i] & hold))
            for (int d = 0; d < 3; d++)
                p->v[3 * i + d] += dtfm * p->f[3 * i + d];
        for (int d = 0; d < 3; d++)
            p->x[3 * i + d] += dt * p->v[3 * i + d];
    }
    tstop(md, TIMER_INTEGRATE);
}

int md_step_forces(struct md *md, struct err *e)
{
    int rc = md_compute_forces(md, e);
    if (rc)
        return rc;
    if (md->thermo.style == THERMOSTAT_LANGEVIN)
        thermostat_langevin_forces(&md->thermo, md->p, md->dt, md->seed, md->step + 1);
    return 0;
}

void md_step_kick(struct md *md)
{
    struct particles *p = md->p;
    const double dt = md->dt;
    const uint32_t hold = md->frozen_mask | md->rigid_mask;
    tstart(md, TIMER_INTEGRATE);
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & hold)
            continue;
        double dtfm = 0.5 * dt * UNITS_FTM2V / p->mass[p->type[i]];
        for (int d = 0; d < 3; d++)
            p->v[3 * i + d] += dtfm * p->f[3 * i + d];
    }
    if (md->thermo.style == THERMOSTAT_BERENDSEN)
        thermostat_berendsen_rescale(&md->thermo, p, dt, md_temperature(md));
    tstop(md, TIMER_INTEGRATE);
    md->step++;
    md->time += dt;
}

int md_step(struct md *md, struct err *e)
{
    md_step_drift(md);
    int rc = md_step_forces(md, e);
    if (rc)
        return rc;
    md_step_kick(md);
    return 0;
}

double md_kinetic_energy(const struct md *md)
{
    const struct particles *p = md->p;
    double ke = 0;
    for (int i = 0; i < p->n_owned; i++) {
        const double *v = p->v + 3 * i;
        ke += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    if (md->halo)
        halo_sum(md->halo, &ke, 1);
    return 0.5 * ke * UNITS_MVV2E;
}

double md_temperature_of(const struct md *md, double ke)
{
    long n = md_natoms(md);
    double dof = n > 1 ? 3.0 * n - 3.0 : 3.0 * n;
    return dof > 0 ? 2.0 * ke / (dof * UNITS_KB) : 0.0;
}

double md_temperature(const struct md *md)
{
    return md_temperature_of(md, md_kinetic_energy(md));
}

void md_pressure_tensor(const struct md *md, double P[6])
{
    double k[6];
    particles_kinetic_tensor(md->p, k);
    if (md->halo)
        halo_sum(md->halo, k, 6);
    double V = box_volume(&md->box);
    for (int c = 0; c < 6; c++)
        P[c] = (k[c] + md->last.virial[c]) / V;
}

void md_momentum(const struct md *md, double P[3])
{
    const struct particles *p = md->p;
    P[0] = P[1] = P[2] = 0;
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++)
            P[d] += p->mass[p->type[i]] * p->v[3 * i + d];
    if (md->halo)
        halo_sum(md->halo, P, 3);
}

void md_peratom_stress(const struct md *md, double *out)
{
    md_peratom_stress_of(md, md_natoms(md), out);
}

void md_peratom_stress_of(const struct md *md, long natoms, double *out)
{
    const struct particles *p = md->p;
    double omega = natoms > 0 ? box_volume(&md->box) / natoms : 1.0;
    for (int i = 0; i < p->n_owned; i++) {
        double m = p->mass[p->type[i]] * UNITS_MVV2E;
        const double *v = p->v + 3 * i, *w = p->virial + 6 * i;
        double kv[6] = {v[0] * v[0], v[1] * v[1], v[2] * v[2], v[0] * v[1], v[0] * v[2], v[1] * v[2]};
        for (int c = 0; c < 6; c++)
            out[6 * i + c] = -(m * kv[c] + w[c]) / omega;
    }
}

int md_einstein_frequency(struct md *md, double *omega, struct err *e)
{
    struct particles *p = md->p;
    *omega = 0;
    int n = p->n_owned;
    /* bricks: the force calls are collective, so every rank takes part;
     * rank 0 alone displaces atoms (its own), the others none */
    int sampler = !md->halo || md->halo->dc.par == NULL || md->halo->dc.par->rank == 0;
    if (md->halo ? md_natoms(md) < 2 : n < 2)
        return 0;
    const double delta = 1e-3;   /* Å: small enough to be harmonic */
    /* Sample atoms far enough apart (2 cutoffs: EAM couples through the
     * density of shared neighbours) that displacing them together leaves
     * each one's restoring force unaffected by the others; periodic images
     * count, so compare minimum-image distances. */
    enum { MAXS = 8 };
    int sample[MAXS], ns = 0;
    double sep = 2.0 * md->pot->cutoff + 0.1;
    for (int i = 0; sampler && i < n && ns < MAXS; i += 1 + n / (4 * MAXS)) {
        int ok = 1;
        for (int k = 0; k < ns && ok; k++) {
            double r2 = 0, dd[3];
            for (int d = 0; d < 3; d++)
                dd[d] = p->x[3 * i + d] - p->x[3 * sample[k] + d];
            box_min_image(&md->box, dd);
            for (int d = 0; d < 3; d++)
                r2 += dd[d] * dd[d];
            ok = r2 > sep * sep;
        }
        if (ok)
            sample[ns++] = i;
    }
    double *f0 = malloc((size_t)3 * (n ? n : 1) * sizeof *f0);
    int64_t ids[MAXS];
    if (!f0)
        return err_nomem(e, "frequency estimate");
    memcpy(f0, p->f, (size_t)3 * n * sizeof(double));
    int sort_saved = md->sort_every;
    md->sort_every = 0;   /* keep indices stable while probing */
    struct force_result keep = md->last;
    for (int k = 0; k < ns; k++)
        ids[k] = p->id[sample[k]];
    int rc = 0;
    for (int d = 0; d < 3 && !rc; d++) {
        double x0[MAXS];
        for (int k = 0; k < ns; k++) {
            x0[k] = p->x[3 * sample[k] + d];
            p->x[3 * sample[k] + d] += delta;
        }
        rc = md_compute_forces(md, e);
        for (int k = 0; k < ns && !rc; k++) {
            int i = sample[k];
            if (p->id[i] != ids[k])
                continue;   /* a rebuild reordered atoms: skip this sample */
            double kspring = -(p->f[3 * i + d] - f0[3 * i + d]) / delta;   /* eV/Å^2 */
            double w2 = kspring * UNITS_FTM2V / p->mass[p->type[i]];
            if (w2 > *omega * *omega)
                *omega = sqrt(w2);
        }
        for (int k = 0; k < ns; k++)
            p->x[3 * sample[k] + d] = x0[k];   /* exactly, not x + delta - delta */
    }
    /* restore the unperturbed forces */
    if (!rc && p->n_owned == n)
        memcpy(p->f, f0, (size_t)3 * n * sizeof(double));
    md->sort_every = sort_saved;
    md->last = keep;
    free(f0);
    if (md->halo)
        halo_max(md->halo, omega, 1);
    return rc;
}
