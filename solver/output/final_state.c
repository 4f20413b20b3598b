#include "output/final_state.h"

int final_state_write(struct run *run, struct halo *halo, const struct particles *p,
                      const struct box *b, long step, double time, struct err *e)
{
    /* the same options on every rank, so all ranks skip the gather or none */
    if (!run->out.final_state)
        return 0;
    if (!halo)
        return run_write_final_state(run, p, b, step, time, e);
    struct particles *all = NULL;   /* rank 0 only */
    int rc = halo_gather(halo, p, &all, e);
    if (!rc && all)
        rc = run_write_final_state(run, all, b, step, time, e);
    particles_destroy(&all);
    return rc;
}
