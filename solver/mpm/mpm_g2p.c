/*
 * mpm_g2p: grid-to-particle stages.
 *
 * mpm_map_to_particles: Chen 2014 s6 -- a_p = sum_i a_i N_i(x_p), v_p +=
 * a_p dt (rigid points keep their body's velocity; extra sets that do not
 * follow the grid keep theirs) -- and, in MUSL, s10: the updated momenta are
 * mapped back, r_i += M_p v_p N_i(x_p) (coloured, like the other scatter).
 *
 * mpm_update_particles: s7-s8 -- x_p += dt sum_i v_i(t+dt) N_i(x_p), with
 * the nodal velocities of s5 -- and s12-s14 with the velocity gradient
 * L_p = sum_i v_i G_i(x_p) from the remapped velocities of s11 (MUSL) or
 * those of s5 (USL).  Shape functions are evaluated at x_p(t) throughout.
 */
#pragma GCC optimize("fp-contract=fast")   /* multiply-adds in the hot loops */
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_linear.h"
#include "mpm/mpm_p2g_lin.h"
#include "mpm/mpm_stress.h"
#include "mpm/mpm_stress_chunk.h"
#include "mpm/mpm_view.h"

static inline __attribute__((always_inline)) void
g2p_particle(const struct mpm *m, const struct mpm_view *w, long p, const int kind, double dt,
             int musl, double *r, const struct mpm_node *node, double *v2max, double *kec)
{
    struct mpm_stencil st;
    mpm_stencil_at(m, w, p, kind, &st);
    double *v = w->v + 3 * p;
    const struct mpm_body *body = w->body ? &m->body[w->body[p]] : NULL;
    if (body && body->rigid) {
        v[0] = body->velocity[0];
        v[1] = body->velocity[1];
        v[2] = body->velocity[2];
        kec[0] += mpm_view_mass(w, p) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } else if (w->follow) {
        mpm_v4 a = {0, 0, 0, 0};
        for (int k = 0; k < st.n; k++)   /* Eq. (s6): the node's f holds its acceleration */
            a += st.w[k] * *(const mpm_v4 *)&node[st.node[k]].f[0];
        double v0 = v[0], v1 = v[1], v2 = v[2];
        v[0] += a[0] * dt;
        v[1] += a[1] * dt;
        v[2] += a[2] * dt;
        if (body)
            kec[0] += mpm_view_mass(w, p) * (v0 * v[0] + v1 * v[1] + v2 * v[2]);
    }
    double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (vv > *v2max)
        *v2max = vv;
    if (body)
        kec[1] += mpm_view_mass(w, p) * vv;
    if (musl) {   /* Eq. (s10) */
        double M = mpm_view_mass(w, p);
        const mpm_v4 P = mpm_v4_set(M * v[0], M * v[1], M * v[2], 0);
        for (int k = 0; k < st.n; k++)
            *(mpm_v4 *)(r + 4 * (long)st.node[k]) += st.w[k] * P;
    }
}

/* Linear fast path of s6 and s10: the remapped momenta of a run of points
 * in one cell are summed in registers and added to its 8 nodes once. */
static inline void g2p_flush(double *r, long cur, const long off[8], const mpm_v4 R[8])
{
#pragma GCC unroll 8
    for (int q = 0; q < 8; q++)
        *(mpm_v4 *)(r + 4 * (cur + off[q])) += R[q];
}

