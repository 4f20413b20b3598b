/*
 * MD engine: NVE energy conservation and momentum, neighbour lists against
 * brute force, thread-count independence, thermostats.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>

#include "core/ghost.h"
#include "core/units.h"
#include "helpers/th.h"
#include "core/velocity.h"

#define POT_MISHIN "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n"

/* NVE, 300 K Cu, 1 fs, 10,000 steps: relative total-energy drift < 1e-5,
 * momentum conserved to round-off.  (600 K initial velocities equilibrate
 * to about 300 K by equipartition.) */
Test(md, nve_energy_drift_and_momentum, .timeout = 600)
{
    struct box box = {0};
    struct particles *p = th_crystal(LATTICE_FCC, 3.615, 4, "Cu", 0.0, 1, &box);
    struct err e = {0};
    struct potential *pot = th_potential(POT_MISHIN);
    cr_assert_eq(potential_bind(pot, p, &e), 0);
    cr_assert_eq(velocity_maxwell(p, 600.0, 42, 1u, &e), 0);
    struct md md;
    th_md(&md, p, &box, pot, 1);
    md.dt = 0.001;
    double e0 = md.last.energy + md_kinetic_energy(&md);
    double P0[3];
    md_momentum(&md, P0);
    double pscale = 0;
    for (int i = 0; i < md.p->n_owned; i++)
        pscale += md.p->mass[0] * sqrt(md.p->v[3 * i] * md.p->v[3 * i]);
    double emin = e0, emax = e0, tsum = 0;
    for (int s = 0; s < 10000; s++) {
        cr_assert_eq(md_step(&md, &e), 0, "%s", e.msg);
        double et = md.last.energy + md_kinetic_energy(&md);
        emin = fmin(emin, et);
        emax = fmax(emax, et);
        if (s >= 5000)
            tsum += md_temperature(&md);
    }
    double e1 = md.last.energy + md_kinetic_energy(&md);
    double tmean = tsum / 5000;
    cr_assert(tmean > 250 && tmean < 350, "mean temperature %g K is not about 300 K", tmean);
    cr_assert_lt(fabs(e1 - e0) / fabs(e0), 1e-5, "drift %g", fabs(e1 - e0) / fabs(e0));
    cr_assert_lt((emax - emin) / fabs(e0), 1e-5, "fluctuation %g", (emax - emin) / fabs(e0));
    double P1[3];
    md_momentum(&md, P1);
    for (int d = 0; d < 3; d++)
        cr_assert_lt(fabs(P1[d] - P0[d]), 1e-10 * pscale, "momentum %c: %g -> %g", "xyz"[d],
                     P0[d], P1[d]);
    md_free(&md);
}

static int cmp_int(const void *a, const void *b)
{
    return *(const int *)a - *(const int *)b;
}

/* Every listed pair (as a sorted set of (owned, neighbour id+image) keys)
 * equals the brute-force set (p with its ghosts built). */
static void compare_with_brute(struct particles *p, double cutoff, double skin,
                               enum nlist_kind kind)
{
    struct err e = {0};
    struct nlist *a = nlist_create(kind, cutoff, skin), *b = nlist_create(kind, cutoff, skin);
    cr_assert_eq(nlist_build(a, p, &e), 0);
    cr_assert_eq(nlist_build_brute(b, p, &e), 0);
    long total = 0;
    for (int i = 0; i < p->n_owned; i++) {
        int na = a->offset[i + 1] - a->offset[i], nb = b->offset[i + 1] - b->offset[i];
        cr_assert_eq(na, nb, "atom %d: %d neighbours vs %d brute force", i, na, nb);
        int *la = malloc((size_t)(na + 1) * sizeof *la), *lb = malloc((size_t)(nb + 1) * sizeof *lb);
        for (int k = 0; k < na; k++) {
            la[k] = a->neigh[a->offset[i] + k];
            lb[k] = b->neigh[b->offset[i] + k];
        }
        qsort(la, (size_t)na, sizeof *la, cmp_int);
        qsort(lb, (size_t)nb, sizeof *lb, cmp_int);
        for (int k = 0; k < na; k++)
            cr_assert_eq(la[k], lb[k]);
        free(la);
        free(lb);
        total += na;
    }
    cr_assert_gt(total, 0);
    /* a half list holds each physical pair once: twice the half count equals
     * the full count */
    if (kind == NLIST_HALF) {
        struct nlist *f = nlist_create(NLIST_FULL, cutoff, skin);
        cr_assert_eq(nlist_build(f, p, &e), 0);
        cr_assert_eq(2 * total, (long)f->offset[p->n_owned]);
        nlist_destroy(&f);
    }
    nlist_destroy(&a);
    nlist_destroy(&b);
}

/* uniform positions in box b (xorshift from seed *s) */
static void add_uniform(struct particles *p, const double lo[3], const double hi[3], int n,
                        unsigned *s, int64_t *id)
{
    for (int i = 0; i < n; i++) {
        double x[3];
        for (int d = 0; d < 3; d++) {
            *s ^= *s << 13;
            *s ^= *s >> 17;
            *s ^= *s << 5;
            x[d] = lo[d] + (*s / 4294967296.0) * (hi[d] - lo[d]);
        }
        particles_add(p, x, NULL, 0, (*id)++);
    }
}

