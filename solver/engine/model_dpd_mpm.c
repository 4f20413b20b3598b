/*
 * model_dpd_mpm: DPD particles carried by the MPM grid as engine stages
 * (models.h; the physics is couple/dpd_mpm.h, Chen et al. 2014, Sec. 3).
 *
 * One table serves both models of the paper: the DPD/MPM-grid model (every
 * free DPD particle carried by the grid, its pair forces mapped to the
 * nodes with N_i, Eq. (s3b)) and the concurrent DPD/MPM model (the same
 * grid also carrying material points with a constitutive law, nodal force
 * Eq. (3.1)) -- the concurrent model is the grid model with material
 * points, and dpd_mpm_step treats both.
 *
 * Stages of one step (MUSL, Supplement s1-s14):
 *   force      dpd_mpm_step_forces: the DPD pair forces (C + D + R) at x(t),
 *              v(t) with the partners at their material points, their
 *              reaction on those points, the force on each rigid body and
 *              the free bodies' kick
 *   integrate  dpd_mpm_step_update: s1-s14 on the grid, the DPDE heat of the
 *              D + R forces and of the grid's smoothing, the bodies' drift
 * Energy for the divergence check: the time-centred total of dpd_mpm.h
 * (kinetic + conservative + internal + strain), which must stay finite;
 * no limit on its change (the grid model is not a conserving integrator in
 * the engine's sense: the isothermal variant loses the grid's share).
 *
 * Checkpoint: the DPD model's particles in their fixed order ([carried |
 * partners | bodies], couple/dpd_mpm.h) with every field (internal energy,
 * reference positions, structure classes), box, step, time, bodies; the
 * coupling's accumulated heats and last-step energies; the material points
 * (every array) and the grid's energies; the positions at the last build
 * of the neighbour list.  Not stored: the grid's nodes (cleared and
 * refilled every step) and the per-step scratch of the coupling.
 *
 * The ghosts and the neighbour list are not stored either, but a restarted
 * run rebuilds them exactly as the continuing run has them: from the
 * positions of their last build, in the fixed particle order (no spatial
 * sorting in these models) and with the box of that build (a free
 * boundary's box changes only at builds).  So a run is the same with and
 * without checkpoints, bitwise -- which a rebuild at every checkpoint
 * would not give here: a rebuild wraps particles across a periodic
 * boundary, and the MPM grid is not periodic, so when a particle is
 * wrapped changes which nodes carry it.
 *
 * On bricks (the grid-carried rod, docs/dpd_mpm.md "Under MPI") the
 * particles go into the checkpoint as in the DPD model on bricks: rank 0
 * writes the rest and lays out the particle datasets, every rank writes
 * its own rows (collective HDF5); the list positions are not stored.  A
 * read puts every particle on every rank, and checkpoint_sync keeps the
 * brick's (the continuing run too: it goes on from the same state); the
 * next step rebuilds ghosts and lists, which puts the particles back in
 * their class order.  A serial run reading such a checkpoint orders them
 * and rebuilds likewise.  So a checkpoint moves between rank counts (to
 * round-off: the sums over the ranks run in another order).
 */
#include "engine/models.h"

#include "core/halo.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int dpd_mpm_model_init(void *self, struct sim *s, struct err *e)
{
    struct dpd_mpm_model *m = self;
    /* the forces at step 0 are those of the build (dpd_mpm_order); the run
     * whose particles are written recomputes them with the per-particle
     * energies of the first snapshot */
    if (!m->snapshots)
        return 0;
    m->c->d->peratom = s->peratom;
    return dpd_compute_forces(m->c->d, e);
}

static int dpd_mpm_model_pre_force(void *self, struct sim *s, struct err *e)
{
    struct dpd_mpm_model *m = self;
    (void)e;
    if (m->snapshots)
        m->c->d->peratom = s->peratom;
    return 0;
}

static int dpd_mpm_model_force(void *self, struct sim *s, struct err *e)
{
    struct dpd_mpm_model *m = self;
    (void)s;
    if (m->sync_rc)
        return err_set(e, m->sync_rc, "the particles could not be redistributed over the "
                                      "bricks after a checkpoint");
    return dpd_mpm_step_forces(m->c, e);
}

