/*
 * model_dpd: DPD and DPDE (dpd/dpd.h) as engine stages (models.h).
 *
 *   pre_force  the Shardlow pair sweep at the positions of t (dissipative +
 *              random forces, exact per pair; DPDE moves their energy into
 *              the internal energies), the first half kick, the drift
 *   force      conservative forces at t + dt (ghosts and list refreshed)
 *   integrate  the second half kick, the Berendsen rescaling, the rigid
 *              bodies' forces of the step
 *
 * What a restarted step needs, and where it is: positions, velocities,
 * forces f(t) (the first half kick uses them), ids, masks, images and every
 * per-particle field -- the DPDE internal energies u_i among them -- with the
 * particles; the box (free boundaries follow the particles); the step
 * counter, which keys every pair's random number with the seed and the two
 * ids (dpd_pair.h), so no random stream is stored; the conservative energy
 * and virial of the last force call; the rigid bodies' velocities (free
 * flyers) and last forces; the rebuild counter (it schedules the spatial
 * sort).  Not stored: ghosts and the neighbour list.  The sweep visits the
 * pairs in list order and each pair sees the velocities the previous ones
 * left, so the list order is part of the arithmetic: at every checkpoint
 * the continuing run and the restarted one both rebuild ghosts and list
 * from the stored state before the next sweep (checkpoint_sync), and go on
 * with the same list.  Body impulses, densities and accumulators are
 * scratch of one step.
 */
#include <stdio.h>
#include <string.h>

#include "core/halo.h"
#include "engine/models.h"

static int dpd_model_init(void *self, struct sim *s, struct err *e)
{
    struct dpd_model *m = self;
    if (m->snapshots)
        m->d->peratom = s->peratom;
    return dpd_compute_forces(m->d, e);
}

static int dpd_model_pre_force(void *self, struct sim *s, struct err *e)
{
    struct dpd_model *m = self;
    if (m->snapshots)
        m->d->peratom = s->peratom;
    if (m->sync_rc)
        return err_set(e, m->sync_rc, "the particles could not be redistributed over the "
                                      "bricks after a checkpoint");
    return dpd_step_sweep_drift(m->d, e);
}

static int dpd_model_force(void *self, struct sim *s, struct err *e)
{
    (void)s;
    struct dpd_model *m = self;
    return dpd_step_forces(m->d, e);
}

static int dpd_model_integrate(void *self, struct sim *s, struct err *e)
{
    (void)s;
    (void)e;
    struct dpd_model *m = self;
    dpd_step_kick(m->d);
    return 0;
}

static void dpd_model_observe(void *self, const struct sim *s, struct sim_energy *en)
{
    (void)s;
    struct dpd_model *m = self;
    const struct dpd *d = m->d;
    /* kinetic + potential + internal: conserved by DPDE without a thermostat
     * and without prescribed bodies (which do work on the system).  No case
     * key limits its change (limit 0): only finiteness is checked. */
    en->total = d->epot + dpd_kinetic_energy(d) + dpd_internal_energy(d);
    int prescribed = 0;
    for (int b = 0; b < d->nbodies; b++)
        prescribed |= d->body[b].kind == DPD_BODY_PRESCRIBED;
    en->conserved = d->set.variant == DPD_ENERGY && d->thermo.style == THERMOSTAT_NONE &&
                    !prescribed;
    long n = dpd_nparticles(d);
    en->scale = n > 0 ? (double)n : 1;
    en->limit = 0;
    en->limit_key = NULL;
    en->unit = "eV/particle";
}

static int dpd_model_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    (void)e;
    struct dpd_model *m = self;
    const struct dpd *d = m->d;
    char g[160], box[200], parts[200];
    snprintf(g, sizeof g, "%s", ck->where);   /* model/<name>, entered by the engine */
    snprintf(box, sizeof box, "%s/box", g);
    snprintf(parts, sizeof parts, "%s/particles", g);
    double bv[3 * DPD_MAX_BODIES], bf[3 * DPD_MAX_BODIES];
    for (int b = 0; b < d->nbodies; b++)
        for (int c = 0; c < 3; c++) {
            bv[3 * b + c] = d->body[b].v[c];
            bf[3 * b + c] = d->body[b].force[c];
        }
    int rc = ckpt_put_long(ck, "step", d->step);
    if (!rc) rc = ckpt_put_double(ck, "time", d->time);
    if (!rc) rc = ckpt_put_long(ck, "nrebuilds", d->nrebuilds);
    if (!rc) rc = ckpt_put_double(ck, "energy", d->epot);
    if (!rc) rc = ckpt_put_doubles(ck, "virial", d->virial, 6);
    if (!rc) rc = ckpt_put_long(ck, "nbodies", d->nbodies);
    if (!rc) rc = ckpt_put_doubles(ck, "body_velocity", bv, 3 * d->nbodies);
    if (!rc) rc = ckpt_put_doubles(ck, "body_force", bf, 3 * d->nbodies);
    if (!rc) rc = ckpt_put_box(ck, box, &d->box);
    /* bricks: the datasets for every rank's particles; each rank writes
     * its own (dpd_model_checkpoint_write_part) */
    if (!rc && d->p->halo)
        rc = ckpt_put_particles_layout(ck, parts, d->p, m->ck_total);
    else if (!rc)
        rc = ckpt_put_particles(ck, parts, d->p);
    return rc;
}

