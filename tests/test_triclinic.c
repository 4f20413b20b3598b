/*
 * Triclinic (tilted) boxes: LAMMPS' restricted triclinic cell of
 * core/box.h through ghosts, neighbour lists, forces, virial and NVE.
 *
 * The reference for the forces is the same periodic crystal described in
 * an orthogonal box: the tilted cell a = (2L, 0, 0), b = (L, 2L, 0),
 * c = (L, L, L) (tilts xy = xz = yz = L, each at LAMMPS' limit of half
 * the length it is measured against, the most skewed cell allowed) holds
 * 4 L^3 of a cubic crystal of period L; its lattice contains the
 * orthogonal one of 2L x 4L x 4L, which holds 8 copies of the tilted cell
 * (the cosets of the two lattices).  The atoms of the tilted cell, each
 * randomly displaced, and their 8 copies give the same infinite system:
 * energy 8 times, forces and pressure tensor equal, up to round-off.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/box.h"
#include "core/elements.h"
#include "core/velocity.h"
#include "helpers/th.h"
#include "helpers/th_bricks.h"
#include "helpers/th_restart.h"
#include "input/config_read.h"
#include "output/lammps_data_write.h"

#define POT_MISHIN "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n"
#define POT_SW "style: sw\nfile: Si.sw\nelements: [Si]\n"

/* The cell vectors in units of L (columns a, b, c) and the orthogonal
 * supercell 2L x 4L x 4L. */
static const int tri_h[3][3] = {{2, 1, 1}, {0, 2, 1}, {0, 0, 1}};
static const int orth_n[3] = {2, 4, 4};

