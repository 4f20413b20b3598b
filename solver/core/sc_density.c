/* sc_density: the Sutton-Chen density pass (see sc_density.h). */
#include "core/sc_density.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#include "core/ghost.h"

double sc_density_embed(const struct sc_params *sc, struct particles *p, const struct nlist *nl,
                        struct thread_accum *acc, int nthreads, double *rho, double *fp,
                        double *pe)
{
    const int ntot = p->n_owned + p->n_ghost;
    const double rc2 = sc->rc * sc->rc;
    memset(rho, 0, (size_t)ntot * sizeof *rho);
#pragma omp parallel num_threads(nthreads)
    {
        int tid = omp_get_thread_num();
        double *r = thread_accum_target(acc, tid, rho, (size_t)ntot);
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            double rhoi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= rc2)
                    continue;
                double v, dv, rr, drr;
                sc_pair_terms(sc, sqrt(r2), &v, &dv, &rr, &drr);
                rhoi += rr;
                r[j] += rr;
            }
            r[i] += rhoi;
        }
    }
    return sc_density_finish(sc, p, nl, acc, rho, fp, pe);
}

double sc_density_finish(const struct sc_params *sc, struct particles *p, const struct nlist *nl,
                         struct thread_accum *acc, double *rho, double *fp, double *pe)
{
    const int ntot = p->n_owned + p->n_ghost;
    thread_accum_reduce(acc, rho, (size_t)ntot);
    ghost_reverse_add(p, rho, 1);

    double embed = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double F;
        sc_embed(sc, rho[i], &F, &fp[i]);
        /* every rank needs every F'(rho); the energy belongs to one slice */
        if (i < nl->ilo || i >= nl->ihi)
            continue;
        embed += F;
        if (pe)
            pe[i] = F;
    }
    ghost_forward(p, fp, 1);
    return embed;
}
