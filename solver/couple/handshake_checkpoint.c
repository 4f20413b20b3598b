/* handshake_checkpoint: the MPM side and the coupling state of a handshake
 * in a checkpoint (handshake.h). */
#include <string.h>

#include "core/halo.h"
#include "couple/handshake.h"
#include "couple/handshake_bricks.h"
#include "couple/handshake_thermal.h"

/* Every per-point array, in the stored order (the handshake never reorders
 * its points: their indices are the links of the MD copies; on bricks the
 * points of every rank, gathered in id order, which is that order). */
static int put_points(struct ckpt *ck, const struct mpm_points *pt)
{
    long n = pt->n;
    int rc = ckpt_put_long(ck, "points", n);
    if (!rc) rc = ckpt_put_long(ck, "nstate", pt->nstate);
    if (!rc) rc = ckpt_put_doubles(ck, "x", pt->x, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "x0", pt->x0, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "v", pt->v, 3 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "mass", pt->mass, n);
    if (!rc) rc = ckpt_put_doubles(ck, "vol0", pt->vol0, n);
    if (!rc) rc = ckpt_put_doubles(ck, "vol", pt->vol, n);
    if (!rc) rc = ckpt_put_doubles(ck, "stress", pt->stress, 6 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "F", pt->F, 9 * n);
    if (!rc) rc = ckpt_put_doubles(ck, "eint", pt->eint, n);
    if (!rc) rc = ckpt_put_doubles(ck, "state", pt->state, (long)pt->nstate * n);
    if (!rc) rc = ckpt_put_doubles(ck, "fext", pt->fext, pt->fext ? 3 * n : 0);
    if (!rc) rc = ckpt_put_ints(ck, "body", (const int *)pt->body, n);
    if (!rc) rc = ckpt_put_i64(ck, "id", pt->id, n);
    if (!rc) rc = ckpt_put_u32(ck, "mask", pt->mask, n);
    return rc;
}

static int get_points(struct ckpt *ck, struct mpm_points *pt)
{
    long n = 0, nstate = 0;
    int rc = ckpt_get_long(ck, "points", &n);
    if (!rc) rc = ckpt_get_long(ck, "nstate", &nstate);
    /* the points are built from the case file: the checkpoint replaces
     * their state, not their number */
    if (!rc && (n != pt->n || nstate != pt->nstate))
        rc = err_set(ck->e, ERR_INPUT,
                     "%s: checkpoint has %ld material points with %ld state variables, the case "
                     "builds %ld with %d",
                     ck->path, n, nstate, pt->n, pt->nstate);
    long nf = rc ? -1 : ckpt_len(ck, "fext");
    if (!rc && nf != (pt->fext ? 3 * n : 0))
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint %s point loads do not match the case's",
                     ck->path, nf > 0 ? "has" : "has no");
    if (!rc) rc = ckpt_get_doubles(ck, "x", pt->x, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "x0", pt->x0, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "v", pt->v, 3 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "mass", pt->mass, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol0", pt->vol0, n);
    if (!rc) rc = ckpt_get_doubles(ck, "vol", pt->vol, n);
    if (!rc) rc = ckpt_get_doubles(ck, "stress", pt->stress, 6 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "F", pt->F, 9 * n);
    if (!rc) rc = ckpt_get_doubles(ck, "eint", pt->eint, n);
    if (!rc) rc = ckpt_get_doubles(ck, "state", pt->state, (long)pt->nstate * n);
    if (!rc && pt->fext) rc = ckpt_get_doubles(ck, "fext", pt->fext, 3 * n);
    if (!rc) rc = ckpt_get_ints(ck, "body", (int *)pt->body, n);
    if (!rc) rc = ckpt_get_i64(ck, "id", pt->id, n);
    if (!rc) rc = ckpt_get_u32(ck, "mask", pt->mask, n);
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
    /* bricks: every rank's points, gathered by handshake_checkpoint_collect */
    const struct mpm_points *pts = hs->bricks ? hs_bricks_checkpoint_points(hs) : &m->pts;
    if (!rc && !pts)
        rc = err_set(ck->e, ERR_RUNTIME, "handshake: checkpoint written before its points were "
                                         "collected");
    if (!rc) rc = put_points(ck, pts);
    return rc;
}

int handshake_checkpoint_collect(struct handshake *hs, struct err *e)
{
    return hs->bricks ? hs_bricks_checkpoint_collect(hs, e) : 0;
}

/* Bricks: every rank reads the whole set (as the file stores it) and keeps
 * its share, as handshake_connect dealt the points out.  rc: the reads
 * before; collective. */
static int get_points_bricks(struct handshake *hs, struct ckpt *ck, int rc)
{
    const struct halo *h = hs->md->halo;
    struct mpm_points all;
    const struct mpm_points *mine = &hs->mpm.pts;
    int have = 0;
    if (!(rc = halo_agree(h, rc, ck->e))) {
        rc = mpm_points_init(&all, mine->nstate, ck->e);
        have = !rc;
    }
    if (!rc) rc = mpm_points_reserve(&all, hs->npoints > 0 ? hs->npoints : 1, ck->e);
    if (!rc && mine->fext) rc = mpm_points_enable_fext(&all, ck->e);
    if (!rc) {
        all.n = hs->npoints;
        rc = get_points(ck, &all);
    }
    if (!(rc = halo_agree(h, rc, ck->e)))
        rc = hs_bricks_keep_points(hs, &all, ck->e);
    if (have)
        mpm_points_free(&all);
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
    if (!rc) rc = get_points(ck, &m->pts);
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
    hs_bricks_checkpoint_release(hs);   /* bricks: rank 0's gathered points */
}