static unsigned xorshift(unsigned *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* Sites of an fcc (diamond: 8 sites) crystal of cube edge a, m cubes per
 * L, inside the tilted cell (fractional coordinates in [0, 1)), displaced
 * by up to `displace` Å; the box is set to the tilted cell. */
static struct particles *tilted_crystal(int diamond, double a, int m, const char *el,
                                        double displace, struct box *b)
{
    static const double fcc[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    double L = m * a;
    memset(b, 0, sizeof *b);
    for (int d = 0; d < 3; d++) {
        b->hi[d] = tri_h[d][d] * L;
        b->bc[d] = BOUNDARY_PERIODIC;
    }
    b->tilt[0] = tri_h[0][1] * L;
    b->tilt[1] = tri_h[0][2] * L;
    b->tilt[2] = tri_h[1][2] * L;
    struct particles *p = particles_create(256);
    int t = particles_type_index(p, el, element_mass(el));
    /* an offset keeps the sites off the faces of the cell */
    const double off[3] = {0.1234, 0.2345, 0.3456};
    int nb = diamond ? 8 : 4;
    int64_t id = 1;
    unsigned seed = 12345;
    for (int i = -4 * m; i < 4 * m; i++)
        for (int j = -4 * m; j < 4 * m; j++)
            for (int k = -2 * m; k < 2 * m; k++)
                for (int q = 0; q < nb; q++) {
                    const double *f = fcc[q % 4];
                    double sh = q >= 4 ? 0.25 : 0.0;
                    double x[3] = {(i + f[0] + sh) * a + off[0], (j + f[1] + sh) * a + off[1],
                                   (k + f[2] + sh) * a + off[2]};
                    double s[3];
                    box_to_fractional(b, x, s);
                    if (s[0] < 0 || s[0] >= 1 || s[1] < 0 || s[1] >= 1 || s[2] < 0 || s[2] >= 1)
                        continue;
                    for (int d = 0; d < 3; d++)
                        x[d] += displace * (2.0 * (xorshift(&seed) / 4294967296.0) - 1.0);
                    particles_add(p, x, NULL, t, id++);
                }
    cr_assert_eq(p->n_owned, 4 * m * m * m * nb, "%d sites in the tilted cell", p->n_owned);
    return p;
}

/* The same atoms with their 8 copies in the orthogonal 2L x 4L x 4L box:
 * copy k of atom id has id k * n + id. */
static struct particles *orthogonal_copies(const struct particles *t, double L, struct box *b)
{
    memset(b, 0, sizeof *b);
    for (int d = 0; d < 3; d++) {
        b->hi[d] = orth_n[d] * L;
        b->bc[d] = BOUNDARY_PERIODIC;
    }
    /* coset representatives: m1 a + m2 b + m3 c modulo the orthogonal
     * lattice, in units of L */
    int reps[64][3], nrep = 0;
    for (int m1 = 0; m1 < 2; m1++)
        for (int m2 = 0; m2 < 4; m2++)
            for (int m3 = 0; m3 < 4; m3++) {
                int v[3];
                for (int d = 0; d < 3; d++) {
                    int c = tri_h[d][0] * m1 + tri_h[d][1] * m2 + tri_h[d][2] * m3;
                    v[d] = c % orth_n[d];
                }
                int dup = 0;
                for (int r = 0; r < nrep; r++)
                    dup |= reps[r][0] == v[0] && reps[r][1] == v[1] && reps[r][2] == v[2];
                if (!dup)
                    memcpy(reps[nrep++], v, sizeof v);
            }
    cr_assert_eq(nrep, 8, "the orthogonal box holds 8 tilted cells (%d cosets)", nrep);
    struct particles *p = particles_create(8 * t->n_owned);
    int ty = particles_type_index(p, t->type_name[0], t->mass[0]);
    for (int r = 0; r < nrep; r++)
        for (int i = 0; i < t->n_owned; i++) {
            double x[3];
            for (int d = 0; d < 3; d++)
                x[d] = t->x[3 * i + d] + reps[r][d] * L;
            particles_add(p, x, NULL, ty, (int64_t)r * t->n_owned + t->id[i]);
        }
    return p;
}

static const double *force_of(const struct particles *p, int64_t id)
{
    for (int i = 0; i < p->n_owned; i++)
        if (p->id[i] == id)
            return p->f + 3 * i;
    cr_assert_fail("atom id %lld missing", (long long)id);
    return NULL;
}

static void same_system_in_both_boxes(int diamond, double a, int m, const char *el,
                                      const char *pot, double ftol)
{
    struct box bt, bo;
    struct particles *pt = tilted_crystal(diamond, a, m, el, 0.15, &bt);
    struct particles *po = orthogonal_copies(pt, m * a, &bo);
    int n = pt->n_owned;
    struct md mt, mo;
    th_md(&mt, pt, &bt, th_potential(pot), 2);   /* two threads: the same forces */
    th_md(&mo, po, &bo, th_potential(pot), 1);
    cr_assert(mt.p->n_ghost > 4 * n, "a skewed cell thinner than the range has several image "
              "layers (%d ghosts of %d atoms)", mt.p->n_ghost, n);
    double et = mt.last.energy, eo = mo.last.energy;
    cr_assert_lt(fabs(8 * et - eo), 1e-10 * fabs(eo), "%s: energy 8 x %.15g (tilted) against "
                 "%.15g (orthogonal)", el, et, eo);
    double fbig = 0;
    for (int k = 0; k < 8; k++)
        for (int i = 0; i < n; i++) {
            int64_t id = mt.p->id[i];
            const double *f1 = mt.p->f + 3 * i, *f2 = force_of(mo.p, (int64_t)k * n + id);
            for (int d = 0; d < 3; d++) {
                cr_assert_lt(fabs(f1[d] - f2[d]), ftol, "%s: atom %lld copy %d f%c %.15g "
                             "(tilted) %.15g (orthogonal)", el, (long long)id, k, "xyz"[d],
                             f1[d], f2[d]);
                fbig = fmax(fbig, fabs(f1[d]));
            }
        }
    cr_assert_gt(fbig, 0.1, "%s: the displaced crystal has forces (max %g eV/Å)", el, fbig);
    double Pt[6], Po[6];
    md_pressure_tensor(&mt, Pt);
    md_pressure_tensor(&mo, Po);
    for (int c = 0; c < 6; c++)
        cr_assert_lt(fabs(Pt[c] - Po[c]), 1e-12 + 1e-10 * fabs(Po[c]),
                     "%s: pressure component %d %.15g (tilted) %.15g (orthogonal) eV/Å^3", el, c,
                     Pt[c], Po[c]);
    md_free(&mt);
    md_free(&mo);
}

/* EAM (half list, two passes through the ghosts) and Stillinger-Weber
 * (full list, three-body): energy to 1e-10 relative, forces to 1e-9 eV/Å,
 * the pressure tensor (off-diagonal included) to 1e-10 relative. */
Test(triclinic, sheared_fcc_cu_equals_its_orthogonal_supercell)
{
    same_system_in_both_boxes(0, 3.615, 2, "Cu", POT_MISHIN, 1e-9);
}

Test(triclinic, sheared_diamond_si_equals_its_orthogonal_supercell)
{
    same_system_in_both_boxes(1, 5.431, 1, "Si", POT_SW, 1e-9);
}

/* Two Lennard-Jones atoms that meet only across the tilted c face (the
 * image x2 - c moves x and y by xz and yz): the energy and force are those
 * of the pair at that image's distance; an atom crossing the face wraps by
 * -c with its z image flag counting, and its unwrapped position does not
 * jump. */
Test(triclinic, pair_across_the_tilted_face_and_wrap)
{
    struct box b = {{0, 0, 0}, {10, 10, 10}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC,
                                              BOUNDARY_PERIODIC}, {3, 4, -2}};
    double s1[3] = {0.5, 0.5, 0.02}, s2[3] = {0.58, 0.43, 0.95};
    double h[3][3], x1[3] = {0}, x2[3] = {0};
    box_cell_matrix(&b, h);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            x1[r] += h[r][c] * s1[c];
            x2[r] += h[r][c] * s2[c];
        }
    /* the image of atom 2 below the c face: x2 - c */
    double dv[3] = {x1[0] - (x2[0] - b.tilt[1]), x1[1] - (x2[1] - b.tilt[2]), x1[2] - (x2[2] - 10)};
    double r = sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
    double md_[3] = {x1[0] - x2[0], x1[1] - x2[1], x1[2] - x2[2]};
    box_min_image(&b, md_);
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(md_[d] - dv[d]), 1e-12, "minimum image %c", "xyz"[d]);
    /* r = 0.9 of the LJ minimum 2^(1/6) sigma: repulsive */
    const double eps = 0.0104, sig = r / (0.9 * pow(2.0, 1.0 / 6.0)), rc = 2.0 * sig;
    cr_assert(2.0 * sig < 5.0, "only the image across the face is within the cutoff");
    char pot[256];
    snprintf(pot, sizeof pot, "style: lj\nelements: [Ar]\nepsilon: %.17g\nsigma: %.17g\ncutoff: "
             "%.17g\n", eps, sig, rc);
    struct particles *p = particles_create(4);
    int t = particles_type_index(p, "Ar", element_mass("Ar"));
    particles_add(p, x1, NULL, t, 1);
    particles_add(p, x2, NULL, t, 2);
    struct md md;
    th_md(&md, p, &b, th_potential(pot), 1);
    double sr6 = pow(sig / r, 6), src6 = pow(sig / rc, 6);
    double e_ref = 4 * eps * (sr6 * sr6 - sr6) - 4 * eps * (src6 * src6 - src6);
    double fr = 24 * eps * (2 * sr6 * sr6 - sr6) / r;   /* -dE/dr, repulsive > 0 */
    cr_assert_lt(fabs(md.last.energy - e_ref), 1e-12 * fabs(e_ref), "E %.15g, LJ(r = %.6f Å) "
                 "%.15g", md.last.energy, r, e_ref);
    cr_assert_gt(fr, 0, "r = 0.9 r_min: repulsive");
    const double *f1 = force_of(md.p, 1), *f2 = force_of(md.p, 2);
    for (int d = 0; d < 3; d++) {
        cr_assert_lt(fabs(f1[d] - fr * dv[d] / r), 1e-10 * fr, "f1%c", "xyz"[d]);
        cr_assert_lt(fabs(f2[d] + fr * dv[d] / r), 1e-10 * fr, "f2%c", "xyz"[d]);
    }
    /* virial W = r (x) f of the pair: P_xy = W_xy / V */
    double Ps[6];
    md_pressure_tensor(&md, Ps);
    cr_assert_lt(fabs(Ps[3] * 1000.0 - fr * dv[0] * dv[1] / r), 1e-10 * fr, "P_xy V");
    md_free(&md);

    /* wrap: an atom just below the top face moves up through it */
    struct particles *q = particles_create(2);
    int tq = particles_type_index(q, "Ar", element_mass("Ar"));
    double s[3] = {0.3, 0.7, 0.999}, x[3] = {0};
    for (int rr = 0; rr < 3; rr++)
        for (int c = 0; c < 3; c++)
            x[rr] += h[rr][c] * s[c];
    particles_add(q, x, NULL, tq, 1);
    double u0[3], u1[3];
    box_unwrap(&b, q, 0, u0);
    q->x[2] += 0.05;   /* s_z = 1.004: outside */
    u0[2] += 0.05;
    struct err e = {0};
    cr_assert_eq(box_remap(&b, q, 0.0, &e), 0, "%s", e.msg);
    cr_assert_eq(q->image[2], 1, "the z image flag counts the c edge");
    cr_assert_eq(q->image[0], 0);
    cr_assert_eq(q->image[1], 0);
    cr_assert_lt(fabs(q->x[0] - (x[0] - b.tilt[1])), 1e-12, "x moves by -xz");
    cr_assert_lt(fabs(q->x[1] - (x[1] - b.tilt[2])), 1e-12, "y moves by -yz");
    box_unwrap(&b, q, 0, u1);
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(u1[d] - u0[d]), 1e-12, "unwrapped %c continuous", "xyz"[d]);
    double sf[3];
    box_to_fractional(&b, q->x, sf);
    for (int d = 0; d < 3; d++)
        cr_assert(sf[d] >= 0 && sf[d] < 1, "inside: s%c = %g", "xyz"[d], sf[d]);
    particles_destroy(&q);
}

