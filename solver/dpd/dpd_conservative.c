/*
 * dpd_conservative: the coarse-grained Sutton-Chen force (Chen 2014,
 * Eq. (2.3)) with its many-body density term, on a half list with ghosts:
 *   pass 1  rho_i and F'(rho_i) (core/sc_density.h, shared with the
 *           atomistic Sutton-Chen potential);
 *   pass 2  f_i = -sum_j [eps V'(r) + (F'(rho_i) + F'(rho_j)) rho'(r)] e_ij.
 * Threads accumulate into private buffers summed in thread order
 * (core/thread_accum.h), so a thread count always gives the same sums.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "core/halo.h"
#include "core/sc_density.h"
#include "dpd/dpd_pair.h"

static int reserve(struct dpd *d, int ntot, int nt, struct err *e)
{
    if (ntot > d->cap) {
        int cap = ntot + ntot / 4 + 64;
        double *r = realloc(d->rho, (size_t)cap * sizeof *r);
        if (r)
            d->rho = r;
        double *f = realloc(d->fp, (size_t)cap * sizeof *f);
        if (f)
            d->fp = f;
        if (!r || !f)
            return err_nomem(e, "DPD densities");
        d->cap = cap;
    }
    int rc = thread_accum_reserve(&d->acc_rho, nt, (size_t)ntot, e);
    if (!rc)
        rc = thread_accum_reserve(&d->acc_f, nt, (size_t)3 * ntot, e);
    if (!rc && d->peratom)
        rc = thread_accum_reserve(&d->acc_pe, nt, (size_t)ntot, e);
    if (!rc && d->peratom)
        rc = thread_accum_reserve(&d->acc_vir, nt, (size_t)6 * ntot, e);
    return rc;
}

/* On bricks, this brick's energy and virial -> the totals. */
static int totals(struct dpd *d)
{
    if (d->p->halo) {
        double ev[7] = {d->epot, d->virial[0], d->virial[1], d->virial[2],
                        d->virial[3], d->virial[4], d->virial[5]};
        halo_sum(d->p->halo, ev, 7);
        d->epot = ev[0];
        memcpy(d->virial, ev + 1, sizeof d->virial);
    }
    return 0;
}

