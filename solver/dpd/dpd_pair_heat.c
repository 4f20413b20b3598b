/*
 * dpd_pair_heat: the DPDE internal-energy update for models that move the
 * DPD particles themselves instead of with dpd_step -- the DPD/MPM-grid and
 * concurrent models of Chen et al. 2014, Sec. 3, where the pair forces are
 * mapped to grid nodes (Eq. (s3b)) and the particles follow the grid.
 *
 * In DPDE the mechanical energy a pair's dissipative and random forces
 * change is taken from (or given to) the two internal energies in equal
 * halves (Espanol 1997; Avalos & Mackie 1997).  When another model moves
 * the particles, the energy those forces put into the motion over a step
 * is their power with the velocities the particles were actually moved
 * with: for pair (i, j) with force f^DR_ij e_ij on i and its opposite on j,
 *   W_ij = f^DR_ij e_ij . (w_i - w_j) dt,
 * w the (time-centred) velocities the caller supplies.  Summed over pairs
 * this is sum_p f^DR_p . w_p dt, which is the exact share of these forces
 * in the kinetic-energy change when w_p is the model's centred velocity
 * at p (see couple/dpd_mpm.h); each pair's W_ij is Galilean invariant, so
 * a body in uniform motion exchanges no heat.
 *
 * On bricks (p->halo) w holds the ghosts' velocities too (the caller
 * forwards them); a pair with a ghost is on one rank only, so the ghost's
 * half goes into a buffer that the reverse communication adds to its
 * owner, and the total is summed over the ranks.
 */
#include <math.h>
#include <stdlib.h>

#include "core/ghost.h"
#include "core/halo.h"

#include "dpd/dpd_pair.h"

int dpd_pair_heat(struct dpd *d, double dt, const double *w, double *heat, struct err *e)
{
    if (heat)
        *heat = 0;
    if (d->set.variant != DPD_ENERGY || d->ufield < 0)
        return 0;
    if (!d->keep_pair_dr || !d->pair_dr)
        return err_set(e, ERR_RUNTIME, "dpd_pair_heat needs the pair forces kept (keep_pair_dr)");
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const double *fdr = d->pair_dr;
    double *u = particles_field(p, d->ufield);
    double total = 0;
    double *du = NULL;   /* bricks: the changes, owned and ghosts */
    if (p->halo && !(du = calloc((size_t)(p->n_owned + p->n_ghost) + 1, sizeof *du)))
        return err_nomem(e, "DPDE heat");
    for (int i = 0; i < p->n_owned; i++) {
        const double *wi = w + 3 * i;
        for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
            if (fdr[k] == 0)
                continue;
            int j = nl->neigh[k], oj = p->origin[j];
            double dx = p->x[3 * i] - p->x[3 * j], dy = p->x[3 * i + 1] - p->x[3 * j + 1],
                   dz = p->x[3 * i + 2] - p->x[3 * j + 2];
            double inv_r = 1.0 / sqrt(dx * dx + dy * dy + dz * dz);
            const double *wj = w + 3 * oj;
            double wrel = (dx * (wi[0] - wj[0]) + dy * (wi[1] - wj[1]) + dz * (wi[2] - wj[2])) *
                          inv_r;
            double W = fdr[k] * wrel * dt;   /* eV: work of the pair's D + R force */
            if (du) {
                du[i] -= 0.5 * W;
                du[oj] -= 0.5 * W;
            } else {
                u[i] -= 0.5 * W;
                u[oj] -= 0.5 * W;
            }
            total += W;
        }
    }
    int bad = -1;
    if (du) {
        ghost_reverse_add(p, du, 1);
        for (int i = 0; i < p->n_owned; i++)
            u[i] += du[i];
        free(du);
        halo_sum(p->halo, &total, 1);
    }
    if (heat)
        *heat = total;
    for (int i = 0; i < p->n_owned && bad < 0; i++)
        if (!(u[i] > 0))
            bad = i;
    if (p->halo && halo_any(p->halo, bad >= 0) && bad < 0)
        return err_set_elsewhere(e, ERR_DIVERGED,
                                 "an internal energy became zero or negative at step %ld "
                                 "on another rank",
                                 d->step);
    for (int i = bad; i >= 0 && i < p->n_owned; i++)
        if (!(u[i] > 0))
            return err_set(e, ERR_DIVERGED,
                           "internal energy of particle %lld became %.3g eV at step %ld (time "
                           "step too large for the heat exchanged?)",
                           (long long)p->id[i], u[i], d->step);
    return 0;
}
