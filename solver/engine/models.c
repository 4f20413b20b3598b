/* models: the registry of model stage tables (models.h). */
#include "engine/models.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"

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
