/* handshake_record: the handshake's part of the `parallel` record
 * (handshake_record.h). */
#include "scenarios/handshake_record.h"

#include "core/halo.h"
#include "couple/handshake_bricks.h"
#include "mpm/mpm_hgrid.h"
#include "output/decomp_record.h"

void handshake_record_parallel(const struct handshake *hs, struct result *res)
{
    if (!hs->bricks)
        return;
    decomp_record_add_counts(res, hs->md->halo->dc.par, "mpm_points_per_rank", hs->mpm.pts.n);
    decomp_record_add_integer(res, "handshake_remote_copies_max",
                              hs_bricks_remote_copies_max(hs));
    long shared = 0, plans = 0;
    hs_bricks_shared_counts(hs, &shared, &plans);
    decomp_record_add_integer(res, "mpm_shared_nodes_max", shared);
    decomp_record_add_integer(res, "mpm_shared_node_plans", plans);
    const struct mpm_hgrid *hg = hs->mpm.grid.hg;
    if (hg)
        decomp_record_add_cell_tables(res, hs->md->halo->dc.par, hg->ncell, hg->ncell_made);
}
