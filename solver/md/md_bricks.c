/* md_bricks: the decomposition an MD case runs on (md_bricks.h). */
#include "md/md_bricks.h"

#include <stdio.h>
#include <stdlib.h>

#include "core/parallel.h"

int md_bricks_plan(const struct parallel *par, const struct parallel_settings *ps,
                   const struct box *b, double range, struct cfg *c, struct halo **out)
{
    *out = NULL;
    if (!par || !par->mpi || ps->decomposition == DECOMP_REPLICATED)
        return 0;
    /* one rank: bricks only when asked for (auto keeps the serial path) */
    if (ps->decomposition == DECOMP_AUTO && par->size == 1)
        return 0;
    /* a tilted box is cut in its fractional coordinates (core/decomp.h) */
    int grid[3] = {1, 1, 1};
    char why[512];
    if (ps->grid_given) {
        int grid_rc = parallel_settings_check_grid_ranks(c, ps, par->size);
        if (grid_rc != 0)
            return grid_rc;
        if (decomp_check_grid(ps->grid, b, range, why, sizeof why) != 0)
            return cfg_error_at(c, "parallel.grid", "%s", why);
        for (int d = 0; d < 3; d++)
            grid[d] = ps->grid[d];
    } else if (decomp_choose_grid(par->size, b, range, grid) != 0) {
        /* a tilted box's bricks are as thick as its heights across its faces */
        char shape[160];
        if (box_tilted(b))
            snprintf(shape, sizeof shape, "tilted box, %g x %g x %g Å high across its faces,",
                     box_height(b, 0), box_height(b, 1), box_height(b, 2));
        else
            snprintf(shape, sizeof shape, "%g x %g x %g Å box", box_length(b, 0),
                     box_length(b, 1), box_length(b, 2));
        if (ps->decomposition == DECOMP_BRICKS)
            return cfg_error_at(c, "parallel.decomposition",
                                "no grid of %d bricks of the %s is at least the interaction "
                                "range %g Å (cutoff + skin) wide; use fewer ranks or "
                                "decomposition: replicated",
                                par->size, shape, range);
        if (par->rank == 0)
            fprintf(stderr, "note: the %s has no grid of %d bricks at least %g Å (cutoff + "
                            "skin) wide: replicated data\n",
                    shape, par->size, range);
        return 0;
    }
    struct halo *h = malloc(sizeof *h);
    if (!h)
        return err_nomem(c->err, "halo");
    int rc = halo_init(h, par, grid, b, c->err);
    if (rc) {
        free(h);
        return rc;
    }
    *out = h;
    return 0;
}
