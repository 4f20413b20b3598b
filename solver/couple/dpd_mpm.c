/* dpd_mpm: set-up, the coupled step and observables (see dpd_mpm.h). */
#include "couple/dpd_mpm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "core/halo.h"
#include "core/units.h"
#include "mpm/mpm_shape.h"

/* --- particle order ------------------------------------------------------- */

static int body_of(const struct dpd *d, uint32_t mask)
{
    for (int b = 0; b < d->nbodies; b++)
        if (mask & d->body[b].mask)
            return b;
    return -1;
}

/* 0: carried by the grid, 1: passive partner, 2: rigid body */
static int particle_class(const struct dpd *d, int i, uint32_t partner_bit)
{
    uint32_t m = d->p->mask[i];
    if (body_of(d, m) >= 0)
        return 2;
    return (m & partner_bit) ? 1 : 0;
}

int dpd_mpm_order(struct dpd *d, uint32_t partner_bit, struct err *e)
{
    return dpd_fix_class_order(d, partner_bit, e);
}

/* --- set-up ----------------------------------------------------------------- */

/* Buffers for the owned particles, and on bricks for the ghosts too (w is
 * forwarded to them for dpd_pair_heat). */
static int reserve(struct dpd_mpm *c, struct err *e)
{
    const struct particles *p = c->d->p;
    long n = p->n_owned + (p->halo ? p->n_ghost : 0);
    if (n <= c->cap)
        return 0;
    long cap = n + 16;
    double *f = realloc(c->f, (size_t)cap * 3 * sizeof *f);
    if (f)
        c->f = f;
    double *w = realloc(c->w, (size_t)cap * 3 * sizeof *w);
    if (w)
        c->w = w;
    double *v = realloc(c->vprev, (size_t)cap * 3 * sizeof *v);
    if (v)
        c->vprev = v;
    if (!f || !w || !v)
        return err_nomem(e, "DPD/MPM buffers");
    c->cap = cap;
    return 0;
}

/* The classes must come in the order [carried | partners | bodies]: count
 * them (at set-up, and on bricks after every migration). */
static int count_classes(struct dpd_mpm *c, struct err *e)
{
    const struct dpd *d = c->d;
    const struct particles *p = d->p;
    int stage = 0;
    c->ncarried = c->npartner = 0;
    for (int i = 0; i < p->n_owned; i++) {
        int k = particle_class(d, i, c->partner_bit);
        if (k < stage)
            return err_set(e, ERR_RUNTIME, "DPD particles not in [carried | partners | bodies] "
                                           "order (call dpd_mpm_order)");
        stage = k;
        if (k == 0)
            c->ncarried++;
        else if (k == 1)
            c->npartner++;
    }
    return 0;
}

int dpd_mpm_init(struct dpd_mpm *c, struct dpd *d, const struct dpd_mpm_grid *g,
                 uint32_t partner_bit, int64_t partner_id0, struct err *e)
{
    memset(c, 0, sizeof *c);
    c->d = d;
    c->partner_bit = partner_bit;
    c->partner_id0 = partner_id0;
    double cutoff = fmax(d->prm.sc.rc, d->set.cutoff);
    if (!(g->cell > 0) || !(g->cell < cutoff))
        return err_set(e, ERR_INPUT,
                       "MPM cell edge %g Å is not smaller than the DPD cutoff %g Å: the DPD "
                       "forces must reach beyond a cell (Chen 2014, Sec. 3)",
                       g->cell, cutoff);
    int rc = count_classes(c, e);
    if (rc)
        return rc;
    struct mpm_grid grid;
    rc = mpm_grid_init_uniform(&grid, g->lo, g->cell, g->ncell, MPM_SHAPE_LINEAR, e);
    if (rc)
        return rc;
    if ((rc = mpm_init(&c->m, &grid, MPM_MAX_STATE, d->nthreads, e)))
        return rc;
    c->m.sort_every = 0;   /* material points keep their indices (partners refer to them) */
    c->m.small_mass_rel = g->small_mass;
    c->extra.name = "dpd";
    c->extra.follow_grid = 1;
    if ((rc = mpm_attach(&c->m, &c->extra, e)))
        return rc;
    c->vbar = malloc((size_t)c->m.grid.nnodes * 8 * sizeof *c->vbar);
    if (!c->vbar)
        return err_nomem(e, "DPD/MPM nodes");
    return reserve(c, e);
}