static void g2p_linear_block(const struct mpm *m, const struct mpm_view *w, const int32_t *idx,
                             long count, double dt, int musl, double *r,
                             const struct mpm_node *node, const long off[8], double *v2max,
                             double *kec)
{
    const struct mpm_grid *g = &m->grid;
    mpm_v4 R[8] = {{0}};
    long cur = -1;
    const long ahead = 2 * off[2] + off[4];   /* mpm_lin_prefetch */
    for (long k = 0; k < count; k++) {
        long p = idx[k];
        struct mpm_lin st;
        mpm_lin_eval(g, w->x + 3 * p, &st);
        if (st.base != cur) {   /* a new cell: flush the run's remap */
            if (musl && cur >= 0)
                g2p_flush(r, cur, off, R);
            cur = st.base;
            mpm_lin_prefetch(node, sizeof *node, cur, ahead);
            if (musl)
                mpm_lin_prefetch(r, 4 * sizeof *r, cur, ahead);
#pragma GCC unroll 8
            for (int q = 0; q < 8; q++)
                R[q] = (mpm_v4){0, 0, 0, 0};
        }
        double *v = w->v + 3 * p;
        const struct mpm_body *body = w->body ? &m->body[w->body[p]] : NULL;
        if (body && body->rigid) {
            v[0] = body->velocity[0];
            v[1] = body->velocity[1];
            v[2] = body->velocity[2];
            kec[0] += mpm_view_mass(w, p) * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        } else if (w->follow) {
            mpm_v4 a = {0, 0, 0, 0};
            const struct mpm_node *nb = node + st.base;
#pragma GCC unroll 4
            for (int bc = 0; bc < 4; bc++)   /* Eq. (s6): a_p = sum N_q a_q */
                a += st.t[bc] * (st.wx[0] * *(const mpm_v4 *)&nb[off[2 * bc]].f[0] +
                                 st.wx[1] * *(const mpm_v4 *)&nb[off[2 * bc + 1]].f[0]);
            double v0 = v[0], v1 = v[1], v2 = v[2];
            v[0] += a[0] * dt;
            v[1] += a[1] * dt;
            v[2] += a[2] * dt;
            if (w->body)
                kec[0] += mpm_view_mass(w, p) * (v0 * v[0] + v1 * v[1] + v2 * v[2]);
        }
        double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (vv > *v2max)
            *v2max = vv;
        if (w->body)
            kec[1] += mpm_view_mass(w, p) * vv;
        if (musl) {   /* Eq. (s10) */
            double M = mpm_view_mass(w, p);
            const mpm_v4 P = mpm_v4_set(M * v[0], M * v[1], M * v[2], 0);
            const mpm_v4 P0 = st.wx[0] * P, P1 = st.wx[1] * P;
#pragma GCC unroll 4
            for (int bc = 0; bc < 4; bc++) {
                R[2 * bc] += st.t[bc] * P0;
                R[2 * bc + 1] += st.t[bc] * P1;
            }
        }
    }
    if (musl && cur >= 0)
        g2p_flush(r, cur, off, R);
}

static inline __attribute__((always_inline)) void
g2p_all(struct mpm *m, const struct mpm_view *views, int nv, double dt, const int kind)
{
    const struct mpm_grid *g = &m->grid;
    const struct mpm_node *node = g->node;
    double *r = g->r;
    int musl = m->algorithm == MPM_MUSL;
    double v2max = 0, kec0 = 0, kec1 = 0;
    long off[8];
    mpm_lin_offsets(g, off);
#pragma omp parallel num_threads(m->nthreads) reduction(max : v2max) reduction(+ : kec0, kec1)
    {
        double kec[2] = {0, 0};   /* M v(t-dt).v(t), M v(t)^2 */
        for (int c = 0; c < MPM_COLOURS; c++) {
            if (g->ncolour[c] == 0)
                continue;   /* the same for every thread: no barrier skipped unevenly */
#pragma omp for schedule(dynamic, 1)
            for (long bi = 0; bi < g->ncolour[c]; bi++) {
                long b = g->colour_block[c][bi];
                for (int s = 0; s < nv; s++) {
                    const struct mpm_bins *bn = views[s].bins;
                    if (kind == MPM_ST_LINEAR) {
                        g2p_linear_block(m, &views[s], bn->order + bn->start[b],
                                         bn->start[b + 1] - bn->start[b], dt, musl, r, node, off,
                                         &v2max, kec);
                        continue;
                    }
                    for (long k = bn->start[b]; k < bn->start[b + 1]; k++)
                        g2p_particle(m, &views[s], bn->order[k], kind, dt, musl, r, node,
                                     &v2max, kec);
                }
            }
        }
        kec0 += kec[0];
        kec1 += kec[1];
    }
    m->vmax = sqrt(v2max);
    m->ke_centred = 0.5 * kec0 * UNITS_MVV2E;
    m->ke = 0.5 * kec1 * UNITS_MVV2E;
}

