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
 *
 * Each particle's pairs are handled in two passes: the first gathers the
 * pairs within r_d (squared distances in one vector loop, the list order
 * kept) and computes everything that does not depend on the velocities --
 * direction, weight, masses, the random number -- with no pair waiting on
 * another; the second runs the updates in list order, each waiting only on
 * the short chain of dpd_ou.h.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dpd/dpd_ou.h"
#include "dpd/dpd_pair.h"

/* Scratch for one particle's pairs, structure of arrays (the first pass's
 * loops vectorise over them). */
struct sweep_scratch {
    double *r2, *wj, *P, *xi, *ex, *ey, *ez, *mu, *mu4, *dvi, *dvj, *xcoef, *noise, *wr, *invmu;
    int *j, *oj, *bj, *tail;
    void *block;
};

static int scratch_alloc(struct sweep_scratch *s, int n)
{
    n = n < 8 ? 8 : n;
    const int nd = 15, ni = 4;
    s->block = malloc((size_t)n * (nd * sizeof(double) + ni * sizeof(int)));
    if (!s->block)
        return -1;
    double *dp = s->block;
    double **dv[] = {&s->r2, &s->wj, &s->P, &s->xi, &s->ex, &s->ey, &s->ez,
                     &s->mu, &s->mu4, &s->dvi, &s->dvj, &s->xcoef, &s->noise, &s->wr,
                     &s->invmu};
    for (int k = 0; k < nd; k++)
        *dv[k] = dp + (size_t)k * n;
    int *ip = (int *)(dp + (size_t)nd * n);
    int **iv[] = {&s->j, &s->oj, &s->bj, &s->tail};
    for (int k = 0; k < ni; k++)
        *iv[k] = ip + (size_t)k * n;
    return 0;
}

/* Inverse of the mass a particle has in a pair: its own, its free body's,
 * or 0 for a prescribed body (infinite mass). */
static double pair_inv_mass(const struct dpd *d, int i, int b)
{
    if (b < 0)
        return 1.0 / d->p->mass[d->p->type[i]];
    return d->body[b].kind == DPD_BODY_FREE ? 1.0 / d->body[b].mass : 0.0;
}

/* Pass 1 for owned particle i (inverse mass wi, body bi): its pairs within
 * r_d in list order and what their updates need that does not depend on
 * the velocities; returns their number. */
