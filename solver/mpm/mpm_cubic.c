/*
 * mpm_cubic: cubic linear elasticity with the crystal axes along the box
 * axes (Guo & Yang 2005: C11, C12, C44 computed from the same potential as
 * the MD region, e.g. by the `crystal` case type).
 *
 *   law: cubic_elastic
 *   C11, C12, C44: elastic constants (GPa | Pa)
 *
 * mpm_material_cubic_elastic_rotated gives the same crystal with its axes
 * turned (the MPM side of a handshake along [110]): the stiffness tensor
 * C'_ijkl = R_ia R_jb R_kc R_ld C_abcd, which is orthotropic (not cubic)
 * in the box frame, kept as a full 6 x 6 Voigt matrix.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_material.h"

struct cubic {
    struct mpm_material base;
    double c11, c12, c44;   /* eV/Å^3, in the crystal frame */
    double C[6][6];         /* rotated: Voigt stiffness in the box frame (xx yy zz xy xz
                               yz; acting on engineering shears 2 eps_ij), eV/Å^3 */
};

static void cubic_update(const struct mpm_material *m, double s[6], const double de[6],
                         double *state)
{
    (void)state;
    const struct cubic *c = (const struct cubic *)m;
    s[0] += c->c11 * de[0] + c->c12 * (de[1] + de[2]);
    s[1] += c->c11 * de[1] + c->c12 * (de[0] + de[2]);
    s[2] += c->c11 * de[2] + c->c12 * (de[0] + de[1]);
    /* Voigt: sigma_xy = C44 * gamma_xy = C44 * 2 eps_xy */
    s[3] += 2 * c->c44 * de[3];
    s[4] += 2 * c->c44 * de[4];
    s[5] += 2 * c->c44 * de[5];
}

static void rotated_update(const struct mpm_material *m, double s[6], const double de[6],
                           double *state)
{
    (void)state;
    const struct cubic *c = (const struct cubic *)m;
    const double g[6] = {de[0], de[1], de[2], 2 * de[3], 2 * de[4], 2 * de[5]};
    for (int i = 0; i < 6; i++) {
        double ds = 0;
        for (int j = 0; j < 6; j++)
            ds += c->C[i][j] * g[j];
        s[i] += ds;
    }
}

static double cubic_wave_speed(const struct mpm_material *m)
{
    const struct cubic *c = (const struct cubic *)m;
    /* longitudinal moduli along <100>, <110>, <111>; the largest bounds all */
    double m100 = c->c11;
    double m110 = (c->c11 + c->c12 + 2 * c->c44) / 2;
    double m111 = (c->c11 + 2 * c->c12 + 4 * c->c44) / 3;
    double mx = fmax(m100, fmax(m110, m111));
    return sqrt(mx / m->density * UNITS_FTM2V);
}

static const struct mpm_material_ops cubic_ops = {
    "cubic_elastic", 0, cubic_update, cubic_wave_speed, NULL,
};
/* the largest longitudinal modulus of a cubic crystal does not depend on
 * how it is turned, so the CFL bound is cubic_wave_speed's */
static const struct mpm_material_ops rotated_ops = {
    "cubic_elastic", 0, rotated_update, cubic_wave_speed, NULL,
};

/* C_abcd of a cubic crystal in its own frame. */
static double cubic_tensor(const struct cubic *c, int a, int b, int p, int q)
{
    double v = 0;
    if (a == b && p == q)
        v += c->c12;
    if (a == p && b == q)   /* C44 (d_ap d_bq + d_aq d_bp): both terms when a = b */
        v += c->c44;
    if (a == q && b == p)
        v += c->c44;
    if (a == b && b == p && p == q)
        v += c->c11 - c->c12 - 2 * c->c44;
    return v;
}

struct mpm_material *mpm_material_cubic_elastic_rotated(const char *name, double density,
                                                        double c11, double c12, double c44,
                                                        const double R[3][3])
{
    struct mpm_material *m = mpm_material_cubic_elastic(name, density, c11, c12, c44);
    if (!m)
        return NULL;
    struct cubic *c = (struct cubic *)m;
    static const int pair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (int I = 0; I < 6; I++)
        for (int J = 0; J < 6; J++) {
            int i = pair[I][0], j = pair[I][1], k = pair[J][0], l = pair[J][1];
            double v = 0;
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    for (int p = 0; p < 3; p++)
                        for (int q = 0; q < 3; q++)
                            v += R[i][a] * R[j][b] * R[k][p] * R[l][q] *
                                 cubic_tensor(c, a, b, p, q);
            c->C[I][J] = fabs(v) < 1e-14 * c11 ? 0.0 : v;   /* round-off of the zeros */
        }
    c->base.ops = &rotated_ops;
    snprintf(c->base.description, sizeof c->base.description,
             "cubic elastic C11 = %g, C12 = %g, C44 = %g eV/Å^3, rotated (C'11 = %g, C'12 = "
             "%g, C'13 = %g)",
             c11, c12, c44, c->C[0][0], c->C[0][1], c->C[0][2]);
    return m;
}

void mpm_material_cubic_stiffness(const struct mpm_material *m, double C[6][6])
{
    const struct cubic *c = (const struct cubic *)m;
    if (m->ops == &rotated_ops) {
        memcpy(C, c->C, sizeof c->C);
        return;
    }
    memset(C, 0, 36 * sizeof C[0][0]);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            C[i][j] = i == j ? c->c11 : c->c12;
        C[3 + i][3 + i] = c->c44;
    }
}

struct mpm_material *mpm_material_cubic_elastic(const char *name, double density, double c11,
                                                double c12, double c44)
{
    struct cubic *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->base.ops = &cubic_ops;
    c->c11 = c11;
    c->c12 = c12;
    c->c44 = c44;
    mpm_material_base_init(&c->base, name, density);
    snprintf(c->base.description, sizeof c->base.description,
             "cubic elastic C11 = %g, C12 = %g, C44 = %g eV/Å^3", c11, c12, c44);
    return &c->base;
}

int mpm_cubic_create(struct cfg_obj *o, const struct mpm_units *u, double density,
                     struct mpm_material **out)
{
    double c11, c12, c44;
    int rc;
    if ((rc = cfg_real(o, "C11", CFG_REQUIRED, CFG_ANY, &c11)) ||
        (rc = cfg_real(o, "C12", CFG_REQUIRED, CFG_ANY, &c12)) ||
        (rc = cfg_real(o, "C44", CFG_REQUIRED, CFG_ANY, &c44)))
        return rc;
    /* Born stability of a cubic crystal */
    if (!(c44 > 0))
        return mpm_key_error(o, "C44", "C44 = %g must be positive", c44);
    if (!(c11 > fabs(c12)))
        return mpm_key_error(o, "C11", "C11 = %g must exceed |C12| = %g (Born stability)", c11,
                             fabs(c12));
    if (!(c11 + 2 * c12 > 0))
        return mpm_key_error(o, "C12",
                             "C11 + 2 C12 = %g must be positive (bulk modulus, Born stability)",
                             c11 + 2 * c12);
    if (o->cfg->shallow)
        return 0;
    struct cubic *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(o->cfg->err, "material");
    c->base.ops = &cubic_ops;
    c->c11 = c11 * u->stress;
    c->c12 = c12 * u->stress;
    c->c44 = c44 * u->stress;
    snprintf(c->base.description, sizeof c->base.description,
             "cubic elastic C11 = %g, C12 = %g, C44 = %g %s", c11, c12, c44, u->stress_name);
    (void)density;
    *out = &c->base;
    return 0;
}