void mpm_map_to_particles(struct mpm *m, double dt)
{
    struct mpm_view views[1 + MPM_MAX_EXTRA];
    int nv = mpm_views(m, views);
    switch (mpm_stencil_kind(&m->grid)) {
    case MPM_ST_LINEAR:
        g2p_all(m, views, nv, dt, MPM_ST_LINEAR);
        break;
    case MPM_ST_GIMP:
        g2p_all(m, views, nv, dt, MPM_ST_GIMP);
        break;
    default:
        g2p_all(m, views, nv, dt, MPM_ST_HIER);
        break;
    }
}

static inline __attribute__((always_inline)) void
update_particle(const struct mpm *m, const struct mpm_view *w, long p, const int kind, double dt,
                const double *vel, const struct mpm_node *node, struct mpm_points *pts)
{
    double *x = w->x + 3 * p;
    const struct mpm_body *body = w->body ? &m->body[w->body[p]] : NULL;
    if (body && body->rigid) {
        x[0] += body->velocity[0] * dt;
        x[1] += body->velocity[1] * dt;
        x[2] += body->velocity[2] * dt;
        return;
    }
    if (!w->follow)
        return;
    struct mpm_stencil st;
    mpm_stencil_at(m, w, p, kind, &st);
    /* vb: [., vbar] from the s5 velocities held in q (Eq. (s7));
     * Lx, Ly, Lz: the columns d v / d x_b of L (Eq. (s12)) */
    mpm_v4 vb = {0, 0, 0, 0}, Lx = vb, Ly = vb, Lz = vb;
    if (body && vel) {
        for (int k = 0; k < st.n; k++) {
            long i = st.node[k];
            vb += st.w[k] * *(const mpm_v4 *)&node[i].m;
            mpm_v4 vi = *(const mpm_v4 *)(vel + 4 * i);
            Lx += st.gx[k] * vi;
            Ly += st.gy[k] * vi;
            Lz += st.gz[k] * vi;
        }
    } else if (body) {   /* USL: the gradient of the s5 velocities */
        for (int k = 0; k < st.n; k++) {
            mpm_v4 vi = *(const mpm_v4 *)&node[st.node[k]].m;
            vb += st.w[k] * vi;
            Lx += st.gx[k] * vi;
            Ly += st.gy[k] * vi;
            Lz += st.gz[k] * vi;
        }
    } else {
        for (int k = 0; k < st.n; k++)
            vb += st.w[k] * *(const mpm_v4 *)&node[st.node[k]].m;
    }
    x[0] += vb[1] * dt;   /* Eq. (s8) */
    x[1] += vb[2] * dt;
    x[2] += vb[3] * dt;
    if (!body)
        return;
    int o = vel ? 0 : 1;   /* USL: velocities sit in lanes 1-3 of [m v] */
    double L[9] = {Lx[o], Ly[o], Lz[o], Lx[o + 1], Ly[o + 1], Lz[o + 1],
                   Lx[o + 2], Ly[o + 2], Lz[o + 2]};
    const struct mpm_material *mat = m->mat[body->material];
    mpm_point_stress(mat, L, dt, pts->stress + 6 * p, pts->F + 9 * p,
                     pts->vol + p, pts->vol0[p], pts->eint + p,
                     pts->nstate ? pts->state + (long)pts->nstate * p : NULL);
}

/* Linear fast path of s7-s8 and s12-s14 for the material points. */
/* The cells of a chunk's points at their new positions (by their place in
 * the chunk; mpm_lin_cell), for the fused pass's mapping. */
struct chunk_cells {
    long key[MPM_CHUNK][3];
    double f[MPM_CHUNK][3];
};

/* s7-s8 and s12 of point p: its new position, block and cell (key, f), and
 * its velocity gradient L (row-major) from the nodal velocities; returns
 * the point's material, or -1 for a point of a rigid body (moved at the
 * body's velocity, no stress update). */
