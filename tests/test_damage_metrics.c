/*
 * The damage metrics of cluster impacts on synthetic data with known
 * answers (solver/analysis/damage_shape.h, stacking_faults.h, crater.h):
 *
 *   - damage shape: point sets whose second-moment tensor is known in
 *     closed form (a rotated ellipse, four points on two axes, a disc)
 *     give its eigenvalues, their ratio and the major axis; four arms along
 *     <100>, four along <110>, a filled square and a disc give the <110> /
 *     <100> extent ratios of the header (0.795, 1.258, 1.075, 1);
 *   - stacking faults: a noisy sigmoidal jump of the hcp count gives its
 *     midpoint and 10-90 % rise time to one sampling interval, a slow
 *     linear growth a rise time of 80 % of its duration, a handful of
 *     atoms no burst;
 *   - crater volume: bowls (spherical caps, from a hemisphere to a shallow
 *     dish) dug into fcc(001): the column measure lies between 0.85 and 1
 *     of the removed atoms' volume (a^3/4 each) and within 12 % of the
 *     cap's analytic volume; flat-floored pits are exact
 *     (test_sputter_crater.c).
 */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/crater.h"
#include "analysis/damage_shape.h"
#include "analysis/stacking_faults.h"
#include "core/lattice.h"
#include "core/particles.h"

/* --- damage shape -------------------------------------------------------- */

/* Points of a fine square grid (spacing h) inside the ellipse with
 * semi-axes (ax, by) whose first axis is turned by `deg` from x, centred at
 * (cx, cy); returns the count. */
static int ellipse(double *x, int cap, double ax, double by, double deg, double cx, double cy,
                   double h)
{
    double c = cos(deg * M_PI / 180), s = sin(deg * M_PI / 180);
    double r = fmax(ax, by);
    int n = 0;
    for (double u = -r; u <= r; u += h)
        for (double v = -r; v <= r; v += h) {
            if ((u / ax) * (u / ax) + (v / by) * (v / by) > 1)
                continue;
            cr_assert_lt(n, cap);
            x[3 * n] = cx + c * u - s * v;
            x[3 * n + 1] = cy + s * u + c * v;
            x[3 * n + 2] = -5.0;
            n++;
        }
    return n;
}

enum { NPTS = 200000 };

Test(damage_shape, ellipse_tensor_eigenvalues_and_axis)
{
    double *x = malloc(3 * NPTS * sizeof *x);
    struct damage_shape ds;
    struct err e = {0};
    /* a uniform ellipse with semi-axes A, B has <u^2> = A^2/4, <v^2> = B^2/4 */
    const double A = 20, B = 10;
    const double angles[] = {0, 30, 45, -45, 90, -60};
    for (size_t k = 0; k < sizeof angles / sizeof *angles; k++) {
        int n = ellipse(x, NPTS, A, B, angles[k], 7.0, -3.0, 0.1);
        cr_assert_eq(damage_shape_measure(x, n, NULL, NULL, &ds, &e), 0, "%s", e.msg);
        cr_assert_eq(ds.n, n);
        cr_assert_float_eq(ds.centroid[0], 7.0, 1e-3);
        cr_assert_float_eq(ds.centroid[1], -3.0, 1e-3);
        cr_assert_float_eq(ds.lmax, A * A / 4, 2e-3 * A * A / 4, "lmax %g", ds.lmax);
        cr_assert_float_eq(ds.lmin, B * B / 4, 2e-3 * B * B / 4, "lmin %g", ds.lmin);
        cr_assert_float_eq(ds.eig_ratio, 0.25, 1e-3, "ratio %g", ds.eig_ratio);
        double want = angles[k] == -90 ? 90 : angles[k];
        cr_assert_float_eq(ds.axis_deg, want, 0.05, "axis %g, want %g", ds.axis_deg, want);
        /* the tensor itself: R diag(A^2/4, B^2/4) R^T */
        double c = cos(angles[k] * M_PI / 180), s = sin(angles[k] * M_PI / 180);
        double l1 = A * A / 4, l2 = B * B / 4;
        cr_assert_float_eq(ds.m[0], c * c * l1 + s * s * l2, 0.2);
        cr_assert_float_eq(ds.m[1], s * s * l1 + c * c * l2, 0.2);
        cr_assert_float_eq(ds.m[2], c * s * (l1 - l2), 0.2);
    }
    /* a disc: no preferred direction, equal extents */
    int n = ellipse(x, NPTS, 15, 15, 0, 0, 0, 0.1);
    cr_assert_eq(damage_shape_measure(x, n, NULL, NULL, &ds, &e), 0);
    cr_assert_float_eq(ds.eig_ratio, 1.0, 2e-3, "disc ratio %g", ds.eig_ratio);
    cr_assert_float_eq(ds.extent_ratio, 1.0, 5e-3, "disc extents %g", ds.extent_ratio);
    /* the quantile extent of a disc of radius R along any u: |u.r| has
     * P(|s| > s0) = (2/pi)(acos(s0/R) - (s0/R) sqrt(1 - (s0/R)^2)); at
     * q = 0.9, s0 = 0.80538 R */
    cr_assert_float_eq(ds.extent_100, 2 * 0.80538 * 15, 0.1, "disc extent %g", ds.extent_100);
    free(x);
}

