/* parallel_settings: the `parallel` section (parallel_settings.h). */
#include "input/parallel_settings.h"

#include <string.h>

static const char *const decomposition_names[] = {"auto", "replicated", "bricks", NULL};
static const char *const balance_names[] = {"none", "shift", NULL};

int parallel_settings_read(struct cfg_obj *root, struct parallel_settings *ps)
{
    memset(ps, 0, sizeof *ps);
    ps->grid[0] = ps->grid[1] = ps->grid[2] = 1;
    struct cfg_obj o;
    int rc = cfg_section_opt(root, "parallel", &o, &ps->given);
    if (rc || !ps->given)
        return rc;
    int which;
    if ((rc = cfg_enum(&o, "decomposition", "auto", decomposition_names, &which)))
        return rc;
    ps->decomposition = (enum decomposition)which;
    cfg_allow(&o, "grid");   /* optional without a default: absent means chosen at run time */
    if (json_object_get(o.node, "grid")) {
        long g[3];
        if ((rc = cfg_ints(&o, "grid", 3, NULL, CFG_RANGE(1, 1 << 20), g)))
            return rc;
        for (int d = 0; d < 3; d++)
            ps->grid[d] = (int)g[d];
        ps->grid_given = 1;
        if (ps->decomposition == DECOMP_REPLICATED)
            return cfg_error_at(o.cfg, "parallel.grid",
                                "a grid of bricks needs decomposition: bricks (or auto), not "
                                "replicated");
    }
    cfg_allow(&o, "balance");   /* absent: none, not written (job keys stay) */
    if (json_object_get(o.node, "balance")) {
        int b;
        if ((rc = cfg_enum(&o, "balance", NULL, balance_names, &b)))
            return rc;
        ps->balance = (enum balance)b;
        if (ps->balance != BALANCE_NONE && ps->decomposition == DECOMP_REPLICATED)
            return cfg_error_at(o.cfg, "parallel.balance",
                                "balance moves the boundaries of bricks: it needs "
                                "decomposition: bricks (or auto), not replicated");
    }
    /* dynamic balance, as LAMMPS' fix balance (Nfreq, thresh): absent,
     * not written either */
    int every_given = 0, threshold_given = 0;
    if ((rc = cfg_int_opt(&o, "balance_every", CFG_RANGE(1, 1e12), &ps->balance_every,
                          &every_given)) ||
        (rc = cfg_real_opt(&o, "balance_threshold", CFG_GE(1.0), &ps->balance_threshold,
                           &threshold_given)))
        return rc;
    if (every_given && ps->balance != BALANCE_SHIFT)
        return cfg_error_at(o.cfg, "parallel.balance_every",
                            "balance_every moves the cuts of balance: shift again during the "
                            "run; add balance: shift");
    if (threshold_given && !every_given)
        return cfg_error_at(o.cfg, "parallel.balance_threshold",
                            "balance_threshold applies to the checks of balance_every; give "
                            "balance_every too (without it the cuts are set once, at set-up)");
    if (!threshold_given)
        ps->balance_threshold = 1.1;
    return cfg_close(&o);
}

int parallel_settings_check_grid_ranks(struct cfg *c, const struct parallel_settings *ps,
                                       int ranks)
{
    long prod = (long)ps->grid[0] * ps->grid[1] * ps->grid[2];
    if (prod == ranks)
        return 0;
    return cfg_error_at(c, "parallel.grid",
                        "a grid of %d x %d x %d = %ld bricks for %d MPI ranks: the "
                        "product must equal the rank count",
                        ps->grid[0], ps->grid[1], ps->grid[2], prod, ranks);
}