static inline __attribute__((always_inline)) int
kinematics_point_linear(const struct mpm *m, long p, double dt, const double *vel,
                        const struct mpm_node *node, const long s1, const long s2, const int musl,
                        struct mpm_points *pts, int32_t *blk, double L[9], long *pf,
                        long key[3], double f[3])
{
    double *x = pts->x + 3 * p;
    const struct mpm_body *body = &m->body[pts->body[p]];
    if (body->rigid) {
        x[0] += body->velocity[0] * dt;
        x[1] += body->velocity[1] * dt;
        x[2] += body->velocity[2] * dt;
        blk[p] = (int32_t)mpm_lin_cell(&m->grid, x, key, f);
        return -1;
    }
    struct mpm_lin st;
    mpm_lin_eval(&m->grid, x, &st);
    if (st.base != *pf) {
        *pf = st.base;
        mpm_lin_prefetch(node, sizeof *node, st.base, 2 * s1 + s2);
        if (musl)
            mpm_lin_prefetch(vel, 4 * sizeof *vel, st.base, 2 * s1 + s2);
    }
    const struct mpm_node *nb = node + st.base;
    const double *vb4 = musl ? vel + 4 * st.base : NULL;
    const double *ih = m->grid.inv_hd;
    /* vq: the velocities whose gradient is L -- s11 (MUSL) or s5 (USL) */
    mpm_v4 vq[8], vs[8];
#pragma GCC unroll 8
    for (int q = 0; q < 8; q++) {
        long o = (q & 1) + ((q >> 1) & 1) * s1 + (q >> 2) * s2;
        vs[q] = *(const mpm_v4 *)&nb[o].m;   /* [m, v(s5)] */
        vq[q] = musl ? *(const mpm_v4 *)(vb4 + 4 * o) : vs[q];
    }
    mpm_v4 vb = {0, 0, 0, 0}, Lx = vb, Ly = vb, Lz = vb;
#pragma GCC unroll 4
    for (int bc = 0; bc < 4; bc++) {
        int bb = bc & 1, cc = bc >> 1;
        vb += st.t[bc] * (st.wx[0] * vs[2 * bc] + st.wx[1] * vs[2 * bc + 1]);   /* Eq. (s7) */
        Lx += st.t[bc] * (vq[2 * bc + 1] - vq[2 * bc]);                         /* Eq. (s12) */
        if (bb)
            Ly += (st.wz[cc]) * (st.wx[0] * (vq[2 * bc] - vq[2 * bc - 2]) +
                                 st.wx[1] * (vq[2 * bc + 1] - vq[2 * bc - 1]));
        if (cc)
            Lz += (st.wy[bb]) * (st.wx[0] * (vq[2 * bc] - vq[2 * bc - 4]) +
                                 st.wx[1] * (vq[2 * bc + 1] - vq[2 * bc - 3]));
    }
    Lx *= ih[0];
    Ly *= ih[1];
    Lz *= ih[2];
    x[0] += vb[1] * dt;   /* Eq. (s8) */
    x[1] += vb[2] * dt;
    x[2] += vb[3] * dt;
    blk[p] = (int32_t)mpm_lin_cell(&m->grid, x, key, f);
    const int o = musl ? 0 : 1;   /* USL: velocities sit in lanes 1-3 of [m v] */
    double lc[3][4];
    memcpy(lc[0], &Lx, sizeof lc[0]);
    memcpy(lc[1], &Ly, sizeof lc[1]);
    memcpy(lc[2], &Lz, sizeof lc[2]);
    L[0] = lc[0][o];
    L[1] = lc[1][o];
    L[2] = lc[2][o];
    L[3] = lc[0][o + 1];
    L[4] = lc[1][o + 1];
    L[5] = lc[2][o + 1];
    L[6] = lc[0][o + 2];
    L[7] = lc[1][o + 2];
    L[8] = lc[2][o + 2];
    return body->material;
}

/* s13-s14 of point p of material `mat` from its velocity gradient L. */
static inline __attribute__((always_inline)) void
stress_point(const struct mpm *m, long p, int mat, const double L[9], double dt,
             struct mpm_points *pts)
{
    mpm_point_stress(m->mat[mat], L, dt, pts->stress + 6 * p, pts->F + 9 * p, pts->vol + p,
                     pts->vol0[p], pts->eint + p,
                     pts->nstate ? pts->state + (long)pts->nstate * p : NULL);
}

