/* handshake_checkpoint: the MPM side and the coupling state of a handshake
 * in a checkpoint (handshake.h). */
#include <string.h>

#include "core/halo.h"
#include "couple/handshake.h"
#include "couple/handshake_bricks.h"
#include "couple/handshake_thermal.h"
#include "mpm/mpm_bricks.h"
#include "output/mpm_checkpoint.h"

/* Every per-point array (output/mpm_checkpoint.h; fext empty without
 * loads).  The handshake never reorders its points: their indices are the
 * links of the MD copies, in the order of the build, which is id order.  A
 * serial run stores them so; on bricks every rank writes its own rows
 * (handshake_checkpoint_write_part), rank 0's points first, and `order` =
 * 1 tells a reader to put them back in id order. */
static int put_points(struct ckpt *ck, const struct mpm_points *pt, long n, int bricks)
{
    int rc = ckpt_put_long(ck, "points", n);
    if (!rc) rc = ckpt_put_long(ck, "nstate", pt->nstate);
    if (!rc && bricks) rc = ckpt_put_long(ck, "order", 1);
    struct ckpt_col col[MPM_CKPT_COLUMNS];
    int ncol = mpm_ckpt_columns(pt, 1, col);
    if (!rc) rc = ckpt_put_columns(ck, col, ncol, n, !bricks);
    return rc;
}

/* The header: the stored count into *n, the state variables and loads
 * checked against the case's points, *by_rank whether the rows are in
 * rank order. */
static int get_points_header(struct ckpt *ck, const struct mpm_points *pt, long *n, int *by_rank)
{
    long nstate = 0;
    int rc = mpm_ckpt_get_count(ck, "points", n, by_rank);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    if (!rc && nstate != pt->nstate)
        rc = err_set(ck->e, ERR_INPUT,
                     "%s: checkpoint has material points with %ld state variables, the case's "
                     "have %d",
                     ck->path, nstate, pt->nstate);
    long nf = rc ? -1 : ckpt_len(ck, "fext");
    if (!rc && nf != (pt->fext ? 3 * *n : 0))
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint %s point loads do not match the case's",
                     ck->path, nf > 0 ? "has" : "has no");
    return rc;
}

/* Serially: the points are built from the case file; the checkpoint
 * replaces their state, not their number. */
static int get_points(struct ckpt *ck, struct mpm *m)
{
    struct mpm_points *pt = &m->pts;
    long n = 0;
    int by_rank = 0;
    int rc = get_points_header(ck, pt, &n, &by_rank);
    if (!rc && n != pt->n)
        rc = err_set(ck->e, ERR_INPUT,
                     "%s: checkpoint has %ld material points, the case builds %ld", ck->path, n,
                     pt->n);
    long want = pt->n;
    pt->n = 0;
    if (!rc)
        rc = mpm_ckpt_get_points_where(ck, n, pt, 1, m->nbody, NULL, NULL);
    if (!rc && by_rank)   /* a checkpoint of bricks: back in id order */
        rc = mpm_bricks_sort_by_id(NULL, m, ck->e);
    for (long i = 0; !rc && i < pt->n; i++)
        if (pt->id[i] != i + 1)
            rc = err_set(ck->e, ERR_INPUT, "%s: material point %ld has id %lld", ck->path, i + 1,
                         (long long)pt->id[i]);
    if (rc)
        pt->n = want;
    mpm_points_moved(m);
    return rc;
}

int handshake_checkpoint_write(const struct handshake *hs, struct ckpt *ck, const char *group)
{
    const struct mpm *m = &hs->mpm;
    int rc = ckpt_enter(ck, group);
    if (!rc) rc = ckpt_put_long(ck, "step", hs->step);
    if (!rc) rc = ckpt_put_double(ck, "time", hs->time);
    /* the MPM's clock and the sums of its last step: strain becomes the
     * next step's strain_before, time sets the load ramp */
    if (!rc) rc = ckpt_put_long(ck, "mpm_step", m->step);
    if (!rc) rc = ckpt_put_double(ck, "mpm_time", m->time);
    if (!rc) rc = ckpt_put_double(ck, "mpm_vmax", m->vmax);
    if (!rc) rc = ckpt_put_double(ck, "mpm_ke", m->ke);
    if (!rc) rc = ckpt_put_double(ck, "mpm_ke_centred", m->ke_centred);
    if (!rc) rc = ckpt_put_double(ck, "mpm_strain", m->strain);
    if (!rc) rc = ckpt_put_double(ck, "mpm_strain_before", m->strain_before);
    if (!rc) rc = ckpt_put_double(ck, "mpm_fext_scale", m->fext_scale);
    if (!rc && hs->thermal) rc = ckpt_put_double(ck, "bath_heat", hs->thermal->heat);
    if (!rc && hs->thermal) rc = ckpt_put_long(ck, "bath_step", hs->thermal->step);
    if (!rc && hs->thermal) rc = ckpt_put_double(ck, "bath_heat_copies", hs->thermal->heat_copies);
    /* bricks: the datasets for every rank's points (counted by the
     * collect), which each rank fills (handshake_checkpoint_write_part) */
    if (!rc)
        rc = put_points(ck, &m->pts, hs->bricks ? hs_bricks_checkpoint_total(hs) : m->pts.n,
                        hs->bricks != NULL);
    return rc;
}

