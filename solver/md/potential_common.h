/*
 * potential_common: the pieces every pair-loop kernel shares -- zeroing and
 * threading the output arrays, tallying the virial, reading element lists.
 */
#ifndef CASCADE_POTENTIAL_COMMON_H
#define CASCADE_POTENTIAL_COMMON_H

#include "md/potential.h"
#include "core/thread_accum.h"

struct pair_scratch {
    struct thread_accum f, pe, vir;
    int nthreads, peratom;
    size_t ntot;
    double esum[THREAD_ACCUM_MAX];
    double w[THREAD_ACCUM_MAX][6];
};

/* Where a thread accumulates: f always; pe and vir only for POT_PERATOM. */
struct pair_target {
    double *f, *pe, *vir;
};

int pair_scratch_begin(struct pair_scratch *ps, struct particles *p, int flags, int nthreads,
                       struct err *e);
struct pair_target pair_scratch_target(struct pair_scratch *ps, struct particles *p, int tid);
void pair_scratch_store_sums(struct pair_scratch *ps, int tid, double esum, const double w[6]);
/* Reduce thread buffers and sums (in thread order) into p and *out. */
void pair_scratch_end(struct pair_scratch *ps, struct particles *p, struct force_result *out);
void pair_scratch_free(struct pair_scratch *ps);

/* Pair virial: W_ab += d_a d_b fpair with d = x_i - x_j, F_i = fpair d. */
static inline void pair_tally_virial(double w[6], double dx, double dy, double dz, double fpair)
{
    w[0] += dx * dx * fpair;
    w[1] += dy * dy * fpair;
    w[2] += dz * dz * fpair;
    w[3] += dx * dy * fpair;
    w[4] += dx * dz * fpair;
    w[5] += dy * dz * fpair;
}

/* Virial W_ab = sum over owned and ghost particles of x_a f_b, valid when
 * every force of a half-list ("newton on") kernel is still on the particle
 * it acts on, i.e. before ghost forces are added to their owners. */
void pair_virial_fdotr(const struct particles *p, double w[6]);

/* Half of a pair's energy and virial to each particle. */
static inline void pair_tally_peratom(struct pair_target *t, int i, int j, double epair, double dx,
                                      double dy, double dz, double fpair)
{
    double h = 0.5 * fpair;
    double v[6] = {dx * dx * h, dy * dy * h, dz * dz * h, dx * dy * h, dx * dz * h, dy * dz * h};
    t->pe[i] += 0.5 * epair;
    t->pe[j] += 0.5 * epair;
    for (int c = 0; c < 6; c++) {
        t->vir[6 * i + c] += v[c];
        t->vir[6 * j + c] += v[c];
    }
}

/* Read `elements` (required) and `masses` (optional, default: standard
 * atomic masses) into the base struct. */
int potential_read_elements(struct cfg_obj *o, struct potential *base);

#endif
