/*
 * lj: Lennard-Jones 12-6, cut and shifted so the energy is continuous at the
 * cutoff:  E(r) = 4 eps [(s/r)^12 - (s/r)^6] - E_LJ(rc)  for r < rc.
 *
 * Case keys: elements (list), epsilon (eV), sigma (Å), cutoff (Å, default
 * 2.5 sigma), masses (amu, default: standard atomic masses).  With several
 * elements, epsilon and sigma are lists and pairs mix by Lorentz-Berthelot.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "md/potential.h"
#include "md/potential_common.h"
#include "core/thread_accum.h"

struct lj {
    struct potential base;
    double eps[PARTICLES_MAX_TYPES][PARTICLES_MAX_TYPES];
    double sig[PARTICLES_MAX_TYPES][PARTICLES_MAX_TYPES];
    double shift[PARTICLES_MAX_TYPES][PARTICLES_MAX_TYPES];
    struct pair_scratch scratch;
};

static int lj_compute(struct potential *pot, struct particles *p, const struct nlist *nl, int flags,
                      struct force_result *out, struct err *e)
{
    struct lj *lj = (struct lj *)pot;
    int nt = pot->nthreads;
    int rc = pair_scratch_begin(&lj->scratch, p, flags, nt, e);
    if (rc)
        return rc;
    const double rc2 = pot->cutoff * pot->cutoff;
    const int *tmap = pot->type_map;
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&lj->scratch, p, tid);
        double esum = 0, w[6] = {0};
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            int ti = tmap[p->type[i]];
            double fxi = 0, fyi = 0, fzi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= rc2)
                    continue;
                int tj = tmap[p->type[j]];
                double s2 = lj->sig[ti][tj] * lj->sig[ti][tj] / r2;
                double s6 = s2 * s2 * s2;
                double eps4 = 4.0 * lj->eps[ti][tj];
                /* fpair = -(dE/dr)/r, force on i = fpair * (xi - xj) */
                double fpair = eps4 * (12.0 * s6 * s6 - 6.0 * s6) / r2;
                double epair = eps4 * (s6 * s6 - s6) - lj->shift[ti][tj];
                fxi += dx * fpair;
                fyi += dy * fpair;
                fzi += dz * fpair;
                t.f[3 * j] -= dx * fpair;
                t.f[3 * j + 1] -= dy * fpair;
                t.f[3 * j + 2] -= dz * fpair;
                esum += epair;
                pair_tally_virial(w, dx, dy, dz, fpair);
                if (t.pe)
                    pair_tally_peratom(&t, i, j, epair, dx, dy, dz, fpair);
            }
            t.f[3 * i] += fxi;
            t.f[3 * i + 1] += fyi;
            t.f[3 * i + 2] += fzi;
        }
        pair_scratch_store_sums(&lj->scratch, tid, esum, w);
    }
    pair_scratch_end(&lj->scratch, p, out);
    return 0;
}

static void lj_destroy(struct potential *pot)
{
    struct lj *lj = (struct lj *)pot;
    pair_scratch_free(&lj->scratch);
    free(lj);
}

static const struct potential_ops lj_ops = {"lj", lj_compute, lj_destroy};

int lj_create(struct cfg_obj *o, struct potential **out)
{
    struct lj *lj = calloc(1, sizeof *lj);
    if (!lj)
        return err_nomem(o->cfg->err, "lj");
    lj->base.ops = &lj_ops;
    lj->base.list_kind = NLIST_HALF;
    int rc = potential_read_elements(o, &lj->base);
    double *eps = NULL, *sig = NULL;
    size_t neps = 0, nsig = 0;
    if (!rc)
        rc = cfg_real_list(o, "epsilon", 1, CFG_GT(0), &eps, &neps);
    if (!rc)
        rc = cfg_real_list(o, "sigma", 1, CFG_GT(0), &sig, &nsig);
    int ne = lj->base.nelements;
    if (!rc && ((int)neps != ne || (int)nsig != ne))
        rc = cfg_error_at(o->cfg, o->path,
                          "epsilon and sigma need one value per element (%d elements, got %zu "
                          "and %zu)",
                          ne, neps, nsig);
    double smax = 0;
    for (int a = 0; !rc && a < ne; a++)
        for (int b = 0; b < ne; b++) {
            lj->eps[a][b] = sqrt(eps[a] * eps[b]);
            lj->sig[a][b] = 0.5 * (sig[a] + sig[b]);
            if (lj->sig[a][b] > smax)
                smax = lj->sig[a][b];
        }
    free(eps);
    free(sig);
    if (!rc)
        rc = cfg_real(o, "cutoff", 2.5 * smax, CFG_GT(0), &lj->base.cutoff);
    if (rc) {
        free(lj);
        return rc;
    }
    double rc2 = lj->base.cutoff * lj->base.cutoff;
    for (int a = 0; a < ne; a++)
        for (int b = 0; b < ne; b++) {
            double s6 = pow(lj->sig[a][b] * lj->sig[a][b] / rc2, 3);
            lj->shift[a][b] = 4.0 * lj->eps[a][b] * (s6 * s6 - s6);
        }
    snprintf(lj->base.description, sizeof lj->base.description,
             "Lennard-Jones 12-6, cut and shifted at %g Å", lj->base.cutoff);
    *out = &lj->base;
    return 0;
}
