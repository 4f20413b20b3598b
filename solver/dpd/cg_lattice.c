/* cg_lattice: fcc lattice sums of the Sutton-Chen form. */
#include "dpd/cg_lattice.h"

#include <math.h>
#include <stdlib.h>

#include "core/units.h"

enum { CG_MAX_NEIGH = 8192 };

/* Distances (Å) of the fcc sites (i, j, k) aL / 2, i + j + k even, other
 * than the origin, mapped by F (NULL = identity), that lie inside the
 * cutoff; returns their count (at most CG_MAX_NEIGH). */
static int fcc_neighbours(const struct sc_params *sc, double aL, const double *F, double *r)
{
    int kmax = (int)(2.2 * sc->rc / aL) + 1, n = 0;
    for (int i = -kmax; i <= kmax; i++)
        for (int j = -kmax; j <= kmax; j++)
            for (int k = -kmax; k <= kmax; k++) {
                if (((i + j + k) & 1) || (i == 0 && j == 0 && k == 0))
                    continue;
                double s[3] = {0.5 * aL * i, 0.5 * aL * j, 0.5 * aL * k}, d[3];
                for (int q = 0; q < 3; q++)
                    d[q] = F ? F[3 * q] * s[0] + F[3 * q + 1] * s[1] + F[3 * q + 2] * s[2] : s[q];
                double rr = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                if (rr < sc->rc && n < CG_MAX_NEIGH)
                    r[n++] = rr;
            }
    return n;
}

/* Sums over the neighbours of one site: pair energy V, density R, and their
 * derivatives with respect to aL (r = u aL, so dr/daL = r / aL). */
struct shell_sums {
    double V, R, dV, dR;
};

static struct shell_sums lattice_sums(const struct sc_params *sc, double aL, const double *F)
{
    double *r = malloc(CG_MAX_NEIGH * sizeof *r);
    struct shell_sums s = {0, 0, 0, 0};
    if (!r)
        return (struct shell_sums){NAN, NAN, NAN, NAN};
    int nn = fcc_neighbours(sc, aL, F, r);
    for (int q = 0; q < nn; q++) {
        double v, dv, rho, drho;
        sc_pair_terms(sc, r[q], &v, &dv, &rho, &drho);
        s.V += v;
        s.R += rho;
        s.dV += dv * r[q] / aL;
        s.dR += drho * r[q] / aL;
    }
    free(r);
    return s;
}

double cg_lattice_energy(const struct sc_params *sc, double aL, const double *F)
{
    struct shell_sums s = lattice_sums(sc, aL, F);
    double Fe, dF;
    sc_embed(sc, s.R, &Fe, &dF);
    return 0.5 * sc->eps * s.V + Fe;
}

void cg_lattice_static(const struct sc_params *sc, double aL, double *e, double *P)
{
    struct shell_sums s = lattice_sums(sc, aL, NULL);
    double Fe, dF;
    sc_embed(sc, s.R, &Fe, &dF);
    if (e)
        *e = 0.5 * sc->eps * s.V + Fe;
    double deda = 0.5 * sc->eps * s.dV + dF * s.dR;
    if (P)
        *P = -deda / (0.75 * aL * aL);   /* dOmega/daL = 3 aL^2 / 4 */
}

