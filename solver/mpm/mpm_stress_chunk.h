/*
 * mpm_stress_chunk: internal to solver/mpm -- Chen 2014 Eqs. (s13)-(s14)
 * for a chunk of up to MPM_CHUNK points of one isotropic linear elastic
 * material, four points at a time in vector lanes.  It is mpm_point_stress
 * (mpm_stress.h) with the same operations in the same order -- the strain
 * increment, the Hughes-Winget rotation of the Jaumann rate, the elastic
 * increment, the stress work, F <- (I + L dt) F and V = V0 det F -- on
 * structure-of-arrays copies of the points' values, so that the compiler
 * needs no shuffles: the per-point form spends most of its instructions
 * moving the components of one point between lanes.
 *
 * The caller gathers the points' stress, F, volumes and stress work into
 * the chunk, pads the lanes past n (any finite values), calls
 * mpm_stress_chunk_iso and scatters the results back.  Every point goes
 * through the same vector code whatever its lane, so results do not depend
 * on how points fall into chunks.
 */
#ifndef CASCADE_MPM_STRESS_CHUNK_H
#define CASCADE_MPM_STRESS_CHUNK_H

#include <stdint.h>

#include "mpm/mpm_material.h"
#include "mpm/mpm_simd.h"

#define MPM_CHUNK 64

struct mpm_chunk {
    double L[9][MPM_CHUNK] __attribute__((aligned(64)));   /* velocity gradient, row-major */
    double s[6][MPM_CHUNK] __attribute__((aligned(64)));   /* stress xx yy zz xy xz yz */
    double F[9][MPM_CHUNK] __attribute__((aligned(64)));   /* deformation gradient */
    double vol[MPM_CHUNK] __attribute__((aligned(64)));
    double vol0[MPM_CHUNK] __attribute__((aligned(64)));
    double eint[MPM_CHUNK] __attribute__((aligned(64)));
    int32_t p[MPM_CHUNK];     /* the points */
    int32_t mat[MPM_CHUNK];   /* their materials */
};

#define MPM_V4(a) (*(mpm_v4 *)(a))

