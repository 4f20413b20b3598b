/*
 * mpm_stress_chunk: internal to solver/mpm -- Chen 2014 Eqs. (s13)-(s14)
 * for a chunk of up to MPM_CHUNK points of one isotropic linear elastic
 * material, four points at a time in vector lanes.  It is mpm_point_stress
 * (mpm_stress.h) with the same operations in the same order -- the strain
 * increment, the Hughes-Winget rotation of the Jaumann rate, the elastic
 * increment, the stress work, F <- (I + L dt) F and V = V0 det F -- on
 * one component of four points per vector, so that the arithmetic needs no
 * shuffles: the per-point form spends most of its instructions moving the
 * components of one point between lanes.
 *
 * The caller puts the chunk's velocity gradients in structure-of-arrays
 * form (L, with finite values in the lanes past n up to a multiple of 4)
 * and the points' indices (p); mpm_stress_chunk_iso reads each group of
 * four points' stress, F, volumes and stress work straight from the
 * points' arrays into vector lanes and writes the results straight back.
 * (It used to update structure-of-arrays copies of those too, which the
 * caller gathered point by point and scattered back: some 70 scalar loads
 * and stores per point, 13 % of the fused pass, docs/bench.md.)  Every
 * point goes through the same vector code whatever its lane, so results do
 * not depend on how points fall into chunks.
 */
#ifndef CASCADE_MPM_STRESS_CHUNK_H
#define CASCADE_MPM_STRESS_CHUNK_H

#include <stdint.h>

#include "mpm/mpm_material.h"
#include "mpm/mpm_points.h"
#include "mpm/mpm_simd.h"

#define MPM_CHUNK 64

struct mpm_chunk {
    double L[9][MPM_CHUNK] __attribute__((aligned(64)));   /* velocity gradient, row-major */
    int32_t p[MPM_CHUNK];     /* the points */
    int32_t mat[MPM_CHUNK];   /* their materials */
};

#define MPM_V4(a) (*(mpm_v4 *)(a))

/* Component c of the records of `stride` doubles of points q[0..3] as one
 * vector (a macro: a vector returned by value would change the ABI without
 * AVX, mpm_simd.h). */
#define mpm_lanes_get(a, stride, q, c)                                                      \
    ((mpm_v4){(a)[(long)(stride) * (q)[0] + (c)], (a)[(long)(stride) * (q)[1] + (c)],     \
              (a)[(long)(stride) * (q)[2] + (c)], (a)[(long)(stride) * (q)[3] + (c)]})

/* Lanes [0, nl) of *v back to component c of points q[0..nl). */
static inline __attribute__((always_inline)) void mpm_lanes_put(double *a, int stride,
                                                               const int32_t q[4], int c,
                                                               const mpm_v4 *v, int nl)
{
    if (nl == 4) {
        a[(long)stride * q[0] + c] = (*v)[0];
        a[(long)stride * q[1] + c] = (*v)[1];
        a[(long)stride * q[2] + c] = (*v)[2];
        a[(long)stride * q[3] + c] = (*v)[3];
        return;
    }
    for (int i = 0; i < nl; i++)
        a[(long)stride * q[i] + c] = (*v)[i];
}

/* Points ch->p[0, n) of pts; the lanes of L past n up to a multiple of 4
 * must hold finite values (their results are not stored). */
