/*
 * Boundary conditions and loads of the MPM:
 *
 * - quasi-static end-loaded bar: fixed face at x = 0, sliding lateral faces,
 *   a traction on the last layer of points, velocity damping: at rest the
 *   stress is uniform and equal to the traction, and the loaded end has
 *   moved by t L / C11 (uniaxial strain);
 * - tensile rod with rigid ends pulled apart (Chen 2014, section 4.1.2):
 *   the rigid points move exactly at their velocity, the force the ends
 *   exert balances (equal and opposite) and equals the rod's stress times
 *   its cross-section, and the stress follows C11 times the strain.
 */
#include <criterion/criterion.h>
#include <math.h>

#include "helpers/th_mpm.h"

#define E_MOD 1.0
#define NU 0.25
#define RHO 5.0
#define C11 (E_MOD * (1 - NU) / ((1 + NU) * (1 - 2 * NU)))

Test(mpm_bc, quasi_static_end_loaded_bar)
{
    const enum mpm_face_bc faces[6] = {MPM_FACE_FIXED,   MPM_FACE_FREE,    MPM_FACE_SLIDING,
                                       MPM_FACE_SLIDING, MPM_FACE_SLIDING, MPM_FACE_SLIDING};
    struct mpm m;
    long nc[3] = {36, 1, 1};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, faces, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", RHO, E_MOD, NU));
    const double L = 32, t = 1e-3;   /* eV/Å^3, tension */
    double lo[3] = {0, 0, 0}, hi[3] = {L, 1, 1};
    th_mpm_box(&m, "bar", mat, lo, hi, 2, NULL, 0);
    struct err e = {0};
    cr_assert_eq(mpm_points_enable_fext(&m.pts, &e), 0);
    for (long p = 0; p < m.pts.n; p++)
        if (m.pts.x[3 * p] > L - 0.5)
            m.pts.fext[3 * p] = t * m.pts.vol[p] / 0.5;   /* one layer of spacing 1/2 */
    /* damping near critical for the first mode, omega = pi c / (2 L) */
    double c = sqrt(C11 / RHO * 9648.533);
    m.damping = 2.0 * M_PI * c / (2 * L);
    th_mpm_run(&m, 1500, 0.5);
    double smid = th_mpm_mean_stress(&m, 0, 4, L - 4);
    cr_assert(fabs(smid / t - 1) < 0.01, "interior stress %g, traction %g", smid, t);
    double u_end = 0;
    long n = 0;
    for (long p = 0; p < m.pts.n; p++)
        if (m.pts.x0[3 * p] > L - 0.5) {
            u_end += m.pts.x[3 * p] - m.pts.x0[3 * p];
            n++;
        }
    u_end /= n;
    double u0 = t * (L - 0.25) / C11;   /* the layer sits 1/4 cell inside the end */
    cr_assert(fabs(u_end / u0 - 1) < 0.02, "end displacement %g, t L / C11 = %g", u_end, u0);
    cr_assert(m.vmax < 1e-3 * c * t / C11 * 10, "not at rest: %g Å/ps", m.vmax);
    mpm_free(&m);
}

Test(mpm_bc, tensile_rod_with_rigid_ends)
{
    struct mpm m;
    long nc[3] = {48, 2, 2};
    th_mpm_uniform(&m, nc, 1.0, MPM_SHAPE_LINEAR, th_mpm_faces_bar, 1);
    int mat = th_mpm_material(&m, mpm_material_linear_elastic("s", RHO, E_MOD, NU));
    const double v = 0.05;   /* Å/ps each end, c ~ 48 Å/ps: quasi-static */
    double lo1[3] = {4, 0, 0}, hi1[3] = {8, 2, 2}, vl[3] = {-v, 0, 0};
    double lo2[3] = {8, 0, 0}, hi2[3] = {40, 2, 2};
    double lo3[3] = {40, 0, 0}, hi3[3] = {44, 2, 2}, vr[3] = {v, 0, 0};
    int left = th_mpm_box(&m, "left", mat, lo1, hi1, 2, vl, 1);
    th_mpm_box(&m, "rod", mat, lo2, hi2, 2, NULL, 0);
    int right = th_mpm_box(&m, "right", mat, lo3, hi3, 2, vr, 1);
    double c = sqrt(C11 / RHO * 9648.533);
    m.damping = 0.5 * M_PI * c / 32;
    double t = 0;
    struct err e = {0};
    /* 400 steps stretch each end by 0.2 Å: no rod point has yet crossed into
     * a cell whose nodes the rigid ends drive (it would then move with them) */
    for (int s = 0; s < 400; s++) {
        double dt = 0.5 * mpm_stable_dt(&m);
        cr_assert_eq(mpm_step(&m, dt, &e), 0, "%s", e.msg);
        t += dt;
    }
    /* rigid points moved exactly with their bodies */
    double dx = 0;
    for (long p = 0; p < m.pts.n; p++) {
        int b = m.pts.body[p];
        if (!m.body[b].rigid)
            continue;
        dx = fmax(dx, fabs(m.pts.x[3 * p] - m.pts.x0[3 * p] - m.body[b].velocity[0] * t));
        cr_assert(m.pts.stress[6 * p] == 0, "rigid point stressed");
    }
    cr_assert(dx < 1e-10, "rigid points off by %g Å", dx);
    /* force balance and stress = force / area (area 2 x 2 Å^2) */
    double fl = m.body[left].reaction[0], fr = m.body[right].reaction[0];
    cr_assert(fr > 0 && fl < 0, "ends do not pull: %g %g", fl, fr);
    cr_assert(fabs(fl + fr) < 0.03 * fr, "unbalanced ends %g %g eV/Å", fl, fr);
    double smid = th_mpm_mean_stress(&m, 0, 14, 34);
    cr_assert(fabs(smid * 4.0 / fr - 1) < 0.05, "stress %g vs force/area %g", smid, fr / 4);
    /* uniaxial strain: sigma = C11 eps over the stretched length between the ends */
    double eps = 2 * v * t / 32.0;
    cr_assert(fabs(smid / (C11 * eps) - 1) < 0.05, "stress %g, C11 eps %g", smid, C11 * eps);
    mpm_free(&m);
}
