/*
 * mpm_stress: internal to solver/mpm -- the per-point constitutive update,
 * Chen 2014 Eqs. (s12)-(s14): from the velocity gradient L (s12) the strain
 * increment de = sym(L) dt (s13), the Jaumann rotation of the stress when
 * the material asks for it (incrementally objective, Hughes & Winget 1980),
 * the law's increment (s14), and the kinematic bookkeeping
 * (F <- (I + L dt) F, V = V0 det F, stress work).  The strain of a point is
 * derived from F when needed (mpm_points_strain).
 */
#ifndef CASCADE_MPM_STRESS_H
#define CASCADE_MPM_STRESS_H

#include "mpm/mpm_material.h"

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
        double S[9] = {s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2]};
        double T[9];   /* T = Q S */
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                T[3 * i + j] = Q[3 * i] * S[j] + Q[3 * i + 1] * S[3 + j] + Q[3 * i + 2] * S[6 + j];
        /* sigma = T Q^T */
        s[0] = T[0] * Q[0] + T[1] * Q[1] + T[2] * Q[2];
        s[1] = T[3] * Q[3] + T[4] * Q[4] + T[5] * Q[5];
        s[2] = T[6] * Q[6] + T[7] * Q[7] + T[8] * Q[8];
        s[3] = T[0] * Q[3] + T[1] * Q[4] + T[2] * Q[5];
        s[4] = T[0] * Q[6] + T[1] * Q[7] + T[2] * Q[8];
        s[5] = T[3] * Q[6] + T[4] * Q[7] + T[5] * Q[8];
    }
    mat->ops->update(mat, s, de, state);   /* Eq. (s14) */
    /* stress work, midpoint rule: V (sigma_old + sigma_new) / 2 : de */
    double w = (s_old[0] + s[0]) * de[0] + (s_old[1] + s[1]) * de[1] + (s_old[2] + s[2]) * de[2] +
               2 * ((s_old[3] + s[3]) * de[3] + (s_old[4] + s[4]) * de[4] + (s_old[5] + s[5]) * de[5]);
    *eint += 0.5 * *vol * w;
    /* F <- (I + L dt) F: first order, as the rest of the explicit step */
    double Fn[9];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            Fn[3 * a + b] = F[3 * a + b] + dt * (L[3 * a + 0] * F[0 + b] + L[3 * a + 1] * F[3 + b] +
                                                 L[3 * a + 2] * F[6 + b]);
    for (int k = 0; k < 9; k++)
        F[k] = Fn[k];
    double J = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) - Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
               Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
    *vol = vol0 * J;
}

#endif
