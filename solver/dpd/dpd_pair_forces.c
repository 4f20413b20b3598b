/*
 * dpd_pair_forces: the total DPD pair force per particle, for models that
 * integrate DPD particles themselves -- the DPD/MPM-grid model maps these
 * forces to the grid nodes with N_i (Chen 2014, Eq. (s3b)) and the
 * concurrent model uses them in its interface force (Eq. (3.1)).
 *
 * With the velocities held, the dissipative and random forces of a step of
 * length dt are (Chen 2014, Eqs. (2.4)-(2.5); Euler-Maruyama form of the
 * Wiener increment dW = theta sqrt(dt)):
 *   f^D_ij = -gamma_ij w^D(r) (e_ij . v_ij) e_ij
 *   f^R_ij =  sigma_ij w^R(r) theta_ij / sqrt(dt) e_ij,
 *   sigma_ij^2 = 2 gamma_ij kB Theta_ij,
 * antisymmetric in i and j, so they sum to zero over all particles.
 * Pairs of two passive partners (d->passive_mask) exert none.  With
 * d->keep_pair_dr each list entry's D + R force is kept in d->pair_dr for
 * the DPDE bookkeeping of dpd_pair_heat.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "dpd/dpd_pair.h"

int dpd_pair_forces(struct dpd *d, double dt, double *fout, struct err *e)
{
    int rc = dpd_compute_forces(d, e);
    if (rc)
        return rc;
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    if (p->halo) {   /* bricks: the ghosts' velocities and internal energies of this step */
        ghost_update_velocities(p);
        if (d->ufield >= 0)
            ghost_forward(p, particles_field(p, d->ufield), 1);
    }
    const int nt = d->nthreads < 1 ? 1 : d->nthreads;
    const int ntot = p->n_owned + p->n_ghost;
    const double rd = d->set.cutoff, rd2 = rd * rd;
    const int dpde = d->set.variant == DPD_ENERGY;
    const int site = dpde ? RNG_SITE_DPDE_PAIR : RNG_SITE_DPD_PAIR;
    const uint64_t prefix = dpd_key_prefix(d, site);
    const double *u = d->ufield >= 0 ? particles_field(p, d->ufield) : NULL;
    const uint32_t pm = d->passive_mask;
    double *buf = calloc((size_t)3 * (ntot ? ntot : 1), sizeof *buf);
    struct thread_accum acc = {0};
    if (!buf)
        return err_nomem(e, "DPD pair forces");
    double *keep = NULL;
    if (d->keep_pair_dr) {
        long nk = nl->offset[p->n_owned];
        if (nk > d->pair_dr_cap) {
            long cap = nk + nk / 4 + 64;
            double *q = realloc(d->pair_dr, (size_t)cap * sizeof *q);
            if (!q) {
                free(buf);
                return err_nomem(e, "DPD pair forces");
            }
            d->pair_dr = q;
            d->pair_dr_cap = cap;
        }
        keep = d->pair_dr;
        memset(keep, 0, (size_t)nk * sizeof *keep);
    }
    if ((rc = thread_accum_reserve(&acc, nt, (size_t)3 * ntot, e))) {
        free(buf);
        return rc;
    }
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        double *f = thread_accum_target(&acc, tid, buf, (size_t)3 * ntot);
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            int bi = dpd_body_of(d, i);
            const int passive_i = pm && (p->mask[i] & pm);
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = p->x[3 * i] - p->x[3 * j], dy = p->x[3 * i + 1] - p->x[3 * j + 1],
                       dz = p->x[3 * i + 2] - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= rd2 || (passive_i && (p->mask[j] & pm)))
                    continue;
                int oj = p->origin[j];
                if (oj == i || (bi >= 0 && bi == dpd_body_of(d, j)))
                    continue;
                double r = sqrt(r2), ex = dx / r, ey = dy / r, ez = dz / r;
                const double *vi = p->v + 3 * i, *vj = p->v + 3 * oj;
                double urel = ex * (vi[0] - vj[0]) + ey * (vi[1] - vj[1]) + ez * (vi[2] - vj[2]);
                double wr = 1.0 - r / rd;
                double theta, gij;
                if (dpde) {
                    theta = dpd_pair_temperature(d, u, i, oj);
                    gij = theta > 0 ? d->set.gamma * d->set.temperature / theta : 0.0;
                } else {
                    theta = d->set.temperature;
                    gij = d->set.gamma;
                }
                /* amu/ps, amu Å / ps^(3/2) */
                double sigma = sqrt(2.0 * gij * UNITS_KB * theta * UNITS_FTM2V);
                double xi = dpd_normal(dpd_pair_key_pre(p, prefix, i, j));
                double fmag = (-gij * wr * wr * urel + sigma * wr * xi / sqrt(dt)) * UNITS_MVV2E;
                if (keep)
                    keep[k] = fmag;
                f[3 * i] += fmag * ex;
                f[3 * i + 1] += fmag * ey;
                f[3 * i + 2] += fmag * ez;
                f[3 * j] -= fmag * ex;
                f[3 * j + 1] -= fmag * ey;
                f[3 * j + 2] -= fmag * ez;
            }
        }
    }
    thread_accum_reduce(&acc, buf, (size_t)3 * ntot);
    ghost_reverse_add(p, buf, 3);
    for (int i = 0; i < p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            fout[3 * i + c] = p->f[3 * i + c] + buf[3 * i + c];
    thread_accum_free(&acc);
    free(buf);
    return 0;
}