static int dpd_mpm_model_integrate(void *self, struct sim *s, struct err *e)
{
    struct dpd_mpm_model *m = self;
    (void)s;
    return dpd_mpm_step_update(m->c, e);
}

static void dpd_mpm_model_observe(void *self, const struct sim *s, struct sim_energy *en)
{
    struct dpd_mpm_model *m = self;
    (void)s;
    struct dpd_mpm_energy de;
    dpd_mpm_energy(m->c, &de);
    en->total = de.centred;
    en->conserved = 0;
    en->scale = 1;
    en->unit = "eV";
}

/* --- checkpoint --------------------------------------------------------- */

/* Datasets of a subgroup `sub` of the model's group `base`. */
static int enter(struct ckpt *ck, const char *base, const char *sub)
{
    char g[sizeof ck->where + 32];
    snprintf(g, sizeof g, "%s%s%s", base, sub[0] ? "/" : "", sub);
    return ckpt_enter(ck, g);
}

static int put_points(struct ckpt *ck, const struct mpm_points *p)
{
    long n = p->n;
    int rc = ckpt_put_long(ck, "n", n);
    if (!rc) rc = ckpt_put_long(ck, "nstate", p->nstate);
    if (!rc) rc = ckpt_put_doubles(ck, "x", p->x, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "x0", p->x0, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "v", p->v, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "mass", p->mass, n);
    if (!rc) rc = ckpt_put_doubles(ck, "vol0", p->vol0, n);
    if (!rc) rc = ckpt_put_doubles(ck, "vol", p->vol, n);
    if (!rc) rc = ckpt_put_doubles(ck, "stress", p->stress, 6 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "F", p->F, 9 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "eint", p->eint, n);
    if (!rc) rc = ckpt_put_doubles(ck, "state", p->state, (long)p->nstate * n);
    if (!rc && p->fext) rc = ckpt_put_doubles(ck, "fext", p->fext, 3 * n);
    if (!rc) rc = ckpt_put_ints(ck, "body", p->body, n);
    if (!rc) rc = ckpt_put_i64(ck, "id", p->id, n);
    if (!rc) rc = ckpt_put_u32(ck, "mask", p->mask, n);
    return rc;
}

/* The points were built from the same case: the same number, replaced. */
static int get_points(struct ckpt *ck, struct mpm_points *p, struct err *e)
{
    long n = 0, nstate = 0;
    int rc = ckpt_get_long(ck, "n", &n);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    if (!rc && (n != p->n || nstate != p->nstate))
        rc = err_set(e, ERR_INPUT,
                     "%s: checkpoint has %ld material points with %ld state variables, the "
                     "case has %ld with %d",
                     ck->path, n, nstate, p->n, p->nstate);
    if (!rc) rc = ckpt_get_doubles(ck, "x", p->x, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "x0", p->x0, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "v", p->v, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "mass", p->mass, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol0", p->vol0, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol", p->vol, n);
    if (!rc) rc = ckpt_get_doubles(ck, "stress", p->stress, 6 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "F", p->F, 9 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "eint", p->eint, n);
    if (!rc) rc = ckpt_get_doubles(ck, "state", p->state, (long)p->nstate * n);
    if (!rc && p->fext) rc = ckpt_get_doubles(ck, "fext", p->fext, 3 * n);
    if (!rc) rc = ckpt_get_ints(ck, "body", p->body, n);
    if (!rc) rc = ckpt_get_i64(ck, "id", p->id, n);
    if (!rc) rc = ckpt_get_u32(ck, "mask", p->mask, n);
    return rc;
}

/* Bricks: the positions of the last list build, as a particle field for
 * the checkpoint (it migrates and is permuted with the particles). */
#define LIST_FIELD "list_position"

static void swap_list_field(struct particles *p)
{
    double *xb = particles_field(p, particles_find_field(p, LIST_FIELD));
    for (long k = 0; k < 3L * p->n_owned; k++) {
        double t = p->x[k];
        p->x[k] = xb[k];
        xb[k] = t;
    }
}