/* NVE in the most skewed cell: 128 Cu atoms at 1200 K, velocity Verlet at
 * 1 fs over 0.5 ps, against the same atoms and velocities in the
 * orthogonal supercell (8 copies, the same trajectory): the total energy
 * per atom of the two runs agrees to 1e-9 eV/atom at every step (a missed
 * or doubled image pair would differ by ~0.1 eV/atom at once), stays
 * within 1e-4 eV/atom of its start (velocity Verlet's fluctuation at this
 * step and temperature is ~4e-5), momentum stays zero, and atoms cross
 * the tilted faces (image flags change). */
Test(triclinic, nve_energy_conserved_in_a_tilted_box)
{
    struct box bt, bo;
    struct particles *pt = tilted_crystal(0, 3.615, 2, "Cu", 0.0, &bt);
    struct err e = {0};
    struct potential *pot = th_potential(POT_MISHIN);
    cr_assert_eq(potential_bind(pot, pt, &e), 0, "%s", e.msg);
    cr_assert_eq(velocity_maxwell(pt, 1200.0, 42, 1u, &e), 0, "%s", e.msg);
    struct particles *po = orthogonal_copies(pt, 2 * 3.615, &bo);
    int n = pt->n_owned;
    for (int i = 0; i < po->n_owned; i++)   /* copy k of atom i is atom k n + i */
        memcpy(po->v + 3 * i, pt->v + 3 * (i % n), 3 * sizeof(double));
    struct md mt, mo;
    th_md(&mt, pt, &bt, pot, 1);
    th_md(&mo, po, &bo, th_potential(POT_MISHIN), 1);
    double e0 = (mt.last.energy + md_kinetic_energy(&mt)) / n, dmax = 0, dpair = 0;
    for (int s = 0; s < 500; s++) {
        cr_assert_eq(md_step(&mt, &e), 0, "%s", e.msg);
        cr_assert_eq(md_step(&mo, &e), 0, "%s", e.msg);
        double et = (mt.last.energy + md_kinetic_energy(&mt)) / n;
        double eo = (mo.last.energy + md_kinetic_energy(&mo)) / (8 * n);
        dmax = fmax(dmax, fabs(et - e0));
        dpair = fmax(dpair, fabs(et - eo));
    }
    cr_assert_lt(dpair, 1e-9, "tilted and orthogonal runs differ by %.3g eV/atom", dpair);
    cr_assert_lt(dmax, 1e-4, "max |E - E0| = %.3g eV/atom", dmax);
    double mom[3];
    md_momentum(&mt, mom);
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(mom[d]), 1e-9, "momentum %c %g", "xyz"[d], mom[d]);
    cr_assert_gt(md_temperature(&mt), 300.0, "still hot: %g K", md_temperature(&mt));
    int crossed = 0;
    for (int i = 0; i < n; i++)
        crossed += mt.p->image[3 * i] || mt.p->image[3 * i + 1] || mt.p->image[3 * i + 2];
    cr_assert_gt(crossed, 0, "some atoms crossed a face of the cell");
    cr_assert_gt(mt.nrebuilds, 2, "the lists were rebuilt (%ld)", mt.nrebuilds);
    md_free(&mt);
    md_free(&mo);
}

