/*
 * DPD and DPDE (solver/dpd): conservative forces against finite differences
 * of the energy and against the perfect-crystal lattice sums; exact momentum
 * conservation with dissipative and random forces; the fluctuation-
 * dissipation balance bringing a crystal to the bath temperature; DPDE
 * total energy (kinetic + potential + internal) conserved through a flyer
 * impact; results independent of the thread count; the per-particle pair
 * forces handed to a grid summing to zero.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "core/velocity.h"
#include "dpd/cg_lattice.h"
#include "helpers/th.h"
#include "helpers/th_dpd.h"

static double energy_at(struct dpd *d)
{
    struct err e = {0};
    cr_assert_eq(dpd_compute_forces(d, &e), 0, "%s", e.msg);
    return d->epot;
}

/* Central differences of the energy against the analytic force, for a few
 * particles and every direction. */
static void check_fd(int periodic)
{
    struct dpd d;
    struct dpd_settings set = th_dpd_settings(DPD_ISOTHERMAL, 0.0, 0.0);
    th_dpd(&d, 3, 7.23, periodic, 0.4, &set, 0.005, 1, 1);
    d.sort_every = 0;
    d.skin = 3.0;   /* no rebuild while probing: indices stay put */
    struct err e = {0};
    cr_assert_eq(dpd_compute_forces(&d, &e), 0);
    int n = d.p->n_owned;
    double *f0 = malloc((size_t)3 * n * sizeof *f0);
    memcpy(f0, d.p->f, (size_t)3 * n * sizeof(double));
    const double h = 1e-5;
    double fscale = 0;
    for (int i = 0; i < 3 * n; i++)
        fscale = fmax(fscale, fabs(f0[i]));
    cr_assert(fscale > 1e-3, "displaced crystal must carry forces (max %g eV/Å)", fscale);
    for (int i = 0; i < n; i += n / 7)
        for (int c = 0; c < 3; c++) {
            double x0 = d.p->x[3 * i + c];
            d.p->x[3 * i + c] = x0 + h;
            double ep = energy_at(&d);
            d.p->x[3 * i + c] = x0 - h;
            double em = energy_at(&d);
            d.p->x[3 * i + c] = x0;
            double fd = -(ep - em) / (2 * h);
            cr_assert_lt(fabs(fd - f0[3 * i + c]), 1e-6 * fscale + 1e-8,
                         "particle %d dir %d: analytic %.10g, finite difference %.10g eV/Å", i, c,
                         f0[3 * i + c], fd);
        }
    free(f0);
    dpd_free(&d);
}

Test(dpd, conservative_force_matches_fd_periodic) { check_fd(1); }
Test(dpd, conservative_force_matches_fd_free_cluster) { check_fd(0); }

/* The kernel on a perfect periodic crystal gives the lattice sums of
 * cg_lattice: energy per particle and pressure. */
Test(dpd, perfect_crystal_matches_lattice_sums)
{
    struct dpd d;
    struct dpd_settings set = th_dpd_settings(DPD_ISOTHERMAL, 0.0, 0.0);
    const double a = 7.1;
    th_dpd(&d, 3, a, 1, 0.0, &set, 0.005, 1, 1);
    double e_lat, P_lat;
    cg_lattice_static(&d.prm.sc, a, &e_lat, &P_lat);
    double e_md = d.epot / d.p->n_owned;
    double P[6];
    dpd_pressure_tensor(&d, P);
    cr_assert_lt(fabs(e_md - e_lat), 1e-10 * fabs(e_lat), "energy %.12g vs lattice sum %.12g eV",
                 e_md, e_lat);
    for (int k = 0; k < 3; k++)
        cr_assert_lt(fabs(P[k] - P_lat), 1e-9 * fabs(P_lat) + 1e-12,
                     "P_%d %.10g vs lattice sum %.10g eV/Å^3", k, P[k], P_lat);
    /* the Einstein force constant: one particle displaced by 1e-4 Å */
    const double du = 1e-4;
    double x0 = d.p->x[0];
    d.p->x[0] = x0 + du;
    struct err e = {0};
    cr_assert_eq(dpd_compute_forces(&d, &e), 0);
    double k_md = -d.p->f[0] / du;
    double k_lat = cg_lattice_einstein_k(&d.prm.sc, a);
    cr_assert_lt(fabs(k_md / k_lat - 1), 1e-3, "Einstein k %.6g (displacement) vs %.6g eV/Å^2",
                 k_md, k_lat);
    dpd_free(&d);
}