/* Lanes [0, nlanes) of the chunk (nlanes a multiple of 4). */
static inline __attribute__((always_inline)) void
mpm_stress_chunk_iso(const struct mpm_iso *c, const int jaumann, double dt, struct mpm_chunk *ch,
                     int nlanes)
{
    const double lam = c->lambda, mu = c->mu;
    for (int j = 0; j < nlanes; j += 4) {
        const mpm_v4 L0 = MPM_V4(&ch->L[0][j]), L1 = MPM_V4(&ch->L[1][j]),
                     L2 = MPM_V4(&ch->L[2][j]), L3 = MPM_V4(&ch->L[3][j]),
                     L4 = MPM_V4(&ch->L[4][j]), L5 = MPM_V4(&ch->L[5][j]),
                     L6 = MPM_V4(&ch->L[6][j]), L7 = MPM_V4(&ch->L[7][j]),
                     L8 = MPM_V4(&ch->L[8][j]);
        /* Eq. (s13): de = sym(L) dt */
        const mpm_v4 d0 = L0 * dt, d1 = L4 * dt, d2 = L8 * dt, d3 = 0.5 * (L1 + L3) * dt,
                     d4 = 0.5 * (L2 + L6) * dt, d5 = 0.5 * (L5 + L7) * dt;
        const mpm_v4 o0 = MPM_V4(&ch->s[0][j]), o1 = MPM_V4(&ch->s[1][j]),
                     o2 = MPM_V4(&ch->s[2][j]), o3 = MPM_V4(&ch->s[3][j]),
                     o4 = MPM_V4(&ch->s[4][j]), o5 = MPM_V4(&ch->s[5][j]);
        mpm_v4 r0 = o0, r1 = o1, r2 = o2, r3 = o3, r4 = o4, r5 = o5;
        if (jaumann) {
            /* Hughes & Winget: sigma <- Q sigma Q^T, Q = I + 2 (A + A^2) / (1 + a.a),
             * a = axial(W) / 2 (see mpm_stress.h) */
            const mpm_v4 a0 = -0.25 * (L5 - L7) * dt, a1 = 0.25 * (L2 - L6) * dt,
                         a2 = -0.25 * (L1 - L3) * dt;
            const mpm_v4 aa = a0 * a0 + a1 * a1 + a2 * a2, k = 2.0 / (1.0 + aa);
            const mpm_v4 Q0 = 1 + k * (a0 * a0 - aa), Q1 = k * (-a2 + a0 * a1),
                         Q2 = k * (a1 + a0 * a2), Q3 = k * (a2 + a1 * a0),
                         Q4 = 1 + k * (a1 * a1 - aa), Q5 = k * (-a0 + a1 * a2),
                         Q6 = k * (-a1 + a2 * a0), Q7 = k * (a0 + a2 * a1),
                         Q8 = 1 + k * (a2 * a2 - aa);
            /* T = Q S (rows of S: [s0 s3 s4], [s3 s1 s5], [s4 s5 s2]) */
            const mpm_v4 T00 = Q0 * o0 + Q1 * o3 + Q2 * o4, T01 = Q0 * o3 + Q1 * o1 + Q2 * o5,
                         T02 = Q0 * o4 + Q1 * o5 + Q2 * o2;
            const mpm_v4 T10 = Q3 * o0 + Q4 * o3 + Q5 * o4, T11 = Q3 * o3 + Q4 * o1 + Q5 * o5,
                         T12 = Q3 * o4 + Q4 * o5 + Q5 * o2;
            const mpm_v4 T20 = Q6 * o0 + Q7 * o3 + Q8 * o4, T21 = Q6 * o3 + Q7 * o1 + Q8 * o5,
                         T22 = Q6 * o4 + Q7 * o5 + Q8 * o2;
            /* sigma = T Q^T */
            r0 = T00 * Q0 + T01 * Q1 + T02 * Q2;
            r3 = T00 * Q3 + T01 * Q4 + T02 * Q5;
            r4 = T00 * Q6 + T01 * Q7 + T02 * Q8;
            r1 = T10 * Q3 + T11 * Q4 + T12 * Q5;
            r5 = T10 * Q6 + T11 * Q7 + T12 * Q8;
            r2 = T20 * Q6 + T21 * Q7 + T22 * Q8;
        }
        /* Eq. (s14), isotropic: dsigma = lambda tr(de) I + 2 mu de (mpm_iso_increment) */
        const mpm_v4 tr = d0 + d1 + d2;
        r0 += lam * tr + 2 * mu * d0;
        r1 += lam * tr + 2 * mu * d1;
        r2 += lam * tr + 2 * mu * d2;
        r3 += 2 * mu * d3;
        r4 += 2 * mu * d4;
        r5 += 2 * mu * d5;
        MPM_V4(&ch->s[0][j]) = r0;
        MPM_V4(&ch->s[1][j]) = r1;
        MPM_V4(&ch->s[2][j]) = r2;
        MPM_V4(&ch->s[3][j]) = r3;
        MPM_V4(&ch->s[4][j]) = r4;
        MPM_V4(&ch->s[5][j]) = r5;
        /* stress work, midpoint rule, with the volume before the step */
        const mpm_v4 w = (o0 + r0) * d0 + (o1 + r1) * d1 + (o2 + r2) * d2 +
                         2 * ((o3 + r3) * d3 + (o4 + r4) * d4 + (o5 + r5) * d5);
        MPM_V4(&ch->eint[j]) += 0.5 * MPM_V4(&ch->vol[j]) * w;
        /* F <- (I + L dt) F, row a: F_a + dt sum_b L_ab F_b */
        const mpm_v4 f0 = MPM_V4(&ch->F[0][j]), f1 = MPM_V4(&ch->F[1][j]),
                     f2 = MPM_V4(&ch->F[2][j]), f3 = MPM_V4(&ch->F[3][j]),
                     f4 = MPM_V4(&ch->F[4][j]), f5 = MPM_V4(&ch->F[5][j]),
                     f6 = MPM_V4(&ch->F[6][j]), f7 = MPM_V4(&ch->F[7][j]),
                     f8 = MPM_V4(&ch->F[8][j]);
        const mpm_v4 n0 = f0 + dt * (L0 * f0 + L1 * f3 + L2 * f6),
                     n1 = f1 + dt * (L0 * f1 + L1 * f4 + L2 * f7),
                     n2 = f2 + dt * (L0 * f2 + L1 * f5 + L2 * f8),
                     n3 = f3 + dt * (L3 * f0 + L4 * f3 + L5 * f6),
                     n4 = f4 + dt * (L3 * f1 + L4 * f4 + L5 * f7),
                     n5 = f5 + dt * (L3 * f2 + L4 * f5 + L5 * f8),
                     n6 = f6 + dt * (L6 * f0 + L7 * f3 + L8 * f6),
                     n7 = f7 + dt * (L6 * f1 + L7 * f4 + L8 * f7),
                     n8 = f8 + dt * (L6 * f2 + L7 * f5 + L8 * f8);
        MPM_V4(&ch->F[0][j]) = n0;
        MPM_V4(&ch->F[1][j]) = n1;
        MPM_V4(&ch->F[2][j]) = n2;
        MPM_V4(&ch->F[3][j]) = n3;
        MPM_V4(&ch->F[4][j]) = n4;
        MPM_V4(&ch->F[5][j]) = n5;
        MPM_V4(&ch->F[6][j]) = n6;
        MPM_V4(&ch->F[7][j]) = n7;
        MPM_V4(&ch->F[8][j]) = n8;
        const mpm_v4 J = n0 * (n4 * n8 - n5 * n7) - n1 * (n3 * n8 - n5 * n6) +
                         n2 * (n3 * n7 - n4 * n6);
        MPM_V4(&ch->vol[j]) = MPM_V4(&ch->vol0[j]) * J;
    }
}

#endif
