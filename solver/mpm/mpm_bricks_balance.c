/* mpm_bricks_balance: the dynamic balance of the MPM's bricks
 * (`parallel.balance_every`, mpm_bricks.h).  The set-up cuts at the
 * quantiles of the points the case makes (mpm_bricks_shift_cuts); during
 * the run the points move (an impact piles them up on one side of a face)
 * and the checks here cut again at the quantiles of their present cells. */
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"
#include "mpm/mpm_bricks.h"

void mpm_bricks_balance_schedule(struct mpm_bricks *b, long every, double threshold)
{
    b->balance_every = b->fixed ? 0 : every;
    b->balance_threshold = threshold;
    b->balance_next = every;   /* the set-up has cut at the points */
}

/* The cuts at the quantiles of the points' present cells along every axis
 * cut more than once: every rank counts its points by cell layer, the
 * counts are summed over the ranks (exactly: integers below 2^53), so
 * every rank computes the same cuts; when a cut moved, the points and the
 * patches follow (mpm_bricks_recut).  Collective. */
static int cut_at_points(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    struct mpm_bricks_hist h;
    int rc = mpm_bricks_agree(b, mpm_bricks_hist_init(b, &h, e), e);
    if (rc)
        return rc;
    for (long i = 0; i < m->pts.n; i++)
        mpm_bricks_hist_add(b, &m->grid, &h, m->pts.x + 3 * i);
    double *sum = NULL;
    long nmax = 1;
    for (int d = 0; d < 3; d++)
        nmax = b->ncell[d] + 1 > nmax ? b->ncell[d] + 1 : nmax;
    sum = malloc((size_t)nmax * sizeof *sum);
    long *old = malloc((size_t)(b->grid[0] + b->grid[1] + b->grid[2] + 3) * sizeof *old);
    rc = mpm_bricks_agree(b, sum && old ? 0 : err_nomem(e, "MPM balance"), e);
    for (int d = 0; !rc && d < 3; d++) {
        if (!h.layer[d])
            continue;
        for (long k = 0; k < b->ncell[d]; k++)
            sum[k] = (double)h.layer[d][k];
        sum[b->ncell[d]] = (double)h.n;
        mpm_bricks_sum(b, sum, (int)b->ncell[d] + 1);
        for (long k = 0; k < b->ncell[d]; k++)
            h.layer[d][k] = (long)sum[k];
        h.n = (long)sum[b->ncell[d]];
    }
    int moved = 0;
    if (!rc) {
        size_t at = 0;   /* the cuts before, axis after axis */
        for (int d = 0; d < 3; d++) {
            memcpy(old + at, b->cut[d], (size_t)(b->grid[d] + 1) * sizeof *old);
            at += (size_t)b->grid[d] + 1;
        }
        mpm_bricks_shift_cuts(b, &h);
        at = 0;
        for (int d = 0; d < 3; d++) {
            moved |= memcmp(old + at, b->cut[d], (size_t)(b->grid[d] + 1) * sizeof *old) != 0;
            at += (size_t)b->grid[d] + 1;
        }
    }
    mpm_bricks_hist_free(&h);
    free(sum);
    free(old);
    if (rc || !moved)   /* the same on every rank: the same sums */
        return rc;
    b->balance_shifts++;
    return mpm_bricks_recut(b, m, e);
}

int mpm_bricks_balance_step(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    long every = b->balance_every;
    if (every <= 0 || m->step < b->balance_next)
        return 0;
    b->balance_next = (m->step / every + 1) * every;
    double most = (double)m->pts.n, total = (double)m->pts.n;
    mpm_bricks_max(b, &most, 1);
    mpm_bricks_sum(b, &total, 1);
    double mean = total / b->par->size;
    double imbalance = mean > 0 ? most / mean : 1.0;
    b->balance_checks++;
    if (imbalance > b->balance_worst)
        b->balance_worst = imbalance;
    if (!(imbalance > b->balance_threshold))
        return 0;
    return cut_at_points(b, m, e);
}

int mpm_bricks_balance_sync(struct mpm_bricks *b, struct mpm *m, struct err *e)
{
    long every = b->balance_every;
    if (every <= 0)
        return 0;
    b->balance_next = (m->step / every + 1) * every;
    return cut_at_points(b, m, e);
}