/* --- read_data: the tilt line ------------------------------------------- */

static const char *data_file(const char *name, const char *tilt_line, const char *extra_atom)
{
    static char text[2048];
    snprintf(text, sizeof text,
             "tilted\n\n2 atoms\n1 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n0 10 zlo zhi\n%s\n"
             "\nMasses\n\n1 63.546 # Cu\n\nAtoms # atomic\n\n1 1 1 1 1 0 0 0\n%s\n"
             "\nVelocities\n\n1 0.5 -1 2\n2 1 2 3\n",
             tilt_line, extra_atom);
    return th_write_temp(6, name, text);
}

static int read_with(const char *path, const struct config_rules *r, struct box *b,
                     struct particles **pp, struct err *e)
{
    *pp = particles_create(8);
    return config_read_lammps_data(path, NULL, 0, r, *pp, b, e);
}

Test(triclinic, read_data_takes_the_tilt_and_unwraps_with_it)
{
    const char *path = data_file("ok.data", "2.5 -1 4 xy xz yz", "2 1 5 6 9.5 1 -1 2");
    struct box b = {0};
    struct particles *p;
    struct err e = {0};
    cr_assert_eq(read_with(path, NULL, &b, &p, &e), 0, "%s", e.msg);
    cr_assert_eq(b.tilt[0], 2.5);
    cr_assert_eq(b.tilt[1], -1.0);
    cr_assert_eq(b.tilt[2], 4.0);
    cr_assert_eq(p->v[3 * 1 + 2], 3.0);
    double u[3];
    box_unwrap(&b, p, 1, u);
    /* x + 1 a - 1 b + 2 c: a = (10,0,0), b = (2.5,10,0), c = (-1,4,10) */
    cr_assert_lt(fabs(u[0] - (5 + 10 - 2.5 - 2)), 1e-12, "x %g", u[0]);
    cr_assert_lt(fabs(u[1] - (6 - 10 + 8)), 1e-12, "y %g", u[1]);
    cr_assert_lt(fabs(u[2] - (9.5 + 20)), 1e-12, "z %g", u[2]);
    particles_destroy(&p);
}

