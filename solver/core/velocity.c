/* velocity: Maxwell-Boltzmann initial velocities. */
#include "core/velocity.h"

#include <math.h>
#include <stdlib.h>

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
    int n = p->n_owned;
    struct id_index *pairs = malloc((size_t)(n ? n : 1) * sizeof *pairs);
    int *order = malloc((size_t)(n ? n : 1) * sizeof *order);
    struct rng_seq *r = rng_seq_create(seed);
    if (!order || !r || !pairs) {
        free(order);
        free(pairs);
        rng_seq_destroy(&r);
        return err_nomem(e, "velocities");
    }
    int m = 0;
    for (int i = 0; i < n; i++)
        if (p->mask[i] & group_mask)
            pairs[m++] = (struct id_index){p->id[i], i};
    qsort(pairs, (size_t)m, sizeof *pairs, by_id);
    for (int k = 0; k < m; k++)
        order[k] = pairs[k].index;
    free(pairs);
    double mom[3] = {0}, mtot = 0;
    for (int k = 0; k < m; k++) {
        int i = order[k];
        double mass = p->mass[p->type[i]];
        double s = sqrt(UNITS_KB * T / (mass * UNITS_MVV2E));
        for (int d = 0; d < 3; d++) {
            p->v[3 * i + d] = s * rng_seq_gaussian(r);
            mom[d] += mass * p->v[3 * i + d];
        }
        mtot += mass;
    }
    rng_seq_destroy(&r);
    double ke = 0;
    for (int k = 0; k < m; k++) {
        int i = order[k];
        double mass = p->mass[p->type[i]];
        for (int d = 0; d < 3; d++) {
            p->v[3 * i + d] -= mom[d] / mtot;
            ke += 0.5 * mass * UNITS_MVV2E * p->v[3 * i + d] * p->v[3 * i + d];
        }
    }
    double dof = m > 1 ? 3.0 * m - 3.0 : 3.0 * m;
    double Tnow = dof > 0 ? 2.0 * ke / (dof * UNITS_KB) : 0;
    double scale = Tnow > 0 ? sqrt(T / Tnow) : 0;
    for (int k = 0; k < m; k++)
        for (int d = 0; d < 3; d++)
            p->v[3 * order[k] + d] *= scale;
    free(order);
    return 0;
}
