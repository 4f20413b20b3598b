/* mpm_checkpoint: material points in a checkpoint (mpm_checkpoint.h). */
#include "output/mpm_checkpoint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int mpm_ckpt_columns(const struct mpm_points *p, int fext_always, struct ckpt_col *col)
{
    const struct ckpt_col fixed[MPM_CKPT_COLUMNS] = {
        {"x", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->x},
        {"x0", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->x0},
        {"v", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->v},
        {"mass", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, p->mass},
        {"vol0", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, p->vol0},
        {"vol", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, p->vol},
        {"stress", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 6, p->stress},
        {"F", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 9, p->F},
        {"eint", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, p->eint},
        {"state", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, p->nstate, p->state},
        {"body", H5T_NATIVE_INT32, H5T_STD_I32LE, 1, p->body},
        {"id", H5T_NATIVE_INT64, H5T_STD_I64LE, 1, p->id},
        {"mask", H5T_NATIVE_UINT32, H5T_STD_U32LE, 1, p->mask},
        {"fext", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, p->fext ? 3 : 0, p->fext},
    };
    int n = MPM_CKPT_COLUMNS - (p->fext || fext_always ? 0 : 1);
    memcpy(col, fixed, (size_t)n * sizeof *col);
    return n;
}

struct take_points {
    struct ckpt *ck;
    struct mpm_points *p;
    int fext_always, ncol, nbody;
    int (*keep)(const void *ctx, const double x[3], int64_t id);
    const void *ctx;
    long row;   /* stored row of the next point, for messages */
};

static int take_point(void *ctx, const void *const *buf, long k)
{
    struct take_points *t = ctx;
    struct mpm_points *p = t->p;
    long row = t->row++;
    const double *x = (const double *)buf[0] + 3 * k;
    int body = ((const int32_t *)buf[10])[k];
    int64_t id = ((const int64_t *)buf[11])[k];
    if (body < 0 || body >= t->nbody)
        return err_set(t->ck->e, ERR_INPUT, "%s: material point %ld of the checkpoint is in "
                                            "body %d; the case has %d bodies",
                       t->ck->path, row, body, t->nbody);
    if (id < 1)
        return err_set(t->ck->e, ERR_INPUT, "%s: checkpoint %s/id: material point %ld has id "
                                            "%lld, below 1",
                       t->ck->path, t->ck->where, row, (long long)id);
    for (int q = 0; q < 3; q++)   /* x, x0, v */
        for (int d = 0; d < 3; d++)
            if (!isfinite(((const double *)buf[q])[3 * k + d]))
                return err_set(t->ck->e, ERR_INPUT, "%s: checkpoint %s/x/x0/v: a non-finite "
                                                    "position or velocity (material point id "
                                                    "%lld)",
                               t->ck->path, t->ck->where, (long long)id);
    if (t->keep && !t->keep(t->ctx, x, id))
        return 0;
    if (p->n >= p->cap && mpm_points_reserve(p, p->cap > 0 ? 2 * p->cap : 1024, t->ck->e))
        return t->ck->e->code ? t->ck->e->code : ERR_RUNTIME;
    struct ckpt_col col[MPM_CKPT_COLUMNS];
    mpm_ckpt_columns(p, t->fext_always, col);   /* after the reserve: the arrays may move */
    long i = p->n++;
    for (int q = 0; q < t->ncol; q++) {
        size_t bytes = H5Tget_size(col[q].memtype) * (size_t)col[q].ncomp;
        if (bytes == 0)
            continue;   /* an empty column (no state variables, no loads) */
        memcpy((unsigned char *)col[q].data + bytes * (size_t)i,
               (const unsigned char *)buf[q] + bytes * (size_t)k, bytes);
    }
    return 0;
}

int mpm_ckpt_get_count(struct ckpt *ck, const char *count_name, long *n, int *by_rank)
{
    long order = 0;
    int rc = ckpt_get_long(ck, count_name, n);
    if (!rc && ckpt_has(ck, "order"))
        rc = ckpt_get_long(ck, "order", &order);
    if (!rc && (*n < 0 || *n > 2000000000L))
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint %s/%s: impossible point count %ld",
                     ck->path, ck->where, count_name, *n);
    if (!rc && order != 0 && order != 1)
        rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint %s/order: %ld is no row order (0: memory "
                                       "order, 1: rank order)",
                     ck->path, ck->where, order);
    *by_rank = order == 1;
    return rc;
}

static int cmp_id(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

int mpm_ckpt_check_ids(struct ckpt *ck, const struct mpm_points *p)
{
    if (p->n < 2)
        return 0;
    int64_t *ids = malloc((size_t)p->n * sizeof *ids);
    if (!ids)
        return err_nomem(ck->e, "checkpoint ids");
    memcpy(ids, p->id, (size_t)p->n * sizeof *ids);
    qsort(ids, (size_t)p->n, sizeof *ids, cmp_id);
    int rc = 0;
    for (long i = 1; !rc && i < p->n; i++)
        if (ids[i] == ids[i - 1])
            rc = err_set(ck->e, ERR_INPUT, "%s: checkpoint %s/id: id %lld given twice",
                         ck->path, ck->where, (long long)ids[i]);
    free(ids);
    return rc;
}

int mpm_ckpt_get_points_where(struct ckpt *ck, long n, struct mpm_points *p, int fext_always,
                              int nbody, int (*keep)(const void *ctx, const double x[3], int64_t id),
                              const void *ctx)
{
    struct ckpt_col col[MPM_CKPT_COLUMNS];
    int ncol = mpm_ckpt_columns(p, fext_always, col);
    struct take_points t = {ck, p, fext_always, ncol, nbody, keep, ctx, 0};
    return ckpt_get_columns_blocks(ck, col, ncol, n, take_point, &t);
}