Test(damage_shape, exact_tensor_of_four_points_and_the_mask)
{
    /* (+-p, 0), (0, +-q) turned by 30 degrees: M = R diag(p^2/2, q^2/2) R^T */
    const double p = 6, q = 2, th = 30 * M_PI / 180;
    double x[3 * 6];
    double pts[4][2] = {{p, 0}, {-p, 0}, {0, q}, {0, -q}};
    for (int i = 0; i < 4; i++) {
        x[3 * i] = 1 + cos(th) * pts[i][0] - sin(th) * pts[i][1];
        x[3 * i + 1] = 2 + sin(th) * pts[i][0] + cos(th) * pts[i][1];
        x[3 * i + 2] = 0;
    }
    /* two atoms the mask leaves out */
    for (int i = 4; i < 6; i++) {
        x[3 * i] = 100.0 * i;
        x[3 * i + 1] = -50.0;
        x[3 * i + 2] = 0;
    }
    unsigned char use[6] = {1, 1, 1, 1, 0, 0};
    struct damage_shape ds;
    struct err e = {0};
    cr_assert_eq(damage_shape_measure(x, 6, use, NULL, &ds, &e), 0);
    cr_assert_eq(ds.n, 4);
    cr_assert_float_eq(ds.lmax, p * p / 2, 1e-12);
    cr_assert_float_eq(ds.lmin, q * q / 2, 1e-12);
    cr_assert_float_eq(ds.eig_ratio, (q * q) / (p * p), 1e-12);
    cr_assert_float_eq(ds.axis_deg, 30.0, 1e-9);
    cr_assert_float_eq(ds.m[2], cos(th) * sin(th) * (p * p - q * q) / 2, 1e-12);
    /* fewer than three atoms: the shape is undefined, not 0 or 1 */
    unsigned char two[6] = {1, 1, 0, 0, 0, 0};
    cr_assert_eq(damage_shape_measure(x, 6, two, NULL, &ds, &e), 0);
    cr_assert_eq(ds.n, 2);
    cr_assert(isnan(ds.eig_ratio) && isnan(ds.axis_deg) && isnan(ds.extent_ratio));
    unsigned char none[6] = {0};
    cr_assert_eq(damage_shape_measure(x, 6, none, NULL, &ds, &e), 0);
    cr_assert_eq(ds.n, 0);
    cr_assert(isnan(ds.eig_ratio));
}

/* Four thin arms of length R from the origin, turned by `deg`, m points each. */
static int arms(double *x, int m, double R, double deg)
{
    int n = 0;
    for (int arm = 0; arm < 4; arm++) {
        double a = (deg + 90.0 * arm) * M_PI / 180;
        for (int k = 1; k <= m; k++) {
            double r = R * k / m;
            x[3 * n] = r * cos(a);
            x[3 * n + 1] = r * sin(a);
            x[3 * n + 2] = 0;
            n++;
        }
    }
    return n;
}

