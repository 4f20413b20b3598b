/* models: the registry of model stage tables (models.h). */
#include "engine/models.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"
#include "output/checkpoint.h"

static const struct sim_model_ops *const registry[] = {
    &sim_model_md,
    &sim_model_impact_boundary,
    &sim_model_handshake,
    &sim_model_mpm,
    &sim_model_dpd,
    &sim_model_dpd_ref,
    &sim_model_dpd_mpm,
    NULL,
};

const struct sim_model_ops *sim_model_find(const char *name)
{
    for (int k = 0; registry[k]; k++)
        if (strcmp(registry[k]->name, name) == 0)
            return registry[k];
    return NULL;
}

int model_checkpoint_rows(struct halo *h, const struct particles *p, long *offset, long *total,
                          struct err *e)
{
    int nr = halo_nranks(h), me = h->dc.par->rank;
    long *counts = malloc((size_t)nr * sizeof *counts);
    int rc = halo_agree(h, counts ? 0 : err_nomem(e, "checkpoint counts"), e);
    *offset = *total = 0;
    if (!rc) {
        halo_counts(h, p, counts);
        for (int r = 0; r < nr; r++) {
            *offset += r < me ? counts[r] : 0;
            *total += counts[r];
        }
    }
    free(counts);
    return rc;
}

static int in_brick(const void *ctx, const double x[3])
{
    return decomp_owns(ctx, x);
}

static int cmp_id(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

int model_ids_unique_over_ranks(struct halo *h, const struct particles *p, struct ckpt *ck,
                                const char *group, struct err *e)
{
    int n = p->n_owned;
    int64_t *ids = malloc((size_t)(n ? n : 1) * sizeof *ids);
    long *pos = malloc((size_t)(n ? n : 1) * sizeof *pos), shared = 0;
    int rc = halo_agree(h, ids && pos ? 0 : err_nomem(e, "checkpoint ids"), e);
    if (!rc) {
        memcpy(ids, p->id, (size_t)n * sizeof *ids);
        qsort(ids, (size_t)n, sizeof *ids, cmp_id);
        rc = halo_id_positions(h, ids, n, pos, &shared, e);
    }
    double dup = (double)shared;
    if (!rc)
        halo_sum(h, &dup, 1);
    if (!rc && dup > 0)
        rc = err_set(e, ERR_INPUT,
                     "%s: checkpoint %s/id: %.0f id(s) given twice (in two ranks' bricks)",
                     ck->path, group, dup / 2);
    free(ids);
    free(pos);
    return rc;
}

int model_particles_read_brick(struct halo *h, const struct box *b, struct ckpt *ck,
                               const char *group, const char *field, struct particles *p, int rc,
                               struct err *e)
{
    if (!rc)
        decomp_set_box(&h->dc, b);
    if (!rc)
        rc = field ? ckpt_get_particles_where_field(ck, group, p, field, in_brick, &h->dc)
                   : ckpt_get_particles_where(ck, group, p, in_brick, &h->dc);
    rc = halo_adopt(h, p, rc, e);
    return rc ? rc : model_ids_unique_over_ranks(h, p, ck, group, e);
}
