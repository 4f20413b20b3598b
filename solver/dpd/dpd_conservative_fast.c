/*
 * dpd_conservative_fast: the pair loops of the coarse-grained Sutton-Chen
 * force (dpd_conservative.c) as vector loops, for the common case -- no
 * passive partners, no per-particle energies, integer exponents (Chen
 * 2014's n = 9, m = 6).  The techniques of the EAM kernel (docs/bench.md,
 * "The kernels"):
 *   - the density pass computes the squared distances of a particle's whole
 *     list in one vector loop and gathers those inside the cutoff, in list
 *     order, into a second list (d->inner; the neighbour list itself is not
 *     reordered: the pair sweep walks it in its own order);
 *   - both passes then run `omp simd` loops over the inner pairs only (each
 *     neighbour appears once in a half list, so the scattered rho[j] and
 *     f[j] updates of one loop never collide);
 *   - the integer powers (a/r)^n, (a/r)^m are six fixed squaring steps, a
 *     vector loop's form of sc_ipow (the same products), and 1/r is taken
 *     once.
 * The sums run in vector lanes, so the forces and energies differ from the
 * scalar loops' in the last bits.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/sc_density.h"
#include "dpd/dpd_pair.h"

/* x^k for 0 < k < 64 by squaring: sc_ipow's products in a fixed number of
 * steps, so a vector loop can carry it. */
static inline double ipow6(double x, int k)
{
    double r = 1.0;
    for (int b = 0; b < 6; b++) {
        r = (k >> b) & 1 ? r * x : r;
        x *= x;
    }
    return r;
}

int dpd_conservative_fast_ok(const struct dpd *d)
{
    const struct sc_params *sc = &d->prm.sc;
    return !d->peratom && !d->passive_mask && sc->n_int > 0 && sc->m_int > 0;
}

static int reserve_inner(struct dpd *d, int nt, int *maxlen, struct err *e)
{
    const struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    long nk = nl->offset[p->n_owned];
    int ml = 1;
    for (int i = 0; i < p->n_owned; i++)
        if (nl->offset[i + 1] - nl->offset[i] > ml)
            ml = nl->offset[i + 1] - nl->offset[i];
    if (nk > d->inner_cap) {
        long cap = nk + nk / 4 + 64;
        int *q = realloc(d->inner, (size_t)cap * sizeof *q);
        if (!q)
            return err_nomem(e, "DPD inner lists");
        d->inner = q;
        d->inner_cap = cap;
    }
    if (p->n_owned + 1 > d->ninner_cap) {
        int cap = p->n_owned + p->n_owned / 4 + 64;
        int *q = realloc(d->ninner, (size_t)cap * sizeof *q);
        if (!q)
            return err_nomem(e, "DPD inner lists");
        d->ninner = q;
        d->ninner_cap = cap;
    }
    if ((long)nt * ml > d->r2buf_cap) {
        long cap = (long)nt * ml + 64;
        double *q = realloc(d->r2buf, (size_t)cap * sizeof *q);
        if (!q)
            return err_nomem(e, "DPD pair scratch");
        d->r2buf = q;
        d->r2buf_cap = cap;
    }
    *maxlen = ml;
    return 0;
}

double dpd_density_fast(struct dpd *d, int nt, struct err *e, int *rc)
{
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const struct sc_params *sc = &d->prm.sc;
    const int ntot = p->n_owned + p->n_ghost;
    int maxlen;
    if ((*rc = reserve_inner(d, nt, &maxlen, e)))
        return 0;
    const double rc2 = sc->rc * sc->rc, a = sc->a, rcut = sc->rc, rho_rc = sc->rho_rc,
                 drho_rc = sc->drho_rc;
    const int m = sc->m_int;
    const double *restrict x = p->x;
    const int *restrict off = nl->offset;
    const int *restrict neigh = nl->neigh;
    int *restrict inner = d->inner, *restrict ninner = d->ninner;
    memset(d->rho, 0, (size_t)ntot * sizeof *d->rho);
#pragma omp parallel num_threads(nt) firstprivate(rc2, a, rcut, rho_rc, drho_rc, m, x, off, neigh, inner, ninner)
    {
        int tid = omp_get_thread_num();
        double *restrict rho = thread_accum_target(&d->acc_rho, tid, d->rho, (size_t)ntot);
        double *restrict r2 = d->r2buf + (size_t)tid * maxlen;
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
            const int *restrict nbi = neigh + off[i];
            int *restrict inn = inner + off[i];
            const int len = off[i + 1] - off[i];
#pragma omp simd
            for (int k = 0; k < len; k++) {
                int j = nbi[k];
                double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
                r2[k] = dx * dx + dy * dy + dz * dz;
            }
            int nin = 0;
            for (int k = 0; k < len; k++) {
                inn[nin] = nbi[k];
                r2[nin] = r2[k];
                nin += r2[k] < rc2;   /* a NaN distance counts as outside */
            }
            ninner[i] = nin;
            double rhoi = 0;
#pragma omp simd reduction(+ : rhoi)
            for (int q = 0; q < nin; q++) {
                double r = sqrt(r2[q]), inv_r = 1.0 / r;
                double rr = ipow6(a * inv_r, m) - rho_rc - (r - rcut) * drho_rc;
                rhoi += rr;
                rho[inn[q]] += rr;
            }
            rho[i] += rhoi;
        }
    }
    return sc_density_finish(sc, p, nl, &d->acc_rho, d->rho, d->fp, NULL);
}

