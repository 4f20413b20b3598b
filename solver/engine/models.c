/* models: the registry of model stage tables (models.h). */
#include "engine/models.h"

#include <stdio.h>
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

/* Values of a stored particle set's positions (v: 3 a particle) more
 * than a box length outside the stored box b are no state of a run (the
 * box wraps or shrink-wraps the particles at every list build): refused,
 * naming the file and the dataset. */
static int check_near_box(const struct particles *p, const double *v, const struct box *b,
                          struct ckpt *ck, const char *group, const char *dataset,
                          struct err *e)
{
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            double L = b->hi[d] - b->lo[d], x = v[3 * i + d];
            if (!(x >= b->lo[d] - L && x < b->hi[d] + L))
                return err_set(e, ERR_INPUT,
                               "%s: checkpoint %s/%s: particle %lld at %c = %g Å, more than a "
                               "box length outside the stored box [%g, %g)",
                               ck->path, group, dataset, (long long)p->id[i], "xyz"[d], x,
                               b->lo[d], b->hi[d]);
        }
    return 0;
}

int model_particles_read_brick(struct halo *h, const struct box *b, struct ckpt *ck,
                               const char *group, const char *field, struct particles *p, int rc,
                               struct err *e)
{
    if (!rc)
        decomp_set_box(&h->dc, b);
    if (!rc)
        rc = field ? ckpt_get_particles_where_field(ck, group, p, field, decomp_owns_point, &h->dc)
                   : ckpt_get_particles_where(ck, group, p, decomp_owns_point, &h->dc);
    if (!rc)
        rc = check_near_box(p, p->x, b, ck, group, "x", e);
    if (!rc && field) {
        char name[96];
        snprintf(name, sizeof name, "field_%s", field);
        rc = check_near_box(p, particles_field(p, particles_find_field(p, field)), b, ck, group,
                            name, e);
    }
    rc = halo_adopt(h, p, rc, e);
    return rc ? rc : model_ids_unique_over_ranks(h, p, ck, group, e);
}