/* The points idx[0..n) (n <= MPM_CHUNK): s7-s8 and s12 of each, then
 * s13-s14 of all -- for a chunk of one isotropic linear elastic material
 * four points at a time (mpm_stress_chunk.h: stress, F, volumes and stress
 * work move between the points' arrays and vector lanes there, with no
 * copies), else point by point. */
static inline __attribute__((always_inline)) void
update_chunk_linear(const struct mpm *m, const int32_t *idx, long n, double dt, const double *vel,
                    const struct mpm_node *node, const long s1, const long s2, const int musl,
                    struct mpm_points *pts, int32_t *blk, struct mpm_chunk *ch,
                    struct chunk_cells *cc)
{
    int nd = 0, same = 1;
    long pf = -1;   /* the cell whose next nodes were prefetched */
    for (long k = 0; k < n; k++) {
        long p = idx[k];
        double L[9];
        int mat = kinematics_point_linear(m, p, dt, vel, node, s1, s2, musl, pts, blk, L, &pf,
                                          cc->key[k], cc->f[k]);
        if (mat < 0)
            continue;
        for (int c = 0; c < 9; c++)
            ch->L[c][nd] = L[c];
        ch->p[nd] = (int32_t)p;
        ch->mat[nd] = mat;
        same &= mat == ch->mat[0];
        nd++;
    }
    if (nd == 0)
        return;
    const struct mpm_material *mat0 = m->mat[ch->mat[0]];
    if (!same || !mat0->iso) {
        for (int j = 0; j < nd; j++) {
            double L[9];
            for (int c = 0; c < 9; c++)
                L[c] = ch->L[c][j];
            stress_point(m, ch->p[j], ch->mat[j], L, dt, pts);
        }
        return;
    }
    int n4 = (nd + 3) & ~3;
    for (int j = nd; j < n4; j++)   /* padding lanes: finite values, results unused */
        for (int c = 0; c < 9; c++)
            ch->L[c][j] = 0;
    if (mat0->jaumann)
        mpm_stress_chunk_iso(mat0->iso, 1, dt, ch, nd, pts);
    else
        mpm_stress_chunk_iso(mat0->iso, 0, dt, ch, nd, pts);
}

static inline __attribute__((always_inline)) void
update_all(struct mpm *m, const struct mpm_view *views, int nv, double dt, const int kind)
{
    const struct mpm_node *node = m->grid.node;
    const double *vel = m->algorithm == MPM_MUSL ? m->grid.r : NULL;
    struct mpm_points *pts = &m->pts;
    const long s1 = m->grid.stride[1], s2 = m->grid.stride[2];
    m->strain_before = m->strain;
    double se = 0;
    struct mpm_bins *b0 = &m->bins[0];
    int32_t *blk = b0->blk;   /* sized by mpm_locate_particles, which runs first */
    for (int s = 0; s < nv; s++) {
        const struct mpm_view *w = &views[s];
        long n = w->n;
        if (kind == MPM_ST_LINEAR && s == 0) {   /* chunks of consecutive points */
#pragma omp parallel for schedule(static) num_threads(m->nthreads) reduction(+ : se)
            for (long p0 = 0; p0 < n; p0 += MPM_CHUNK) {
                struct mpm_chunk ch;
                struct chunk_cells cc;
                int32_t idx[MPM_CHUNK];
                long c = n - p0 < MPM_CHUNK ? n - p0 : MPM_CHUNK;
                for (long k = 0; k < c; k++)
                    idx[k] = (int32_t)(p0 + k);
                if (vel)
                    update_chunk_linear(m, idx, c, dt, vel, node, s1, s2, 1, pts, blk, &ch, &cc);
                else
                    update_chunk_linear(m, idx, c, dt, vel, node, s1, s2, 0, pts, blk, &ch, &cc);
                for (long k = 0; k < c; k++)
                    se += pts->eint[p0 + k];
            }
            b0->blk_step = m->step + 1;
        } else if (s == 0) {
#pragma omp parallel for schedule(static) num_threads(m->nthreads) reduction(+ : se)
            for (long p = 0; p < n; p++) {
                update_particle(m, w, p, kind, dt, vel, node, pts);
                se += pts->eint[p];
            }
        } else {
#pragma omp parallel for schedule(static) num_threads(m->nthreads)
            for (long p = 0; p < n; p++)
                update_particle(m, w, p, kind, dt, vel, node, pts);
        }
    }
    m->strain = se;
}

