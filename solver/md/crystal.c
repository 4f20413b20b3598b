/* crystal: 0 K lattice constant, cohesive energy and elastic constants. */
#include "md/crystal.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/elements.h"
#include "md/md.h"


/* Whether the site at x (Å, unstrained, lattice origin at 0, crystal
 * directions `orient` along x, y, z or cubic) belongs to the second fcc
 * sublattice of diamond, the one at (1/4, 1/4, 1/4) a from the first: its
 * cube coordinates are odd multiples of a/4. */
static int second_sublattice(const struct lattice *l, const double x[3])
{
    double R[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int oriented = 0;
    for (int d = 0; d < 3; d++)
        for (int k = 0; k < 3; k++)
            oriented |= l->orient[d][k] != 0;
    if (oriented)
        for (int d = 0; d < 3; d++) {
            const int *v = l->orient[d];
            double len = sqrt((double)(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            for (int k = 0; k < 3; k++)
                R[d][k] = v[k] / len;
        }
    for (int k = 0; k < 3; k++) {
        /* cube coordinate k = sum_d R[d][k] x[d] */
        double c = 4 * (R[0][k] * x[0] + R[1][k] * x[1] + R[2][k] * x[2]) / l->a;
        long n = lround(c);
        if (fabs(c - n) > 1e-6 || !(n & 1))
            return 0;
    }
    return 1;
}

/* The crystal of crystal_energy with the second diamond sublattice moved
 * by shift[3] (Å, in the box frame, after the strain; NULL: none), and
 * the mean force on that sublattice (fB, eV/Å; may be NULL). */
static int crystal_probe(struct potential *pot, const struct crystal_spec *c, double a,
                         const int (*orient)[3], const double eps[3], const double shift[3],
                         double *e_atom, double P[6], double fB[3], struct err *e)
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
    char *second = calloc((size_t)p->n_owned + 1, 1);
    if (!second) {
        particles_destroy(&p);
        return err_nomem(e, "crystal");
    }
    long nsecond = 0;
    if (c->style == LATTICE_DIAMOND)
        for (int i = 0; i < p->n_owned; i++)
            nsecond += second[i] = (char)second_sublattice(&l, p->x + 3 * i);
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
        for (int d = 0; d < 3; d++) {
            p->x[3 * i + d] *= s[d];
            if (shift && second[i])
                p->x[3 * i + d] += shift[d];
        }
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
        if (fB) {
            fB[0] = fB[1] = fB[2] = 0;
            for (int i = 0; i < md.p->n_owned && nsecond; i++)
                if (second[md.p->id[i] - 1])
                    for (int d = 0; d < 3; d++)
                        fB[d] += md.p->f[3 * i + d] / nsecond;
        }
    }
    free(second);
    md.pot = NULL;
    md_free(&md);
    return rc;
}

int crystal_energy(struct potential *pot, const struct crystal_spec *c, double a,
                   const int (*orient)[3], const double eps[3], double *e_atom, double P[6],
                   struct err *e)
{
    return crystal_probe(pot, c, a, orient, eps, NULL, e_atom, P, NULL, e);
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

/* The internal shift of diamond's second sublattice under a strain: the
 * u at which the mean force on it vanishes, by Newton steps with the
 * optical force constant k (isotropic: the zone-centre optical mode of
 * diamond is triply degenerate).  Returns the pressure there in P. */
static int relax_sublattice(struct potential *pot, const struct crystal_spec *c, double a,
                            const int (*orient)[3], const double eps[3], double k, double u[3],
                            double P[6], struct err *e)
{
    double ea, f[3];
    u[0] = u[1] = u[2] = 0;
    for (int it = 0; it < 6; it++) {
        int rc = crystal_probe(pot, c, a, orient, eps, u, &ea, P, f, e);
        if (rc)
            return rc;
        double fn = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        if (fn < 1e-13)
            return 0;
        for (int d = 0; d < 3; d++)
            u[d] += f[d] / k;
    }
    return crystal_probe(pot, c, a, orient, eps, u, &ea, P, NULL, e);
}

int crystal_elastic_constants(struct potential *pot, const struct crystal_spec *c, double a,
                              struct crystal_elastic *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    const double h = 1e-5;
    double Pp[6], Pm[6], ea;
    double ep[3] = {h, 0, 0}, em[3] = {-h, 0, 0};
    int rc = crystal_energy(pot, c, a, NULL, ep, &ea, Pp, e);
    if (!rc)
        rc = crystal_energy(pot, c, a, NULL, em, &ea, Pm, e);
    if (rc)
        return rc;
    /* sigma = -P; the strain is engineering (box scaled by 1 + eps).
     * Strains along the cube axes move no site of these lattices off its
     * symmetric place: C11 and C12 need no relaxation. */
    out->c11 = -(Pp[0] - Pm[0]) / (2 * h);
    out->c12 = -(Pp[1] - Pm[1]) / (2 * h);
    /* uniaxial strain h along [110] (crystal [110] [-110] [001]): in the
     * cube axes eps_xx = eps_yy = eps_xy = h/2, so C'11 = (C11 + C12 + 2
     * C44) / 2 */
    static const int rot[3][3] = {{1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
    rc = crystal_energy(pot, c, a, rot, ep, &ea, Pp, e);
    if (!rc)
        rc = crystal_energy(pot, c, a, rot, em, &ea, Pm, e);
    if (rc)
        return rc;
    double c11r = -(Pp[0] - Pm[0]) / (2 * h);
    out->c44_unrelaxed = c11r - 0.5 * (out->c11 + out->c12);
    out->c44 = out->c44_unrelaxed;
    if (c->style != LATTICE_DIAMOND)
        return 0;   /* every site a centre of inversion: no internal strain */
    /* Diamond: the shear eps_xy pulls the two fcc sublattices apart along
     * z (Kleinman 1962).  The optical force constant k from +-du along z
     * of the unstrained crystal, then the shift that zeroes the force at
     * +-h, and the stress there (the relaxed C44, Cousins 1978). */
    const double du = 1e-4;
    double fp[3], fm[3], up[3] = {0, 0, du}, um[3] = {0, 0, -du};
    rc = crystal_probe(pot, c, a, rot, NULL, up, &ea, NULL, fp, e);
    if (!rc)
        rc = crystal_probe(pot, c, a, rot, NULL, um, &ea, NULL, fm, e);
    if (rc)
        return rc;
    double k = -(fp[2] - fm[2]) / (2 * du);
    if (!(k > 0))
        return err_set(e, ERR_RUNTIME,
                       "diamond: the sublattices are not held in place (optical force constant "
                       "%g eV/Å^2)",
                       k);
    double sp[3], sm[3];
    rc = relax_sublattice(pot, c, a, rot, ep, k, sp, Pp, e);
    if (!rc)
        rc = relax_sublattice(pot, c, a, rot, em, k, sm, Pm, e);
    if (rc)
        return rc;
    c11r = -(Pp[0] - Pm[0]) / (2 * h);
    out->c44 = c11r - 0.5 * (out->c11 + out->c12);
    /* u_z = -zeta (a/4) gamma_xy with gamma_xy = 2 eps_xy = h */
    out->zeta = -(sp[2] - sm[2]) / (2 * h) * 4 / a;
    out->optical_k = k;
    return 0;
}

int crystal_elastic_cubic(struct potential *pot, const struct crystal_spec *c, double a,
                          double *c11, double *c12, double *c44, struct err *e)
{
    struct crystal_elastic ce;
    int rc = crystal_elastic_constants(pot, c, a, &ce, e);
    *c11 = ce.c11;
    *c12 = ce.c12;
    *c44 = ce.c44;
    return rc;
}