/* The owned particles, holding their last build's positions in LIST_FIELD,
 * put in class order with ghosts and lists built at those positions, as
 * the continuing run has them (rebuild_lists_at for a set that was
 * distributed over bricks); their positions, the energy and the virial
 * are then those read.  Collective on bricks. */
static int rebuild_ordered_at_field(struct dpd *d, uint32_t partner_bit, struct err *e)
{
    struct particles *p = d->p;
    double epot = d->epot, virial[6];
    memcpy(virial, d->virial, sizeof virial);
    int peratom = d->peratom;
    d->peratom = 0;
    swap_list_field(p);
    int rc = dpd_fix_class_order(d, partner_bit, e);   /* rebuilds at the build positions */
    p = d->p;
    swap_list_field(p);
    particles_remove_field(p, LIST_FIELD);
    d->peratom = peratom;
    d->epot = epot;
    memcpy(d->virial, virial, sizeof virial);
    return rc;
}

static int dpd_mpm_model_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    struct dpd_mpm_model *m = self;
    const struct dpd_mpm *c = m->c;
    const struct dpd *d = c->d;
    const struct mpm *g = &c->m;
    (void)e;
    char base[sizeof ck->where];
    snprintf(base, sizeof base, "%s", ck->where);
    double bv[3 * DPD_MAX_BODIES], bf[3 * DPD_MAX_BODIES];
    for (int b = 0; b < d->nbodies; b++)
        for (int q = 0; q < 3; q++) {
            bv[3 * b + q] = d->body[b].v[q];
            bf[3 * b + q] = d->body[b].force[q];
        }
    /* the DPD model */
    int rc = ckpt_put_long(ck, "step", d->step);
    if (!rc) rc = ckpt_put_double(ck, "time", d->time);
    if (!rc) rc = ckpt_put_long(ck, "nrebuilds", d->nrebuilds);
    if (!rc) rc = ckpt_put_double(ck, "epot", d->epot);
    if (!rc) rc = ckpt_put_doubles(ck, "virial", d->virial, 6);
    if (!rc) rc = ckpt_put_doubles(ck, "body_velocity", bv, 3 * d->nbodies);
    if (!rc) rc = ckpt_put_doubles(ck, "body_force", bf, 3 * d->nbodies);
    /* the coupling (bricks: the counts over the ranks) */
    const struct halo *h = d->p->halo;
    if (!rc) rc = ckpt_put_long(ck, "carried", h ? m->ck_carried : c->ncarried);
    if (!rc) rc = ckpt_put_long(ck, "partners", h ? m->ck_partners : c->npartner);
    if (!rc) rc = ckpt_put_double(ck, "heat", c->heat);
    if (!rc) rc = ckpt_put_double(ck, "subgrid_heat", c->subgrid_heat);
    if (!rc) rc = ckpt_put_double(ck, "ke_centred", c->ke_centred);
    if (!rc) rc = ckpt_put_double(ck, "epot_before", c->epot_before);
    if (!rc) rc = ckpt_put_double(ck, "uint_before", c->uint_before);
    /* the grid's run */
    if (!rc) rc = ckpt_put_long(ck, "mpm_step", g->step);
    if (!rc) rc = ckpt_put_double(ck, "mpm_time", g->time);
    if (!rc) rc = ckpt_put_double(ck, "mpm_vmax", g->vmax);
    if (!rc) rc = ckpt_put_double(ck, "mpm_ke", g->ke);
    if (!rc) rc = ckpt_put_double(ck, "mpm_ke_centred", g->ke_centred);
    if (!rc) rc = ckpt_put_double(ck, "mpm_strain", g->strain);
    if (!rc) rc = ckpt_put_double(ck, "mpm_strain_before", g->strain_before);
    if (!rc && !h)   /* bricks: rebuilt after the checkpoint instead */
        rc = ckpt_put_doubles(ck, "list_positions", d->nl->x_build, 3L * d->nl->n);
    char sub[sizeof base + 16];
    if (!rc) {
        snprintf(sub, sizeof sub, "%s/box", base);
        rc = ckpt_put_box(ck, sub, &d->box);
    }
    if (!rc) {   /* bricks: the datasets; each rank writes its rows (write_part) */
        snprintf(sub, sizeof sub, "%s/particles", base);
        rc = h ? ckpt_put_particles_layout(ck, sub, d->p, m->ck_total)
               : ckpt_put_particles(ck, sub, d->p);
    }
    if (!rc && !(rc = enter(ck, base, "points")))
        rc = put_points(ck, &g->pts);
    return rc;
}

