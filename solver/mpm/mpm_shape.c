/*
 * mpm_shape: shape functions on the cells of a hierarchical grid.
 *
 * A cell has up to 27 candidate nodes: 8 corners, 12 edge midpoints, 6 face
 * centres (the interior centre never exists).  In each direction the 1-D
 * functions are b0 = 1 - t, b2 = t and the midpoint bubble b1; a candidate's
 * product function B = b_a(t_x) b_b(t_y) b_c(t_z) is its hierarchical basis
 * function.  Interpolating by hierarchical surpluses and collecting the
 * coefficients of the nodal values gives the nodal shape functions
 *
 *   face centre f:    N_f = B_f
 *   edge midpoint e:  N_e = B_e - 1/2 sum_{faces f on e} B_f
 *   corner c:         N_c = B_c - 1/2 sum_{edges e at c} B_e + 1/4 sum_{faces f at c} B_f
 *
 * (sums over present nodes; a present face centre has its four edge
 * midpoints, which the 2:1 grid guarantees).  With the bubble
 * b1 = 1 - (2t - 1)^2 these are the standard transition-element functions
 * of Guo & Yang 2005, Eq. (9); with b1 = 1 - |2t - 1| they are the modified
 * functions of Eq. (11), linear on each half of the cell, for which a
 * uniform stress gives zero force on every hanging node.
 */
#include "mpm/mpm_shape.h"

/* The 8 corners among the candidates a + 3b + 9c (a, b, c in {0, 2}), in
 * increasing order; the 19 others have some coordinate 1 (a midpoint). */
static const int hier_corner[8] = {0, 2, 6, 8, 18, 20, 24, 26};
/* 2^-k for cell sizes of 2^k finest cells (k <= MPM_MAX_LEVELS) */
static const double inv_pow2[8] = {1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625, 0.0078125};

