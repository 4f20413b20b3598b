/* velocity: Maxwell-Boltzmann initial velocities. */
#include "core/velocity.h"

#include <math.h>
#include <stdlib.h>

#include "core/halo.h"
#include "core/rng.h"
#include "core/units.h"

struct id_index {
    int64_t id;
    int index;
};

static int by_id(const void *a, const void *b)
{
    int64_t x = ((const struct id_index *)a)->id, y = ((const struct id_index *)b)->id;
    return (x > y) - (x < y);
}

int velocity_maxwell(struct particles *p, double T, uint64_t seed, uint32_t group_mask,
                     struct err *e)
{
    return velocity_maxwell_split(p, T, seed, group_mask, NULL, e);
}

int velocity_maxwell_split(struct particles *p, double T, uint64_t seed, uint32_t group_mask,
                           const struct halo *h, struct err *e)
{
    int n = p->n_owned;
    struct id_index *pairs = malloc((size_t)(n ? n : 1) * sizeof *pairs);
    int *order = malloc((size_t)(n ? n : 1) * sizeof *order);
    int64_t *ids = malloc((size_t)(n ? n : 1) * sizeof *ids);
    long *pos = malloc((size_t)(n ? n : 1) * sizeof *pos);
    struct rng_seq *r = rng_seq_create(seed);
    int rc = order && r && pairs && ids && pos ? 0 : err_nomem(e, "velocities");
    int m = 0;
    if (!rc) {
        for (int i = 0; i < n; i++)
            if (p->mask[i] & group_mask)
                pairs[m++] = (struct id_index){p->id[i], i};
        qsort(pairs, (size_t)m, sizeof *pairs, by_id);
        for (int k = 0; k < m; k++) {
            order[k] = pairs[k].index;
            ids[k] = pairs[k].id;
            pos[k] = k;
        }
    }
    /* bricks: the k-th draw of the one sequence goes to the k-th id of all
     * ranks, so every rank count gets the serial velocities (the momentum
     * and temperature sums below run in another order: equal to round-off) */
    if (h && halo_any(h, rc != 0) && !rc)   /* no rank left waiting for another */
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    if (h && !rc)
        rc = halo_id_positions(h, ids, m, pos, NULL, e);
    free(pairs);
    free(ids);
    if (rc) {
        free(order);
        free(pos);
        rng_seq_destroy(&r);
        return rc;
    }
    double sums[5] = {0};   /* momentum, mass, count */
    long next = 0;
    for (int k = 0; k < m; k++) {
        for (; next < pos[k]; next++)   /* other ranks' draws: skipped */
            for (int d = 0; d < 3; d++)
                (void)rng_seq_gaussian(r);
        next++;
        int i = order[k];
        double mass = p->mass[p->type[i]];
        double s = sqrt(UNITS_KB * T / (mass * UNITS_MVV2E));
        for (int d = 0; d < 3; d++) {
            p->v[3 * i + d] = s * rng_seq_gaussian(r);
            sums[d] += mass * p->v[3 * i + d];
        }
        sums[3] += mass;
    }
    sums[4] = m;
    rng_seq_destroy(&r);
    free(pos);
    if (h)
        halo_sum(h, sums, 5);
    double ke = 0;
    for (int k = 0; k < m; k++) {
        int i = order[k];
        double mass = p->mass[p->type[i]];
        for (int d = 0; d < 3; d++) {
            p->v[3 * i + d] -= sums[d] / sums[3];
            ke += 0.5 * mass * UNITS_MVV2E * p->v[3 * i + d] * p->v[3 * i + d];
        }
    }
    if (h)
        halo_sum(h, &ke, 1);
    double mall = sums[4];
    double dof = mall > 1 ? 3.0 * mall - 3.0 : 3.0 * mall;
    double Tnow = dof > 0 ? 2.0 * ke / (dof * UNITS_KB) : 0;
    double scale = Tnow > 0 ? sqrt(T / Tnow) : 0;
    for (int k = 0; k < m; k++)
        for (int d = 0; d < 3; d++)
            p->v[3 * order[k] + d] *= scale;
    free(order);
    return 0;
}