static int dpd_model_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct dpd_model *m = self;
    char parts[200];
    snprintf(parts, sizeof parts, "%s/particles", ck->where);   /* model/<name> */
    return m->d->p->halo ? ckpt_put_particles_part(ck, parts, m->d->p, m->ck_offset) : 0;
}

/* Bricks: this rank's rows of the checkpoint's particles follow those of
 * the lower ranks. */
static int dpd_model_checkpoint_collect(void *self, struct err *e)
{
    struct dpd_model *m = self;
    m->ck_offset = m->ck_total = 0;
    struct halo *h = m->d->p->halo;
    if (!h)
        return 0;
    return model_checkpoint_rows(h, m->d->p, &m->ck_offset, &m->ck_total, e);
}

static int dpd_model_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct dpd_model *m = self;
    struct dpd *d = m->d;
    char g[160], box[200], parts[200];
    snprintf(g, sizeof g, "%s", ck->where);
    snprintf(box, sizeof box, "%s/box", g);
    snprintf(parts, sizeof parts, "%s/particles", g);
    long nbodies = 0;
    double bv[3 * DPD_MAX_BODIES], bf[3 * DPD_MAX_BODIES];
    int rc = ckpt_get_long(ck, "step", &d->step);
    if (!rc) rc = ckpt_get_double(ck, "time", &d->time);
    if (!rc) rc = ckpt_get_long(ck, "nrebuilds", &d->nrebuilds);
    if (!rc) rc = ckpt_get_double(ck, "energy", &d->epot);
    if (!rc) rc = ckpt_get_doubles(ck, "virial", d->virial, 6);
    if (!rc) rc = ckpt_get_long(ck, "nbodies", &nbodies);
    if (!rc && nbodies != d->nbodies)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld rigid bodies in %s, the case has %d",
                     ck->path, nbodies, g, d->nbodies);
    if (!rc) rc = ckpt_get_doubles(ck, "body_velocity", bv, 3 * nbodies);
    if (!rc) rc = ckpt_get_doubles(ck, "body_force", bf, 3 * nbodies);
    for (int b = 0; !rc && b < d->nbodies; b++)
        for (int c = 0; c < 3; c++) {
            d->body[b].v[c] = bv[3 * b + c];
            d->body[b].force[c] = bf[3 * b + c];
        }
    if (!rc) rc = ckpt_get_box(ck, box, &d->box);
    /* bricks: each rank reads the particles of its brick of the stored
     * box; the sync puts them where the continuing run has them */
    if (d->p->halo)
        rc = model_particles_read_brick(d->p->halo, &d->box, ck, parts, NULL, d->p, rc, e);
    else if (!rc)
        rc = ckpt_get_particles(ck, parts, d->p);
    return rc;
}

/* Ghosts and list rebuilt from the stored state before the next sweep, in
 * the continuing run as in the restarted one. */
static void dpd_model_checkpoint_sync(void *self)
{
    struct dpd_model *m = self;
    struct dpd *d = m->d;
    d->rebuild_next = 1;
    struct halo *h = d->p->halo;
    if (!h)
        return;
    /* bricks: the same particles in the same order in the continuing and
     * the restarted run (an error is reported by the next step) */
    struct err e = {0};
    struct particles *p = d->p;
    particles_clear_ghosts(p);
    int rc = halo_remap(h, &d->box, p, 0, &e);
    /* dynamic balance: both runs cut at the stored particles */
    if (!rc)
        rc = halo_balance_sync(h, p, dpd_ghost_range(d), d->step, &e);
    if (!rc)
        rc = halo_migrate(h, p, &e);
    if (!rc)
        rc = halo_sort_by_id(p, &e);
    m->sync_rc = rc;
}

const struct sim_model_ops sim_model_dpd = {
    .name = "dpd",
    .init = dpd_model_init,
    .pre_force = dpd_model_pre_force,
    .force = dpd_model_force,
    .integrate = dpd_model_integrate,
    .observe = dpd_model_observe,
    .checkpoint_write = dpd_model_checkpoint_write,
    .checkpoint_read = dpd_model_checkpoint_read,
    .checkpoint_sync = dpd_model_checkpoint_sync,
    .checkpoint_collect = dpd_model_checkpoint_collect,
    .checkpoint_write_part = dpd_model_checkpoint_write_part,
};

const struct sim_model_ops sim_model_dpd_ref = {
    .name = "dpd_ref",
    .init = dpd_model_init,
    .pre_force = dpd_model_pre_force,
    .force = dpd_model_force,
    .integrate = dpd_model_integrate,
    .observe = dpd_model_observe,
    .checkpoint_write = dpd_model_checkpoint_write,
    .checkpoint_read = dpd_model_checkpoint_read,
    .checkpoint_sync = dpd_model_checkpoint_sync,
    .checkpoint_collect = dpd_model_checkpoint_collect,
    .checkpoint_write_part = dpd_model_checkpoint_write_part,
};
