/*
 * Agreement with LAMMPS to round-off on the same configuration and file.
 *
 * tests/data/cu256.data: 4x4x4 fcc Cu, a = 3.615 Å, displaced by up to
 * 0.1 Å.  Reference values from Debian's LAMMPS (29 Sep 2021) with
 *   pair_style eam/alloy; pair_coeff * * Cu_mishin1.eam.alloy Cu   (setfl)
 *   pair_style eam;       pair_coeff * * Cu_u3.eam                 (funcfl)
 *   thermo_style custom step pe press pxx pyy pzz pxy pxz pyz; run 0
 *   dump custom id fx fy fz (format %.15g)
 * Pressures are in bar there (1 eV/Å^3 = 1.6021766208e6 bar).
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>

#include "helpers/th.h"
#include "input/config_read.h"

struct lmp_ref {
    const char *pot;
    double pe;
    double P[6];   /* bar: xx yy zz xy xz yz */
    int ids[4];
    double f[4][3];
};

static const struct lmp_ref mishin = {
    "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n",
    -896.542338245357,
    {16788.6586707177, 16364.6564756361, 17127.9459263355, -544.592418649536, -1071.85242976471,
     -498.454897588829},
    {1, 2, 128, 256},
    {{-0.66701603511603, -0.0628155278669595, -0.340822154386592},
     {0.0925058525660809, 0.603997182431162, -0.0886302166358168},
     {-0.470297242225235, 0.00994752165264901, 0.343082108282696},
     {-0.58198020115734, -0.700775979868155, 0.0468567771020199}}};

static const struct lmp_ref u3 = {
    "style: eam\nfile: Cu_u3.eam\n",
    -896.960862496048,
    {16078.7449390529, 15755.9270387998, 16246.3111868076, -397.363481212612, -854.827789806888,
     -442.57970562171},
    {1, 2, 128, 256},
    {{-0.633378433283304, -0.0647032233734925, -0.310778746816732},
     {0.0899971837003011, 0.567815283592683, -0.0791746883482934},
     {-0.443428279086823, 0.0107198255726106, 0.334099277342938},
     {-0.552378100136546, -0.677782724073214, 0.0524443042009388}}};

static void compare(const struct lmp_ref *ref)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/cu256.data", th_root());
    struct particles *p = particles_create(300);
    struct box box = {0};
    struct err e = {0};
    cr_assert_eq(config_read_lammps_data(path, NULL, 0, NULL, p, &box, &e), 0, "%s", e.msg);
    for (int d = 0; d < 3; d++)
        box.bc[d] = BOUNDARY_PERIODIC;
    cr_assert_eq(p->n_owned, 256);
    struct md md;
    th_md(&md, p, &box, th_potential(ref->pot), 1);
    cr_assert_lt(fabs(md.last.energy - ref->pe), 1e-9 * fabs(ref->pe), "pe %.15g vs LAMMPS %.15g",
                 md.last.energy, ref->pe);
    double P[6];
    md_pressure_tensor(&md, P);
    for (int k = 0; k < 6; k++) {
        double bar = P[k] * 1.6021766208e6;
        cr_assert_lt(fabs(bar - ref->P[k]), 1e-6 * fabs(ref->P[0]), "P[%d] %.12g vs %.12g bar", k,
                     bar, ref->P[k]);
    }
    for (int a = 0; a < 4; a++)
        for (int i = 0; i < md.p->n_owned; i++)
            if (md.p->id[i] == ref->ids[a])
                for (int d = 0; d < 3; d++)
                    cr_assert_lt(fabs(md.p->f[3 * i + d] - ref->f[a][d]), 1e-10,
                                 "atom %d f%c %.15g vs LAMMPS %.15g", ref->ids[a], "xyz"[d],
                                 md.p->f[3 * i + d], ref->f[a][d]);
    md_free(&md);
}

Test(lammps, setfl_mishin_energy_forces_pressure) { compare(&mishin); }
Test(lammps, funcfl_u3_energy_forces_pressure) { compare(&u3); }