void dpd_mpm_free(struct dpd_mpm *c)
{
    mpm_free(&c->m);
    free(c->partner_point);
    free(c->point_by_id);
    free(c->partner_was_here);
    free(c->f);
    free(c->w);
    free(c->vprev);
    free(c->vbar);
    memset(c, 0, sizeof *c);
}

int dpd_mpm_add_points(struct dpd_mpm *c, struct mpm_material *mat, long n, const double *x,
                       const double *v, double mass, double volume, const int64_t *id,
                       struct err *e)
{
    int im = mpm_add_material(&c->m, mat, e);
    if (im < 0)
        return ERR_INPUT;
    struct mpm_body b;
    memset(&b, 0, sizeof b);
    snprintf(b.name, sizeof b.name, "mpm");
    b.material = im;
    for (int k = 0; k < 3; k++)
        b.lp[k] = 0.25;
    int ib = mpm_add_body(&c->m, &b, e);
    if (ib < 0)
        return ERR_INPUT;
    int rc = mpm_points_reserve(&c->m.pts, c->m.pts.n + n, e);
    static const double zero[3] = {0, 0, 0};
    for (long k = 0; !rc && k < n; k++)
        if (mpm_points_add(&c->m.pts, x + 3 * k, v ? v + 3 * k : zero, mass, volume, ib, id[k],
                           e) < 0)
            rc = ERR_RUNTIME;
    return rc;
}

