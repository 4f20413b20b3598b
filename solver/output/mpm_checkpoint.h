/*
 * mpm_checkpoint: the per-point datasets of material points in a
 * checkpoint (output/checkpoint.h), shared by the MPM model and the
 * handshake's MPM side.
 *
 * A serial run writes its points in memory order.  On bricks rank 0 lays
 * the datasets out for every rank's points (ckpt_put_columns without
 * data) and every rank writes its own rows (ckpt_put_columns_part): the
 * rows are the ranks' points in rank order, which the group marks with
 * `order` = 1 so that a reader puts them in id order.  A rank restarting
 * on bricks reads the rows in blocks and keeps its own
 * (mpm_ckpt_get_points_where): no rank holds every point.
 */
#ifndef CASCADE_MPM_CHECKPOINT_H
#define CASCADE_MPM_CHECKPOINT_H

#include <stdint.h>

#include "mpm/mpm_points.h"
#include "output/checkpoint.h"

#define MPM_CKPT_COLUMNS 14

/* The datasets of p's points (x, x0, v, mass, vol0, vol, stress, F, eint,
 * state, body, id, mask, fext) into col; returns their number.  fext: with
 * loads 3 values a point; without, an empty dataset when fext_always, else
 * none. */
int mpm_ckpt_columns(const struct mpm_points *p, int fext_always, struct ckpt_col *col);

/* The n stored rows of the current group, in blocks, appending to p (its
 * arrays grown as needed; p->n counts on) the points keep(ctx, x, id)
 * accepts (all when keep is NULL).  A row whose body is not below nbody is
 * refused (file, row and body named).  Collective on a file of
 * ckpt_open_parallel. */
int mpm_ckpt_get_points_where(struct ckpt *ck, long n, struct mpm_points *p, int fext_always,
                              int nbody, int (*keep)(const void *ctx, const double x[3], int64_t id),
                              const void *ctx);

/* The group's stored point count (dataset count_name) and `order` (absent:
 * 0) read and checked: a count below 0 or above 2e9, or an order other
 * than 0 (memory order) and 1 (rank order), is refused naming the file and
 * the dataset.  *by_rank: the rows are in rank order. */
int mpm_ckpt_get_count(struct ckpt *ck, const char *count_name, long *n, int *by_rank);

/* No id twice among p's points (e names the file and dataset). */
int mpm_ckpt_check_ids(struct ckpt *ck, const struct mpm_points *p);

#endif
