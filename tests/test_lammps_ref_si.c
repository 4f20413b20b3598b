/*
 * Silicon potentials against LAMMPS on the same configuration and file:
 * energy, pressure tensor and forces to round-off for the spline MEAM of
 * Lenosky et al. (meam/spline, Si_1.meam.spline) and Stillinger-Weber; and
 * the two-element Stillinger-Weber of GaN (GaN.sw, whose mixed entries have
 * sigma = a = 0) on tests/data/gan64.data: zincblende GaN, 2x2x2 cells of
 * a = 4.52 Å, every coordinate displaced by up to 0.12 Å (Python's random,
 * seed 7), types 1 Ga and 2 N, pair_coeff * * GaN.sw Ga N.
 *
 * tests/data/si216.data: 3x3x3 diamond Si, a = 5.431 Å, every coordinate
 * displaced by up to 0.15 Å (xorshift32, seed 12345).  Reference values
 * from Debian's LAMMPS (29 Sep 2021 - Update 2) with
 *   units metal; atom_style atomic; boundary p p p; read_data si216.data
 *   pair_style meam/spline; pair_coeff * * Si_1.meam.spline Si
 *   (or pair_style sw; pair_coeff * * Si.sw Si)
 *   thermo_style custom step pe press pxx pyy pzz pxy pxz pyz
 *   thermo_modify format float %.15g
 *   dump d all custom 1 f id fx fy fz; dump_modify d format float %.15g sort id
 *   run 0
 * Pressures are in bar there; this LAMMPS converts with 1 eV/Å^3 = 1.6021765e6
 * bar (its metal-units nktv2p), so that factor is used here.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>

#include "helpers/th.h"
#include "input/config_read.h"

struct lmp_ref {
    const char *data;   /* tests/data/ */
    int natoms;
    const char *pot;
    double pe;
    double P[6];   /* bar: xx yy zz xy xz yz */
    int ids[4];
    double f[4][3];
};

static const struct lmp_ref meam = {
    "si216.data", 216,
    "style: meam/spline\nfile: Si_1.meam.spline\nelements: [Si]\n",
    -960.752141461617,
    {-1252.86659833677, -2721.72125477559, -3295.11942135988, -2676.48702427921, -780.9180595971,
     4242.5882494247},
    {1, 2, 109, 216},
    {{-1.47805523755044, 0.084959593800904, -0.963204305314098},
     {-0.723699408711707, 0.0103494408852286, -1.12622133508619},
     {0.0750692039575869, 0.879704823422112, -0.877531066891536},
     {-2.59930826919275, -3.51878637949272, 0.628547334833997}}};

static const struct lmp_ref sw = {
    "si216.data", 216,
    "style: sw\nfile: Si.sw\nelements: [Si]\n",
    -891.143098616966,
    {16531.2590812784, 14892.2271993397, 14431.7134153998, -4058.13135479232, -804.169150543003,
     4366.53614004205},
    {1, 2, 109, 216},
    {{-1.93797074357964, 0.207531967138548, -1.40392100947786},
     {-1.13374672919764, 0.0563895189268608, -1.7583059061915},
     {0.152902191018864, 1.24234752492827, -1.1939542541604},
     {-3.34322821722262, -4.69971505515792, 0.275190839834147}}};

static const struct lmp_ref sw_gan = {
    "gan64.data", 64,
    "style: sw\nfile: GaN.sw\nelements: [Ga, N]\n",
    -261.905551384905,
    {36021.0930663894, 36693.3684253389, 32447.5971381637, 619.859906682298, 19616.7144556142,
     -11196.1861049076},
    {1, 2, 33, 64},
    {{0.722235896711311, 2.224568812012, -1.93058930724398},
     {0.734107102223971, -0.50876963687172, -0.170272988580105},
     {-1.90361614170709, -5.99941878904412, -5.50180267449607},
     {2.43271260125884, 5.69181191055393, 4.41066006947448}}};

static void compare(const struct lmp_ref *ref, int nthreads)
{
    static const char *const elements[] = {"Ga", "N"};
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/%s", th_root(), ref->data);
    struct particles *p = particles_create(300);
    struct box box = {0};
    struct err e = {0};
    int two = ref == &sw_gan;
    cr_assert_eq(config_read_lammps_data(path, two ? elements : NULL, two ? 2 : 0, NULL, p, &box,
                                         &e),
                 0, "%s", e.msg);
    for (int d = 0; d < 3; d++)
        box.bc[d] = BOUNDARY_PERIODIC;
    cr_assert_eq(p->n_owned, ref->natoms);
    struct md md;
    th_md(&md, p, &box, th_potential(ref->pot), nthreads);
    cr_assert_lt(fabs(md.last.energy - ref->pe), 1e-9 * fabs(ref->pe), "pe %.15g vs LAMMPS %.15g",
                 md.last.energy, ref->pe);
    double P[6];
    md_pressure_tensor(&md, P);
    for (int k = 0; k < 6; k++) {
        double bar = P[k] * 1.6021765e6;
        cr_assert_lt(fabs(bar - ref->P[k]), 1e-6, "P[%d] %.12g vs %.12g bar", k, bar, ref->P[k]);
    }
    int found = 0;
    for (int a = 0; a < 4; a++)
        for (int i = 0; i < md.p->n_owned; i++)
            if (md.p->id[i] == ref->ids[a]) {
                found++;
                for (int d = 0; d < 3; d++)
                    cr_assert_lt(fabs(md.p->f[3 * i + d] - ref->f[a][d]), 1e-9,
                                 "atom %d f%c %.15g vs LAMMPS %.15g", ref->ids[a], "xyz"[d],
                                 md.p->f[3 * i + d], ref->f[a][d]);
            }
    cr_assert_eq(found, 4);
    md_free(&md);
}

Test(lammps, meam_spline_si_energy_forces_pressure) { compare(&meam, 1); }
Test(lammps, meam_spline_si_two_threads) { compare(&meam, 2); }
Test(lammps, sw_si_energy_forces_pressure) { compare(&sw, 1); }
Test(lammps, sw_si_two_threads) { compare(&sw, 2); }
Test(lammps, sw_gan_two_elements_energy_forces_pressure) { compare(&sw_gan, 1); }
