/*
 * model_mpm: the material point method as engine stages (models.h).
 *
 * One MUSL (or USL) step of mpm_step (Chen et al. 2014, section 3.2, steps
 * s1-s14; Guo & Yang 2005 on hierarchical grids) splits where it splits
 * naturally:
 *   pre_force  the time step: the CFL step with the current largest speed
 *              (adaptive) or the fixed one, into s->dt; the load ramp
 *   force      mpm_step_map: s9 (cells, colouring blocks, the occasional
 *              reorder of the points), then s1-s3 (nodal mass, momentum,
 *              internal force from the stresses, external forces), unless
 *              the previous step's fused pass already left them on the grid
 *   integrate  mpm_step_update: s4-s5 (nodal momenta, boundary conditions,
 *              rigid bodies, damping), s6 and s10 (particle velocities, the
 *              MUSL remap), s11, s7-s8 and s12-s14 (positions, velocity
 *              gradient, strain, stress through the constitutive law)
 *
 * What survives a step, and so goes into a checkpoint: every array of the
 * material points in their current order (the points are reordered every
 * mpm.sort_every steps) -- positions, initial positions, velocities,
 * masses, initial and current volumes, Cauchy stress, deformation gradient,
 * stress work, the constitutive state (the plastic strain of J2), external
 * forces, body, id and mask; the step, time, largest speed (it sets the
 * next CFL step), the energies the kernels summed, the load factor and the
 * rigid bodies' reactions.  The grid layout (uniform or hierarchical) is
 * rebuilt from the case.  The nodal arrays are scratch of each step --
 * except after a fused pass (mpm.h: mpm->fuse), which maps the next step's
 * s1-s3 in the order of the points' old blocks: a fresh mapping would sum
 * the same terms in another order, so those nodes are stored too.  The
 * particle-to-block cache of the linear fast path is dropped at every
 * checkpoint in both runs: the locate step recomputes it with the same
 * formula from the same positions.
 */
#include "engine/models.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpm/mpm_bricks.h"

/* the nodes are stored as doubles */
_Static_assert(sizeof(struct mpm_node) == 8 * sizeof(double), "mpm_node is 8 doubles");
/* body indices go through the 32-bit integer datasets */
_Static_assert(sizeof(int) == sizeof(int32_t), "int is 32 bits");

double mpm_model_timestep(const struct mpm_model *mm)
{
    return mm->dt_fixed > 0 ? mm->dt_fixed : mm->cfl * mpm_stable_dt(mm->m);
}

static int mpm_model_init(void *self, struct sim *s, struct err *e)
{
    (void)e;
    s->dt = mpm_model_timestep(self);
    return 0;
}

static int mpm_model_pre_force(void *self, struct sim *s, struct err *e)
{
    struct mpm_model *mm = self;
    struct mpm *m = mm->m;
    (void)e;
    if (mm->adaptive && mm->dt_fixed <= 0)
        s->dt = mpm_model_timestep(mm);   /* CFL with the current largest speed */
    m->fext_scale = mm->load_ramp > 0 ? fmin(1.0, (m->time + s->dt) / mm->load_ramp) : 1.0;
    return 0;
}

static int mpm_model_force(void *self, struct sim *s, struct err *e)
{
    struct mpm_model *mm = self;
    (void)s;
    if (mm->sync_rc)
        return err_set(e, mm->sync_rc, "mpm: no memory to reorder the points after a checkpoint");
    return mm->bricks ? mpm_bricks_step_map(mm->bricks, mm->m, e) : mpm_step_map(mm->m, e);
}

static int mpm_model_integrate(void *self, struct sim *s, struct err *e)
{
    struct mpm_model *mm = self;
    return mm->bricks ? mpm_bricks_step_update(mm->bricks, mm->m, s->dt, e)
                      : mpm_step_update(mm->m, s->dt, e);
}

/* Energy is conserved only without driving or damping: no rigid body, load
 * or damping, no fixed or sliding face. */