static void refused(const char *name, const char *tilt_line, const struct config_rules *r,
                    const char *want)
{
    const char *path = data_file(name, tilt_line, "2 1 5 5 5");
    struct box b = {0};
    struct particles *p;
    struct err e = {0};
    cr_assert_neq(read_with(path, r, &b, &p, &e), 0, "%s is read", name);
    char full[1200];
    snprintf(full, sizeof full, "%s:9: %s", path, want);
    cr_assert(strstr(e.msg, full), "%s\nwant: %s", e.msg, full);
    particles_destroy(&p);
}

Test(triclinic, read_data_refuses_bad_tilt_lines_at_their_line)
{
    refused("word.data", "0 1.5x 0 xy xz yz", NULL,
            "xy xz yz: tilt factor xz must be a finite decimal number, found '1.5x'");
    refused("nan.data", "nan 0 0 xy xz yz", NULL,
            "xy xz yz: tilt factor xy must be a finite decimal number, found 'nan'");
    refused("huge.data", "0 1e999 0 xy xz yz", NULL,
            "xy xz yz: tilt factor xz must be a finite decimal number, found '1e999'");
    refused("xy.data", "5.5 0 0 xy xz yz", NULL, "xy xz yz: tilt xy = 5.5 is more than half the "
            "box length lx = 10");
    refused("yz.data", "0 0 -5.01 xy xz yz", NULL, "xy xz yz: tilt yz = -5.01 is more than half "
            "the box length ly = 10");
    struct config_rules r = config_rules_default();
    r.bc[2] = BOUNDARY_FREE;
    refused("free.data", "1 0 0 xy xz yz", &r, "xy xz yz: a tilted box (xy xz yz = 1 0 0) is "
            "simulated periodic along x, y and z only; z is free");
    r = config_rules_default();
    r.allow_tilt = 0;
    r.who = "case type dpd";
    refused("dpd.data", "0 1 0 xy xz yz", &r, "xy xz yz: tilt xz = 1: case type dpd simulates "
            "orthogonal boxes only");
    /* tilt 0 0 0 is the orthogonal box, for every case type */
    const char *path = data_file("zero.data", "0 0 0 xy xz yz", "2 1 5 5 5");
    struct box b = {0};
    struct particles *p;
    struct err e = {0};
    cr_assert_eq(read_with(path, &r, &b, &p, &e), 0, "%s", e.msg);
    cr_assert(!box_tilted(&b));
    particles_destroy(&p);
}

/* --- the case file: type md runs it, serially, on replicated data and on
 * bricks; other types refuse it -- */

/* A tilted crystal (fcc, or diamond), m cubes of edge a per L, at 600 K,
 * written with Cascade's own data writer. */
static const char *write_tilted_crystal(const char *name, int diamond, double a, int m,
                                        const char *el)
{
    struct box b;
    struct particles *p = tilted_crystal(diamond, a, m, el, 0.05, &b);
    struct err e = {0};
    cr_assert_eq(velocity_maxwell(p, 600.0, 9, 1u, &e), 0, "%s", e.msg);
    static char path[1200];
    snprintf(path, sizeof path, "%s/%s", th_temp_dir(), name);
    cr_assert_eq(lammps_data_write(path, p, &b, "tilted crystal", &e), 0, "%s", e.msg);
    particles_destroy(&p);
    return path;
}

/* The small tilted Cu cell (L = 7.23 Å, 128 atoms). */
static const char *write_tilted_data(const char *name)
{
    return write_tilted_crystal(name, 0, 3.615, 2, "Cu");
}

#define TILTED_CASE                                                                               \
    "system: {read_data: %s, elements: [Cu]}\n"                                                  \
    "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"                                \
    "md: {steps: 40, timestep: 0.001}\noutput: {thermo_every: 10, final_state: end.data}\n"

/* Serial and replicated data on 2 ranks (auto: a note says why not bricks:
 * the small cell is 11.8 x 10.2 x 7.23 Å high across its faces, no brick
 * of half of it holds the range) give the same thermo to 1e-10 of each
 * column's largest value; the final state keeps the tilt line; bricks
 * asked for are refused at the key. */
