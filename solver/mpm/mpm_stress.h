/*
 * mpm_stress: internal to solver/mpm -- the per-point constitutive update,
 * Chen 2014 Eqs. (s12)-(s14): from the velocity gradient L (s12) the strain
 * increment de = sym(L) dt (s13), the Jaumann rotation of the stress when
 * the material asks for it (incrementally objective, Hughes & Winget 1980),
 * the law's increment (s14), and the kinematic bookkeeping
 * (F <- (I + L dt) F, V = V0 det F, stress work).  The strain of a point is
 * derived from F when needed (mpm_points_strain).  mpm_stress_chunk.h is
 * the same update for chunks of isotropic linear elastic points in vector
 * lanes: keep the two in step.
 */
#ifndef CASCADE_MPM_STRESS_H
#define CASCADE_MPM_STRESS_H

#include "mpm/mpm_material.h"
#include "mpm/mpm_simd.h"

/* L is row-major: L[3a + b] = d v_a / d x_b. */
static inline __attribute__((always_inline)) void
mpm_point_stress(const struct mpm_material *mat, const double L[9], double dt, double *s, double *F,
                 double *vol, double vol0, double *eint, double *state)
{
    double de[6] = {L[0] * dt, L[4] * dt, L[8] * dt, 0.5 * (L[1] + L[3]) * dt,
                    0.5 * (L[2] + L[6]) * dt, 0.5 * (L[5] + L[7]) * dt};
    double s_old[6] = {s[0], s[1], s[2], s[3], s[4], s[5]};
    if (mat->jaumann) {
        /* Jaumann rate integrated as Hughes & Winget (1980): sigma <- Q sigma Q^T
         * with Q = (I - W/2)^-1 (I + W/2), W = skew(L) dt.  Q is exactly
         * orthogonal, so the invariants survive any rotation; for a skew
         * matrix with axial vector a (of W/2), Q = I + 2 (A + A^2) / (1 + a.a)
         * and A^2 = a a^T - (a.a) I. */
        double a0 = -0.25 * (L[5] - L[7]) * dt;   /* a = axial(W) / 2 */
        double a1 = 0.25 * (L[2] - L[6]) * dt;
        double a2 = -0.25 * (L[1] - L[3]) * dt;
        double aa = a0 * a0 + a1 * a1 + a2 * a2, k = 2.0 / (1.0 + aa);
        double Q[9] = {1 + k * (a0 * a0 - aa), k * (-a2 + a0 * a1), k * (a1 + a0 * a2),
                       k * (a2 + a1 * a0), 1 + k * (a1 * a1 - aa), k * (-a0 + a1 * a2),
                       k * (-a1 + a2 * a0), k * (a0 + a2 * a1), 1 + k * (a2 * a2 - aa)};
        /* rows of S, Q; T = Q S row by row, then sigma = T Q^T: its row i is
         * sum_k T_ik (column k of Q) */
        const mpm_v4 S0 = mpm_v4_set(s[0], s[3], s[4], 0), S1 = mpm_v4_set(s[3], s[1], s[5], 0),
                     S2 = mpm_v4_set(s[4], s[5], s[2], 0);
        mpm_v4 T0 = Q[0] * S0 + Q[1] * S1 + Q[2] * S2;
        mpm_v4 T1 = Q[3] * S0 + Q[4] * S1 + Q[5] * S2;
        mpm_v4 T2 = Q[6] * S0 + Q[7] * S1 + Q[8] * S2;
        const mpm_v4 C0 = mpm_v4_set(Q[0], Q[3], Q[6], 0), C1 = mpm_v4_set(Q[1], Q[4], Q[7], 0),
                     C2 = mpm_v4_set(Q[2], Q[5], Q[8], 0);
        mpm_v4 R0 = T0[0] * C0 + T0[1] * C1 + T0[2] * C2;
        mpm_v4 R1 = T1[0] * C0 + T1[1] * C1 + T1[2] * C2;
        mpm_v4 R2 = T2[0] * C0 + T2[1] * C1 + T2[2] * C2;
        s[0] = R0[0];
        s[1] = R1[1];
        s[2] = R2[2];
        s[3] = R0[1];
        s[4] = R0[2];
        s[5] = R1[2];
    }
    if (mat->iso)   /* Eq. (s14); linear elastic inlined */
        mpm_iso_increment(mat->iso, s, de);
    else
        mat->ops->update(mat, s, de, state);
    /* stress work, midpoint rule: V (sigma_old + sigma_new) / 2 : de */
    double w = (s_old[0] + s[0]) * de[0] + (s_old[1] + s[1]) * de[1] + (s_old[2] + s[2]) * de[2] +
               2 * ((s_old[3] + s[3]) * de[3] + (s_old[4] + s[4]) * de[4] + (s_old[5] + s[5]) * de[5]);
    *eint += 0.5 * *vol * w;
    /* F <- (I + L dt) F: first order, as the rest of the explicit step */
    /* rows: Fn_a = F_a + dt sum_b L_ab F_b */
    const mpm_v4 F0 = mpm_v4_load3(F), F1 = mpm_v4_load3(F + 3), F2 = mpm_v4_load3(F + 6);
    mpm_v4 N0 = F0 + dt * (L[0] * F0 + L[1] * F1 + L[2] * F2);
    mpm_v4 N1 = F1 + dt * (L[3] * F0 + L[4] * F1 + L[5] * F2);
    mpm_v4 N2 = F2 + dt * (L[6] * F0 + L[7] * F1 + L[8] * F2);
    mpm_v4_store3(F, &N0);
    mpm_v4_store3(F + 3, &N1);
    mpm_v4_store3(F + 6, &N2);
    const double *Fn = F;
    double J = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) - Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
               Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
    *vol = vol0 * J;
}

#endif
