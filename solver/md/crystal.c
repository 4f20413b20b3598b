/* crystal: 0 K lattice constant, cohesive energy and elastic constants. */
#include "md/crystal.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <math.h>
#include <string.h>

#include "core/elements.h"
#include "md/md.h"


int crystal_energy(struct potential *pot, const struct crystal_spec *c, double a,
                   const int (*orient)[3], const double eps[3], double *e_atom, double P[6],
                   struct err *e)
{
    struct lattice l = {c->style, a, {0, 0, 0}, {{0}}};
    if (orient)
        memcpy(l.orient, orient, sizeof l.orient);
    struct particles *p = particles_create(64);
    if (!p)
        return err_nomem(e, "crystal");
    double mass = c->mass > 0 ? c->mass : element_mass(c->element);
    int t = particles_type_index(p, c->element, mass);
    int64_t id = 1;
    long n[3] = {c->cells, c->cells, c->cells};
    if (lattice_fill(&l, n, NULL, p, t, &id, e) < 0) {
        particles_destroy(&p);
        return ERR_RUNTIME;
    }
    double cell[3];
    lattice_cell(&l, cell);
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    double s[3] = {1, 1, 1};
    if (eps)
        for (int d = 0; d < 3; d++)
            s[d] = 1.0 + eps[d];
    for (int d = 0; d < 3; d++)
        b.hi[d] = n[d] * cell[d] * s[d];
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++)
            p->x[3 * i + d] *= s[d];
    /* the md takes ownership of p; the potential stays the caller's */
    struct md md;
    int rc = md_init(&md, p, &b, pot, 0.001, 0.5, 1, e);
    if (!rc) {
        *e_atom = md.last.energy / p->n_owned;
        if (P) {
            double V = box_volume(&md.box);
            for (int k = 0; k < 6; k++)
                P[k] = md.last.virial[k] / V;
        }
    }
    md.pot = NULL;
    md_free(&md);
    return rc;
}

struct energy_ctx {
    struct potential *pot;
    const struct crystal_spec *c;
    struct err *e;
    int rc;
};

static double energy_of_a(double a, void *arg)
{
    struct energy_ctx *x = arg;
    double ea;
    if (x->rc)
        return 0;
    x->rc = crystal_energy(x->pot, x->c, a, NULL, NULL, &ea, NULL, x->e);
    return ea;
}

/* Mean virial pressure: dE/da = -3 V P / (N a), so P = 0 at the minimum. */
static double pressure_of_a(double a, void *arg)
{
    struct energy_ctx *x = arg;
    double ea, P[6];
    if (x->rc)
        return 0;
    x->rc = crystal_energy(x->pot, x->c, a, NULL, NULL, &ea, P, x->e);
    return (P[0] + P[1] + P[2]) / 3.0;
}

int crystal_equilibrium(struct potential *pot, const struct crystal_spec *c, double a_lo,
                        double a_hi, double *a0, double *ecoh, struct err *e)
{
    struct energy_ctx ctx = {pot, c, e, 0};
    /* bracket: the best of a coarse scan inside [a_lo, a_hi] */
    const int nscan = 40;
    double best = 0.5 * (a_lo + a_hi), ebest = INFINITY;
    for (int k = 0; k <= nscan; k++) {
        double a = a_lo + (a_hi - a_lo) * k / nscan;
        double ea = energy_of_a(a, &ctx);
        if (ctx.rc)
            return ctx.rc;
        if (ea < ebest) {
            ebest = ea;
            best = a;
        }
    }
    double h = (a_hi - a_lo) / nscan;
    if (best - h < a_lo || best + h > a_hi)
        return err_set(e, ERR_RUNTIME,
                       "no energy minimum inside [%g, %g] Å (lowest at the edge, %g Å)", a_lo,
                       a_hi, best);
    /* the minimum is where the pressure vanishes: a root, found to round-off
     * (the energy itself is too flat there for a minimiser) */
    gsl_set_error_handler_off();
    gsl_function F = {pressure_of_a, &ctx};
    gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    if (!s)
        return err_nomem(e, "root solver");
    if (gsl_root_fsolver_set(s, &F, best - h, best + h) != GSL_SUCCESS) {
        gsl_root_fsolver_free(s);
        return ctx.rc ? ctx.rc
                      : err_set(e, ERR_RUNTIME, "pressure does not change sign around %g Å", best);
    }
    int status = GSL_CONTINUE;
    for (int it = 0; it < 200 && status == GSL_CONTINUE && !ctx.rc; it++) {
        gsl_root_fsolver_iterate(s);
        status = gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s),
                                        1e-12, 0.0);
    }
    *a0 = gsl_root_fsolver_root(s);
    gsl_root_fsolver_free(s);
    if (ctx.rc)
        return ctx.rc;
    if (status != GSL_SUCCESS)
        return err_set(e, ERR_RUNTIME, "lattice-constant search did not converge");
    *ecoh = -energy_of_a(*a0, &ctx);
    return ctx.rc;
}

int crystal_elastic_cubic(struct potential *pot, const struct crystal_spec *c, double a,
                          double *c11, double *c12, double *c44, struct err *e)
{
    const double h = 1e-5;
    double Pp[6], Pm[6], ea;
    double ep[3] = {h, 0, 0}, em[3] = {-h, 0, 0};
    int rc = crystal_energy(pot, c, a, NULL, ep, &ea, Pp, e);
    if (!rc)
        rc = crystal_energy(pot, c, a, NULL, em, &ea, Pm, e);
    if (rc)
        return rc;
    /* sigma = -P; the strain is engineering (box scaled by 1 + eps) */
    *c11 = -(Pp[0] - Pm[0]) / (2 * h);
    *c12 = -(Pp[1] - Pm[1]) / (2 * h);
    static const int rot[3][3] = {{1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
    rc = crystal_energy(pot, c, a, rot, ep, &ea, Pp, e);
    if (!rc)
        rc = crystal_energy(pot, c, a, rot, em, &ea, Pm, e);
    if (rc)
        return rc;
    double c11r = -(Pp[0] - Pm[0]) / (2 * h);
    *c44 = c11r - 0.5 * (*c11 + *c12);
    return 0;
}
