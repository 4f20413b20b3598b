/* handshake_crystal: the crystal the MPM side must match -- lattice
 * constant, cohesive energy and C11, C12, C44 from the same potential as
 * the MD (Guo & Yang 2005, section 2.2: "these constants can be derived
 * from the atomic potential and then are used in the MPM region") -- and
 * the cubic lattices the handshake lays out. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/elements.h"
#include "couple/handshake.h"
#include "md/crystal.h"

const char *const hs_lattice_names[] = {"fcc", "bcc", "diamond", NULL};

int hs_lattice_basis(enum hs_lattice l, double basis[8][3])
{
    static const double fcc[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    int n = 0;
    switch (l) {
    case HS_LATTICE_BCC:
        memset(basis, 0, 2 * sizeof basis[0]);
        for (int d = 0; d < 3; d++)
            basis[1][d] = 0.5;
        return 2;
    case HS_LATTICE_DIAMOND:   /* fcc and fcc + (1/4, 1/4, 1/4) */
        for (int b = 0; b < 4; b++)
            for (int d = 0; d < 3; d++) {
                basis[b][d] = fcc[b][d];
                basis[4 + b][d] = fcc[b][d] + 0.25;
            }
        return 8;
    case HS_LATTICE_FCC:
    default:
        for (int b = 0; b < 4; b++, n++)
            memcpy(basis[b], fcc[b], sizeof fcc[b]);
        return n;
    }
}

double hs_lattice_offset(enum hs_lattice l)
{
    return l == HS_LATTICE_DIAMOND ? 0.125 : 0.25;
}

const char *const hs_orientation_names[] = {"100", "110", NULL};

void hs_orientation_axes(enum hs_orientation o, double R[3][3])
{
    memset(R, 0, 9 * sizeof R[0][0]);
    if (o == HS_ORIENT_110) {
        const double s = sqrt(0.5);
        R[0][0] = s;    /* x: [110]  */
        R[0][1] = s;
        R[1][0] = -s;   /* y: [-110] */
        R[1][1] = s;
        R[2][2] = 1;    /* z: [001]  */
        return;
    }
    for (int d = 0; d < 3; d++)
        R[d][d] = 1;
}

int hs_cell_basis(enum hs_lattice l, enum hs_orientation o, double basis[8][3],
                  double period[3])
{
    if (o != HS_ORIENT_110) {
        for (int d = 0; d < 3; d++)
            period[d] = 1;
        return hs_lattice_basis(l, basis);
    }
    /* the cube sites turned by 45 degrees about z: x' = (x + y)/sqrt2,
     * y' = (y - x)/sqrt2.  fcc: a body-centred cell a/sqrt2 x a/sqrt2 x a
     * (2 sites); diamond: that and the same shifted by (1/4, 1/4, 1/4) a,
     * i.e. (a/(2 sqrt2), 0, a/4) (4 sites); bcc: a face-centred cell
     * sqrt2 a x sqrt2 a x a (4 sites) */
    static const double fcc[2][3] = {{0, 0, 0}, {0.5, 0.5, 0.5}};
    static const double dia[4][3] = {{0, 0, 0}, {0.5, 0.5, 0.5}, {0.5, 0, 0.25}, {0, 0.5, 0.75}};
    static const double bcc[4][3] = {{0, 0, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}, {0.5, 0.5, 0}};
    const double s = l == HS_LATTICE_BCC ? sqrt(2.0) : sqrt(0.5);
    period[0] = period[1] = s;
    period[2] = 1;
    const double(*src)[3] = l == HS_LATTICE_BCC ? bcc : l == HS_LATTICE_DIAMOND ? dia : fcc;
    int n = l == HS_LATTICE_FCC ? 2 : 4;
    memcpy(basis, src, (size_t)n * sizeof basis[0]);
    return n;
}

double hs_cell_offset(enum hs_lattice l, enum hs_orientation o, int d)
{
    double basis[8][3], period[3];
    int n = hs_cell_basis(l, o, basis, period);
    for (int b = 0; b < n; b++) {
        double f = 4 * basis[b][d];
        if (fabs(f - round(f)) < 1e-9 && ((long)round(f) & 1))
            return 0.125;   /* a site at a quarter edge */
    }
    return 0.25;
}

void hs_oriented_moduli(enum hs_orientation o, double c11, double c12, double c44, double *cl,
                        double *cxy, double *cxz)
{
    if (o == HS_ORIENT_110) {
        *cl = 0.5 * (c11 + c12 + 2 * c44);
        *cxy = 0.5 * (c11 + c12 - 2 * c44);
        *cxz = c12;
        return;
    }
    *cl = c11;
    *cxy = *cxz = c12;
}