static inline __attribute__((always_inline)) void
mpm_stress_chunk_iso(const struct mpm_iso *c, const int jaumann, double dt,
                     const struct mpm_chunk *ch, int n, struct mpm_points *pts)
{
    const double lam = c->lambda, mu = c->mu;
    double *S = pts->stress, *Fp = pts->F, *vol = pts->vol, *eint = pts->eint;
    const double *vol0 = pts->vol0;
    for (int j = 0; j < n; j += 4) {
        const int nl = n - j < 4 ? n - j : 4;
        int32_t q[4];   /* lanes past n read the last point again (not written) */
        for (int i = 0; i < 4; i++)
            q[i] = ch->p[j + (i < nl ? i : nl - 1)];
        const mpm_v4 L0 = MPM_V4(&ch->L[0][j]), L1 = MPM_V4(&ch->L[1][j]),
                     L2 = MPM_V4(&ch->L[2][j]), L3 = MPM_V4(&ch->L[3][j]),
                     L4 = MPM_V4(&ch->L[4][j]), L5 = MPM_V4(&ch->L[5][j]),
                     L6 = MPM_V4(&ch->L[6][j]), L7 = MPM_V4(&ch->L[7][j]),
                     L8 = MPM_V4(&ch->L[8][j]);
        /* Eq. (s13): de = sym(L) dt */
        const mpm_v4 d0 = L0 * dt, d1 = L4 * dt, d2 = L8 * dt, d3 = 0.5 * (L1 + L3) * dt,
                     d4 = 0.5 * (L2 + L6) * dt, d5 = 0.5 * (L5 + L7) * dt;
        const mpm_v4 o0 = mpm_lanes_get(S, 6, q, 0), o1 = mpm_lanes_get(S, 6, q, 1),
                     o2 = mpm_lanes_get(S, 6, q, 2), o3 = mpm_lanes_get(S, 6, q, 3),
                     o4 = mpm_lanes_get(S, 6, q, 4), o5 = mpm_lanes_get(S, 6, q, 5);
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
        mpm_lanes_put(S, 6, q, 0, &r0, nl);
        mpm_lanes_put(S, 6, q, 1, &r1, nl);
        mpm_lanes_put(S, 6, q, 2, &r2, nl);
        mpm_lanes_put(S, 6, q, 3, &r3, nl);
        mpm_lanes_put(S, 6, q, 4, &r4, nl);
        mpm_lanes_put(S, 6, q, 5, &r5, nl);
        /* stress work, midpoint rule, with the volume before the step */
        const mpm_v4 w = (o0 + r0) * d0 + (o1 + r1) * d1 + (o2 + r2) * d2 +
                         2 * ((o3 + r3) * d3 + (o4 + r4) * d4 + (o5 + r5) * d5);
        const mpm_v4 V = mpm_lanes_get(vol, 1, q, 0);
        const mpm_v4 E = mpm_lanes_get(eint, 1, q, 0) + 0.5 * V * w;
        mpm_lanes_put(eint, 1, q, 0, &E, nl);
        /* F <- (I + L dt) F, row a: F_a + dt sum_b L_ab F_b */
        const mpm_v4 f0 = mpm_lanes_get(Fp, 9, q, 0), f1 = mpm_lanes_get(Fp, 9, q, 1),
                     f2 = mpm_lanes_get(Fp, 9, q, 2), f3 = mpm_lanes_get(Fp, 9, q, 3),
                     f4 = mpm_lanes_get(Fp, 9, q, 4), f5 = mpm_lanes_get(Fp, 9, q, 5),
                     f6 = mpm_lanes_get(Fp, 9, q, 6), f7 = mpm_lanes_get(Fp, 9, q, 7),
                     f8 = mpm_lanes_get(Fp, 9, q, 8);
        const mpm_v4 n0 = f0 + dt * (L0 * f0 + L1 * f3 + L2 * f6),
                     n1 = f1 + dt * (L0 * f1 + L1 * f4 + L2 * f7),
                     n2 = f2 + dt * (L0 * f2 + L1 * f5 + L2 * f8),
                     n3 = f3 + dt * (L3 * f0 + L4 * f3 + L5 * f6),
                     n4 = f4 + dt * (L3 * f1 + L4 * f4 + L5 * f7),
                     n5 = f5 + dt * (L3 * f2 + L4 * f5 + L5 * f8),
                     n6 = f6 + dt * (L6 * f0 + L7 * f3 + L8 * f6),
                     n7 = f7 + dt * (L6 * f1 + L7 * f4 + L8 * f7),
                     n8 = f8 + dt * (L6 * f2 + L7 * f5 + L8 * f8);
        mpm_lanes_put(Fp, 9, q, 0, &n0, nl);
        mpm_lanes_put(Fp, 9, q, 1, &n1, nl);
        mpm_lanes_put(Fp, 9, q, 2, &n2, nl);
        mpm_lanes_put(Fp, 9, q, 3, &n3, nl);
        mpm_lanes_put(Fp, 9, q, 4, &n4, nl);
        mpm_lanes_put(Fp, 9, q, 5, &n5, nl);
        mpm_lanes_put(Fp, 9, q, 6, &n6, nl);
        mpm_lanes_put(Fp, 9, q, 7, &n7, nl);
        mpm_lanes_put(Fp, 9, q, 8, &n8, nl);
        const mpm_v4 J = n0 * (n4 * n8 - n5 * n7) - n1 * (n3 * n8 - n5 * n6) +
                         n2 * (n3 * n7 - n4 * n6);
        const mpm_v4 Vn = mpm_lanes_get(vol0, 1, q, 0) * J;
        mpm_lanes_put(vol, 1, q, 0, &Vn, nl);
    }
}

#endif