void dpd_force_fast(struct dpd *d, int nt, double *epot, double virial[6])
{
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const struct sc_params *sc = &d->prm.sc;
    const int ntot = p->n_owned + p->n_ghost;
    const double a = sc->a, rcut = sc->rc, eps = sc->eps, v_rc = sc->v_rc, dv_rc = sc->dv_rc,
                 drho_rc = sc->drho_rc, nexp = sc->n, mexp = sc->m;
    const int n = sc->n_int, m = sc->m_int;
    const double *restrict x = p->x;
    const double *restrict fp = d->fp;
    const int *restrict off = nl->offset;
    const int *restrict inner = d->inner, *restrict ninner = d->ninner;
    double esum[THREAD_ACCUM_MAX] = {0}, wsum[THREAD_ACCUM_MAX][6];
    memset(wsum, 0, sizeof wsum);
#pragma omp parallel num_threads(nt) firstprivate(a, rcut, eps, v_rc, dv_rc, drho_rc, nexp, mexp, n, m, x, fp, off, inner, ninner)
    {
        int tid = omp_get_thread_num();
        double *restrict f = thread_accum_target(&d->acc_f, tid, p->f, (size_t)3 * ntot);
        double es = 0, w0 = 0, w1 = 0, w2 = 0, w3 = 0, w4 = 0, w5 = 0;
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
            const double fpi = fp[i];
            const int *restrict inn = inner + off[i];
            const int nin = ninner[i];
            double fxi = 0, fyi = 0, fzi = 0;
#pragma omp simd reduction(+ : fxi, fyi, fzi, es, w0, w1, w2, w3, w4, w5)
            for (int q = 0; q < nin; q++) {
                int j = inn[q];
                double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
                double r = sqrt(dx * dx + dy * dy + dz * dz), inv_r = 1.0 / r;
                double s = a * inv_r, vn = ipow6(s, n), vm = ipow6(s, m);
                double v = vn - v_rc - (r - rcut) * dv_rc;
                double dv = -nexp * inv_r * vn - dv_rc;
                double drr = -mexp * inv_r * vm - drho_rc;
                double fpair = -(eps * dv + (fpi + fp[j]) * drr) * inv_r;
                double fx = dx * fpair, fy = dy * fpair, fz = dz * fpair;
                fxi += fx;
                fyi += fy;
                fzi += fz;
                f[3 * j] -= fx;
                f[3 * j + 1] -= fy;
                f[3 * j + 2] -= fz;
                es += eps * v;
                w0 += dx * fx;
                w1 += dy * fy;
                w2 += dz * fz;
                w3 += dx * fy;
                w4 += dx * fz;
                w5 += dy * fz;
            }
            f[3 * i] += fxi;
            f[3 * i + 1] += fyi;
            f[3 * i + 2] += fzi;
        }
        esum[tid] = es;
        wsum[tid][0] = w0;
        wsum[tid][1] = w1;
        wsum[tid][2] = w2;
        wsum[tid][3] = w3;
        wsum[tid][4] = w4;
        wsum[tid][5] = w5;
    }
    *epot = 0;
    memset(virial, 0, 6 * sizeof *virial);
    for (int t = 0; t < nt; t++) {
        *epot += esum[t];
        for (int c = 0; c < 6; c++)
            virial[c] += wsum[t][c];
    }
}
