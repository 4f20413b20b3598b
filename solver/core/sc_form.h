/*
 * sc_form: the Sutton-Chen functional form (Sutton & Chen, Philos. Mag.
 * Lett. 61, 139 (1990)), shared by the atomistic potential (md/) and the
 * coarse-grained DPD conservative force (dpd/):
 *
 *   E = eps [ 1/2 sum_i sum_j!=i (a/r_ij)^n  -  c sum_i sqrt(rho_i) ],
 *   rho_i = sum_j!=i (a/r_ij)^m.
 *
 * Both power laws are truncated at rc in shifted-force form,
 *   g_s(r) = g(r) - g(rc) - (r - rc) g'(rc),
 * so energy and force go to zero continuously at the cutoff (no energy drift
 * from atoms crossing it).  The truncation changes the equilibrium lattice
 * constant and cohesive energy slightly from the infinite-range values; the
 * tests state the values for the default cutoff.
 */
#ifndef CASCADE_SC_FORM_H
#define CASCADE_SC_FORM_H

#include <math.h>

struct sc_params {
    double eps;      /* eV */
    double c;        /* dimensionless */
    double a;        /* Å */
    double n, m;     /* repulsive and density exponents */
    double rc;       /* cutoff, Å */
    /* derived: shift terms of the shifted-force truncation */
    double v_rc, dv_rc, rho_rc, drho_rc;
    int n_int, m_int;   /* exponents when integral (fast powers), else 0 */
};

static inline double sc_ipow(double x, int k)
{
    double r = 1.0;
    while (k > 0) {
        if (k & 1)
            r *= x;
        x *= x;
        k >>= 1;
    }
    return r;
}

static inline double sc_pow(double x, double e, int e_int)
{
    return e_int > 0 ? sc_ipow(x, e_int) : pow(x, e);
}

static inline void sc_params_finish(struct sc_params *s)
{
    s->n_int = (s->n == floor(s->n) && s->n > 0 && s->n < 64) ? (int)s->n : 0;
    s->m_int = (s->m == floor(s->m) && s->m > 0 && s->m < 64) ? (int)s->m : 0;
    double q = s->a / s->rc;
    s->v_rc = sc_pow(q, s->n, s->n_int);
    s->dv_rc = -s->n / s->rc * s->v_rc;
    s->rho_rc = sc_pow(q, s->m, s->m_int);
    s->drho_rc = -s->m / s->rc * s->rho_rc;
}

/* Truncated (a/r)^n and (a/r)^m with their r-derivatives, for r < rc. */
static inline void sc_pair_terms(const struct sc_params *s, double r, double *v, double *dv,
                                 double *rho, double *drho)
{
    double q = s->a / r;
    double vn = sc_pow(q, s->n, s->n_int);
    double vm = sc_pow(q, s->m, s->m_int);
    double dr = r - s->rc;
    *v = vn - s->v_rc - dr * s->dv_rc;
    *dv = -s->n / r * vn - s->dv_rc;
    *rho = vm - s->rho_rc - dr * s->drho_rc;
    *drho = -s->m / r * vm - s->drho_rc;
}

/* Embedding energy -eps c sqrt(rho) and its derivative (0 for rho <= 0). */
static inline void sc_embed(const struct sc_params *s, double rho, double *F, double *dF)
{
    if (rho > 0) {
        double sq = sqrt(rho);
        *F = -s->eps * s->c * sq;
        *dF = -0.5 * s->eps * s->c / sq;
    } else {
        *F = 0;
        *dF = 0;
    }
}

#endif