static int dpd_mpm_model_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct dpd_mpm_model *m = self;
    (void)e;
    char parts[sizeof ck->where + 16];
    snprintf(parts, sizeof parts, "%s/particles", ck->where);
    const struct particles *p = m->c->d->p;
    return p->halo ? ckpt_put_particles_part(ck, parts, p, m->ck_offset) : 0;
}

/* Bricks: this rank's rows of the checkpoint's particles follow those of
 * the lower ranks; the class counts are sums (rank 0 writes them). */
static int dpd_mpm_model_checkpoint_collect(void *self, struct err *e)
{
    struct dpd_mpm_model *m = self;
    struct particles *p = m->c->d->p;
    m->ck_offset = m->ck_total = 0;
    if (!p->halo)
        return 0;
    double n[2] = {(double)m->c->ncarried, (double)m->c->npartner};
    halo_sum(p->halo, n, 2);
    m->ck_carried = (long)n[0];
    m->ck_partners = (long)n[1];
    /* the list positions go with the particles (removed again by the sync) */
    int k = particles_add_field(p, LIST_FIELD, 3, 0, e);
    if (k < 0)
        return ERR_RUNTIME;
    memcpy(particles_field(p, k), m->c->d->nl->x_build, (size_t)3 * p->n_owned * sizeof(double));
    return model_checkpoint_rows(p->halo, p, &m->ck_offset, &m->ck_total, e);
}

/* Bricks: every rank keeps its brick's particles of a checkpoint read,
 * and the next step rebuilds ghosts and lists in the continuing run as in
 * the restarted one (the rebuild restores the class order). */
static void dpd_mpm_model_checkpoint_sync(void *self)
{
    struct dpd_mpm_model *m = self;
    struct dpd *d = m->c->d;
    struct halo *h = d->p->halo;
    if (!h)
        return;   /* serially the run goes on as if no checkpoint was written */
    if (!m->read_all) {   /* the continuing run: as if no checkpoint was written */
        particles_remove_field(d->p, LIST_FIELD);
        return;
    }
    /* the restarted run: the brick's particles, by their positions at the
     * last build (where the continuing run's migration put them) */
    struct err e = {0};
    struct particles *p = d->p;
    particles_clear_ghosts(p);
    int rc = 0;
    if (m->read_all == 1) {   /* every particle read: keep the brick's */
        decomp_set_box(&h->dc, &d->box);
        swap_list_field(p);
        rc = halo_distribute(h, p, &e);
        swap_list_field(d->p);
    }
    if (!rc)
        rc = rebuild_ordered_at_field(d, m->c->partner_bit, &e);
    m->read_all = 0;
    m->sync_rc = rc;
}

/* Ghosts and the neighbour list as the continuing run has them: built with
 * the owned particles at xb, the positions of the list's last build (the
 * forces of that build are thrown away: f, energy and virial come from the
 * checkpoint). */
static int rebuild_lists_at(struct dpd *d, const double *xb, struct err *e)
{
    struct particles *p = d->p;
    const size_t nb = (size_t)3 * p->n_owned * sizeof(double);
    double *keep = malloc(2 * (nb ? nb : 1));
    if (!keep)
        return err_nomem(e, "neighbour list positions");
    memcpy(keep, p->x, nb);
    memcpy((char *)keep + nb, p->f, nb);
    memcpy(p->x, xb, nb);
    int peratom = d->peratom;
    d->peratom = 0;
    d->nl->nbuilds = 0;   /* build now */
    int rc = dpd_compute_forces(d, e);
    d->peratom = peratom;
    memcpy(p->x, keep, nb);   /* p->x may have moved with the ghosts */
    memcpy(p->f, (char *)keep + nb, nb);
    free(keep);
    return rc;
}