static int gather_pairs(const struct dpd *d, int i, int bi, double wi, uint64_t prefix,
                        const struct dpd_ou *ou, struct sweep_scratch *s)
{
    const struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const double rd = d->set.cutoff, rd2 = rd * rd, inv_rd = 1.0 / rd;
    const double *restrict x = p->x;
    const int *restrict origin = p->origin;
    const int *restrict nbi = nl->neigh + nl->offset[i];
    const int len = nl->offset[i + 1] - nl->offset[i];
    const double xi = x[3 * i], yi = x[3 * i + 1], zi = x[3 * i + 2];
    double *restrict r2 = s->r2;
    int *restrict js = s->j, *restrict oj = s->oj, *restrict bj = s->bj;
    double *restrict wj = s->wj;
#pragma omp simd
    for (int k = 0; k < len; k++) {
        int j = nbi[k];
        double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
        r2[k] = dx * dx + dy * dy + dz * dz;
    }
    /* within r_d, not an image of i itself (no relative motion): moved to
     * the front in list order, without branches */
    int n = 0;
    for (int k = 0; k < len; k++) {
        int j = nbi[k];
        js[n] = j;
        r2[n] = r2[k];
        n += (r2[k] < rd2) & (origin[j] != i);
    }
    const double *restrict mass = p->mass;
    const int *restrict type = p->type;
    if (d->nbodies == 0) {
#pragma omp simd
        for (int q = 0; q < n; q++) {
            oj[q] = origin[js[q]];
            bj[q] = -1;
            wj[q] = 1.0 / mass[type[oj[q]]];
        }
    } else {
        /* a neighbour's body: the first whose group bits it carries (as
         * dpd_body_of), its inverse mass that body's (0 when prescribed) */
        const int nb = d->nbodies;
        uint32_t bmask[DPD_MAX_BODIES];
        double bw[DPD_MAX_BODIES];
        for (int b = 0; b < nb; b++) {
            bmask[b] = d->body[b].mask;
            bw[b] = d->body[b].kind == DPD_BODY_FREE ? 1.0 / d->body[b].mass : 0.0;
        }
        const uint32_t *restrict gmask = p->mask;
        int *restrict keep = s->tail;
#pragma omp simd
        for (int q = 0; q < n; q++) {
            int o = origin[js[q]], b = -1;
            uint32_t mj = gmask[js[q]];
            double w = 1.0 / mass[type[o]];
            for (int k = nb - 1; k >= 0; k--) {
                int hit = (mj & bmask[k]) != 0;
                b = hit ? k : b;
                w = hit ? bw[k] : w;
            }
            oj[q] = o;
            bj[q] = b;
            wj[q] = w;
            /* not inside i's own body, not two prescribed bodies */
            keep[q] = (bi < 0 || b != bi) & (wi + w != 0);
        }
        int m = 0;
        for (int q = 0; q < n; q++) {
            js[m] = js[q];
            r2[m] = r2[q];
            oj[m] = oj[q];
            bj[m] = bj[q];
            wj[m] = wj[q];
            m += keep[q];
        }
        n = m;
    }
    /* the random numbers: keys, uniforms, the normal's central form for
     * all (vector loops), the tails' form for the 15 % that need it */
    const int64_t *restrict id = p->id;
    const int *restrict gshift = p->gshift, *restrict image = p->image;
    const int64_t idi = id[i];
    const int im0 = image[3 * i], im1 = image[3 * i + 1], im2 = image[3 * i + 2];
    double *restrict P = s->P, *restrict xn = s->xi;
    int *restrict tail = s->tail;
#pragma omp simd
    for (int q = 0; q < n; q++) {
        int j = js[q], o = oj[q];
        P[q] = rng_uniform(dpd_key_ids(prefix, idi, id[o], gshift[3 * j] - image[3 * o] + im0,
                                       gshift[3 * j + 1] - image[3 * o + 1] + im1,
                                       gshift[3 * j + 2] - image[3 * o + 2] + im2),
                           0);
    }
#pragma omp simd
    for (int q = 0; q < n; q++)
        xn[q] = dpd_normal_central(P[q]);
    int nt = 0;
    for (int q = 0; q < n; q++) {
        tail[nt] = q;
        nt += dpd_normal_is_tail(P[q]) | (P[q] == 1.0);
    }
    for (int t = 0; t < nt; t++)
        xn[tail[t]] = dpd_normal_of_uniform(P[tail[t]]);
    /* geometry, masses and the update's coefficients */
    double *restrict ex = s->ex, *restrict ey = s->ey, *restrict ez = s->ez;
    double *restrict mu = s->mu, *restrict mu4 = s->mu4, *restrict dvi = s->dvi,
                     *restrict dvj = s->dvj;
    double *restrict xcoef = s->xcoef, *restrict noise = s->noise, *restrict wr = s->wr,
                     *restrict invmu = s->invmu;
    const double xfac = ou->xfac, s0 = ou->s0;
#pragma omp simd
    for (int q = 0; q < n; q++) {
        int j = js[q];
        double dx = xi - x[3 * j], dy = yi - x[3 * j + 1], dz = zi - x[3 * j + 2];
        double inv_r = 1.0 / sqrt(r2[q]), r = r2[q] * inv_r;
        ex[q] = dx * inv_r;
        ey[q] = dy * inv_r;
        ez[q] = dz * inv_r;
        double im = wi + wj[q], m = 1.0 / im, w = 1.0 - r * inv_rd;
        invmu[q] = im;
        mu[q] = m;
        mu4[q] = m * (0.25 * UNITS_MVV2E);
        dvi[q] = wi * m;
        dvj[q] = wj[q] * m;
        wr[q] = w;
        xcoef[q] = xfac * w * w * im;
        noise[q] = s0 * w * im * xn[q];
    }
    return n;
}

