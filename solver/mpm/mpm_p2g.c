/*
 * mpm_p2g: particle-to-grid mapping, Chen 2014 steps s1-s3 (Guo & Yang
 * 2005, Eqs. (5) and (7)):
 *
 *   m_i   += M_p N_i(x_p)                         (s1)
 *   q_i   += M_p v_p N_i(x_p)                     (s2)
 *   f_i   -= V_p sigma_p . G_i(x_p)               (s3a, V_p = M_p / rho_p)
 *   f_i   += f_p N_i(x_p)                         (s3b, per-particle forces)
 *
 * Threads take blocks of one colour at a time; blocks of a colour share no
 * node, so the scatters need no atomics and every node receives its
 * contributions in the same order for any thread count.
 */
#pragma GCC optimize("fp-contract=fast")   /* multiply-adds in the hot loops */
#include <string.h>

#include "mpm/mpm_p2g_lin.h"
#include "mpm/mpm_view.h"

void mpm_clear_grid(struct mpm *m)
{
    mpm_grid_clear(&m->grid, m->nthreads);
}

static inline __attribute__((always_inline)) void
p2g_particle(const struct mpm *m, const struct mpm_view *w, long p, const int kind, unsigned what,
             struct mpm_node *node)
{
    struct mpm_stencil st;
    mpm_stencil_at(m, w, p, kind, &st);
    double M = mpm_view_mass(w, p);
    const double *v = w->v + 3 * p;
    int mm = (what & MPM_MAP_MASS_MOMENTUM) != 0;
    int hs = (what & MPM_MAP_STRESS) && w->stress;
    int hf = (what & MPM_MAP_FORCE) && w->force;
    /* [M, M v] for s1-s2; the rows of V sigma for s3a; the force for s3b */
    const mpm_v4 mq = mpm_v4_set(M, M * v[0], M * v[1], M * v[2]);
    mpm_v4 s0 = {0, 0, 0, 0}, s1 = s0, s2 = s0, fe = s0;
    if (hs) {
        const double *s = w->stress + 6 * p;
        double V = w->vol[p];
        s0 = mpm_v4_set(V * s[0], V * s[3], V * s[4], 0);
        s1 = mpm_v4_set(V * s[3], V * s[1], V * s[5], 0);
        s2 = mpm_v4_set(V * s[4], V * s[5], V * s[2], 0);
    }
    if (hf) {
        const double *f = w->force + 3 * p;
        fe = mpm_v4_set(w->fscale * f[0], w->fscale * f[1], w->fscale * f[2], 0);
    }
    double aux = 0;
    if (mm && w->body && m->body[w->body[p]].rigid)
        aux = (double)(w->body[p] + 1);
    int hfor = hs || hf;
    for (int k = 0; k < st.n; k++) {
        struct mpm_node *nd = &node[st.node[k]];
        mpm_v4 *a = (mpm_v4 *)&nd->m, *b = (mpm_v4 *)&nd->f[0];
        double N = st.w[k];
        if (mm) {
            *a += N * mq;                        /* Chen 2014, Eqs. (s1), (s2) */
            if (aux > 0 && N > 0)
                nd->aux = aux;
        }
        if (hfor)                                /* Eq. (s3b) f_p N_i, Eq. (s3a) -G_i . sigma V */
            *b += N * fe - (st.gx[k] * s0 + st.gy[k] * s1 + st.gz[k] * s2);
    }
}

/* Linear shape functions on a uniform grid: points of one cell follow each
 * other in a block (they are created and sorted that way), so their
 * contributions are summed in registers and added to the 8 nodes once per
 * run of points in the same cell. */
static void p2g_linear_block(const struct mpm *m, const struct mpm_view *w, const int32_t *idx,
                             long count, unsigned what, struct mpm_node *node, const long off[8])
{
    const struct mpm_grid *g = &m->grid;
    int mm = (what & MPM_MAP_MASS_MOMENTUM) != 0;
    int hs = (what & MPM_MAP_STRESS) && w->stress;
    int hf = (what & MPM_MAP_FORCE) && w->force;
    mpm_v4 A[8] = {{0}}, B[8] = {{0}};
    double aux[8] = {0};
    long cur = -1;
    for (long k = 0; k < count; k++) {
        long p = idx[k];
        struct mpm_lin st;
        mpm_lin_eval(g, w->x + 3 * p, &st);
        if (st.base != cur) {   /* a new cell: flush the run into its nodes */
            if (cur >= 0)
                p2g_flush(node, cur, off, A, B, aux);
            cur = st.base;
            mpm_lin_prefetch(node, sizeof *node, cur, 2 * off[2] + off[4]);
#pragma GCC unroll 8
            for (int q = 0; q < 8; q++) {
                A[q] = (mpm_v4){0, 0, 0, 0};
                B[q] = (mpm_v4){0, 0, 0, 0};
                aux[q] = 0;
            }
        }
        p2g_lin_add(m, w, p, &st, mm, hs, hf, A, B, aux);
    }
    if (cur >= 0)
        p2g_flush(node, cur, off, A, B, aux);
}

static inline __attribute__((always_inline)) void
p2g_all(struct mpm *m, const struct mpm_view *views, int nv, unsigned what, const int kind)
{
    const struct mpm_grid *g = &m->grid;
    struct mpm_node *node = m->grid.node;
    long off[8];
    mpm_lin_offsets(g, off);
#pragma omp parallel num_threads(m->nthreads)
    for (int c = 0; c < MPM_COLOURS; c++) {
        if (g->ncolour[c] == 0)
            continue;   /* the same for every thread: no barrier skipped unevenly */
#pragma omp for schedule(dynamic, 1)
        for (long bi = 0; bi < g->ncolour[c]; bi++) {
            long b = g->colour_block[c][bi];
            for (int s = 0; s < nv; s++) {
                const struct mpm_bins *bn = views[s].bins;
                if (kind == MPM_ST_LINEAR) {
                    p2g_linear_block(m, &views[s], bn->order + bn->start[b],
                                     bn->start[b + 1] - bn->start[b], what, node, off);
                    continue;
                }
                for (long k = bn->start[b]; k < bn->start[b + 1]; k++)
                    p2g_particle(m, &views[s], bn->order[k], kind, what, node);
            }
        }
    }
}

void mpm_map_to_grid(struct mpm *m, unsigned what)
{
    struct mpm_view views[1 + MPM_MAX_EXTRA];
    int nv = mpm_views(m, views);
    switch (mpm_stencil_kind(&m->grid)) {
    case MPM_ST_LINEAR:
        p2g_all(m, views, nv, what, MPM_ST_LINEAR);
        break;
    case MPM_ST_GIMP:
        p2g_all(m, views, nv, what, MPM_ST_GIMP);
        break;
    default:
        p2g_all(m, views, nv, what, MPM_ST_HIER);
        break;
    }
}