Test(damage_shape, four_fold_patterns_in_the_extent_ratio)
{
    enum { M = 5000 };
    double *x = malloc(3 * NPTS * sizeof *x);
    struct damage_shape ds;
    struct err e = {0};
    /* arms along <100> (the slip-plane intersections seen from above):
     * pooled |x|,|y| are half 0, half uniform on [0, R] -> q-quantile
     * (2q - 1) R = 0.8 R; along <110> all uniform on [0, R/sqrt2] -> 0.9 R/sqrt2 */
    int n = arms(x, M, 20, 0);
    cr_assert_eq(damage_shape_measure(x, n, NULL, NULL, &ds, &e), 0);
    cr_assert_float_eq(ds.extent_100, 2 * 0.8 * 20, 0.02, "%g", ds.extent_100);
    cr_assert_float_eq(ds.extent_110, 2 * 0.9 * 20 / sqrt(2.0), 0.02, "%g", ds.extent_110);
    double r100 = 0.9 / sqrt(2.0) / 0.8;   /* 0.7955 */
    cr_assert_float_eq(ds.extent_ratio, r100, 1e-3, "<100> arms: %g", ds.extent_ratio);
    /* four-fold: the second-moment tensor cannot see it */
    cr_assert_float_eq(ds.eig_ratio, 1.0, 1e-9);
    /* arms along <110> */
    n = arms(x, M, 20, 45);
    cr_assert_eq(damage_shape_measure(x, n, NULL, NULL, &ds, &e), 0);
    cr_assert_float_eq(ds.extent_ratio, 1 / r100, 2e-3, "<110> arms: %g", ds.extent_ratio);
    /* a filled square with [100] edges: sqrt2 (1 - sqrt 0.1) / 0.9 = 1.0745;
     * filled by the R2 low-discrepancy sequence (a square grid has ties in
     * its diagonal projections that move the quantile) */
    const double g = 1.32471795724474602596;   /* the plastic number */
    n = NPTS;
    for (int k = 0; k < n; k++) {
        x[3 * k] = 20 * fmod(0.5 + k / g, 1.0) - 10;
        x[3 * k + 1] = 20 * fmod(0.5 + k / (g * g), 1.0) - 10;
        x[3 * k + 2] = 0;
    }
    cr_assert_eq(damage_shape_measure(x, n, NULL, NULL, &ds, &e), 0);
    cr_assert_float_eq(ds.extent_ratio, sqrt(2.0) * (1 - sqrt(0.1)) / 0.9, 2e-3, "square: %g",
                       ds.extent_ratio);
    free(x);
}

/* --- stacking faults ----------------------------------------------------- */

/* deterministic noise in [-1, 1) */
static double noise(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / (double)(1u << 23) - 1.0;
}

Test(stacking_faults, sigmoidal_burst_and_slow_growth)
{
    enum { M = 101 };
    /* rows of a table (time, other, n_hcp): stride 3, as in the analysis */
    double rows[3 * M];
    unsigned seed = 7;
    const double dt = 0.1, t0 = 6.2, w = 0.15, nmax = 2000;
    for (int k = 0; k < M; k++) {
        double t = k * dt;
        rows[3 * k] = t;
        rows[3 * k + 1] = -1;
        /* a few transient hcp atoms as the shock passes (0.2-0.6 ps), the
         * burst, and +-2 % noise */
        double n = (t > 0.2 && t < 0.6 ? 12 : 0) + nmax / (1 + exp(-(t - t0) / w));
        rows[3 * k + 2] = fmax(0, round(n * (1 + 0.02 * noise(&seed))));
    }
    struct sf_burst b;
    stacking_faults_burst(rows, rows + 2, M, 3, STACKING_FAULTS_MIN_ATOMS, &b);
    cr_assert_float_eq(b.peak, nmax, 0.03 * nmax, "peak %g", b.peak);
    cr_assert_float_eq(b.burst_time, t0, dt, "burst at %g ps, want %g", b.burst_time, t0);
    cr_assert_float_eq(b.rise_time, 2 * log(9.0) * w, dt, "rise %g ps, want %g", b.rise_time,
                       2 * log(9.0) * w);
    /* slow linear growth 0 -> 300 over 2-8 ps: half at 5 ps, rise 0.8 x 6 ps */
    double t[M], n[M];
    for (int k = 0; k < M; k++) {
        t[k] = k * dt;
        n[k] = t[k] < 2 ? 0 : t[k] > 8 ? 300 : 50 * (t[k] - 2);
    }
    stacking_faults_burst(t, n, M, 1, STACKING_FAULTS_MIN_ATOMS, &b);
    cr_assert_float_eq(b.burst_time, 5.0, 1e-9, "%g", b.burst_time);
    cr_assert_float_eq(b.rise_time, 4.8, 1e-9, "%g", b.rise_time);
    cr_assert_float_eq(b.peak_time, 8.0, 1e-9);
    /* a handful of atoms: no burst */
    for (int k = 0; k < M; k++)
        n[k] = (k % 7) * 5.0;   /* up to 30 < 50 */
    stacking_faults_burst(t, n, M, 1, STACKING_FAULTS_MIN_ATOMS, &b);
    cr_assert_eq(b.peak, 30);
    cr_assert(isnan(b.burst_time) && isnan(b.rise_time));
    /* no analyses at all */
    stacking_faults_burst(t, n, 0, 1, STACKING_FAULTS_MIN_ATOMS, &b);
    cr_assert(isnan(b.burst_time) && isnan(b.peak_time));
}