void mpm_update_particles(struct mpm *m, double dt)
{
    struct mpm_view views[1 + MPM_MAX_EXTRA];
    int nv = mpm_views(m, views);
    switch (mpm_stencil_kind(&m->grid)) {
    case MPM_ST_LINEAR:
        update_all(m, views, nv, dt, MPM_ST_LINEAR);
        break;
    case MPM_ST_GIMP:
        update_all(m, views, nv, dt, MPM_ST_GIMP);
        break;
    default:
        update_all(m, views, nv, dt, MPM_ST_HIER);
        break;
    }
}

/* Keys [kmin, kmax] per direction that the points of block b may map to
 * in the fused pass: the block's own and one either side. */
static void block_key_range(const struct mpm_grid *g, long b, long kmin[3], long kmax[3])
{
    for (int d = 0; d < 3; d++) {
        long bc = b % g->nb[d];
        b /= g->nb[d];
        kmin[d] = bc * g->bw[d] - 1;
        kmax[d] = (bc + 1) * g->bw[d];
    }
}

/* Whether keys key[] lie within [kmin, kmax]. */
static inline int near_block(const long key[3], const long kmin[3], const long kmax[3])
{
    int ok = 1;
    for (int d = 0; d < 3; d++)
        ok &= key[d] >= kmin[d] && key[d] <= kmax[d];
    return ok;
}

struct mpm_node *mpm_grid_next_buffer(struct mpm_grid *g)
{
    if (!g->node_next)
        g->node_next = mpm_grid_zeroed_alloc(g->node_bytes);   /* node's size: they swap */
    return g->node_next;
}

void mpm_update_particles_and_map(struct mpm *m, double dt)
{
    mpm_update_particles_and_map_cleared(m, dt, 0);
}

/* The fused pass: s7-s14 of this step for every material point and,
 * straight after, its s1-s3 contribution for the next step at its new
 * position into the grid's second buffer.  It saves a pass over the points.
 * Threads take blocks of one colour at a time as in mpm_p2g.c: blocks are
 * at least 3 cells wide across every cut and a point moves less than a cell
 * per step (the CFL limit), so blocks of one colour still share no node. */
