/*
 * mpm_stress: internal to solver/mpm -- the per-point constitutive update,
 * Chen 2014 Eqs. (s12)-(s14): from the velocity gradient L (s12) the strain
 * increment de = sym(L) dt (s13), the Jaumann rotation of the stress when
 * the material asks for it, the law's increment (s14), and the kinematic
 * bookkeeping (accumulated strain, F <- (I + L dt) F, V = V0 det F, stress
 * work).
 */
#ifndef CASCADE_MPM_STRESS_H
#define CASCADE_MPM_STRESS_H

#include "mpm/mpm_material.h"

/* L is row-major: L[3a + b] = d v_a / d x_b. */
static inline void mpm_point_stress(const struct mpm_material *mat, const double L[9], double dt,
                                    double *s, double *eps, double *F, double *vol, double vol0,
                                    double *eint, double *state)
{
    double de[6] = {L[0] * dt, L[4] * dt, L[8] * dt, 0.5 * (L[1] + L[3]) * dt,
                    0.5 * (L[2] + L[6]) * dt, 0.5 * (L[5] + L[7]) * dt};
    double s_old[6] = {s[0], s[1], s[2], s[3], s[4], s[5]};
    if (mat->jaumann) {
        /* Jaumann rate: sigma += (W sigma - sigma W) dt, W = skew(L) */
        double w01 = 0.5 * (L[1] - L[3]) * dt, w02 = 0.5 * (L[2] - L[6]) * dt,
               w12 = 0.5 * (L[5] - L[7]) * dt;
        /* M = W sigma with W = [[0, w01, w02], [-w01, 0, w12], [-w02, -w12, 0]] */
        double M00 = w01 * s[3] + w02 * s[4], M01 = w01 * s[1] + w02 * s[5],
               M02 = w01 * s[5] + w02 * s[2];
        double M10 = -w01 * s[0] + w12 * s[4], M11 = -w01 * s[3] + w12 * s[5],
               M12 = -w01 * s[4] + w12 * s[2];
        double M20 = -w02 * s[0] - w12 * s[3], M21 = -w02 * s[3] - w12 * s[1],
               M22 = -w02 * s[4] - w12 * s[5];
        /* W sigma - sigma W = M + M^T */
        s[0] += 2 * M00;
        s[1] += 2 * M11;
        s[2] += 2 * M22;
        s[3] += M01 + M10;
        s[4] += M02 + M20;
        s[5] += M12 + M21;
    }
    mat->ops->update(mat, s, de, state);   /* Eq. (s14) */
    for (int k = 0; k < 6; k++)
        eps[k] += de[k];
    /* stress work, midpoint rule: V (sigma_old + sigma_new) / 2 : de */
    double w = (s_old[0] + s[0]) * de[0] + (s_old[1] + s[1]) * de[1] + (s_old[2] + s[2]) * de[2] +
               2 * ((s_old[3] + s[3]) * de[3] + (s_old[4] + s[4]) * de[4] + (s_old[5] + s[5]) * de[5]);
    *eint += 0.5 * *vol * w;
    /* F <- (I + L dt) F */
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
