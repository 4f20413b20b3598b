/*
 * dpd_sweep: the dissipative + random part of a DPD step, pair by pair
 * (Shardlow 2003; Lisal, Brennan & Bonet Avalos 2011 for DPDE).
 *
 * For one pair with the positions held, the forces act along e_ij only and
 * change the relative velocity along it, u = e_ij . (v_i - v_j), as the
 * Ornstein-Uhlenbeck process
 *     du = -lambda u dt + sqrt(2 lambda kB Theta / mu) dW,
 *     lambda = gamma_ij w^D(r) / mu,  1/mu = 1/m_i + 1/m_j,
 * (Chen 2014, Eqs. (2.4)-(2.5) with sigma^2 = 2 gamma kB T, w^D = (w^R)^2),
 * which is integrated exactly over dt:
 *     u' = u e^{-lambda dt} + sqrt(kB Theta / mu (1 - e^{-2 lambda dt})) xi.
 * The pair exchanges the impulse J = mu (u' - u) along e_ij (+J on i, -J on
 * j: momentum is conserved exactly), and its relative kinetic energy
 * changes by mu (u'^2 - u^2) / 2; DPDE takes that energy from the two
 * internal energies in equal halves.  Pairs are visited in neighbour-list
 * order, serially: each update sees the velocities the previous ones left.
 */
#include <math.h>
#include <string.h>

#include "dpd/dpd_pair.h"

/* Inverse of the mass a particle has in a pair: its own, its free body's,
 * or 0 for a prescribed body (infinite mass). */
static double pair_inv_mass(const struct dpd *d, int i, int b)
{
    if (b < 0)
        return 1.0 / d->p->mass[d->p->type[i]];
    return d->body[b].kind == DPD_BODY_FREE ? 1.0 / d->body[b].mass : 0.0;
}

int dpd_sweep(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const double rd = d->set.cutoff, rd2 = rd * rd, inv_rd = 1.0 / rd, dt = d->dt;
    const int dpde = d->set.variant == DPD_ENERGY;
    const int site = dpde ? RNG_SITE_DPDE_PAIR : RNG_SITE_DPD_PAIR;
    const double kT0 = UNITS_KB * d->set.temperature * UNITS_FTM2V;   /* (Å/ps)^2 amu */
    double *u = d->ufield >= 0 ? particles_field(p, d->ufield) : NULL;
    memset(d->body_impulse, 0, sizeof d->body_impulse);
    for (int i = 0; i < p->n_owned; i++) {
        const int bi = dpd_body_of(d, i);
        const double wi = pair_inv_mass(d, i, bi);
        /* i's velocity stays in registers over its pairs: no j aliases it
         * (images of i and members of i's body are skipped) */
        double *vip = bi < 0 ? p->v + 3 * i : d->body[bi].v;
        double vi0 = vip[0], vi1 = vip[1], vi2 = vip[2];
        const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
        for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
            int j = nl->neigh[k];
            double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
            double r2 = dx * dx + dy * dy + dz * dz;
            if (r2 >= rd2)
                continue;
            int oj = p->origin[j];
            if (oj == i)
                continue;   /* an image of itself: no relative motion */
            int bj = d->nbodies ? dpd_body_of(d, j) : -1;
            if (bi >= 0 && bi == bj)
                continue;   /* inside one rigid body */
            double wj = pair_inv_mass(d, oj, bj);
            double invmu = wi + wj;
            if (invmu == 0)
                continue;   /* two prescribed bodies */
            double inv_r = 1.0 / sqrt(r2), r = r2 * inv_r;
            double ex = dx * inv_r, ey = dy * inv_r, ez = dz * inv_r;
            double *vj = bj < 0 ? p->v + 3 * oj : d->body[bj].v;
            double urel = ex * (vi0 - vj[0]) + ey * (vi1 - vj[1]) + ez * (vi2 - vj[2]);
            double wr = 1.0 - r * inv_rd;
            double kT, gij;   /* kB Theta_ij in amu (Å/ps)^2, friction in amu/ps */
            if (dpde) {
                /* gamma_ij = sigma^2 / (2 kB Theta_ij) with sigma^2 = 2 gamma kB T0 */
                double theta = dpd_pair_temperature(d, u, i, oj);
                kT = UNITS_KB * theta * UNITS_FTM2V;
                gij = theta > 0 ? d->set.gamma * kT0 / kT : kT0 > 0 ? INFINITY : 0.0;
            } else {
                kT = kT0;
                gij = d->set.gamma;
            }
            double lam = gij * wr * wr * invmu;
            double decay = isinf(lam) ? 0.0 : exp(-lam * dt);
            double unew = urel * decay + sqrt(kT * invmu * (1.0 - decay * decay)) *
                                             dpd_normal(dpd_pair_key(d, site, i, j));
            double J = (unew - urel) / invmu;   /* amu Å/ps along e_ij, +J on i */
            double Jx = J * ex, Jy = J * ey, Jz = J * ez;
            vi0 += Jx * wi;
            vi1 += Jy * wi;
            vi2 += Jz * wi;
            vj[0] -= Jx * wj;
            vj[1] -= Jy * wj;
            vj[2] -= Jz * wj;
            if (bi >= 0) {
                d->body_impulse[bi][0] += Jx;
                d->body_impulse[bi][1] += Jy;
                d->body_impulse[bi][2] += Jz;
            }
            if (bj >= 0) {
                d->body_impulse[bj][0] -= Jx;
                d->body_impulse[bj][1] -= Jy;
                d->body_impulse[bj][2] -= Jz;
            }
            if (dpde) {
                double dE = 0.5 * (unew * unew - urel * urel) / invmu * UNITS_MVV2E;   /* eV */
                u[i] -= 0.5 * dE;
                u[oj] -= 0.5 * dE;
                if (!(u[i] > 0) || !(u[oj] > 0)) {
                    vip[0] = vi0;
                    vip[1] = vi1;
                    vip[2] = vi2;
                    return err_set(e, ERR_DIVERGED,
                                   "internal energy of particle %lld became %.3g eV at step %ld "
                                   "(time step too large for the heat exchanged?)",
                                   (long long)p->id[u[i] > 0 ? oj : i], u[i] > 0 ? u[oj] : u[i],
                                   d->step);
                }
            }
        }
        vip[0] = vi0;
        vip[1] = vi1;
        vip[2] = vi2;
    }
    return 0;
}