Test(triclinic, md_case_serial_and_replicated_mpi, .timeout = 300)
{
    const char *data = write_tilted_data("mpi.data");
    char yaml[2048], dir1[1200], dir2[1200], out[16384];
    snprintf(yaml, sizeof yaml, TILTED_CASE, data);
    const char *cpath = th_write_temp(0, "tilted.yaml", yaml);
    snprintf(dir1, sizeof dir1, "%s/serial", th_temp_dir());
    snprintf(dir2, sizeof dir2, "%s/np2", th_temp_dir());
    thb_must_run(cpath, 0, dir1, NULL);
    int rc = thb_run(cpath, 2, dir2, NULL, out, sizeof out);
    cr_assert_eq(rc, 0, "mpirun -np 2: exit %d\n%s", rc, out);
    cr_assert(strstr(out, "note: the tilted box, 11.8065 x 10.2248 x 7.23 Å high across its "
                          "faces, has no grid of 2 bricks at least"),
              "%s", out);
    static const char *const cols[] = {"pe_eV", "etotal_eV", "temp_K", "press_GPa", NULL};
    thb_compare_series(dir1, dir2, cols, 1e-10, "tilted np 2");
    char text[65536];
    thb_read_text(dir1, "end.data", text, sizeof text);
    cr_assert(strstr(text, "\n7.2300000000000004 7.2300000000000004 7.2300000000000004 xy xz yz\n"),
              "end.data keeps the tilt:\n%.400s", text);

    char yb[2100];
    snprintf(yb, sizeof yb, "%sparallel: {decomposition: bricks}\n", yaml);
    const char *bpath = th_write_temp(1, "bricks.yaml", yb);
    snprintf(dir2, sizeof dir2, "%s/bricks", th_temp_dir());
    rc = thb_run(bpath, 2, dir2, NULL, out, sizeof out);
    cr_assert_neq(rc, 0, "bricks of a tilted box ran:\n%s", out);
    char want[1400];
    snprintf(want, sizeof want, "%s:5:", bpath);
    cr_assert(strstr(out, want) && strstr(out, "parallel.decomposition: no grid of 2 bricks of "
                                               "the tilted box, 11.8065 x 10.2248 x 7.23 Å high "
                                               "across its faces, is at least"),
              "%s", out);
}

/* On bricks a tilted box is cut in its fractional coordinates, and a
 * periodic face ships ghosts by the cell's edge vectors (core/decomp.h,
 * core/halo.h): the tilted Cu cell four times the small one's edge (L =
 * 14.46 Å, 1024 atoms at 600 K; 23.6 x 20.4 x 14.5 Å high across its
 * faces) runs 100 steps on 2, 4 and 8 ranks, and with shifted cuts moving
 * every 10 steps on 2, with the serial run's thermo to 1e-10 of each
 * column's largest value.  EAM takes the half shell, Stillinger-Weber
 * silicon (a tilted diamond cell, 512 atoms) the full one with its
 * three-body terms, on 2 and 4 ranks. */
static void tilted_bricks_match_serial(const char *stem, const char *data, const char *el,
                                       const char *pot, const int *nps, int nnp,
                                       const char *balance)
{
    char yaml[2048], dir1[1200], dirn[1200], tag[128];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s, elements: [%s]}\npotential: {%s}\n"
             "md: {steps: 100, timestep: 0.001%s}\noutput: {thermo_every: 10}\n",
             data, el, pot, balance ? ", skin: 0.3" : "");
    char name[128];
    snprintf(name, sizeof name, "%s.yaml", stem);
    const char *cpath = th_write_temp(5, name, yaml);
    snprintf(dir1, sizeof dir1, "%s/%s-serial", th_temp_dir(), stem);
    thb_must_run(cpath, 0, dir1, NULL);
    static const char *const cols[] = {"pe_eV", "etotal_eV", "temp_K", "press_GPa", NULL};
    char yb[2300];
    snprintf(yb, sizeof yb, "%sparallel: {decomposition: bricks%s}\n", yaml,
             balance ? balance : "");
    snprintf(name, sizeof name, "%s-bricks.yaml", stem);
    const char *bpath = th_write_temp(6, name, yb);
    for (int k = 0; k < nnp; k++) {
        snprintf(dirn, sizeof dirn, "%s/%s-%d", th_temp_dir(), stem, nps[k]);
        thb_must_run(bpath, nps[k], dirn, NULL);
        thb_assert_bricks(dirn, nps[k], NULL);
        snprintf(tag, sizeof tag, "tilted %s on %d ranks", stem, nps[k]);
        thb_compare_series(dir1, dirn, cols, 1e-10, tag);
        if (!balance)
            continue;
        json_t *r = thb_result(dirn);
        json_t *par = json_object_get(r, "parallel");
        long shifts = (long)json_integer_value(json_object_get(par, "balance_shifts"));
        json_decref(r);
        cr_assert_gt(shifts, 0, "%s: the cuts never moved", tag);
    }
}

