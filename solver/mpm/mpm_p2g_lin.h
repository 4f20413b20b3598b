/*
 * mpm_p2g_lin: internal to solver/mpm -- the particle-to-grid contribution
 * of one particle on the linear fast path (Chen 2014, Eqs. (s1)-(s3)),
 * summed into per-cell registers A (mass, momentum) and B (force) of the
 * 8 nodes, and the flush of such a run into the nodes.  Shared by the
 * mapping stage (mpm_p2g.c) and the fused update-and-map pass (mpm_fused.c).
 */
#ifndef CASCADE_MPM_P2G_LIN_H
#define CASCADE_MPM_P2G_LIN_H

#include "mpm/mpm_linear.h"
#include "mpm/mpm_view.h"

static inline void p2g_flush(struct mpm_node *node, long cur, const long off[8],
                             const mpm_v4 A[8], const mpm_v4 B[8], const double aux[8])
{
#pragma GCC unroll 8
    for (int q = 0; q < 8; q++) {
        struct mpm_node *nd = &node[cur + off[q]];
        *(mpm_v4 *)&nd->m += A[q];
        *(mpm_v4 *)&nd->f[0] += B[q];
        if (aux[q] > 0)
            nd->aux = aux[q];
    }
}

static inline __attribute__((always_inline)) void
p2g_lin_add(const struct mpm *m, const struct mpm_view *w, long p, const struct mpm_lin *stp,
            int mm, int hs, int hf, mpm_v4 A[8], mpm_v4 B[8], double aux[8])
{
    const struct mpm_lin st = *stp;
    const double ihx = m->grid.inv_hd[0], ihy = m->grid.inv_hd[1], ihz = m->grid.inv_hd[2];
    double M = mpm_view_mass(w, p);
    const double *v = w->v + 3 * p;
    mpm_v4 z = {0, 0, 0, 0};
    mpm_v4 mq = mm ? mpm_v4_set(M, M * v[0], M * v[1], M * v[2]) : z;
    mpm_v4 s0 = z, s1 = z, s2 = z, fe = z;
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
#pragma GCC unroll 4
    for (int bc = 0; bc < 4; bc++) {
        int bb = bc & 1, cc = bc >> 1;
        double t = st.t[bc];
        /* Eqs. (s1), (s2): N_q [M, M v] with N_q = wx[a] t[bc] */
        A[2 * bc] += (st.wx[0] * t) * mq;
        A[2 * bc + 1] += (st.wx[1] * t) * mq;
        /* Eq. (s3a): -G_q . (V sigma) = -(dx[a] t s0 + wx[a] (dy[b] wz[c] s1 + wy[b] dz[c] s2)) */
        mpm_v4 U = (ihx * t) * s0;
        mpm_v4 W = (ihy * (bb ? st.wz[cc] : -st.wz[cc])) * s1 +
                   (ihz * (cc ? st.wy[bb] : -st.wy[bb])) * s2;
        B[2 * bc] += U - st.wx[0] * W;
        B[2 * bc + 1] += -U - st.wx[1] * W;
        if (hf) {   /* Eq. (s3b): f_p N_q */
            B[2 * bc] += (st.wx[0] * t) * fe;
            B[2 * bc + 1] += (st.wx[1] * t) * fe;
        }
    }
    if (mm && w->body && m->body[w->body[p]].rigid) {
        double ax = (double)(w->body[p] + 1);
        for (int q = 0; q < 8; q++)
            if (st.wx[q & 1] * st.t[q >> 1] > 0)
                aux[q] = ax;
    }
}

#endif
