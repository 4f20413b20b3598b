/*
 * mpm_simd: internal to solver/mpm -- four doubles handled as one vector
 * (GCC vector extension; plain SSE2 pairs on machines without AVX).  A
 * node record is two of them, [m q0 q1 q2] and [f0 f1 f2 aux], the remap
 * array holds [r0 r1 r2 0], and 3x3 tensors are handled as rows of three
 * lanes, so a point's work on a node or a tensor is a few multiply-adds.
 */
#ifndef CASCADE_MPM_SIMD_H
#define CASCADE_MPM_SIMD_H

#include <string.h>

typedef double mpm_v4 __attribute__((vector_size(32), aligned(32), may_alias));

/* (macros: a vector returned by value would change the ABI without AVX) */
#define mpm_v4_set(a, b, c, d) ((mpm_v4){(a), (b), (c), (d)})
/* Three doubles at p as a vector with lane 3 zero. */
#define mpm_v4_load3(p) ((mpm_v4){(p)[0], (p)[1], (p)[2], 0.0})

static inline void mpm_v4_store3(double *p, const mpm_v4 *v)
{
    p[0] = (*v)[0];
    p[1] = (*v)[1];
    p[2] = (*v)[2];
}

#endif