static int cmp_id(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Material point index of a partner id, or -1. */
static long point_of(const struct dpd_mpm *c, int64_t partner_id)
{
    int64_t want[2] = {partner_id - c->partner_id0, 0};
    const int64_t *hit = c->m.pts.n && c->point_by_id
                             ? bsearch(want, c->point_by_id, (size_t)c->m.pts.n,
                                       2 * sizeof(int64_t), cmp_id)
                             : NULL;
    return hit ? (long)hit[1] : -1;
}

/* Material point index of every partner, from its id (the points' table
 * by id is built once: the points keep their order). */
static int map_partners(struct dpd_mpm *c, struct err *e)
{
    const struct mpm_points *pts = &c->m.pts;
    const struct particles *p = c->d->p;
    if (!c->point_by_id) {
        if (!(c->point_by_id = malloc((size_t)(pts->n ? pts->n : 1) * 2 * sizeof(int64_t))))
            return err_nomem(e, "partner map");
        for (long k = 0; k < pts->n; k++) {
            c->point_by_id[2 * k] = pts->id[k];
            c->point_by_id[2 * k + 1] = k;
        }
        qsort(c->point_by_id, (size_t)pts->n, 2 * sizeof(int64_t), cmp_id);
    }
    if (c->npartner > c->partner_cap) {
        long cap = c->npartner + 16;
        long *pp = realloc(c->partner_point, (size_t)cap * sizeof *pp);
        if (!pp)
            return err_nomem(e, "partner map");
        c->partner_point = pp;
        c->partner_cap = cap;
    }
    for (long k = 0; k < c->npartner; k++) {
        int64_t want[2] = {p->id[c->ncarried + k] - c->partner_id0, 0};
        const int64_t *hit = pts->n ? bsearch(want, c->point_by_id, (size_t)pts->n,
                                              2 * sizeof(int64_t), cmp_id)
                                    : NULL;
        if (!hit)
            return err_set(e, ERR_RUNTIME, "partner %lld has no material point %lld",
                           (long long)p->id[c->ncarried + k], (long long)want[0]);
        c->partner_point[k] = (long)hit[1];
    }
    return 0;
}

/* Partners take their material points' positions and velocities. */
static void sync_partners(struct dpd_mpm *c)
{
    struct particles *p = c->d->p;
    for (long k = 0; k < c->npartner; k++) {
        long i = c->ncarried + k, q = c->partner_point[k];
        memcpy(p->x + 3 * i, c->m.pts.x + 3 * q, 3 * sizeof(double));
        memcpy(p->v + 3 * i, c->m.pts.v + 3 * q, 3 * sizeof(double));
    }
}

/* The extra set's view of the carried particles (their arrays move when
 * the DPD model grows its particle storage). */
static void update_view(struct dpd_mpm *c)
{
    struct particles *p = c->d->p;
    c->extra.n = c->ncarried;
    c->extra.x = p->x;
    c->extra.v = p->v;
    c->extra.mass = NULL;
    c->extra.type = p->type;
    c->extra.type_mass = p->mass;
    c->extra.force = c->f;
}

int dpd_mpm_prepare(struct dpd_mpm *c, struct err *e)
{
    int rc = map_partners(c, e);
    if (rc)
        return rc;
    double npartner = (double)c->npartner;
    if (c->d->p->halo)   /* bricks: every rank holds the points' external force */
        halo_sum(c->d->p->halo, &npartner, 1);
    if (npartner > 0 && (rc = mpm_points_enable_fext(&c->m.pts, e)))
        return rc;
    if ((rc = mpm_prepare(&c->m, e)))
        return rc;
    /* the small-mass rule counts DPD particles too: the lightest particle */
    double mmin = INFINITY;
    const struct particles *p = c->d->p;
    for (long i = 0; i < c->ncarried; i++)
        mmin = fmin(mmin, p->mass[p->type[i]]);
    for (long k = 0; k < c->m.pts.n; k++)
        mmin = fmin(mmin, c->m.pts.mass[k]);
    if (p->halo) {   /* the lightest of all ranks: the same threshold everywhere */
        double neg = -mmin;
        halo_max(p->halo, &neg, 1);
        mmin = -neg;
    }
    c->m.small_mass = isfinite(mmin) ? c->m.small_mass_rel * mmin : 0.0;
    double dt = c->d->dt, limit = mpm_stable_dt(&c->m);
    if (dt > limit)
        return err_set(e, ERR_INPUT,
                       "time step %g ps exceeds the stable step of the MPM grid, %.3g ps (cell "
                       "%g Å over the material's wave speed %.3g Å/ps)",
                       dt, limit, c->m.grid.h, c->m.cmax);
    sync_partners(c);
    update_view(c);
    rc = mpm_locate_particles(&c->m, e);
    if (p->halo && halo_any(p->halo, rc != 0) && !rc)
        return err_set_elsewhere(e, ERR_INPUT, "particles outside the MPM grid on another rank");
    if (rc) {
        char msg[sizeof e->msg];
        snprintf(msg, sizeof msg, "%s", e->msg);
        return err_set(e, ERR_INPUT, "particles outside the MPM grid: %s", msg);
    }
    return 0;
}

/* --- the step ----------------------------------------------------------------- */

/* Per node (8 doubles): [0-2] the centred velocity (v_i + v_i') / 2, with
 * v_i = (m v)_i / m_i of s2 (after s5 the node holds v_i + a_i dt and a_i)
 * and v_i' the remapped velocity of s11; [4-6] v_i' - (v_i + a_i dt), the
 * remapped velocity less the one the particles moved with.  Zero on skipped
 * (small-mass) nodes, whose acceleration is zero. */
static void node_velocities(struct dpd_mpm *c, double dt)
{
    const struct mpm_grid *g = &c->m.grid;
    const double small = c->m.small_mass;
    const int musl = c->m.algorithm == MPM_MUSL;
#pragma omp parallel for schedule(static) num_threads(c->m.nthreads)
    for (long i = 0; i < g->nnodes; i++) {
        const struct mpm_node *nd = &g->node[i];
        double *vb = c->vbar + 8 * i;
        memset(vb, 0, 8 * sizeof *vb);
        if (!(nd->m > small))
            continue;
        for (int k = 0; k < 3; k++) {
            double v0 = nd->q[k] - nd->f[k] * dt;
            double v1 = musl ? g->r[4 * i + k] : nd->q[k];
            vb[k] = 0.5 * (v0 + v1);
            vb[4 + k] = v1 - nd->q[k];
        }
    }
}

/* Bricks: every rank holds the whole grid and has mapped its own
 * particles; the nodes' mass, momentum and force (s1-s3b) are the sums
 * over the ranks.  The coupling has no rigid MPM bodies, so the nodes'
 * rigid marks (aux) are 0 on every rank and stay 0. */
static void sum_nodes(const struct halo *h, struct mpm *m)
{
    _Static_assert(sizeof(struct mpm_node) == 8 * sizeof(double), "node of 8 doubles");
    halo_sum(h, &m->grid.node[0].m, (int)(8 * m->grid.nnodes));
}

/* Both node velocities of node_velocities interpolated at x: w (centred)
 * and dv (remapped less moved). */
static void interpolate(const struct dpd_mpm *c, const double *x, double *w, double *dv)
{
    struct mpm_stencil st;
    mpm_stencil_linear(&c->m.grid, x, &st);
    double s[8] = {0};
    for (int k = 0; k < st.n; k++) {
        const double *vb = c->vbar + 8 * (long)st.node[k];
        for (int q = 0; q < 8; q++)
            s[q] += st.w[k] * vb[q];
    }
    memcpy(w, s, 3 * sizeof *s);
    memcpy(dv, s + 4, 3 * sizeof *s);
}

/* Bricks with material points (the points whole on every rank): s1, s2
 * and s3b of this rank's carried particles alone, with the linear stencil
 * of the uniform grid (the points' share is added after the sum over the
 * ranks, mpm_map_to_grid without the extra set). */
static void p2g_carried(struct dpd_mpm *c)
{
    struct mpm_grid *g = &c->m.grid;
    const struct particles *p = c->d->p;
    for (long i = 0; i < c->ncarried; i++) {
        struct mpm_stencil st;
        mpm_stencil_linear(g, p->x + 3 * i, &st);
        const double M = p->mass[p->type[i]], *v = p->v + 3 * i, *f = c->f + 3 * i;
        for (int k = 0; k < st.n; k++) {
            struct mpm_node *nd = &g->node[st.node[k]];
            const double N = st.w[k];
            nd->m += N * M;                  /* Chen 2014, Eqs. (s1), (s2) */
            for (int q = 0; q < 3; q++) {
                nd->q[q] += N * M * v[q];
                nd->f[q] += N * f[q];        /* Eq. (s3b) */
            }
        }
    }
}

/* Likewise s6 and s10 of this rank's carried particles: v_p += dt sum N_i
 * a_i, and with MUSL their momenta mapped back to the nodes' remap; the
 * largest squared speed is returned. */
static double g2p_carried(struct dpd_mpm *c, double dt)
{
    struct mpm_grid *g = &c->m.grid;
    struct particles *p = c->d->p;
    const int musl = c->m.algorithm == MPM_MUSL;
    double v2max = 0;
    for (long i = 0; i < c->ncarried; i++) {
        struct mpm_stencil st;
        mpm_stencil_linear(g, p->x + 3 * i, &st);
        double a[3] = {0, 0, 0}, *v = p->v + 3 * i;
        for (int k = 0; k < st.n; k++)
            for (int q = 0; q < 3; q++)
                a[q] += st.w[k] * g->node[st.node[k]].f[q];   /* Eq. (s6) */
        for (int q = 0; q < 3; q++)
            v[q] += a[q] * dt;
        v2max = fmax(v2max, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!musl)
            continue;
        const double M = p->mass[p->type[i]];
        for (int k = 0; k < st.n; k++)   /* Eq. (s10) */
            for (int q = 0; q < 3; q++)
                g->r[4 * (long)st.node[k] + q] += st.w[k] * M * v[q];
    }
    return v2max;
}

/* Bricks, the partner-crossing diagnostic (dpd_mpm_partner_moves): mark
 * the points whose partner this rank owns before the step's migration, by
 * the partners' ids (the counts and the map of the last step may be stale
 * after a checkpoint read) ... */
static int mark_partners_here(struct dpd_mpm *c, struct err *e)
{
    const struct particles *p = c->d->p;
    if (!c->partner_was_here &&
        !(c->partner_was_here = calloc((size_t)c->m.pts.n, sizeof *c->partner_was_here)))
        return err_nomem(e, "partner crossings");
    for (int i = 0; i < p->n_owned; i++) {
        long q = (p->mask[i] & c->partner_bit) ? point_of(c, p->id[i]) : -1;
        if (q >= 0)
            c->partner_was_here[q] = 1;
    }
    return 0;
}

/* ... and after it count the partners this rank holds that another rank
 * held before: the partners that crossed a brick face into this brick. */
static void count_partner_arrivals(struct dpd_mpm *c)
{
    for (long k = 0; k < c->npartner; k++)
        c->partner_arrivals += !c->partner_was_here[c->partner_point[k]];
    memset(c->partner_was_here, 0, (size_t)c->m.pts.n);
}

long dpd_mpm_partner_moves(const struct dpd_mpm *c)
{
    const struct halo *h = c->d->p->halo;
    if (!h)
        return 0;
    double n = (double)c->partner_arrivals;
    halo_sum(h, &n, 1);
    return lround(n);
}

int dpd_mpm_step_forces(struct dpd_mpm *c, struct err *e)
{
    struct dpd *d = c->d;
    struct mpm *m = &c->m;
    const double dt = d->dt;
    const int dpde = d->set.variant == DPD_ENERGY && d->ufield >= 0;
    struct halo *h = d->p->halo;
    int rc = 0;
    /* bricks: particles may migrate at this step's rebuild; the classes
     * come back in order (dpd_fix_class_order) with new counts */
    if (h && c->m.pts.n > 0)
        rc = mark_partners_here(c, e);
    if (!rc && h && !(rc = dpd_refresh_neighbours(d, e)) && !(rc = count_classes(c, e)) &&
        c->m.pts.n > 0 && !(rc = map_partners(c, e)))   /* the brick's partners, by id */
        count_partner_arrivals(c);
    if (!rc)
        rc = reserve(c, e);
    if (rc)
        return rc;
    /* s3b input: the pair forces at x(t), v(t), partners at their points */
    sync_partners(c);
    d->keep_pair_dr = dpde;
    c->uint_before = dpd_internal_energy(d);
    if ((rc = dpd_pair_forces(d, dt, c->f, e)))
        return rc;
    struct particles *p = d->p;   /* after any rebuild */
    const long n = p->n_owned, nfree = c->ncarried + c->npartner;
    c->epot_before = d->epot;
    memcpy(c->vprev, p->v, (size_t)n * 3 * sizeof *c->vprev);
    /* what the DPD particles exert on the partners' material points, mapped
     * at the points with N_i like the DPD forces (Eq. (3.1)) */
    if (c->npartner > 0) {
        memset(m->pts.fext, 0, (size_t)m->pts.n * 3 * sizeof *m->pts.fext);
        for (long k = 0; k < c->npartner; k++)
            for (int q = 0; q < 3; q++)
                m->pts.fext[3 * c->partner_point[k] + q] += c->f[3 * (c->ncarried + k) + q];
        mpm_points_moved(m);
    }
    if (h && m->pts.fext) {   /* the points are whole on every rank: 3 numbers a point */
        if (c->npartner == 0)
            memset(m->pts.fext, 0, (size_t)m->pts.n * 3 * sizeof *m->pts.fext);
        halo_sum(h, m->pts.fext, (int)(3 * m->pts.n));
        mpm_points_moved(m);
    }
    /* rigid bodies: the total pair force on each */
    double F[DPD_MAX_BODIES][3];
    memset(F, 0, sizeof F);
    for (long i = nfree; i < n; i++) {
        int b = body_of(d, p->mask[i]);
        for (int q = 0; q < 3; q++)
            F[b][q] += c->f[3 * i + q];
    }
    if (h && d->nbodies > 0)   /* a body's particles on every rank: 3 numbers a body */
        halo_sum(h, &F[0][0], 3 * d->nbodies);
    for (int b = 0; b < d->nbodies; b++) {
        memcpy(d->body[b].force, F[b], sizeof F[b]);
        memcpy(c->body_vold[b], d->body[b].v, sizeof c->body_vold[b]);
        if (d->body[b].kind == DPD_BODY_FREE)
            for (int q = 0; q < 3; q++)
                d->body[b].v[q] += F[b][q] / d->body[b].mass * UNITS_FTM2V * dt;
    }
    return 0;
}

int dpd_mpm_step_update(struct dpd_mpm *c, struct err *e)
{
    struct dpd *d = c->d;
    struct mpm *m = &c->m;
    const double dt = d->dt;
    const int dpde = d->set.variant == DPD_ENERGY && d->ufield >= 0;
    struct particles *p = d->p;
    const long n = p->n_owned, nfree = c->ncarried + c->npartner;
    double (*vold)[3] = c->body_vold;
    struct halo *h = p->halo;
    int rc;
    /* MUSL, Chen 2014 s1-s11 */
    update_view(c);
    if (m->timers)
        timer_start(m->timers, TIMER_MPM_P2G);
    rc = mpm_locate_particles(m, e);
    if (h && halo_any(h, rc != 0) && !rc)   /* every rank stops */
        rc = err_set_elsewhere(e, ERR_DIVERGED, "a particle left the MPM grid on another rank");
    if (rc && e->elsewhere) {
        if (m->timers)
            timer_stop(m->timers, TIMER_MPM_P2G);
        return rc;
    }
    if (rc) {
        char msg[sizeof e->msg];
        snprintf(msg, sizeof msg, "%s", e->msg);
        if (m->timers)
            timer_stop(m->timers, TIMER_MPM_P2G);
        return err_set(e, ERR_DIVERGED, "%s (at step %ld; a larger grid.margin keeps the "
                                        "particles on the grid)",
                       msg, d->step);
    }
    mpm_clear_grid(m);
    /* bricks with material points: those are on every rank, so their share
     * enters once, after the sum of the carried particles' shares */
    const int split = h && m->pts.n > 0;
    const int nextra = m->nextra;
    if (split) {
        p2g_carried(c);
        sum_nodes(h, m);
        m->nextra = 0;   /* the points alone */
        mpm_map_to_grid(m, MPM_MAP_ALL);
        m->nextra = nextra;
    } else {
        mpm_map_to_grid(m, MPM_MAP_ALL);   /* s1, s2, s3a (points), s3b (DPD forces N_i) */
        if (h)   /* the whole grid on every rank: each rank's particles' share summed */
            sum_nodes(h, m);
    }
    if (m->timers) {
        timer_stop(m->timers, TIMER_MPM_P2G);
        timer_start(m->timers, TIMER_MPM_GRID);
    }
    mpm_update_grid(m, dt);            /* s4-s5, small-mass nodes skipped */
    if (m->timers) {
        timer_stop(m->timers, TIMER_MPM_GRID);
        timer_start(m->timers, TIMER_MPM_G2P);
    }
    if (split) {   /* the carried particles' remap summed, then the points' added */
        double v2 = g2p_carried(c, dt);
        if (m->algorithm == MPM_MUSL)
            halo_sum(h, m->grid.r, (int)(4 * m->grid.nnodes));
        m->nextra = 0;
        mpm_map_to_particles(m, dt);
        m->nextra = nextra;
        m->vmax = fmax(m->vmax, sqrt(v2));
    } else {
        mpm_map_to_particles(m, dt);       /* s6, s10 */
        if (h && m->algorithm == MPM_MUSL)   /* the remap's nodal momenta, likewise */
            halo_sum(h, m->grid.r, (int)(4 * m->grid.nnodes));
    }
    if (m->algorithm == MPM_MUSL)
        mpm_update_grid_velocity(m);   /* s11 */
    /* DPDE: the work of the D + R forces comes out of the internal energies
     * (positions still those of time t, as in the force call) */
    double heat = 0;
    if (dpde) {
        node_velocities(c, dt);
        double *u = particles_field(p, d->ufield), sub = 0;
        for (long i = 0; i < nfree; i++) {
            const double *x = i < c->ncarried ? p->x + 3 * i
                                              : m->pts.x + 3 * c->partner_point[i - c->ncarried];
            double dv[3];
            interpolate(c, x, c->w + 3 * i, dv);
            /* the conservative work the grid's smoothing removed (dpd_mpm.h, 2.) */
            const double *fc = p->f + 3 * i;
            double di = dt * (fc[0] * dv[0] + fc[1] * dv[1] + fc[2] * dv[2]);
            u[i] -= di;
            sub -= di;
        }
        if (h)
            halo_sum(h, &sub, 1);
        c->subgrid_heat += sub;
        for (long i = nfree; i < n; i++) {
            int b = body_of(d, p->mask[i]);
            for (int q = 0; q < 3; q++)
                c->w[3 * i + q] = 0.5 * (vold[b][q] + d->body[b].v[q]);
        }
        if (h)
            ghost_forward(p, c->w, 3);
        rc = dpd_pair_heat(d, dt, c->w, &heat, e);
        if (rc) {
            if (m->timers)
                timer_stop(m->timers, TIMER_MPM_G2P);
            return rc;
        }
        c->heat += heat;
    }
    mpm_update_particles(m, dt);       /* s7-s8 (and s12-s14 for the points) */
    if (m->timers)
        timer_stop(m->timers, TIMER_MPM_G2P);
    /* rigid bodies move as bodies */
    for (long i = nfree; i < n; i++) {
        const struct dpd_body *b = &d->body[body_of(d, p->mask[i])];
        for (int q = 0; q < 3; q++) {
            p->v[3 * i + q] = b->v[q];
            p->x[3 * i + q] += b->v[q] * dt;
        }
    }
    sync_partners(c);
    double kec = 0;
    for (long i = 0; i < n; i++) {
        if (i >= c->ncarried && i < nfree)
            continue;
        const double *a = c->vprev + 3 * i, *b = p->v + 3 * i;
        kec += p->mass[p->type[i]] * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    }
    if (h)
        halo_sum(h, &kec, 1);
    c->ke_centred = 0.5 * kec * UNITS_MVV2E;
    d->step++;
    d->time += dt;
    m->step++;
    m->time += dt;
    int bad = !isfinite(m->vmax) || !isfinite(c->ke_centred);
    if (h ? halo_any(h, bad) : bad)
        return err_set(e, ERR_DIVERGED, "non-finite velocity at step %ld", d->step);
    return 0;
}

int dpd_mpm_step(struct dpd_mpm *c, struct err *e)
{
    int rc = dpd_mpm_step_forces(c, e);
    return rc ? rc : dpd_mpm_step_update(c, e);
}

/* --- observables ---------------------------------------------------------------- */

void dpd_mpm_energy(const struct dpd_mpm *c, struct dpd_mpm_energy *en)
{
    const struct dpd *d = c->d;
    const struct particles *p = d->p;
    const long nfree = c->ncarried + c->npartner;
    double ke = 0;
    for (long i = 0; i < p->n_owned; i++) {
        if (i >= c->ncarried && i < nfree)
            continue;
        const double *v = p->v + 3 * i;
        ke += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    if (p->halo)
        halo_sum(p->halo, &ke, 1);
    struct mpm_totals t;
    mpm_totals(&c->m, &t);
    en->ke_dpd = 0.5 * ke * UNITS_MVV2E;
    en->ke_points = t.kinetic;
    en->epot = c->epot_before;
    en->uint = dpd_internal_energy(d);
    en->strain = t.strain;
    en->total = en->ke_dpd + en->ke_points + en->epot + en->uint + en->strain;
    en->centred = c->ke_centred + (c->m.pts.n ? c->m.ke_centred : 0.0) + c->epot_before +
                  c->m.strain_before + 0.5 * (c->uint_before + en->uint);
}

void dpd_mpm_momentum(const struct dpd_mpm *c, double P[3])
{
    const struct particles *p = c->d->p;
    const long nfree = c->ncarried + c->npartner;
    P[0] = P[1] = P[2] = 0;
    for (long i = 0; i < p->n_owned; i++) {
        if (i >= c->ncarried && i < nfree)
            continue;
        for (int q = 0; q < 3; q++)
            P[q] += p->mass[p->type[i]] * p->v[3 * i + q];
    }
    if (p->halo)
        halo_sum(p->halo, P, 3);
    struct mpm_totals t;
    mpm_totals(&c->m, &t);
    for (int q = 0; q < 3; q++)
        P[q] += t.momentum[q];
}

/* --- partners ------------------------------------------------------------------ */

int dpd_mpm_frozen_take(struct dpd_mpm *c, double **byp, int *at, struct err *e)
{
    struct particles *p = c->d->p;
    *byp = NULL;
    int k = particles_find_field(p, DPD_FP_FROZEN_FIELD);
    *at = k;
    if (k < 0 || !p->halo)
        return 0;
    double *v = calloc((size_t)(c->m.pts.n ? c->m.pts.n : 1), sizeof *v);
    if (!v)
        return err_nomem(e, "frozen partner embedding");
    const double *fz = particles_field(p, k);
    for (int i = 0; i < p->n_owned; i++) {
        long q = (p->mask[i] & c->partner_bit) ? point_of(c, p->id[i]) : -1;
        if (q >= 0)
            v[q] = fz[i];   /* one partner a point, on one rank: the sum is exact */
    }
    halo_sum(p->halo, v, (int)c->m.pts.n);
    particles_remove_field(p, DPD_FP_FROZEN_FIELD);
    *byp = v;
    return 0;
}

int dpd_mpm_frozen_put(struct dpd_mpm *c, const double *byp, int at, struct err *e)
{
    struct particles *p = c->d->p;
    if (!byp)
        return 0;
    int k = particles_add_field(p, DPD_FP_FROZEN_FIELD, 1, 0, e);
    if (k < 0)
        return ERR_RUNTIME;
    if (at >= 0 && at < k) {   /* back to its place: the fields after it keep their indices */
        struct particle_field f = p->fields[k];
        memmove(&p->fields[at + 1], &p->fields[at], (size_t)(k - at) * sizeof f);
        p->fields[at] = f;
        k = at;
    }
    double *fz = particles_field(p, k);
    for (int i = 0; i < p->n_owned; i++) {
        long q = (p->mask[i] & c->partner_bit) ? point_of(c, p->id[i]) : -1;
        fz[i] = q >= 0 ? byp[q] : 0.0;
    }
    return 0;
}

struct xkey {
    double x;
    int i;
};

static int cmp_xkey(const void *a, const void *b)
{
    const struct xkey *u = a, *v = b;
    return (u->x > v->x) - (u->x < v->x);
}

int dpd_mpm_partners_create(struct particles *p, int nd, long n, const double *x,
                            const int64_t *id, double range, uint32_t bit, int64_t id0,
                            long *added, struct err *e)
{
    *added = 0;
    struct xkey *xs = malloc((size_t)(nd ? nd : 1) * sizeof *xs);
    if (!xs)
        return err_nomem(e, "partners");
    for (int i = 0; i < nd; i++) {
        xs[i].x = p->x[3 * i];
        xs[i].i = i;
    }
    qsort(xs, (size_t)nd, sizeof *xs, cmp_xkey);
    const double r2max = range * range;
    static const double zero[3] = {0, 0, 0};
    int rc = 0;
    for (long k = 0; k < n && !rc; k++) {
        const double *xk = x + 3 * k;
        /* first DPD particle with x >= xk - range */
        int lo = 0, hi = nd;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (xs[mid].x < xk[0] - range)
                lo = mid + 1;
            else
                hi = mid;
        }
        int near = 0;
        for (int s = lo; s < nd && xs[s].x <= xk[0] + range && !near; s++) {
            const double *xi = p->x + 3 * xs[s].i;
            double dx = xi[0] - xk[0], dy = xi[1] - xk[1], dz = xi[2] - xk[2];
            near = dx * dx + dy * dy + dz * dz < r2max;
        }
        if (!near)
            continue;
        int j = particles_add(p, xk, zero, 0, id0 + id[k]);
        if (j < 0)
            rc = err_nomem(e, "partners");
        else {
            p->mask[j] = bit;
            (*added)++;
        }
    }
    free(xs);
    return rc;
}
