/* mpm_step: one MUSL (or USL) step as the sequence of the stages in mpm.h. */
#include <math.h>

#include "mpm/mpm.h"

static void tstart(struct mpm *m, enum timer_id t)
{
    if (m->timers)
        timer_start(m->timers, t);
}

static void tstop(struct mpm *m, enum timer_id t)
{
    if (m->timers)
        timer_stop(m->timers, t);
}

int mpm_step_map(struct mpm *m, struct err *e)
{
    tstart(m, TIMER_MPM_P2G);
    int rc = mpm_locate_particles(m, e);   /* s9 of the previous step */
    if (rc) {
        tstop(m, TIMER_MPM_P2G);
        return rc;
    }
    if (!(mpm_fusable(m) && m->fused_ready)) {
        mpm_clear_grid(m);
        mpm_map_to_grid(m, MPM_MAP_ALL);   /* s1-s3 (else done by the last step) */
    }
    m->fused_ready = 0;
    m->grid_fresh = 0;
    tstop(m, TIMER_MPM_P2G);
    return 0;
}

int mpm_step_update(struct mpm *m, double dt, struct err *e)
{
    int fused = mpm_fusable(m);
    tstart(m, TIMER_MPM_GRID);
    mpm_update_grid(m, dt);                /* s4-s5 */
    tstop(m, TIMER_MPM_GRID);
    tstart(m, TIMER_MPM_G2P);
    mpm_map_to_particles(m, dt);           /* s6, s10 */
    tstop(m, TIMER_MPM_G2P);
    /* the fused pass's second buffer is zeroed by s11's loop over the nodes */
    struct mpm_node *clear = fused && m->algorithm == MPM_MUSL ? mpm_grid_next_buffer(&m->grid)
                                                                 : NULL;
    if (m->algorithm == MPM_MUSL) {
        tstart(m, TIMER_MPM_GRID);
        mpm_update_grid_velocity_clearing(m, clear);   /* s11 */
        tstop(m, TIMER_MPM_GRID);
    }
    tstart(m, TIMER_MPM_G2P);
    m->fused_map_seconds = 0;
    if (fused)   /* s7-s8, s12-s14 and s1-s3 of the next step */
        mpm_update_particles_and_map_cleared(m, dt, clear != NULL);
    else
        mpm_update_particles(m, dt);           /* s7-s8, s12-s14 */
    tstop(m, TIMER_MPM_G2P);
    if (m->timers && fused) {   /* the next step's mapping is p2g, whoever does it */
        m->timers->total[TIMER_MPM_G2P] -= m->fused_map_seconds;
        m->timers->total[TIMER_MPM_P2G] += m->fused_map_seconds;
    }
    m->time += dt;
    m->step++;
    if (!isfinite(m->vmax))
        return err_set(e, ERR_DIVERGED, "non-finite particle velocity at step %ld", m->step);
    return 0;
}

int mpm_step(struct mpm *m, double dt, struct err *e)
{
    int rc = mpm_step_map(m, e);
    return rc ? rc : mpm_step_update(m, dt, e);
}
