/* handshake_bricks: region I of every rank to the whole MPM on every rank
 * (handshake_bricks.h). */
#include "couple/handshake_bricks.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"

enum { ROW = 12 };   /* x[3], v[3], stress[6] */

struct hs_bricks {
    long nall;         /* region I atoms of all ranks */
    long *pos;         /* rank 0: id-order place of each gathered row */
    double *rows;      /* ROW x nall: the rows of all ranks in id order */
    double *send;      /* ROW x hs->nI: this rank's rows */
};

struct id_mass {
    int64_t id;
    double mass;
};

static int by_id(const void *a, const void *b)
{
    int64_t x = ((const struct id_mass *)a)->id, y = ((const struct id_mass *)b)->id;
    return (x > y) - (x < y);
}

static const struct parallel *par_of(const struct handshake *hs)
{
    return hs->md->halo->dc.par;
}

static int grow(void **p, size_t bytes)
{
    void *q = realloc(*p, bytes ? bytes : 1);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

int hs_bricks_index(struct handshake *hs, struct err *e)
{
    const struct halo *h = hs->md->halo;
    const struct parallel *par = par_of(hs);
    const struct particles *p = hs->md->p;
    int root = !par || par->rank == 0;
    struct hs_bricks *b = hs->bricks;
    if (!b && !(b = hs->bricks = calloc(1, sizeof *b)))
        return halo_agree(h, err_nomem(e, "handshake bricks"), e);
    double n = (double)hs->nI;
    halo_sum(h, &n, 1);
    long nall = (long)n;
    /* this rank's ids and masses to rank 0, which sorts them by id */
    struct id_mass *mine = malloc((size_t)(hs->nI > 0 ? hs->nI : 1) * sizeof *mine);
    int rc = mine ? 0 : err_nomem(e, "handshake region I ids");
    for (long k = 0; mine && k < hs->nI; k++) {
        int i = hs->idxI[k];
        mine[k].id = p->id[i];
        mine[k].mass = p->mass[p->type[i]];
    }
    size_t sz = (size_t)(nall > 0 ? nall : 1);
    if (grow((void **)&hs->xI, 3 * sz * sizeof(double)) ||
        grow((void **)&hs->vI, 3 * sz * sizeof(double)) ||
        grow((void **)&hs->sI, 6 * sz * sizeof(double)) ||
        grow((void **)&hs->mI, sz * sizeof(double)) ||
        grow((void **)&hs->volI, sz * sizeof(double)) ||
        grow((void **)&b->rows, ROW * sz * sizeof(double)) ||
        grow((void **)&b->send, ROW * (size_t)(hs->nI > 0 ? hs->nI : 1) * sizeof(double)) ||
        (root && grow((void **)&b->pos, sz * sizeof(long))))
        rc = rc ? rc : err_nomem(e, "handshake region I of all ranks");
    if ((rc = halo_agree(h, rc, e))) {
        free(mine);
        return rc;
    }
    void *all = NULL;
    size_t bytes = 0;
    rc = parallel_gather_bytes(par, mine, (size_t)hs->nI * sizeof *mine, &all, &bytes, e);
    free(mine);
    if (!rc && root) {
        struct id_mass *im = all;
        if ((long)(bytes / sizeof *im) != nall) {
            rc = err_set(e, ERR_RUNTIME, "handshake: gathered %zu region I atoms, expected %ld",
                         bytes / sizeof *im, nall);
        } else {
            /* the place of gathered row r in id order: sort (id, r) pairs,
             * the mass field carrying r while sorting */
            struct id_mass *order = malloc(sz * sizeof *order);
            if (!order)
                rc = err_nomem(e, "handshake region I order");
            for (long r = 0; order && r < nall; r++) {
                order[r].id = im[r].id;
                order[r].mass = (double)r;
            }
            if (order) {
                qsort(order, (size_t)nall, sizeof *order, by_id);
                for (long k = 0; k < nall; k++) {
                    long r = (long)order[k].mass;
                    b->pos[r] = k;
                    hs->mI[k] = im[r].mass;
                }
            }
            free(order);
        }
    }
    free(all);
    if ((rc = halo_agree(h, rc, e)))
        return rc;
    if ((rc = parallel_bcast_bytes(par, hs->mI, (size_t)nall * sizeof(double), e)))
        return rc;
    for (long k = 0; k < nall; k++)
        hs->volI[k] = hs->omega0;
    b->nall = nall;
    hs_extra_region_i(hs, nall);
    return 0;
}

int hs_bricks_gather(struct handshake *hs, struct err *e)
{
    const struct parallel *par = par_of(hs);
    struct hs_bricks *b = hs->bricks;
    int root = !par || par->rank == 0;
    for (long k = 0; k < hs->nI; k++) {
        double *row = b->send + ROW * k;
        handshake_region_I_row(hs, hs->idxI[k], row, row + 3, row + 6);
    }
    void *all = NULL;
    size_t bytes = 0;
    int rc = parallel_gather_bytes(par, b->send, (size_t)hs->nI * ROW * sizeof(double), &all,
                                   &bytes, e);
    if (!rc && root) {
        const double *in = all;
        for (long r = 0; r < b->nall; r++)
            memcpy(b->rows + ROW * b->pos[r], in + ROW * r, ROW * sizeof(double));
    }
    free(all);
    rc = halo_agree(hs->md->halo, rc, e);
    if (!rc)
        rc = parallel_bcast_bytes(par, b->rows, (size_t)b->nall * ROW * sizeof(double), e);
    if (rc)
        return rc;
    for (long k = 0; k < b->nall; k++) {
        const double *row = b->rows + ROW * k;
        memcpy(hs->xI + 3 * k, row, 3 * sizeof(double));
        memcpy(hs->vI + 3 * k, row + 3, 3 * sizeof(double));
        memcpy(hs->sI + 6 * k, row + 6, 6 * sizeof(double));
    }
    return 0;
}

void hs_bricks_free(struct handshake *hs)
{
    struct hs_bricks *b = hs->bricks;
    if (!b)
        return;
    free(b->pos);
    free(b->rows);
    free(b->send);
    free(b);
    hs->bricks = NULL;
}
