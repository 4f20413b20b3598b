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

#include "core/parallel.h"
#include "mpm/mpm_bricks.h"
#include "output/mpm_checkpoint.h"

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
    if (mm->sync_err.code) {   /* checkpoint_sync has no error channel of its own */
        *e = mm->sync_err;
        return e->code;
    }
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

/* The group's header: the point count n (every rank's), the state
 * variables, the loads; `order` 1 when the rows are the ranks' points in
 * rank order (a reader puts them in id order). */
static int put_points_header(struct ckpt *ck, const struct mpm_points *p, long n, int by_rank)
{
    int rc = ckpt_enter(ck, "model/mpm/points");
    if (!rc) rc = ckpt_put_long(ck, "n", n);
    if (!rc) rc = ckpt_put_long(ck, "nstate", p->nstate);
    if (!rc) rc = ckpt_put_long(ck, "has_fext", p->fext != NULL);
    if (!rc && by_rank) rc = ckpt_put_long(ck, "order", 1);
    return rc;
}

/* The stored header against the case's points: the same state variables
 * and loads; *n the stored count, *by_rank whether a reader sorts by id. */
static int get_points_header(struct ckpt *ck, const struct mpm_points *p, long *n, int *by_rank)
{
    long nstate = 0, has_fext = 0;
    int rc = ckpt_enter(ck, "model/mpm/points");
    if (!rc) rc = mpm_ckpt_get_count(ck, "n", n, by_rank);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    if (!rc) rc = ckpt_get_long(ck, "has_fext", &has_fext);
    if (!rc && (nstate != p->nstate || (has_fext != 0) != (p->fext != NULL)))
        rc = err_set(ck->e, ERR_INPUT,
                     "%s: checkpoint has %ld material points with %ld state variables%s, the "
                     "case's points have %d%s",
                     ck->path, *n, nstate, has_fext ? " and loads" : "", p->nstate,
                     p->fext ? " and loads" : "");
    return rc;
}

/* Serially: the points were built from the case file, the same count; the
 * stored values replace theirs, in the stored order (a checkpoint of
 * bricks: then in id order, as the bricks' runs continue). */
static int get_points(struct ckpt *ck, struct mpm *m, struct err *e)
{
    struct mpm_points *p = &m->pts;
    long n = 0;
    int by_rank = 0;
    int rc = get_points_header(ck, p, &n, &by_rank);
    if (!rc && n != p->n)
        return err_set(ck->e, ERR_INPUT, "%s: checkpoint has %ld material points, the case builds %ld",
                       ck->path, n, p->n);
    long want = p->n;
    p->n = 0;
    if (!rc)
        rc = mpm_ckpt_get_points_where(ck, n, p, 0, m->nbody, NULL, NULL);
    if (!rc)
        rc = mpm_ckpt_check_ids(ck, p);
    if (!rc && by_rank)
        rc = mpm_bricks_sort_by_id(NULL, m, e);
    if (rc)
        p->n = want;
    mpm_points_moved(m);
    return rc;
}

/* Bricks: the stored rows read in blocks by every rank, each keeping the
 * points of its brick (so no rank holds the whole set). */
struct brick_of {
    const struct mpm_bricks *b;
    const struct mpm_grid *g;
};

static int in_my_brick(const void *ctx, const double x[3], int64_t id)
{
    const struct brick_of *o = ctx;
    (void)id;
    return mpm_bricks_owns_point(o->b, o->g, x);
}

static int get_points_bricks(struct ckpt *ck, struct mpm_model *mm, struct err *e)
{
    struct mpm *m = mm->m;
    long n = 0;
    int by_rank = 0;
    int rc = get_points_header(ck, &m->pts, &n, &by_rank);
    struct brick_of mine = {mm->bricks, &m->grid};
    m->pts.n = 0;
    if (!rc)
        rc = mpm_ckpt_get_points_where(ck, n, &m->pts, 0, m->nbody, in_my_brick, &mine);
    if (!rc)   /* within a rank; the count over the ranks below */
        rc = mpm_ckpt_check_ids(ck, &m->pts);
    mpm_points_moved(m);
    rc = mpm_bricks_agree(mm->bricks, rc, e);
    if (!rc && mpm_bricks_npoints(mm->bricks, m) != n)
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
    /* bricks: the datasets for every rank's points, which each rank
     * writes (checkpoint_write_part); the nodes are not stored (each rank
     * maps afresh after a checkpoint, checkpoint_sync) */
    int bricks = mm->bricks != NULL;
    if (!rc) rc = ckpt_put_long(ck, "fused_ready", bricks ? 0 : m->fused_ready);
    if (!rc) rc = ckpt_put_long(ck, "grid_fresh", bricks ? 0 : m->grid_fresh);
    if (!rc) rc = put_points_header(ck, &m->pts, bricks ? mm->ck_total : m->pts.n, bricks);
    if (!rc) {
        struct ckpt_col col[MPM_CKPT_COLUMNS];
        int ncol = mpm_ckpt_columns(&m->pts, 0, col);
        rc = ckpt_put_columns(ck, col, ncol, bricks ? mm->ck_total : m->pts.n, !bricks);
    }
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
        rc = get_points(ck, m, e);
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
        /* with a dynamic balance both runs cut at these points (the same
         * cuts), then put them in the order a restart reads them in; an
         * error stops the next step */
        memset(&mm->sync_err, 0, sizeof mm->sync_err);
        if (!mpm_bricks_balance_sync(mm->bricks, mm->m, &mm->sync_err))
            mpm_bricks_sort_by_id(mm->bricks, mm->m, &mm->sync_err);
    }
}

/* Bricks: this rank's rows of the checkpoint's points (the points of the
 * lower ranks come first) and all of them. */
static int mpm_model_checkpoint_collect(void *self, struct err *e)
{
    struct mpm_model *mm = self;
    if (!mm->bricks)
        return 0;
    const struct parallel *par = mm->bricks->par;
    long *counts = malloc((size_t)par->size * sizeof *counts);
    int rc = mpm_bricks_agree(mm->bricks, counts ? 0 : err_nomem(e, "checkpoint counts"), e);
    mm->ck_offset = mm->ck_total = 0;
    if (!rc) {
        parallel_allgather_long(par, mm->m->pts.n, counts);
        for (int r = 0; r < par->size; r++) {
            mm->ck_offset += r < par->rank ? counts[r] : 0;
            mm->ck_total += counts[r];
        }
    }
    free(counts);
    return rc;
}

/* Bricks: this rank's points into the rows rank 0 laid out.  Collective. */
static int mpm_model_checkpoint_write_part(void *self, struct ckpt *ck, struct err *e)
{
    struct mpm_model *mm = self;
    (void)e;
    if (!mm->bricks)
        return 0;
    int rc = ckpt_agree(ck, ckpt_enter(ck, "model/mpm/points"));
    struct ckpt_col col[MPM_CKPT_COLUMNS];
    int ncol = mpm_ckpt_columns(&mm->m->pts, 0, col);
    if (!rc)
        rc = ckpt_put_columns_part(ck, col, ncol, mm->ck_offset, mm->m->pts.n);
    return rc;
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
    .checkpoint_write_part = mpm_model_checkpoint_write_part,
};