Test(triclinic, md_case_on_bricks_matches_serial, .timeout = 600)
{
    const char *data = write_tilted_crystal("br.data", 0, 3.615, 4, "Cu");
    const char *pot = "style: eam/alloy, file: Cu_mishin1.eam.alloy";
    const int nps[] = {2, 4, 8}, two[] = {2};
    tilted_bricks_match_serial("br", data, "Cu", pot, nps, 3, NULL);
    /* shifted cuts moved at every check (a thin skin: a list build, and
     * so a check, every few steps) */
    tilted_bricks_match_serial("brs", data, "Cu", pot, two, 1,
                               ", balance: shift, balance_every: 10, balance_threshold: 1.0");
}

static void compare_tilted(const char *ref, const char *dir, const char *tag)
{
    static const char *const cols[] = {"pe_eV", "etotal_eV", "temp_K", "press_GPa", NULL};
    thb_compare_series(ref, dir, cols, 1e-10, tag);
}

/* A checkpoint of the tilted cell written on 2 ranks (bricks: each rank
 * writes its own atoms, the tilt with the box) restarts on 1, 2 and 4
 * ranks onto the serial run, 2 to 2 bit for bit (tests/helpers/th_bricks.h,
 * thb_checkpoint_moves). */
Test(triclinic, checkpoint_on_bricks_moves_between_rank_counts, .timeout = 600)
{
    const char *data = write_tilted_crystal("ck.data", 0, 3.615, 4, "Cu");
    char yaml[2048];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 100, timestep: 0.001}\n"
             "output: {thermo_every: 10, snapshot_every: 100, checkpoint_every: 50}\n",
             data);
    const char *path = th_write_temp(7, "ck.yaml", yaml);
    thb_checkpoint_moves(path, "tilted", compare_tilted, "the tilted cell");
}

Test(triclinic, sw_silicon_on_bricks_matches_serial, .timeout = 600)
{
    const char *data = write_tilted_crystal("sw.data", 1, 5.431, 2, "Si");
    const int nps[] = {2, 4};
    tilted_bricks_match_serial("sw", data, "Si", "style: sw, file: Si.sw, elements: [Si]", nps, 2,
                               NULL);
}

/* A case type without tilted images refuses the file at its tilt line. */
Test(triclinic, structure_case_refuses_a_tilted_file)
{
    const char *data = write_tilted_data("st.data");
    char yaml[2048], out[4096];
    snprintf(yaml, sizeof yaml,
             "type: structure\nsystem: {read_data: %s, elements: [Cu]}\n"
             "analysis: {structure: {reference: fcc, lattice_constant: 3.615}}\n",
             data);
    const char *cpath = th_write_temp(2, "st.yaml", yaml);
    const char *argv[] = {th_solver(), "run", cpath, "--out", th_temp_dir(), "--quiet", NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 2, "exit %d: %s", rc, out);
    char want[1400];
    /* title, blank, 2 counts, blank, 3 bounds, then the tilt */
    snprintf(want, sizeof want, "%s:9: xy xz yz: tilt xy = 7.23: case type structure simulates "
             "orthogonal boxes only (tilt 0 0 0)", data);
    cr_assert(strstr(out, want), "%s\nwant: %s", out, want);
}

/* A tilted run killed and restarted from its checkpoint (which stores the
 * tilt) continues bitwise (tests/test_restart.c). */
Test(triclinic, restart_continues_bitwise, .timeout = 300)
{
    const char *data = write_tilted_data("rs.data");
    char yaml[2048];
    snprintf(yaml, sizeof yaml,
             "seed: 3\nsystem: {read_data: %s, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 120, timestep: 0.002, thermostat: {style: langevin, temperature: 500, "
             "tau: 0.1}}\n"
             "output: {thermo_every: 20, snapshot_every: 60, checkpoint_every: 40}\n",
             data);
    static const char *const fields[] = {"position", "velocity", "force", NULL};
    const char *const kills[] = {"70", NULL};
    th_kill_and_restart(yaml, kills, 1, "particles", fields);
}

/* What other tools read: fields.h5 cell/tilt (the file's, bitwise), the
 * XDMF outline's far corner lo + a + b + c, the extended XYZ Lattice as
 * ASE reads it (cell rows a, b, c; Debian's python3-ase), and the XYZ
 * final state read back by Cascade. */