void mpm_update_particles_and_map_cleared(struct mpm *m, double dt, int cleared)
{
    struct mpm_grid *g = &m->grid;
    struct mpm_node *next = mpm_grid_next_buffer(g);
    if (!next) {   /* no memory for a second buffer: the unfused way */
        mpm_update_particles(m, dt);
        return;
    }
    /* With timers, the mapping's part is booked as p2g.  Timing it chunk by
     * chunk takes two clock reads per 64 points (some 1.4 % of the pass on
     * the reference problem), so it is timed on every MPM_SPLIT_EVERY-th
     * step only and its share of the pass applied to the steps between. */
    const int timed = m->timers != NULL;
    const int split = timed && (m->step % MPM_SPLIT_EVERY == 0 || m->fused_map_share < 0);
    double t_clear = timed ? timers_now() : 0;
    if (!cleared)
        mpm_grid_clear_nodes(next, g->nnodes, m->nthreads);
    double t_pass = timed ? timers_now() : 0;
    double t_map = t_pass - t_clear;   /* s1-s3 of the next step: the clear, then the share */
    struct mpm_view views[1 + MPM_MAX_EXTRA];
    mpm_views(m, views);
    const struct mpm_view *w = &views[0];
    const struct mpm_node *node = g->node;
    const double *vel = m->algorithm == MPM_MUSL ? g->r : NULL;
    struct mpm_points *pts = &m->pts;
    const long s1 = g->stride[1], s2 = g->stride[2];
    struct mpm_bins *b0 = &m->bins[0];
    int32_t *blk = b0->blk;
    long off[8];
    mpm_lin_offsets(g, off);
    m->strain_before = m->strain;
    double se = 0;
    int far = 0;   /* a point moved too far for the colouring: map afresh next step */
    double t_scatter = 0;   /* summed over threads */
    long leavers = 0, outside = 0;   /* for the bricks' migration (mpm.h, own_keys) */
    const int own = m->own_keys;
    const long *olo = m->own_lo, *ohi = m->own_hi;
#pragma omp parallel num_threads(m->nthreads) reduction(+ : se, t_scatter, leavers, outside) \
    reduction(| : far)
    for (int c = 0; c < MPM_COLOURS; c++) {
        if (g->ncolour[c] == 0)
            continue;
#pragma omp for schedule(dynamic, 1)
        for (long bi = 0; bi < g->ncolour[c]; bi++) {
            long b = g->colour_block[c][bi];
            /* keys this block may map to: its own and one cell either side */
            long kmin[3], kmax[3];
            block_key_range(g, b, kmin, kmax);
            const int32_t *idx = b0->order + b0->start[b];
            long count = b0->start[b + 1] - b0->start[b];
            mpm_v4 A[8] = {{0}}, B[8] = {{0}};
            double aux[8] = {0};
            long cur = -1;
            struct mpm_chunk ch;
            struct chunk_cells cc;
            /* chunks of points: update them (s7-s14), then map them while
             * they are still in cache (s1-s3 of the next step); two light
             * loops instead of one whose registers spill */
            for (long k0 = 0; k0 < count; k0 += MPM_CHUNK) {
                long k1 = k0 + MPM_CHUNK < count ? k0 + MPM_CHUNK : count;
                if (vel)
                    update_chunk_linear(m, idx + k0, k1 - k0, dt, vel, node, s1, s2, 1, pts, blk,
                                        &ch, &cc);
                else
                    update_chunk_linear(m, idx + k0, k1 - k0, dt, vel, node, s1, s2, 0, pts, blk,
                                        &ch, &cc);
                double t0 = split ? timers_now() : 0;
                for (long k = k0; k < k1; k++) {
                    long p = idx[k];
                    se += pts->eint[p];
                    if (blk[p] < 0) {
                        outside++;
                        continue;   /* left the grid: the next step reports it */
                    }
                    const long *key = cc.key[k - k0];
                    if (own)   /* its new cell is another brick's */
                        leavers += (key[0] < olo[0]) | (key[0] >= ohi[0]) | (key[1] < olo[1]) |
                                   (key[1] >= ohi[1]) | (key[2] < olo[2]) | (key[2] >= ohi[2]);
                    if (!near_block(key, kmin, kmax)) {
                        far = 1;
                        continue;
                    }
                    struct mpm_lin st;   /* the cell kinematics found: mpm_lin_cell */
                    mpm_lin_weights(mpm_lin_base(g, key), cc.f[k - k0], &st);
                    if (st.base != cur) {
                        if (cur >= 0)
                            p2g_flush(next, cur, off, A, B, aux);
                        cur = st.base;
                        mpm_lin_prefetch(next, sizeof *next, cur, 2 * s1 + s2);
#pragma GCC unroll 8
                        for (int q = 0; q < 8; q++) {
                            A[q] = (mpm_v4){0, 0, 0, 0};
                            B[q] = (mpm_v4){0, 0, 0, 0};
                            aux[q] = 0;
                        }
                    }
                    p2g_lin_add(m, w, p, &st, 1, 1, 0, A, B, aux);   /* Eqs. (s1)-(s3a) */
                }
                if (split)
                    t_scatter += timers_now() - t0;
            }
            if (cur >= 0)
                p2g_flush(next, cur, off, A, B, aux);
        }
    }
    m->strain = se;
    m->fused_leavers = leavers;
    m->fused_outside = outside;
    if (timed) {
        t_pass = timers_now() - t_pass;
        if (split)
            m->fused_map_share = t_pass > 0 ? t_scatter / m->nthreads / t_pass : 0;
        m->fused_map_seconds = t_map + m->fused_map_share * t_pass;
    }
    b0->blk_step = m->step + 1;
    if (!far) {   /* the new mapping becomes the grid */
        g->node_next = g->node;
        g->node = next;
    }
    /* else the partial mapping is dropped; the next step maps afresh */
    m->fused_ready = !far;
    m->grid_fresh = !far;
}
