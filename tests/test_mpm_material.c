/*
 * Constitutive laws of the MPM (Chen 2014, s13-s14), driven one point at a
 * time through the same update the solver uses:
 *
 * - isotropic linear elastic: uniaxial strain gives sigma_xx = (lambda +
 *   2 mu) eps, sigma_yy = lambda eps; shear gives 2 mu eps_xy;
 * - cubic elastic: C11, C12 on the diagonal, C44 for shear (Voigt);
 * - J2 with linear hardening: elastic up to the yield stress in pure shear,
 *   then the von Mises stress follows sigma_y + H eps_p, and the plastic
 *   strain accumulates at the rate the consistency condition gives;
 * - Jaumann rate: a stress carried through a rigid rotation of 90 degrees
 *   is rotated with it and keeps its invariants; without it, it is not;
 * - wave speeds for the CFL condition and the registry's laws.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_material.h"
#include "mpm/mpm_points.h"
#include "mpm/mpm_stress.h"

struct point {
    double s[6], F[9], vol, eint, state[MPM_MAX_STATE];
};

static void point_init(struct point *p)
{
    memset(p, 0, sizeof *p);
    p->F[0] = p->F[4] = p->F[8] = 1;
    p->vol = 1;
}

static void drive(const struct mpm_material *m, struct point *p, const double L[9], double dt,
                  int steps)
{
    for (int k = 0; k < steps; k++)
        mpm_point_stress(m, L, dt, p->s, p->F, &p->vol, 1.0, &p->eint, p->state);
}

Test(mpm_material, isotropic_elastic_moduli)
{
    double E = 2.0, nu = 0.3;
    struct mpm_material *m = mpm_material_linear_elastic("s", 1.0, E, nu);
    double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    struct point p;
    point_init(&p);
    double L[9] = {1e-4, 0, 0, 0, 0, 0, 0, 0, 0};
    drive(m, &p, L, 1.0, 10);   /* eps_xx = 1e-3 in 10 increments */
    cr_assert(fabs(p.s[0] - (lambda + 2 * mu) * 1e-3) < 1e-12, "sxx %g", p.s[0]);
    cr_assert(fabs(p.s[1] - lambda * 1e-3) < 1e-12 && fabs(p.s[2] - lambda * 1e-3) < 1e-12);
    /* the logarithmic strain of F = 1 + 1e-4 ten times is 10 ln(1 + 1e-4) */
    struct mpm_points pts = {.n = 1, .F = p.F};
    double eps[6];
    mpm_points_strain(&pts, 0, eps);
    cr_assert(fabs(eps[0] - 10 * log1p(1e-4)) < 1e-14 && fabs(eps[1]) < 1e-15, "eps %g", eps[0]);
    /* stored energy = 1/2 sigma eps V to the accuracy of the volume change */
    cr_assert(fabs(p.eint - 0.5 * (lambda + 2 * mu) * 1e-6) < 2e-3 * p.eint, "eint %g", p.eint);
    /* F and volume follow */
    cr_assert(fabs(p.F[0] - pow(1 + 1e-4, 10)) < 1e-12 && fabs(p.vol - p.F[0]) < 1e-12);
    /* pure shear: symmetric L gives no spin */
    point_init(&p);
    double Ls[9] = {0, 1e-4, 0, 1e-4, 0, 0, 0, 0, 0};
    drive(m, &p, Ls, 1.0, 5);
    cr_assert(fabs(p.s[3] - 2 * mu * 5e-4) < 1e-12, "sxy %g", p.s[3]);
    cr_assert(fabs(p.s[0]) < 1e-12);
    double c = m->ops->wave_speed(m);
    cr_assert(fabs(c - sqrt((lambda + 2 * mu) / 1.0 * UNITS_FTM2V)) < 1e-9 * c);
    mpm_material_destroy(&m);
}

Test(mpm_material, cubic_elastic_constants)
{
    double c11 = 1.1, c12 = 0.75, c44 = 0.5;
    struct mpm_material *m = mpm_material_cubic_elastic("cu", 1.0, c11, c12, c44);
    struct point p;
    point_init(&p);
    double L[9] = {0, 0, 0, 0, 2e-4, 0, 0, 0, 0};   /* eps_yy */
    drive(m, &p, L, 1.0, 1);
    cr_assert(fabs(p.s[1] - c11 * 2e-4) < 1e-15 && fabs(p.s[0] - c12 * 2e-4) < 1e-15 &&
              fabs(p.s[2] - c12 * 2e-4) < 1e-15);
    point_init(&p);
    m->jaumann = 0;
    double Ls[9] = {0, 0, 0, 0, 0, 3e-4, 0, 0, 0};   /* dv_y/dz: eps_yz = 1.5e-4 */
    drive(m, &p, Ls, 1.0, 1);
    cr_assert(fabs(p.s[5] - c44 * 3e-4) < 1e-15, "syz %g (C44 gamma)", p.s[5]);
    /* the fastest longitudinal wave of this crystal runs along <111> */
    double m111 = (c11 + 2 * c12 + 4 * c44) / 3;
    cr_assert(fabs(m->ops->wave_speed(m) - sqrt(m111 * UNITS_FTM2V)) < 1e-12);
    mpm_material_destroy(&m);
}