static void momentum(const struct dpd *d, double P[3], double *scale)
{
    dpd_momentum(d, P);
    *scale = 0;
    for (int i = 0; i < d->p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            *scale += d->p->mass[0] * fabs(d->p->v[3 * i + c]);
}

/* Dissipative and random forces act in equal and opposite pairs: the total
 * momentum stays what it was to round-off, periodic (pairs across the
 * boundary through ghosts) or not, DPD or DPDE. */
static void check_momentum(int periodic, enum dpd_variant v)
{
    struct dpd d;
    struct dpd_settings set = th_dpd_settings(v, 50.0, 600.0);
    th_dpd(&d, 3, 7.23, periodic, 0.2, &set, 0.005, 1, 11);
    struct err e = {0};
    cr_assert_eq(velocity_maxwell(d.p, 1200.0, 5, 1u, &e), 0);
    for (int i = 0; i < d.p->n_owned; i++)
        d.p->v[3 * i] += 0.3;   /* a drift, so the total is not zero */
    double P0[3], P1[3], s0, s1;
    momentum(&d, P0, &s0);
    double u0 = dpd_internal_energy(&d);
    for (int s = 0; s < 300; s++)
        cr_assert_eq(dpd_step(&d, &e), 0, "%s", e.msg);
    momentum(&d, P1, &s1);
    for (int c = 0; c < 3; c++)
        cr_assert_lt(fabs(P1[c] - P0[c]), 1e-12 * fmax(s0, s1), "P_%c %.15g -> %.15g amu Å/ps",
                     "xyz"[c], P0[c], P1[c]);
    if (v == DPD_ENERGY)
        cr_assert_neq(dpd_internal_energy(&d), u0, "DPDE exchanged no heat");
    dpd_free(&d);
}

Test(dpd, momentum_conserved_periodic) { check_momentum(1, DPD_ISOTHERMAL); }
Test(dpd, momentum_conserved_free) { check_momentum(0, DPD_ISOTHERMAL); }
Test(dpd, momentum_conserved_dpde) { check_momentum(1, DPD_ENERGY); }

/* Fluctuation-dissipation: with sigma^2 = 2 gamma kB T the dissipative and
 * random forces alone bring a 256-particle crystal at rest to T.  Mean
 * kinetic temperature over the last 30 ps of a 40 ps run within 2 % of
 * 298 K (seeds scatter it by about 0.6 %; a sigma off by sqrt(2) would give
 * 600 K). */
Test(dpd, fluctuation_dissipation_reaches_bath_temperature, .timeout = 300)
{
    struct dpd d;
    struct dpd_settings set = th_dpd_settings(DPD_ISOTHERMAL, 2000.0, 298.0);
    th_dpd(&d, 4, 7.25, 1, 0.0, &set, 0.005, 1, 2024);
    struct err e = {0};
    const int steps = 8000, skip = 2000;
    double tsum = 0;
    for (int s = 0; s < steps; s++) {
        cr_assert_eq(dpd_step(&d, &e), 0, "%s", e.msg);
        if (s >= skip)
            tsum += dpd_temperature(&d);
    }
    double tmean = tsum / (steps - skip);
    cr_assert_lt(fabs(tmean / 298.0 - 1), 0.02, "mean temperature %.2f K, bath 298 K", tmean);
    dpd_free(&d);
}

/* DPDE, impact-like: a free rigid flyer at 5 Å/ps hits a 298 K bar; the
 * total energy kinetic + potential + internal is conserved within 1e-4
 * relative (the pair sweep conserves it exactly, velocity Verlet to O(dt^2))
 * while heat does flow into the internal energies. */
Test(dpd, dpde_energy_conserved_in_impact, .timeout = 300)
{
    struct box box = {0};
    struct particles *p = th_crystal(LATTICE_FCC, 7.23, 4, "Cu", 0.0, 3, &box);
    /* stretch to 8 x 4 x 4 cells: a second block, then a flyer slab below x = 0 */
    int n1 = p->n_owned;
    for (int i = 0; i < n1; i++) {
        double x[3] = {p->x[3 * i] + 4 * 7.23, p->x[3 * i + 1], p->x[3 * i + 2]};
        particles_add(p, x, NULL, 0, n1 + i + 1);
    }
    int nt = p->n_owned;
    for (int i = 0; i < n1; i++)
        if (p->x[3 * i] < 7.0) {   /* two cells: four (100) planes */
            double x[3] = {p->x[3 * i] - 7.23 * 2, p->x[3 * i + 1], p->x[3 * i + 2]};
            int k = particles_add(p, x, NULL, 0, nt + i + 1);
            p->mask[k] |= 2u;
        }
    for (int k = 0; k < 3; k++)
        box.bc[k] = BOUNDARY_FREE;
    struct err e = {0};
    struct cg_params prm;
    th_cg_params(&prm);
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = prm.mass;
    for (int i = 0; i < nt; i++)
        p->mask[i] |= 4u;
    cr_assert_eq(velocity_maxwell(p, 298.0, 9, 4u, &e), 0);
    struct dpd_settings set = th_dpd_settings(DPD_ENERGY, 20.0, 298.0);
    struct dpd d;
    cr_assert_eq(dpd_init(&d, p, &box, &prm, &set, 0.005, 1.0, 1, 77, &e), 0, "%s", e.msg);
    double v[3] = {5.0, 0, 0};
    cr_assert_eq(dpd_add_body(&d, 2u, DPD_BODY_FREE, v, &e), 0, "%s", e.msg);
    double e0 = d.epot + dpd_kinetic_energy(&d) + dpd_internal_energy(&d);
    double u0 = dpd_internal_energy(&d), dmax = 0;
    for (int s = 0; s < 500; s++) {
        cr_assert_eq(dpd_step(&d, &e), 0, "%s", e.msg);
        double et = d.epot + dpd_kinetic_energy(&d) + dpd_internal_energy(&d);
        dmax = fmax(dmax, fabs(et - e0));
    }
    cr_assert_lt(dmax / fabs(e0), 1e-4, "max |E - E0| / |E0| = %.3g", dmax / fabs(e0));
    cr_assert(d.body[0].v[0] < 4.0, "the flyer must have been slowed by the target (v = %g)",
              d.body[0].v[0]);
    cr_assert_gt(fabs(dpd_internal_energy(&d) - u0), 1e-3, "no heat exchanged");
    dpd_free(&d);
}

/* The same trajectory (random numbers keyed on pair ids and step) with 1
 * and 2 threads: equal to round-off. */
Test(dpd, independent_of_thread_count)
{
    struct dpd d1, d2;
    struct dpd_settings set = th_dpd_settings(DPD_ENERGY, 20.0, 298.0);
    th_dpd(&d1, 3, 7.23, 1, 0.3, &set, 0.005, 1, 5);
    th_dpd(&d2, 3, 7.23, 1, 0.3, &set, 0.005, 2, 5);
    struct err e = {0};
    for (int s = 0; s < 100; s++) {
        cr_assert_eq(dpd_step(&d1, &e), 0);
        cr_assert_eq(dpd_step(&d2, &e), 0);
    }
    cr_assert_eq(d1.p->n_owned, d2.p->n_owned);
    double dx = 0;
    for (int i = 0; i < d1.p->n_owned; i++)
        for (int c = 0; c < 3; c++)
            dx = fmax(dx, fabs(d1.p->x[3 * i + c] - d2.p->x[3 * i + c]));
    cr_assert_lt(dx, 1e-9, "positions differ by %g Å", dx);
    dpd_free(&d1);
    dpd_free(&d2);
}

/* Per-particle pair forces for a grid (Chen 2014 Eq. (s3b)): their sum is
 * zero (Newton's third law pair by pair), the conservative part equals the
 * integrator's force, and the dissipative part opposes relative motion: a
 * crystal whose halves move apart gets pulled together. */
Test(dpd, pair_forces_for_grid_mapping)
{
    struct dpd d;
    struct dpd_settings set = th_dpd_settings(DPD_ISOTHERMAL, 50.0, 0.0);
    th_dpd(&d, 3, 7.23, 0, 0.0, &set, 0.005, 2, 3);
    int n = d.p->n_owned;
    double xmid = 0;
    for (int i = 0; i < n; i++)
        xmid += d.p->x[3 * i] / n;
    for (int i = 0; i < n; i++)
        d.p->v[3 * i] = d.p->x[3 * i] > xmid ? 1.0 : -1.0;
    double *f = malloc((size_t)3 * n * sizeof *f);
    struct err e = {0};
    cr_assert_eq(dpd_pair_forces(&d, 0.005, f, &e), 0, "%s", e.msg);
    double sum[3] = {0, 0, 0}, fmaxabs = 0, pull = 0, cons = 0;
    for (int i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            sum[c] += f[3 * i + c];
            fmaxabs = fmax(fmaxabs, fabs(f[3 * i + c]));
        }
        double fd = f[3 * i] - d.p->f[3 * i];   /* dissipative part along x */
        pull += d.p->x[3 * i] > xmid ? fd : -fd;
        cons += d.p->f[3 * i];
    }
    for (int c = 0; c < 3; c++)
        cr_assert_lt(fabs(sum[c]), 1e-12 * n * fmaxabs, "total force %c = %g", "xyz"[c], sum[c]);
    cr_assert_lt(pull, 0, "dissipative forces must oppose the separation (sum %g)", pull);
    cr_assert_lt(fabs(cons), 1e-10, "conservative forces sum to %g", cons);
    free(f);
    dpd_free(&d);
}