int dpd_conservative(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const struct sc_params *sc = &d->prm.sc;
    const int nt = d->nthreads < 1 ? 1 : d->nthreads;
    const int ntot = p->n_owned + p->n_ghost;
    const int peratom = d->peratom;
    int rc = reserve(d, ntot, nt, e);
    if (rc)
        return rc;
    const double rc2 = sc->rc * sc->rc;
    memset(p->f, 0, (size_t)3 * ntot * sizeof(double));
    if (peratom) {
        memset(p->pe, 0, (size_t)ntot * sizeof(double));
        memset(p->virial, 0, (size_t)6 * ntot * sizeof(double));
    }
    if (dpd_conservative_fast_ok(d)) {
        double embed = dpd_density_fast(d, nt, e, &rc), es, w[6];
        if (rc)
            return rc;
        dpd_force_fast(d, nt, &es, w);
        thread_accum_reduce(&d->acc_f, p->f, (size_t)3 * ntot);
        ghost_reverse_add(p, p->f, 3);
        d->epot = embed + es;
        memcpy(d->virial, w, sizeof d->virial);
        return totals(d);
    }
    /* pass 1 */
    double embed = sc_density_embed(sc, p, nl, &d->acc_rho, nt, d->rho, d->fp,
                                    peratom ? p->pe : NULL);
    /* a passive partner's embedding energy belongs to its own model: out of
     * the DPD energy (its F' still acts in the pairs with DPD particles) */
    const uint32_t pm = d->passive_mask;
    for (int i = 0; pm && i < p->n_owned; i++) {
        if (i < nl->ilo || i >= nl->ihi || !(p->mask[i] & pm))
            continue;
        double F, dF;
        sc_embed(sc, d->rho[i], &F, &dF);
        embed -= F;
        if (peratom)
            p->pe[i] = 0;
    }
    /* Frozen partner embedding.  A partner's density counts its partner
     * neighbours too, so a live F'(rho_P) changes with partner-partner
     * distances, whose forces are the MPM model's and not applied here: the
     * D-P pair forces are then not the gradient of any energy, and the
     * concurrent impact gained or lost 19 % of its impact energy.  With
     * F'(rho_P) fixed at its value in the starting configuration the D-P
     * term F'_P rho(r) is a pair potential, the interface forces are
     * conservative, and its energy is counted in the pair loop below.  The
     * partners sit in the elastic MPM region, where rho_P stays near its
     * start value, so the change to the force is second order in the
     * density change. */
    const int freeze = pm && d->freeze_passive_fp;
    if (freeze && p->halo) {
        /* Bricks: the partners migrate between ranks and change index, so
         * the frozen F'(rho_P) travels with them as a particle field
         * (DPD_FP_FROZEN_FIELD), taken at the same first evaluation. */
        int k = particles_find_field(p, DPD_FP_FROZEN_FIELD);
        if (k < 0) {
            if ((k = particles_add_field(p, DPD_FP_FROZEN_FIELD, 1, 0, e)) < 0)
                return ERR_RUNTIME;
            memcpy(particles_field(p, k), d->fp, (size_t)p->n_owned * sizeof *d->fp);
        }
        const double *fz = particles_field(p, k);
        for (int i = 0; i < p->n_owned; i++)
            if (p->mask[i] & pm)
                d->fp[i] = fz[i];
        ghost_forward(p, d->fp, 1);
    } else if (freeze) {
        if (!d->fp_frozen) {
            d->n_frozen = p->n_owned;
            d->fp_frozen = malloc((size_t)(d->n_frozen ? d->n_frozen : 1) * sizeof *d->fp_frozen);
            if (!d->fp_frozen)
                return err_nomem(e, "frozen partner embedding");
            memcpy(d->fp_frozen, d->fp, (size_t)d->n_frozen * sizeof *d->fp_frozen);
        }
        if (p->n_owned != d->n_frozen)
            return err_set(e, ERR_RUNTIME, "DPD/MPM: %d particles, %d when the partner "
                           "embedding was frozen", p->n_owned, d->n_frozen);
        for (int i = 0; i < p->n_owned; i++)
            if (p->mask[i] & pm)
                d->fp[i] = d->fp_frozen[i];
        ghost_forward(p, d->fp, 1);
    }

    double esum[THREAD_ACCUM_MAX] = {0}, wsum[THREAD_ACCUM_MAX][6];
    memset(wsum, 0, sizeof wsum);
    const double *fp = d->fp;
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        double *f = thread_accum_target(&d->acc_f, tid, p->f, (size_t)3 * ntot);
        double *pe = peratom ? thread_accum_target(&d->acc_pe, tid, p->pe, (size_t)ntot) : NULL;
        double *vir = peratom ? thread_accum_target(&d->acc_vir, tid, p->virial, (size_t)6 * ntot)
                              : NULL;
        double es = 0, w[6] = {0};
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            const int passive_i = pm && (p->mask[i] & pm);
            double fxi = 0, fyi = 0, fzi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= rc2 || (passive_i && (p->mask[j] & pm)))
                    continue;
                double r = sqrt(r2), v, dv, rr, drr;
                sc_pair_terms(sc, r, &v, &dv, &rr, &drr);
                double epair = sc->eps * v;
                if (freeze && (passive_i || (p->mask[j] & pm)))   /* F'_P rho(r) */
                    epair += (passive_i ? fp[i] : fp[j]) * rr;
                double fpair = -(sc->eps * dv + (fp[i] + fp[j]) * drr) / r;
                fxi += dx * fpair;
                fyi += dy * fpair;
                fzi += dz * fpair;
                f[3 * j] -= dx * fpair;
                f[3 * j + 1] -= dy * fpair;
                f[3 * j + 2] -= dz * fpair;
                es += epair;
                double pv[6] = {dx * dx * fpair, dy * dy * fpair, dz * dz * fpair,
                                dx * dy * fpair, dx * dz * fpair, dy * dz * fpair};
                for (int c = 0; c < 6; c++)
                    w[c] += pv[c];
                if (peratom) {
                    pe[i] += 0.5 * epair;
                    pe[j] += 0.5 * epair;
                    for (int c = 0; c < 6; c++) {
                        vir[6 * i + c] += 0.5 * pv[c];
                        vir[6 * j + c] += 0.5 * pv[c];
                    }
                }
            }
            f[3 * i] += fxi;
            f[3 * i + 1] += fyi;
            f[3 * i + 2] += fzi;
        }
        esum[tid] = es;
        for (int c = 0; c < 6; c++)
            wsum[tid][c] = w[c];
    }
    thread_accum_reduce(&d->acc_f, p->f, (size_t)3 * ntot);
    ghost_reverse_add(p, p->f, 3);
    if (peratom) {
        thread_accum_reduce(&d->acc_pe, p->pe, (size_t)ntot);
        thread_accum_reduce(&d->acc_vir, p->virial, (size_t)6 * ntot);
        ghost_reverse_add(p, p->pe, 1);
        ghost_reverse_add(p, p->virial, 6);
    }
    d->epot = embed;
    memset(d->virial, 0, sizeof d->virial);
    for (int t = 0; t < nt; t++) {
        d->epot += esum[t];
        for (int c = 0; c < 6; c++)
            d->virial[c] += wsum[t][c];
    }
    return totals(d);
}