void mpm_stencil_hier(const struct mpm_grid *g, long c, const double *x, struct mpm_stencil *s)
{
    const struct mpm_hgrid *hg = g->hg;
    /* the node table, made by the locate step, with the cell's geometry */
    const int32_t *node = mpm_hgrid_cell_nodes(hg, c);
    const int32_t *lo = node + MPM_HCELL_LO;
    const uint32_t lgs = (uint32_t)node[MPM_HCELL_LG];
    int standard = hg->hanging == MPM_HANGING_STANDARD;
    double b[3][3], db[3][3];
    for (int d = 0; d < 3; d++) {
        /* 1 / size: sizes are powers of two, so the product is the quotient,
         * bit for bit, without a division */
        double isize = inv_pow2[(lgs >> (8 * d)) & 7];
        double inv = g->inv_hd[d] * isize;   /* d t / d x */
        double t = ((x[d] - g->origin[d]) * g->inv_hd[d] - (double)lo[d]) * isize;
        double xi = 2.0 * t - 1.0;
        b[d][0] = 1.0 - t;
        db[d][0] = -inv;
        b[d][2] = t;
        db[d][2] = inv;
        if (standard) {
            b[d][1] = 1.0 - xi * xi;            /* Guo & Yang 2005, Eq. (9) */
            db[d][1] = -4.0 * xi * inv;
        } else {
            b[d][1] = 1.0 - fabs(xi);           /* Guo & Yang 2005, Eq. (11) */
            db[d][1] = (xi < 0 ? 2.0 : -2.0) * inv;
        }
    }
    /* Most cells of a graded grid have no hanging node: their functions are
     * the trilinear products of the corners, which the general path below
     * leaves untouched (it only moves surplus weight from midpoint nodes).
     * Same products, same order of the nodes, so the same bits. */
    int present = 0;   /* the 8 corners always are: more is a hanging node */
    for (int q = 0; q < 27; q++)
        present += node[q] >= 0;
    if (present == 8) {
        for (int k = 0; k < 8; k++) {
            int q = hier_corner[k];
            int a0 = q % 3, a1 = (q / 3) % 3, a2 = q / 9;
            s->node[k] = node[q];
            s->w[k] = b[0][a0] * b[1][a1] * b[2][a2];
            s->gx[k] = db[0][a0] * b[1][a1] * b[2][a2];
            s->gy[k] = b[0][a0] * db[1][a1] * b[2][a2];
            s->gz[k] = b[0][a0] * b[1][a1] * db[2][a2];
        }
        s->n = 8;
        return;
    }
    double N[27], Gx[27], Gy[27], Gz[27];
    for (int q = 0; q < 27; q++) {
        if (node[q] < 0)
            continue;
        int a0 = q % 3, a1 = (q / 3) % 3, a2 = q / 9;
        N[q] = b[0][a0] * b[1][a1] * b[2][a2];
        Gx[q] = db[0][a0] * b[1][a1] * b[2][a2];
        Gy[q] = b[0][a0] * db[1][a1] * b[2][a2];
        Gz[q] = b[0][a0] * b[1][a1] * db[2][a2];
    }
    /* copy the hierarchical functions, then move surplus weight down */
    double Bn[27], Bx[27], By[27], Bz[27];
    for (int q = 0; q < 27; q++)
        if (node[q] >= 0) {
            Bn[q] = N[q];
            Bx[q] = Gx[q];
            By[q] = Gy[q];
            Bz[q] = Gz[q];
        }
    for (int q = 0; q < 27; q++) {
        if (node[q] < 0)
            continue;
        int ab[3] = {q % 3, (q / 3) % 3, q / 9};
        int nmid = (ab[0] == 1) + (ab[1] == 1) + (ab[2] == 1);
        if (nmid == 1) {
            /* edge midpoint: its two ends lose half of B_e */
            int d = ab[0] == 1 ? 0 : ab[1] == 1 ? 1 : 2;
            for (int end = 0; end <= 2; end += 2) {
                int e[3] = {ab[0], ab[1], ab[2]};
                e[d] = end;
                int k = e[0] + 3 * e[1] + 9 * e[2];
                N[k] -= 0.5 * Bn[q];
                Gx[k] -= 0.5 * Bx[q];
                Gy[k] -= 0.5 * By[q];
                Gz[k] -= 0.5 * Bz[q];
            }
        } else if (nmid == 2) {
            /* face centre: its four edge midpoints lose half, its four
             * corners gain a quarter of B_f */
            int d1 = -1, d2 = -1;
            for (int d = 0; d < 3; d++)
                if (ab[d] == 1) {
                    if (d1 < 0)
                        d1 = d;
                    else
                        d2 = d;
                }
            for (int u = 0; u <= 2; u += 2) {
                int e1[3] = {ab[0], ab[1], ab[2]}, e2[3] = {ab[0], ab[1], ab[2]};
                e1[d1] = u;
                e2[d2] = u;
                int k1 = e1[0] + 3 * e1[1] + 9 * e1[2], k2 = e2[0] + 3 * e2[1] + 9 * e2[2];
                N[k1] -= 0.5 * Bn[q];
                Gx[k1] -= 0.5 * Bx[q];
                Gy[k1] -= 0.5 * By[q];
                Gz[k1] -= 0.5 * Bz[q];
                N[k2] -= 0.5 * Bn[q];
                Gx[k2] -= 0.5 * Bx[q];
                Gy[k2] -= 0.5 * By[q];
                Gz[k2] -= 0.5 * Bz[q];
                for (int v = 0; v <= 2; v += 2) {
                    int cc[3] = {ab[0], ab[1], ab[2]};
                    cc[d1] = u;
                    cc[d2] = v;
                    int k = cc[0] + 3 * cc[1] + 9 * cc[2];
                    N[k] += 0.25 * Bn[q];
                    Gx[k] += 0.25 * Bx[q];
                    Gy[k] += 0.25 * By[q];
                    Gz[k] += 0.25 * Bz[q];
                }
            }
        }
    }
    int n = 0;
    for (int q = 0; q < 27; q++) {
        if (node[q] < 0)
            continue;
        s->node[n] = node[q];
        s->w[n] = N[q];
        s->gx[n] = Gx[q];
        s->gy[n] = Gy[q];
        s->gz[n] = Gz[q];
        n++;
    }
    s->n = n;
}