Test(mpm_material, j2_yield_and_linear_hardening)
{
    double E = 1.0, nu = 0.25, sy = 2e-3, H = 0.1;
    struct mpm_material *m = mpm_material_j2("s", 1.0, E, nu, sy, H);
    m->jaumann = 0;
    double mu = E / (2 * (1 + nu));
    struct point p;
    point_init(&p);
    /* pure shear in small increments: q = sqrt(3) |sigma_xy| */
    double L[9] = {0, 1e-5, 0, 1e-5, 0, 0, 0, 0, 0};
    double gamma_y = sy / sqrt(3) / mu;   /* engineering shear strain at yield */
    int n_el = (int)floor(gamma_y / 2e-5) - 1;
    drive(m, &p, L, 1.0, n_el);
    cr_assert(p.state[0] == 0, "yielded too early");
    cr_assert(fabs(p.s[3] - mu * 2e-5 * n_el) < 1e-14, "elastic shear stress");
    drive(m, &p, L, 1.0, 2000);   /* gamma = 0.04: well into the plastic range */
    double q = sqrt(3.0) * fabs(p.s[3]);
    cr_assert(p.state[0] > 0.01, "plastic strain %g", p.state[0]);
    cr_assert(fabs(q - (sy + H * p.state[0])) < 1e-12, "von Mises %g vs yield %g", q,
              sy + H * p.state[0]);
    /* total equivalent strain sqrt(3) eps_xy splits as q/(3 mu) + eps_p */
    double eq_total = 0.5 * (2e-5 * (n_el + 2000)) * 2 / sqrt(3);
    cr_assert(fabs(eq_total - (q / (3 * mu) + p.state[0])) < 1e-9, "strain split");
    mpm_material_destroy(&m);
}

/* A rigid counter-clockwise rotation about z at rate w by `turns` x 90 degrees. */
static void rotate(struct mpm_material *m, struct point *p, double turns)
{
    double w = 1.0;
    int n = (int)(2000 * turns);
    double dt = M_PI / 2 / w / 2000;
    double L[9] = {0, -w, 0, w, 0, 0, 0, 0, 0};   /* v = w (-y, x): dv_x/dy = -w */
    drive(m, p, L, dt, n);
}

Test(mpm_material, jaumann_rate_rotates_stress_with_the_body)
{
    struct mpm_material *m = mpm_material_linear_elastic("s", 1.0, 1.0, 0.3);
    struct point p;
    point_init(&p);
    p.s[0] = 1e-3;   /* uniaxial sigma_xx */
    rotate(m, &p, 0.5);
    /* at 45 degrees counter-clockwise the tension lies along (1, 1) */
    cr_assert(fabs(p.s[0] - 5e-4) < 1e-6 && fabs(p.s[1] - 5e-4) < 1e-6 &&
                  fabs(p.s[3] - 5e-4) < 1e-6,
              "45 degrees: %g %g %g", p.s[0], p.s[1], p.s[3]);
    rotate(m, &p, 0.5);
    /* after 90 degrees the tension points along y */
    cr_assert(fabs(p.s[1] - 1e-3) < 1e-6 && fabs(p.s[0]) < 1e-6 && fabs(p.s[3]) < 1e-6,
              "rotated stress %g %g %g", p.s[0], p.s[1], p.s[3]);
    cr_assert(fabs(p.s[0] + p.s[1] + p.s[2] - 1e-3) < 1e-15, "trace changed");
    double norm = 0;
    for (int k = 0; k < 6; k++)
        norm += (k < 3 ? 1 : 2) * p.s[k] * p.s[k];
    cr_assert(fabs(sqrt(norm) - 1e-3) < 1e-15, "|sigma| changed: exact rotation expected");
    /* the rotation did no work and made (almost) no strain: F <- (I + L dt) F
     * is first order, its stretch grows by (w dt)^2 / 2 per step: 6e-4 here */
    struct mpm_points pts = {.n = 1, .F = p.F};
    double eps[6];
    mpm_points_strain(&pts, 0, eps);
    cr_assert(fabs(p.eint) < 1e-12, "work %g", p.eint);
    for (int k = 0; k < 6; k++)
        cr_assert(fabs(eps[k]) < 1e-3, "rigid rotation strained: eps[%d] = %g", k, eps[k]);
    /* without an objective rate the stress stays along x: wrong */
    m->jaumann = 0;
    point_init(&p);
    p.s[0] = 1e-3;
    rotate(m, &p, 1.0);
    cr_assert(fabs(p.s[0] - 1e-3) < 1e-12 && fabs(p.s[1]) < 1e-12);
    mpm_material_destroy(&m);
}

Test(mpm_material, registry_has_the_three_laws)
{
    const char *want[] = {"linear_elastic", "cubic_elastic", "j2"};
    for (int k = 0; k < 3; k++) {
        int found = 0;
        for (int i = 0; mpm_material_styles[i].law; i++)
            found |= strcmp(mpm_material_styles[i].law, want[k]) == 0;
        cr_assert(found, "law %s not registered", want[k]);
    }
}