double cg_lattice_einstein_k(const struct sc_params *sc, double aL)
{
    /* k = (1/3) sum_j [eps (v'' + 2 v'/r) + 2 F'(rho) (phi'' + 2 phi'/r) + F''(rho) phi'^2]:
     * the pair terms, the displaced particle's own embedding (its density
     * gradient sums to zero by symmetry) and each neighbour's embedding. */
    double *r = malloc(CG_MAX_NEIGH * sizeof *r);
    if (!r)
        return NAN;
    int nn = fcc_neighbours(sc, aL, NULL, r);
    double R = 0;
    for (int q = 0; q < nn; q++) {
        double v, dv, rho, drho;
        sc_pair_terms(sc, r[q], &v, &dv, &rho, &drho);
        R += rho;
    }
    double Fe, dF;
    sc_embed(sc, R, &Fe, &dF);
    double d2F = R > 0 ? 0.25 * sc->eps * sc->c / (R * sqrt(R)) : 0;
    double k = 0;
    for (int q = 0; q < nn; q++) {
        double v, dv, rho, drho, rr = r[q];
        sc_pair_terms(sc, rr, &v, &dv, &rho, &drho);
        double x = sc->a / rr;
        /* the shifted-force terms are linear in r: no second derivative */
        double d2v = sc->n * (sc->n + 1) / (rr * rr) * sc_pow(x, sc->n, sc->n_int);
        double d2rho = sc->m * (sc->m + 1) / (rr * rr) * sc_pow(x, sc->m, sc->m_int);
        k += sc->eps * (d2v + 2 * dv / rr) + 2 * dF * (d2rho + 2 * drho / rr) + d2F * drho * drho;
    }
    free(r);
    return k / 3.0;
}

double cg_lattice_thermal_pressure(const struct sc_params *sc, double aL, double T)
{
    if (!(T > 0))
        return 0;
    const double h = 1e-4;   /* step in ln aL */
    double kp = cg_lattice_einstein_k(sc, aL * exp(h)), km = cg_lattice_einstein_k(sc, aL * exp(-h));
    if (!(kp > 0 && km > 0))
        return 0;
    /* gamma_E = -d ln omega / d ln V = -(1/2) d ln k / (3 d ln aL) */
    double gamma = -(log(kp) - log(km)) / (2 * h) / 6.0;
    double n = 4.0 / (aL * aL * aL);
    return 3.0 * n * UNITS_KB * T * gamma;
}

double cg_lattice_pressure(const struct sc_params *sc, double aL, double T, int thermal)
{
    double P;
    cg_lattice_static(sc, aL, NULL, &P);
    if (thermal)
        P += cg_lattice_thermal_pressure(sc, aL, T);
    return P;
}

int cg_lattice_solve_pressure(const struct sc_params *sc, double T, int thermal, double P0,
                              double lo, double hi, double *aL)
{
    double flo = cg_lattice_pressure(sc, lo, T, thermal) - P0;
    double fhi = cg_lattice_pressure(sc, hi, T, thermal) - P0;
    if (!(flo * fhi <= 0))
        return -1;
    for (int it = 0; it < 200 && hi - lo > 1e-13 * hi; it++) {
        double mid = 0.5 * (lo + hi);
        double fm = cg_lattice_pressure(sc, mid, T, thermal) - P0;
        if ((fm > 0) == (flo > 0)) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
    }
    *aL = 0.5 * (lo + hi);
    return 0;
}

/* Energy per particle under F = [[1+exx, g/2, 0], [g/2, 1+eyy, 0], [0, 0, 1]]. */
static double strained(const struct sc_params *sc, double aL, double exx, double eyy, double g)
{
    double F[9] = {1 + exx, 0.5 * g, 0, 0.5 * g, 1 + eyy, 0, 0, 0, 1};
    return cg_lattice_energy(sc, aL, F);
}

void cg_lattice_elastic(const struct sc_params *sc, double aL, double *c11, double *c12,
                        double *c44)
{
    const double h = 1e-4;
    double omega = aL * aL * aL / 4.0;
    double e0 = cg_lattice_energy(sc, aL, NULL);
    *c11 = (strained(sc, aL, h, 0, 0) - 2 * e0 + strained(sc, aL, -h, 0, 0)) / (h * h) / omega;
    *c12 = (strained(sc, aL, h, h, 0) - strained(sc, aL, h, -h, 0) - strained(sc, aL, -h, h, 0) +
            strained(sc, aL, -h, -h, 0)) /
           (4 * h * h) / omega;
    /* engineering shear g: E / Omega = C44 g^2 / 2 */
    *c44 = (strained(sc, aL, 0, 0, h) - 2 * e0 + strained(sc, aL, 0, 0, -h)) / (h * h) / omega;
}