static int closed(const struct mpm *m)
{
    int c = !m->pts.fext && m->damping == 0 && m->grid.nbc == 0;
    for (int b = 0; b < m->nbody; b++)
        c &= !m->body[b].rigid;
    return c;
}

static void mpm_model_observe(void *self, const struct sim *s, struct sim_energy *en)
{
    const struct mpm_model *mm = self;
    const struct mpm *m = mm->m;
    (void)s;
    /* kinetic + strain energy as summed by the kernels of the last step */
    en->total = m->ke + m->strain;
    en->conserved = closed(m);
    /* the change in per cent of the energy at step 0 (the engine keeps the
     * scale observed then); no check without energy */
    en->scale = en->total > 0 ? en->total / 100 : 0;
    en->limit = 100 * mm->max_energy_change;
    en->limit_key = "mpm.max_energy_change";
    en->unit = "%";
}

/* --- checkpoints ---------------------------------------------------------- */

static int put_points(struct ckpt *ck, const struct mpm_points *p)
{
    long n = p->n;
    int rc = ckpt_enter(ck, "model/mpm/points");
    if (!rc) rc = ckpt_put_long(ck, "n", n);
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
    if (!rc) rc = ckpt_put_long(ck, "has_fext", p->fext != NULL);
    if (!rc && p->fext) rc = ckpt_put_doubles(ck, "fext", p->fext, 3 * n);
    if (!rc) rc = ckpt_put_ints(ck, "body", p->body, n);
    if (!rc) rc = ckpt_put_i64(ck, "id", p->id, n);
    if (!rc) rc = ckpt_put_u32(ck, "mask", p->mask, n);
    return rc;
}

/* The points were built from the case file: same count, same state
 * variables, same external-force array; the stored values replace theirs. */
static int get_points(struct ckpt *ck, struct mpm_points *p, int nbody)
{
    long n = 0, nstate = 0, has_fext = 0;
    int rc = ckpt_enter(ck, "model/mpm/points");
    if (!rc) rc = ckpt_get_long(ck, "n", &n);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    if (!rc) rc = ckpt_get_long(ck, "has_fext", &has_fext);
    if (!rc && (n != p->n || nstate != p->nstate || (has_fext != 0) != (p->fext != NULL)))
        return err_set(ck->e, ERR_INPUT,
                       "%s: checkpoint has %ld material points with %ld state variables%s, the "
                       "case builds %ld with %d%s",
                       ck->path, n, nstate, has_fext ? " and loads" : "", p->n, p->nstate,
                       p->fext ? " and loads" : "");
    if (!rc) rc = ckpt_get_doubles(ck, "x", p->x, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "x0", p->x0, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "v", p->v, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "mass", p->mass, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol0", p->vol0, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol", p->vol, n);
    if (!rc) rc = ckpt_get_doubles(ck, "stress", p->stress, 6 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "F", p->F, 9 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "eint", p->eint, n);
    if (!rc) rc = ckpt_get_doubles(ck, "state", p->state, nstate * n);
    if (!rc && p->fext) rc = ckpt_get_doubles(ck, "fext", p->fext, 3 * n);
    if (!rc) rc = ckpt_get_ints(ck, "body", p->body, n);
    if (!rc) rc = ckpt_get_i64(ck, "id", p->id, n);
    if (!rc) rc = ckpt_get_u32(ck, "mask", p->mask, n);
    for (long i = 0; !rc && i < n; i++)
        if (p->body[i] < 0 || p->body[i] >= nbody)
            rc = err_set(ck->e, ERR_INPUT, "%s: material point %ld of the checkpoint is in body "
                                           "%d; the case has %d bodies",
                         ck->path, i, (int)p->body[i], nbody);
    return rc;
}

/* Bricks: every rank reads the whole set of the checkpoint (written on any
 * rank count, in id order) and keeps the points of its brick. */