int dpd_sweep(struct dpd *d, struct err *e)
{
    struct particles *p = d->p;
    const struct nlist *nl = d->nl;
    const int dpde = d->set.variant == DPD_ENERGY;
    const int site = dpde ? RNG_SITE_DPDE_PAIR : RNG_SITE_DPD_PAIR;
    const uint64_t prefix = dpd_key_prefix(d, site);
    struct dpd_ou ou;
    dpd_ou_init(&ou, dpde, d->set.gamma, d->set.temperature, d->set.heat_capacity, d->dt);
    double *u = d->ufield >= 0 ? particles_field(p, d->ufield) : NULL;
    memset(d->body_impulse, 0, sizeof d->body_impulse);
    int maxlen = 0;
    for (int i = 0; i < p->n_owned; i++)
        if (nl->offset[i + 1] - nl->offset[i] > maxlen)
            maxlen = nl->offset[i + 1] - nl->offset[i];
    struct sweep_scratch s;
    if (scratch_alloc(&s, maxlen))
        return err_nomem(e, "DPD sweep");
    int rc = 0;
    for (int i = 0; !rc && i < p->n_owned; i++) {
        const int bi = dpd_body_of(d, i);
        const double wi = pair_inv_mass(d, i, bi);
        const int m = gather_pairs(d, i, bi, wi, prefix, &ou, &s);
        /* pass 2: the updates in list order.  i's velocity and energy stay
         * in registers: no j aliases them (images of i and members of i's
         * body are out) */
        double *vip = bi < 0 ? p->v + 3 * i : d->body[bi].v;
        double vi0 = vip[0], vi1 = vip[1], vi2 = vip[2];
        double ui = u ? u[i] : 0;
        for (int q = 0; q < m; q++) {
            const int oj = s.oj[q], bj = s.bj[q];
            const double ex = s.ex[q], ey = s.ey[q], ez = s.ez[q];
            double *vj = bj < 0 ? p->v + 3 * oj : d->body[bj].v;
            double urel = ex * (vi0 - vj[0]) + ey * (vi1 - vj[1]) + ez * (vi2 - vj[2]);
            double uj = u ? u[oj] : 0;
            struct dpd_ou_pair op = {s.xcoef[q], s.noise[q], s.wr[q], s.invmu[q], s.xi[q]};
            double unew = dpd_ou_unew(&ou, &op, urel, ui, uj);
            double du = unew - urel;
            double ai = du * s.dvi[q], aj = du * s.dvj[q];
            vi0 = fma(ai, ex, vi0);
            vi1 = fma(ai, ey, vi1);
            vi2 = fma(ai, ez, vi2);
            vj[0] = fma(-aj, ex, vj[0]);
            vj[1] = fma(-aj, ey, vj[1]);
            vj[2] = fma(-aj, ez, vj[2]);
            if (bi >= 0 || bj >= 0) {
                double J = du * s.mu[q];   /* amu Å/ps along e_ij, +J on i */
                double Jx = J * ex, Jy = J * ey, Jz = J * ez;
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
            }
            if (dpde) {
                /* the pair's kinetic energy change mu (u'^2 - u^2) / 2, half
                 * from each internal energy (eV) */
                double dE4 = du * ((unew + urel) * s.mu4[q]);
                ui -= dE4;
                u[oj] = uj - dE4;
                if (!(ui > 0) || !(u[oj] > 0)) {
                    rc = err_set(e, ERR_DIVERGED,
                                 "internal energy of particle %lld became %.3g eV at step %ld "
                                 "(time step too large for the heat exchanged?)",
                                 (long long)p->id[ui > 0 ? oj : i], ui > 0 ? u[oj] : ui, d->step);
                    break;
                }
            }
        }
        vip[0] = vi0;
        vip[1] = vi1;
        vip[2] = vi2;
        if (u)
            u[i] = ui;
    }
    free(s.block);
    return rc;
}
