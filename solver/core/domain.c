/* domain: wrap, sort and ghosts before a neighbour-list build (domain.h). */
#include "core/domain.h"

#include <stdlib.h>

#include "core/ghost.h"
#include "core/halo.h"
#include "core/neighbor.h"

static int rebuild(struct particles *p, struct box *b, double range, int sort_now,
                   domain_order_fn order, void *ctx, struct timers *timers, struct err *e)
{
    particles_clear_ghosts(p);
    /* bricks: wrap and shrink-wrap over all ranks, then particles that
     * left the brick move to their new owner */
    int rc = p->halo ? halo_remap(p->halo, b, p, 1, e) : box_remap(b, p, 0.0, e);
    if (!rc && p->halo)
        rc = halo_migrate(p->halo, p, e);
    if (rc)
        return rc;
    if ((sort_now || order) && p->n_owned > 1) {
        int *perm = malloc((size_t)p->n_owned * sizeof *perm);
        if (!perm)
            return err_nomem(e, "particle order");
        rc = order ? order(ctx, p, perm, e) : nlist_spatial_order(p, 0.5 * range, perm, e);
        if (!rc)
            rc = particles_permute(p, perm, e);
        free(perm);
        if (rc)
            return rc;
    }
    if (timers)
        timer_start(timers, TIMER_COMM);
    rc = p->halo ? halo_build(p->halo, p, range, e) : ghost_build(p, b, range, e);
    /* bricks: the arrays were sized before the ghosts were known; give
     * back what a quarter more than owned + ghosts does not need (memory
     * per rank is what a decomposition is for) */
    long need = (long)p->n_owned + p->n_ghost;
    if (!rc && p->halo && p->capacity > need + need / 4 + 4096)
        rc = particles_fit(p, (int)(need + need / 16 + 1024), e);
    if (timers)
        timer_stop(timers, TIMER_COMM);
    return rc;
}

int domain_rebuild(struct particles *p, struct box *b, double range, int sort_now,
                   struct timers *timers, struct err *e)
{
    return rebuild(p, b, range, sort_now, NULL, NULL, timers, e);
}

int domain_rebuild_ordered(struct particles *p, struct box *b, double range,
                           domain_order_fn order, void *ctx, struct timers *timers,
                           struct err *e)
{
    return rebuild(p, b, range, 0, order, ctx, timers, e);
}
