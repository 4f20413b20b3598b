/*
 * Forces equal minus the finite-difference gradient of the energy, for
 * every potential, on a randomly displaced crystal; the virial pressure
 * equals minus the finite-difference volume derivative of the energy.
 * Derivatives use the 5-point stencil (error O(h^4)), h = 1e-4 Å.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "helpers/th.h"

#define POT_MISHIN "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n"
#define POT_U3 "style: eam\nfile: Cu_u3.eam\n"
#define POT_SC "style: sutton_chen\n"
#define POT_LJ "style: lj\nelements: [Ar]\nepsilon: 0.0104\nsigma: 3.4\ncutoff: 8.5\n"
#define POT_SW "style: sw\nfile: Si.sw\nelements: [Si]\n"
#define POT_MEAMS "style: meam/spline\nfile: Si_1.meam.spline\nelements: [Si]\n"

/* Relative error ||F_fd - F|| / ||F|| over all components of a few atoms. */
static double force_fd_error(const char *potyaml, enum lattice_style style, double a, long n,
                             const char *el, double displace)
{
    struct box box = {0};
    struct particles *p = th_crystal(style, a, n, el, displace, 12345, &box);
    struct md md;
    th_md(&md, p, &box, th_potential(potyaml), 1);
    const double h = 1e-4;
    double num = 0, den = 0;
    int natoms = md.p->n_owned;
    for (int s = 0; s < 5; s++) {
        int i = (int)((long)s * natoms / 5);
        int64_t id = md.p->id[i];
        for (int d = 0; d < 3; d++) {
            th_energy(&md);
            for (int k = 0; k < md.p->n_owned; k++)
                if (md.p->id[k] == id)
                    i = k;
            double f = md.p->f[3 * i + d];
            double x0 = md.p->x[3 * i + d];
            double E[4];
            const double off[4] = {-2 * h, -h, h, 2 * h};
            for (int q = 0; q < 4; q++) {
                for (int k = 0; k < md.p->n_owned; k++)
                    if (md.p->id[k] == id)
                        i = k;
                md.p->x[3 * i + d] = x0 + off[q];
                E[q] = th_energy(&md);
            }
            for (int k = 0; k < md.p->n_owned; k++)
                if (md.p->id[k] == id)
                    i = k;
            md.p->x[3 * i + d] = x0;
            double dEdx = (E[0] - 8 * E[1] + 8 * E[2] - E[3]) / (12 * h);
            num += (f + dEdx) * (f + dEdx);
            den += f * f;
        }
    }
    md_free(&md);
    cr_assert(den > 1e-6, "forces vanish: the test would prove nothing");
    return sqrt(num / den);
}

Test(forces, eam_setfl_mishin_matches_fd)
{
    double err = force_fd_error(POT_MISHIN, LATTICE_FCC, 3.615, 3, "Cu", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

Test(forces, eam_funcfl_u3_matches_fd)
{
    double err = force_fd_error(POT_U3, LATTICE_FCC, 3.615, 3, "Cu", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

Test(forces, sutton_chen_matches_fd)
{
    double err = force_fd_error(POT_SC, LATTICE_FCC, 3.61, 3, "Cu", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

Test(forces, lennard_jones_matches_fd)
{
    double err = force_fd_error(POT_LJ, LATTICE_FCC, 5.26, 3, "Ar", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

Test(forces, stillinger_weber_matches_fd)
{
    double err = force_fd_error(POT_SW, LATTICE_DIAMOND, 5.431, 2, "Si", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

Test(forces, meam_spline_matches_fd)
{
    double err = force_fd_error(POT_MEAMS, LATTICE_DIAMOND, 5.431, 2, "Si", 0.15);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

/* Compressed (pairs inside the first knot) and with the angular spline
 * beyond its last knot: the linear continuation must stay consistent. */
Test(forces, meam_spline_compressed_matches_fd)
{
    double err = force_fd_error(POT_MEAMS, LATTICE_DIAMOND, 4.6, 2, "Si", 0.3);
    cr_assert_lt(err, 1e-6, "relative force error %g", err);
}

/* P = -dE/dV under a uniform scaling of box and positions. */
static void pressure_check(const char *potyaml, enum lattice_style style, double a, long n,
                           const char *el)
{
    double E[4], V[4], P0 = 0;
    const double h = 1e-5;
    const double s[4] = {-2 * h, -h, h, 2 * h};
    for (int q = -1; q < 4; q++) {
        struct box box = {0};
        struct particles *p = th_crystal(style, a, n, el, 0.1, 777, &box);
        double scale = q < 0 ? 1.0 : 1.0 + s[q];
        for (int i = 0; i < p->n_owned; i++)
            for (int d = 0; d < 3; d++)
                p->x[3 * i + d] *= scale;
        for (int d = 0; d < 3; d++)
            box.hi[d] *= scale;
        struct md md;
        th_md(&md, p, &box, th_potential(potyaml), 1);
        double vol = box_volume(&md.box);
        if (q < 0) {
            P0 = (md.last.virial[0] + md.last.virial[1] + md.last.virial[2]) / (3 * vol);
        } else {
            E[q] = md.last.energy;
            V[q] = vol;
        }
        md_free(&md);
    }
    /* dE/dV by the chain rule through the scale factor */
    double dEds = (E[0] - 8 * E[1] + 8 * E[2] - E[3]) / (12 * h);
    double V0 = V[1] / pow(1 - h, 3);
    double dVds = 3 * V0;
    double Pfd = -dEds / dVds;
    cr_assert(fabs(P0) > 1e-4, "pressure too small to test (%g eV/Å^3)", P0);
    cr_assert_lt(fabs(Pfd - P0) / fabs(P0), 1e-6, "virial %g vs -dE/dV %g eV/Å^3", P0, Pfd);
}

Test(pressure, eam_virial_is_minus_dE_dV) { pressure_check(POT_MISHIN, LATTICE_FCC, 3.58, 3, "Cu"); }
Test(pressure, funcfl_virial_is_minus_dE_dV) { pressure_check(POT_U3, LATTICE_FCC, 3.58, 3, "Cu"); }
Test(pressure, sutton_chen_virial_is_minus_dE_dV) { pressure_check(POT_SC, LATTICE_FCC, 3.55, 3, "Cu"); }
Test(pressure, lj_virial_is_minus_dE_dV) { pressure_check(POT_LJ, LATTICE_FCC, 5.2, 3, "Ar"); }
Test(pressure, sw_virial_is_minus_dE_dV) { pressure_check(POT_SW, LATTICE_DIAMOND, 5.40, 2, "Si"); }
Test(pressure, meam_spline_virial_is_minus_dE_dV) { pressure_check(POT_MEAMS, LATTICE_DIAMOND, 5.40, 2, "Si"); }