static int get_points_bricks(struct ckpt *ck, struct mpm_model *mm, struct err *e)
{
    struct mpm *m = mm->m;
    long n = 0, nstate = 0, has_fext = 0;
    int rc = ckpt_enter(ck, "model/mpm/points");
    if (!rc) rc = ckpt_get_long(ck, "n", &n);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    if (!rc) rc = ckpt_get_long(ck, "has_fext", &has_fext);
    if (!rc && (nstate != m->pts.nstate || (has_fext != 0) != (m->pts.fext != NULL) || n < 0))
        rc = err_set(ck->e, ERR_INPUT,
                     "%s: checkpoint has %ld material points with %ld state variables%s, the "
                     "case's points have %d%s",
                     ck->path, n, nstate, has_fext ? " and loads" : "", m->pts.nstate,
                     m->pts.fext ? " and loads" : "");
    struct mpm_points all;
    mpm_points_init(&all, m->pts.nstate, e);
    if (!rc) rc = mpm_points_reserve(&all, n > 0 ? n : 1, e);
    if (!rc && has_fext) rc = mpm_points_enable_fext(&all, e);
    if (!rc) {
        all.n = n;
        rc = get_points(ck, &all, m->nbody);
    }
    double np = (double)n;
    if (!rc) rc = mpm_bricks_keep_owned(mm->bricks, m, &all, e);
    mpm_points_free(&all);
    rc = mpm_bricks_agree(mm->bricks, rc, e);
    if (!rc && mpm_bricks_npoints(mm->bricks, m) != (long)np)
        rc = err_set(e, ERR_INPUT, "%s: the ranks kept %ld of the checkpoint's %ld points",
                     ck->path, mpm_bricks_npoints(mm->bricks, m), n);
    return rc;
}

static int mpm_model_checkpoint_write(void *self, struct ckpt *ck, struct err *e)
{
    struct mpm_model *mm = self;
    const struct mpm *m = mm->m;
    (void)e;
    double react[3 * MPM_MAX_BODIES];
    for (int b = 0; b < m->nbody; b++)
        memcpy(react + 3 * b, m->body[b].reaction, sizeof m->body[b].reaction);
    int rc = ckpt_put_long(ck, "step", m->step);
    if (!rc) rc = ckpt_put_double(ck, "time", m->time);
    if (!rc) rc = ckpt_put_double(ck, "vmax", m->vmax);
    if (!rc) rc = ckpt_put_double(ck, "ke", m->ke);
    if (!rc) rc = ckpt_put_double(ck, "ke_centred", m->ke_centred);
    if (!rc) rc = ckpt_put_double(ck, "strain", m->strain);
    if (!rc) rc = ckpt_put_double(ck, "strain_before", m->strain_before);
    if (!rc) rc = ckpt_put_double(ck, "fext_scale", m->fext_scale);
    if (!rc) rc = ckpt_put_doubles(ck, "reaction", react, 3L * m->nbody);
    /* bricks: the points of every rank in id order; the nodes are not
     * stored (each rank maps afresh after a checkpoint, checkpoint_sync) */
    int bricks = mm->bricks != NULL;
    if (!rc) rc = ckpt_put_long(ck, "fused_ready", bricks ? 0 : m->fused_ready);
    if (!rc) rc = ckpt_put_long(ck, "grid_fresh", bricks ? 0 : m->grid_fresh);
    if (!rc) rc = put_points(ck, bricks ? &mm->gathered : &m->pts);
    if (bricks)
        mpm_points_free(&mm->gathered);
    /* the next step's s1-s3, summed by the fused pass in its own order */
    if (!rc && !bricks && (m->fused_ready || m->grid_fresh) &&
        !(rc = ckpt_enter(ck, "model/mpm/grid"))) {
        rc = ckpt_put_long(ck, "nnodes", m->grid.nnodes);
        if (!rc)
            rc = ckpt_put_doubles(ck, "node", &m->grid.node[0].m, 8 * m->grid.nnodes);
    }
    return rc;
}