static int dpd_mpm_model_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct dpd_mpm_model *m = self;
    struct dpd_mpm *c = m->c;
    struct dpd *d = c->d;
    struct mpm *g = &c->m;
    char base[sizeof ck->where];
    snprintf(base, sizeof base, "%s", ck->where);
    long ncarried = 0, npartner = 0, nb = -1, n = d->p->n_owned;
    double bv[3 * DPD_MAX_BODIES], bf[3 * DPD_MAX_BODIES];
    double *xb = NULL;
    struct halo *h = d->p->halo;
    /* the case's counts (bricks: over the ranks; every rank reads) */
    double cnt[2] = {(double)c->ncarried, (double)c->npartner};
    if (h)
        halo_sum(h, cnt, 2);
    /* a checkpoint written on bricks holds the list positions as a
     * particle field (they travel with the particles), a serial one as a
     * dataset in the particles' order */
    int have_lists = ckpt_len(ck, "list_positions") >= 0;
    int rc = ckpt_get_long(ck, "carried", &ncarried);
    if (!rc) rc = ckpt_get_long(ck, "partners", &npartner);
    if (!rc) nb = ckpt_len(ck, "body_velocity");
    if (!rc && (ncarried != (long)cnt[0] || npartner != (long)cnt[1] || nb != 3L * d->nbodies))
        rc = err_set(e, ERR_INPUT,
                     "%s: checkpoint of %s has %ld carried particles, %ld partners and %ld "
                     "bodies, the case has %ld, %ld and %d",
                     ck->path, base, ncarried, npartner, nb / 3, (long)cnt[0], (long)cnt[1],
                     d->nbodies);
    if (!rc && !have_lists && particles_add_field(d->p, LIST_FIELD, 3, 0, e) < 0)
        rc = ERR_RUNTIME;
    char sub[sizeof base + 16];
    if (!rc) {
        snprintf(sub, sizeof sub, "%s/box", base);
        rc = ckpt_get_box(ck, sub, &d->box);
    }
    /* bricks: the partners' frozen F'(rho) is the set-up's, not the
     * checkpoint's (a serial checkpoint has none): kept aside by point and
     * given back to the particles read */
    double *frozen = NULL;
    int frozen_at = -1;
    if (!rc)
        rc = dpd_mpm_frozen_take(c, &frozen, &frozen_at, e);
    /* bricks, a checkpoint written on bricks (the list positions a field):
     * each rank reads only the particles whose list positions lie in its
     * brick of the stored box, where the continuing run's last migration
     * put them; otherwise every rank reads every particle and the sync
     * keeps its brick's */
    int brick = h && !have_lists;
    snprintf(sub, sizeof sub, "%s/particles", base);
    if (brick)
        rc = model_particles_read_brick(h, &d->box, ck, sub, LIST_FIELD, d->p, rc, e);
    else if (!rc)
        rc = ckpt_get_particles(ck, sub, d->p);
    if (!rc)
        rc = dpd_mpm_frozen_put(c, frozen, frozen_at, e);
    free(frozen);
    /* the classes [carried | partners | bodies] are positions in this order */
    long nall = h ? (long)(cnt[0] + cnt[1]) : n;
    for (int b = 0; h && b < d->nbodies; b++)
        nall += d->body[b].n;
    long nread = d->p->n_owned;
    if (brick) {   /* over the ranks (every rank takes part, whatever its rc) */
        double t = rc ? 0.0 : (double)nread;
        halo_sum(h, &t, 1);
        nread = lround(t);
    }
    if (!rc && nread != nall)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint of %s has %ld DPD particles, the case has %ld",
                     ck->path, base, nread, nall);
    if (!rc && d->sort_every != 0)
        rc = err_set(e, ERR_RUNTIME, "DPD/MPM: particles sorted in space cannot be restored");
    if (!rc && have_lists && !(xb = malloc((size_t)3 * (nall ? nall : 1) * sizeof *xb)))
        rc = err_nomem(e, "neighbour list positions");
    if (!rc && xb) {
        snprintf(sub, sizeof sub, "%s", base);
        if (!(rc = ckpt_enter(ck, sub)))
            rc = ckpt_get_doubles(ck, "list_positions", xb, 3 * nall);
    }
    if (!rc && brick) {   /* the brick's particles: the sync rebuilds at their lists */
        m->read_all = 2;
    } else if (!rc && h) {   /* every particle on every rank: the sync keeps the brick's */
        int k = xb ? particles_add_field(d->p, LIST_FIELD, 3, 0, e) : 0;
        if (k < 0)
            rc = ERR_RUNTIME;
        else if (xb)
            memcpy(particles_field(d->p, k), xb, (size_t)3 * nall * sizeof *xb);
        m->read_all = 1;
    } else if (!rc && xb) {
        rc = rebuild_lists_at(d, xb, e);
    } else if (!rc) {   /* written on bricks, read serially: order, lists at their positions */
        rc = rebuild_ordered_at_field(d, c->partner_bit, e);
    }
    free(xb);
    if (!rc) rc = enter(ck, base, "");
    if (!rc) rc = ckpt_get_long(ck, "step", &d->step);
    if (!rc) rc = ckpt_get_double(ck, "time", &d->time);
    if (!rc) rc = ckpt_get_long(ck, "nrebuilds", &d->nrebuilds);
    if (!rc) rc = ckpt_get_double(ck, "epot", &d->epot);
    if (!rc) rc = ckpt_get_doubles(ck, "virial", d->virial, 6);
    if (!rc) rc = ckpt_get_doubles(ck, "body_velocity", bv, 3 * d->nbodies);
    if (!rc) rc = ckpt_get_doubles(ck, "body_force", bf, 3 * d->nbodies);
    for (int b = 0; !rc && b < d->nbodies; b++)
        for (int q = 0; q < 3; q++) {
            d->body[b].v[q] = bv[3 * b + q];
            d->body[b].force[q] = bf[3 * b + q];
        }
    if (!rc) rc = ckpt_get_double(ck, "heat", &c->heat);
    if (!rc) rc = ckpt_get_double(ck, "subgrid_heat", &c->subgrid_heat);
    if (!rc) rc = ckpt_get_double(ck, "ke_centred", &c->ke_centred);
    if (!rc) rc = ckpt_get_double(ck, "epot_before", &c->epot_before);
    if (!rc) rc = ckpt_get_double(ck, "uint_before", &c->uint_before);
    if (!rc) rc = ckpt_get_long(ck, "mpm_step", &g->step);
    if (!rc) rc = ckpt_get_double(ck, "mpm_time", &g->time);
    if (!rc) rc = ckpt_get_double(ck, "mpm_vmax", &g->vmax);
    if (!rc) rc = ckpt_get_double(ck, "mpm_ke", &g->ke);
    if (!rc) rc = ckpt_get_double(ck, "mpm_ke_centred", &g->ke_centred);
    if (!rc) rc = ckpt_get_double(ck, "mpm_strain", &g->strain);
    if (!rc) rc = ckpt_get_double(ck, "mpm_strain_before", &g->strain_before);
    if (!rc && !(rc = enter(ck, base, "points")))
        rc = get_points(ck, &g->pts, e);
    /* the points changed outside the stages: the next step locates them
     * afresh (the same blocks the continuing run carries over) */
    if (!rc)
        mpm_points_moved(g);
    return rc;
}

const struct sim_model_ops sim_model_dpd_mpm = {
    .name = "dpd_mpm",
    .init = dpd_mpm_model_init,
    .pre_force = dpd_mpm_model_pre_force,
    .force = dpd_mpm_model_force,
    .integrate = dpd_mpm_model_integrate,
    .observe = dpd_mpm_model_observe,
    .checkpoint_write = dpd_mpm_model_checkpoint_write,
    .checkpoint_read = dpd_mpm_model_checkpoint_read,
    /* serially no sync: the continuing run goes on as if none was written */
    .checkpoint_sync = dpd_mpm_model_checkpoint_sync,
    .checkpoint_collect = dpd_mpm_model_checkpoint_collect,
    .checkpoint_write_part = dpd_mpm_model_checkpoint_write_part,
};