int handshake_checkpoint_write_part(const struct handshake *hs, struct ckpt *ck,
                                    const char *group)
{
    if (!hs->bricks)
        return 0;
    int rc = ckpt_agree(ck, ckpt_enter(ck, group));
    struct ckpt_col col[MPM_CKPT_COLUMNS];
    int ncol = mpm_ckpt_columns(&hs->mpm.pts, 1, col);
    if (!rc)
        rc = ckpt_put_columns_part(ck, col, ncol, hs_bricks_checkpoint_offset(hs), hs->mpm.pts.n);
    return rc;
}

int handshake_checkpoint_collect(struct handshake *hs, struct err *e)
{
    return hs->bricks ? hs_bricks_checkpoint_collect(hs, e) : 0;
}

/* Bricks: every rank reads the stored rows in blocks and keeps the points
 * dealt to it, in id order (hs_bricks_read_points).  rc: the reads before;
 * collective. */
static int get_points_bricks(struct handshake *hs, struct ckpt *ck, int rc)
{
    const struct halo *h = hs->md->halo;
    long n = 0;
    int by_rank = 0;
    if (!(rc = halo_agree(h, rc, ck->e)))
        rc = get_points_header(ck, &hs->mpm.pts, &n, &by_rank);
    if (!(rc = halo_agree(h, rc, ck->e)))
        rc = hs_bricks_read_points(hs, ck, n, ck->e);
    return rc;
}

int handshake_checkpoint_read(struct handshake *hs, struct ckpt *ck, const char *group)
{
    struct mpm *m = &hs->mpm;
    int rc = ckpt_enter(ck, group);
    if (!rc) rc = ckpt_get_long(ck, "step", &hs->step);
    if (!rc) rc = ckpt_get_double(ck, "time", &hs->time);
    if (!rc) rc = ckpt_get_long(ck, "mpm_step", &m->step);
    if (!rc) rc = ckpt_get_double(ck, "mpm_time", &m->time);
    if (!rc) rc = ckpt_get_double(ck, "mpm_vmax", &m->vmax);
    if (!rc) rc = ckpt_get_double(ck, "mpm_ke", &m->ke);
    if (!rc) rc = ckpt_get_double(ck, "mpm_ke_centred", &m->ke_centred);
    if (!rc) rc = ckpt_get_double(ck, "mpm_strain", &m->strain);
    if (!rc) rc = ckpt_get_double(ck, "mpm_strain_before", &m->strain_before);
    if (!rc) rc = ckpt_get_double(ck, "mpm_fext_scale", &m->fext_scale);
    if (!rc && hs->thermal) rc = ckpt_get_double(ck, "bath_heat", &hs->thermal->heat);
    if (!rc && hs->thermal) rc = ckpt_get_long(ck, "bath_step", &hs->thermal->step);
    if (!rc && hs->thermal) rc = ckpt_get_double(ck, "bath_heat_copies", &hs->thermal->heat_copies);
    if (hs->bricks)
        return get_points_bricks(hs, ck, rc);
    if (!rc) rc = get_points(ck, m);
    return rc;
}

void handshake_checkpoint_sync(struct handshake *hs)
{
    /* the next step locates the points afresh instead of trusting the
     * blocks the last step cached, and finds region I and the copies in the
     * MD particle order anew (the restarted run's atoms come in the stored
     * order, not the order of the build) */
    mpm_points_moved(&hs->mpm);
    hs->seen_builds = -1;
}