static int mpm_model_checkpoint_read(void *self, struct ckpt *ck, struct err *e)
{
    struct mpm_model *mm = self;
    struct mpm *m = mm->m;
    long step = 0, fused = 0, fresh = 0;
    double react[3 * MPM_MAX_BODIES];
    int rc = ckpt_get_long(ck, "step", &step);
    if (!rc) rc = ckpt_get_double(ck, "time", &m->time);
    if (!rc) rc = ckpt_get_double(ck, "vmax", &m->vmax);
    if (!rc) rc = ckpt_get_double(ck, "ke", &m->ke);
    if (!rc) rc = ckpt_get_double(ck, "ke_centred", &m->ke_centred);
    if (!rc) rc = ckpt_get_double(ck, "strain", &m->strain);
    if (!rc) rc = ckpt_get_double(ck, "strain_before", &m->strain_before);
    if (!rc) rc = ckpt_get_double(ck, "fext_scale", &m->fext_scale);
    if (!rc) rc = ckpt_get_doubles(ck, "reaction", react, 3L * m->nbody);
    if (!rc) rc = ckpt_get_long(ck, "fused_ready", &fused);
    if (!rc) rc = ckpt_get_long(ck, "grid_fresh", &fresh);
    if (!rc && mm->bricks)
        rc = get_points_bricks(ck, mm, e);
    else if (!rc)
        rc = get_points(ck, &m->pts, m->nbody);
    if (!rc && mm->bricks && (fused || fresh))   /* a serial run's stored mapping: remap */
        fused = fresh = 0;
    if (!rc && (fused || fresh) && !(rc = ckpt_enter(ck, "model/mpm/grid"))) {
        long nn = 0;
        rc = ckpt_get_long(ck, "nnodes", &nn);
        if (!rc && nn != m->grid.nnodes)
            rc = err_set(e, ERR_INPUT, "%s: checkpoint grid has %ld nodes, the case's %ld",
                         ck->path, nn, m->grid.nnodes);
        if (!rc)
            rc = ckpt_get_doubles(ck, "node", &m->grid.node[0].m, 8 * nn);
    }
    if (rc)
        return rc;
    m->step = step;
    for (int b = 0; b < m->nbody; b++)
        memcpy(m->body[b].reaction, react + 3 * b, sizeof m->body[b].reaction);
    m->fused_ready = (int)fused;
    m->grid_fresh = (int)fresh;
    m->bins[0].blk_step = -1;   /* recomputed from the positions (checkpoint_sync) */
    if (mm->bricks)   /* every rank's energies and largest speed, as before the write */
        return mpm_bricks_agree(mm->bricks, 0, e);
    return 0;
}

/* The continuing run drops the particle-to-block cache as the restarted one
 * starts without it; the next locate step computes the same blocks. */
static void mpm_model_checkpoint_sync(void *self)
{
    struct mpm_model *mm = self;
    mm->m->bins[0].blk_step = -1;
    if (mm->bricks) {   /* the restarted run maps afresh: so does the continuing one */
        if (mm->m->fused_ready) {
            struct mpm_grid *g = &mm->m->grid;
            struct mpm_node *t = g->node;   /* back to this step's velocities (snapshots) */
            g->node = g->node_next;
            g->node_next = t;
        }
        mm->m->fused_ready = mm->m->grid_fresh = 0;
        /* the order a restart reads them in; an error (out of memory) stops
         * the next step */
        struct err e = {0};
        mm->sync_rc = mpm_bricks_sort_by_id(mm->bricks, mm->m, &e);
    }
}

/* Bricks: the points of every rank, gathered on rank 0 in id order. */
static int mpm_model_checkpoint_collect(void *self, struct err *e)
{
    struct mpm_model *mm = self;
    if (!mm->bricks)
        return 0;
    mpm_points_free(&mm->gathered);
    return mpm_bricks_gather_points(mm->bricks, &mm->m->pts, &mm->gathered, e);
}

const struct sim_model_ops sim_model_mpm = {
    .name = "mpm",
    .init = mpm_model_init,
    .pre_force = mpm_model_pre_force,
    .force = mpm_model_force,
    .integrate = mpm_model_integrate,
    .observe = mpm_model_observe,
    .checkpoint_write = mpm_model_checkpoint_write,
    .checkpoint_read = mpm_model_checkpoint_read,
    .checkpoint_sync = mpm_model_checkpoint_sync,
    .checkpoint_collect = mpm_model_checkpoint_collect,
};