int hs_sublattice(const struct handshake_layout *L, const double axes[3][3],
                  const double x0[3])
{
    if (L->lattice != HS_LATTICE_DIAMOND)
        return 0;
    const double(*R)[3] = axes;
    double r[3];
    for (int d = 0; d < 3; d++)
        r[d] = x0[d] - L->lat_origin[d];
    /* 4/a times the cube coordinates: even on the first sublattice, odd
     * (summing to 3 mod 4, i.e. at +(1, 1, 1) a/4 from it) on the second */
    long n[3], sum = 0;
    int odd = 0;
    for (int k = 0; k < 3; k++) {
        double c = 4 * (R[0][k] * r[0] + R[1][k] * r[1] + R[2][k] * r[2]) / L->a;
        n[k] = lround(c);
        if (fabs(c - (double)n[k]) > 1e-6)
            return 0;
        odd += (int)(n[k] & 1);
        sum += n[k];
    }
    if (odd == 0)
        return -1;
    return odd == 3 && ((sum % 4) + 4) % 4 == 3 ? 1 : 0;
}

void hs_internal_shift(const struct handshake_layout *L, const double axes[3][3], double zeta,
                       int sublattice, const double F[9], double dx[3])
{
    dx[0] = dx[1] = dx[2] = 0;
    if (!sublattice || zeta == 0)
        return;
    /* small strain in the box, then in the cube axes: eps_c = R^T eps R */
    const double(*R)[3] = axes;
    double eps[3][3], ec[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            eps[i][j] = 0.5 * (F[3 * i + j] + F[3 * j + i]) - (i == j);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double s = 0;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    s += R[i][a] * eps[i][j] * R[j][b];
            ec[a][b] = s;
        }
    /* u = -zeta (a/4) (gamma_yz, gamma_xz, gamma_xy), gamma = 2 eps; this
     * site moves by +-u/2 */
    const double f = -zeta * L->a / 4 * 2 * 0.5 * sublattice;
    double uc[3] = {f * ec[1][2], f * ec[0][2], f * ec[0][1]};
    for (int i = 0; i < 3; i++)
        dx[i] = R[i][0] * uc[0] + R[i][1] * uc[1] + R[i][2] * uc[2];
}

static enum lattice_style lattice_style_of(enum hs_lattice l)
{
    return l == HS_LATTICE_BCC ? LATTICE_BCC : l == HS_LATTICE_DIAMOND ? LATTICE_DIAMOND
                                                                         : LATTICE_FCC;
}

int handshake_crystal_of_lattice(struct potential *pot, enum hs_lattice lattice,
                                 const char *element, double a_min, double a_max,
                                 struct handshake_crystal *cr, double *a0, struct err *e)
{
    memset(cr, 0, sizeof *cr);
    snprintf(cr->element, sizeof cr->element, "%s", element);
    for (int k = 0; k < pot->nelements; k++)
        if (strcmp(pot->element[k], element) == 0)
            cr->mass = pot->mass[k];
    if (!(cr->mass > 0))
        cr->mass = element_mass(element);
    if (!(cr->mass > 0))
        return err_set(e, ERR_INPUT, "no mass for element '%s'", element);
    /* C44 of diamond is the relaxed one, the MD's own response to a shear
     * (md/crystal.h); zeta places the copies of regions II and III */
    struct crystal_spec spec = {lattice_style_of(lattice), cr->element, cr->mass, 3};
    double ecoh;
    struct crystal_elastic ce;
    int rc = crystal_equilibrium(pot, &spec, a_min, a_max, a0, &ecoh, e);
    if (!rc)
        rc = crystal_elastic_constants(pot, &spec, *a0, &ce, e);
    if (!rc) {
        cr->c11 = ce.c11;
        cr->c12 = ce.c12;
        cr->c44 = ce.c44;
        cr->c44_unrelaxed = ce.c44_unrelaxed;
        cr->zeta = ce.zeta;
    }
    cr->pe_ref = -ecoh;
    return rc;
}

int handshake_crystal_zeta_at(struct potential *pot, enum hs_lattice lattice,
                              const struct handshake_crystal *cr, double a, double *zeta,
                              struct err *e)
{
    *zeta = 0;
    if (lattice != HS_LATTICE_DIAMOND)
        return 0;
    /* the static relaxation at the expanded lattice: the thermal mean of
     * the sublattice shift under a shear is this to first order in the
     * anharmonicity (quasi-harmonic), as a(T) is the thermal part */
    struct crystal_spec spec = {lattice_style_of(lattice), cr->element, cr->mass, 3};
    struct crystal_elastic ce;
    int rc = crystal_elastic_constants(pot, &spec, a, &ce, e);
    if (!rc)
        *zeta = ce.zeta;
    return rc;
}

int handshake_crystal_from_potential(struct potential *pot, const char *element, double a_min,
                                     double a_max, struct handshake_crystal *cr, double *a0,
                                     struct err *e)
{
    return handshake_crystal_of_lattice(pot, HS_LATTICE_FCC, element, a_min, a_max, cr, a0, e);
}