/* --- crater volume ------------------------------------------------------- */

/* fcc(001) slab of n x n x nz cells; the top layer at 'top'. */
static struct particles *slab(long n, long nz, double a, double *top)
{
    struct lattice l = {LATTICE_FCC, a, {0, 0, 0}, {{0}}};
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, "Cu", 63.546);
    int64_t id = 1;
    long cells[3] = {n, n, nz};
    struct err e = {0};
    cr_assert(lattice_fill(&l, cells, NULL, p, t, &id, &e) > 0);
    *top = (nz - 0.5) * a;
    return p;
}

/* Dig the spherical cap of depth h and opening radius r0 (the sphere of
 * radius (r0^2 + h^2) / 2h) centred at c below the plane z = top; returns
 * the atoms removed. */
static long dig_cap(struct particles *p, double top, const double c[2], double r0, double h)
{
    double R = (r0 * r0 + h * h) / (2 * h), zc = top - h + R;
    unsigned char *keep = malloc((size_t)p->n_owned);
    long removed = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double dx = p->x[3 * i] - c[0], dy = p->x[3 * i + 1] - c[1], dz = p->x[3 * i + 2] - zc;
        keep[i] = dx * dx + dy * dy + dz * dz >= R * R;
        removed += !keep[i];
    }
    particles_compact(p, keep);
    free(keep);
    return removed;
}

Test(crater, volume_of_dug_bowls)
{
    const double a = 3.615;
    /* (opening radius, depth) in lattice constants: a hemisphere, a shallow
     * bowl, a deep one; the measured volume against the removed atoms'
     * volume (a^3/4 each) and the cap's pi h^2 (3R - h) / 3 */
    const double bowls[][2] = {{5, 5}, {6, 3}, {4, 4}, {7, 2.5}};
    for (size_t k = 0; k < sizeof bowls / sizeof *bowls; k++) {
        double top, r0 = bowls[k][0] * a, h = bowls[k][1] * a;
        struct particles *p = slab(24, 10, a, &top);
        double c[2] = {12 * a + 0.3, 12 * a - 0.2};
        long removed = dig_cap(p, top, c, r0, h);
        const double q = 0.25 * a;
        struct crater_params cp = {top, {c[0], c[1]}, {-q, -q}, {24 * a - q, 24 * a - q}, a, 0.25 * a};
        struct crater_stats st;
        struct err e = {0};
        cr_assert_eq(crater_measure(p->x, p->n_owned, NULL, &cp, NULL, &st, &e), 0, "%s", e.msg);
        double v_atoms = removed * a * a * a / 4;
        double R = (r0 * r0 + h * h) / (2 * h), v_cap = M_PI * h * h * (3 * R - h) / 3;
        /* each column's depth is that of its highest atom: on a sloped
         * floor the column's shallow side, so the measure reads low against
         * the removed atoms (by 8-14 % for these bowls, docs/analysis.md) */
        cr_assert(st.volume > 0.85 * v_atoms && st.volume < v_atoms,
                  "bowl r0 %.1f a, h %.1f a: measured %.0f A^3, removed atoms %.0f A^3", bowls[k][0],
                  bowls[k][1], st.volume, v_atoms);
        cr_assert_float_eq(st.volume, v_cap, 0.12 * v_cap, "bowl r0 %.1f a, h %.1f a: measured %.0f, cap %.0f",
                           bowls[k][0], bowls[k][1], st.volume, v_cap);
        /* the depth is the deepest floor atom's: the cap's depth rounded
         * down to a layer */
        cr_assert(st.depth <= h + 1e-9 && st.depth > h - 0.5 * a, "depth %g of %g", st.depth, h);
        particles_destroy(&p);
    }
}
