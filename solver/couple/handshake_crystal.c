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
    /* C11 and C12 come from strains along the cube axes, which move no
     * site of these lattices off its symmetric position; C44 of diamond is
     * the unrelaxed one (crystal.h), which the [100] cases do not use */
    struct crystal_spec spec = {lattice_style_of(lattice), cr->element, cr->mass, 3};
    double ecoh;
    int rc = crystal_equilibrium(pot, &spec, a_min, a_max, a0, &ecoh, e);
    if (!rc)
        rc = crystal_elastic_cubic(pot, &spec, *a0, &cr->c11, &cr->c12, &cr->c44, e);
    cr->pe_ref = -ecoh;
    return rc;
}

int handshake_crystal_from_potential(struct potential *pot, const char *element, double a_min,
                                     double a_max, struct handshake_crystal *cr, double *a0,
                                     struct err *e)
{
    return handshake_crystal_of_lattice(pot, HS_LATTICE_FCC, element, a_min, a_max, cr, a0, e);
}