static void check_lists(double L, double cutoff, double skin, enum nlist_kind kind)
{
    struct particles *p = particles_create(64);
    particles_type_index(p, "Ar", 39.948);
    struct box box = {{0, 0, 0}, {L, 0.8 * L, 1.1 * L}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    unsigned s = 99;
    int64_t id = 1;
    add_uniform(p, box.lo, box.hi, 300, &s, &id);
    struct err e = {0};
    cr_assert_eq(ghost_build(p, &box, cutoff + skin, &e), 0);
    compare_with_brute(p, cutoff, skin, kind);
    particles_destroy(&p);
}

Test(neighbor, half_list_equals_brute_force) { check_lists(30.0, 5.0, 1.0, NLIST_HALF); }
Test(neighbor, full_list_equals_brute_force) { check_lists(30.0, 5.0, 1.0, NLIST_FULL); }
/* boxes just over two list ranges long, and shorter than one */
Test(neighbor, box_just_over_two_cutoffs) { check_lists(2 * 6.0 + 0.01, 5.0, 1.0, NLIST_HALF); }
Test(neighbor, box_shorter_than_the_cutoff) { check_lists(5.5, 5.0, 1.0, NLIST_HALF); }

/* Two dense clumps in opposite corners of a 400 Å periodic box (neighbours
 * of each other across the faces): cells of half the list range would
 * number about 2e6, far more than the particles and their ghosts, so the
 * build falls back to cells of the whole range (3x3x3 stencil); the lists
 * must still equal brute force, half and full. */
Test(neighbor, sparse_system_wide_cells_equal_brute_force)
{
    for (int kind = 0; kind < 2; kind++) {
        struct particles *p = particles_create(64);
        particles_type_index(p, "Ar", 39.948);
        struct box box = {{0, 0, 0}, {420, 410, 400}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
        unsigned s = 7;
        int64_t id = 1;
        double lo1[3] = {0, 0, 0}, hi1[3] = {12, 12, 12};
        double lo2[3] = {400, 395, 390}, hi2[3] = {420, 410, 400};
        add_uniform(p, lo1, hi1, 150, &s, &id);
        add_uniform(p, lo2, hi2, 150, &s, &id);
        struct err e = {0};
        cr_assert_eq(ghost_build(p, &box, 6.0, &e), 0);
        compare_with_brute(p, 5.0, 1.0, kind == 0 ? NLIST_HALF : NLIST_FULL);
        particles_destroy(&p);
    }
}

/* Forces with 1 and 2 threads agree to round-off. */
Test(md, forces_independent_of_threads)
{
    const char *pots[] = {POT_MISHIN, "style: sw\nfile: Si.sw\nelements: [Si]\n"};
    for (int k = 0; k < 2; k++) {
        struct box b1 = {0}, b2 = {0};
        enum lattice_style st = k ? LATTICE_DIAMOND : LATTICE_FCC;
        double a = k ? 5.431 : 3.615;
        const char *el = k ? "Si" : "Cu";
        struct particles *p1 = th_crystal(st, a, 3, el, 0.2, 5, &b1);
        struct particles *p2 = th_crystal(st, a, 3, el, 0.2, 5, &b2);
        struct md m1, m2;
        th_md(&m1, p1, &b1, th_potential(pots[k]), 1);
        th_md(&m2, p2, &b2, th_potential(pots[k]), 2);
        cr_assert_lt(fabs(m1.last.energy - m2.last.energy), 1e-10 * fabs(m1.last.energy));
        for (int i = 0; i < m1.p->n_owned; i++)
            for (int d = 0; d < 3; d++)
                cr_assert_lt(fabs(m1.p->f[3 * i + d] - m2.p->f[3 * i + d]), 1e-11);
        for (int c = 0; c < 6; c++)
            cr_assert_lt(fabs(m1.last.virial[c] - m2.last.virial[c]), 1e-9);
        md_free(&m1);
        md_free(&m2);
    }
}

/* Langevin and Berendsen bring a cold crystal to the target temperature. */
Test(md, thermostats_reach_target, .timeout = 300)
{
    for (int style = THERMOSTAT_BERENDSEN; style <= THERMOSTAT_LANGEVIN; style++) {
        struct box box = {0};
        struct particles *p = th_crystal(LATTICE_FCC, 3.615, 3, "Cu", 0.0, 1, &box);
        struct err e = {0};
        struct potential *pot = th_potential(POT_MISHIN);
        cr_assert_eq(potential_bind(pot, p, &e), 0);
        cr_assert_eq(velocity_maxwell(p, 50.0, 3, 1u, &e), 0);
        struct md md;
        th_md(&md, p, &box, pot, 1);
        md.dt = 0.002;
        md.seed = 11;
        md.thermo = (struct thermostat){(enum thermostat_style)style, 500.0, 0.1, 1u};
        double tsum = 0;
        int n = 0;
        for (int s = 0; s < 6000; s++) {
            cr_assert_eq(md_step(&md, &e), 0, "%s", e.msg);
            if (s >= 2000) {
                tsum += md_temperature(&md);
                n++;
            }
        }
        double tmean = tsum / n;
        cr_assert_lt(fabs(tmean - 500.0) / 500.0, 0.03, "%s: mean T %g K",
                     style == THERMOSTAT_LANGEVIN ? "langevin" : "berendsen", tmean);
        md_free(&md);
    }
}