static const char *const ase_cell =
    "import sys\nimport ase.io\n"
    "a = ase.io.read(sys.argv[1], index=-1)\n"
    "print('cell', *['%.17g' % c for c in a.cell.array.ravel()])\n"
    "print('volume %.17g' % a.get_volume())\n"
    "print('pbc', *[int(b) for b in a.pbc])\n";

Test(triclinic, fields_h5_xdmf_and_xyz_carry_the_tilt, .timeout = 120)
{
    const char *data = write_tilted_data("out.data");
    char yaml[2048], dir[1200], out[8192];
    snprintf(yaml, sizeof yaml,
             "system: {read_data: %s, elements: [Cu]}\n"
             "potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}\n"
             "md: {steps: 2}\noutput: {xyz_every: 1, snapshot_every: 2, final_state: end.xyz}\n",
             data);
    const char *cpath = th_write_temp(3, "out.yaml", yaml);
    snprintf(dir, sizeof dir, "%s/out", th_temp_dir());
    thb_must_run(cpath, 0, dir, NULL);
    const double L = 2 * 3.615, lx = 2 * L, ly = 2 * L, lz = L;

    long n;
    double *tilt = thb_read_h5(dir, "/particles/00000000/cell/tilt", H5T_NATIVE_DOUBLE,
                               sizeof(double), &n);
    double *lo = thb_read_h5(dir, "/particles/00000000/cell/lo", H5T_NATIVE_DOUBLE,
                             sizeof(double), &n);
    for (int d = 0; d < 3; d++)
        cr_assert_eq(tilt[d], L, "cell/tilt %d: %.17g", d, tilt[d]);

    /* XDMF: corner 7 of the cell_0 polyline */
    char xdmf[65536];
    thb_read_text(dir, "fields.xdmf", xdmf, sizeof xdmf);
    const char *g = strstr(xdmf, "<Grid Name=\"cell_0\"");
    cr_assert_not_null(g, "no cell_0 grid");
    g = strstr(g, "<Geometry");
    cr_assert_not_null(g);
    g = strstr(g, "Format=\"XML\">");
    cr_assert_not_null(g);
    g += strlen("Format=\"XML\">");
    double c[24];
    for (int k = 0; k < 24; k++) {
        char *end;
        c[k] = strtod(g, &end);
        cr_assert(end != g, "corner %d", k / 3);
        g = end;
    }
    const double far[3] = {lo[0] + lx + L + L, lo[1] + ly + L, lo[2] + lz};
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(c[21 + d] - far[d]), 1e-12, "outline corner lo + a + b + c %c: %.17g",
                     "xyz"[d], c[21 + d]);
    free(tilt);
    free(lo);

    /* ASE: cell rows a, b, c */
    char xyz[1300];
    snprintf(xyz, sizeof xyz, "%s/snapshots.xyz", dir);
    const char *script = th_write_temp(4, "cell.py", ase_cell);
    const char *argv[] = {"/usr/bin/python3", script, xyz, NULL};
    int rc = th_run(argv, out, sizeof out);
    cr_assert_eq(rc, 0, "ase could not read %s (exit %d): %s", xyz, rc, out);
    double cell[9], vol;
    int pbc[3];
    cr_assert_eq(sscanf(out, "cell %lf %lf %lf %lf %lf %lf %lf %lf %lf\nvolume %lf\npbc %d %d %d",
                        &cell[0], &cell[1], &cell[2], &cell[3], &cell[4], &cell[5], &cell[6],
                        &cell[7], &cell[8], &vol, &pbc[0], &pbc[1], &pbc[2]),
                 13, "%s", out);
    const double want[9] = {lx, 0, 0, L, ly, 0, L, L, lz};
    for (int k = 0; k < 9; k++)
        cr_assert_lt(fabs(cell[k] - want[k]), 1e-9 * lx, "ASE cell[%d][%d] %.12g, want %.12g",
                     k / 3, k % 3, cell[k], want[k]);
    cr_assert_lt(fabs(vol - lx * ly * lz), 1e-9 * vol, "ASE volume %.12g", vol);
    cr_assert(pbc[0] && pbc[1] && pbc[2]);

    /* the XYZ final state read back */
    char end[1300];
    snprintf(end, sizeof end, "%s/end.xyz", dir);
    struct particles *p = particles_create(8);
    struct box b = {0};
    int bpbc[3];
    struct err e = {0};
    cr_assert_eq(config_read_extxyz(end, NULL, p, &b, bpbc, &e), 0, "%s", e.msg);
    cr_assert_eq(p->n_owned, 128);
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(b.tilt[d] - L), 1e-9 * L, "end.xyz tilt %d: %.12g", d, b.tilt[d]);
    particles_destroy(&p);
}
