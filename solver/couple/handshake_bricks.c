/* handshake_bricks: the handshake's material points dealt out over the
 * ranks of the MD's bricks, the grid whole (handshake_bricks.h). */
#include "couple/handshake_bricks.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"
#include "mpm/mpm_bricks.h"
#include "output/mpm_checkpoint.h"

struct hs_bricks {
    struct mpm_bricks *mb;    /* the MPM step: grid whole, fixed owners */
    const struct parallel *par;
    int rank, nranks;
    long npoints;             /* points of all ranks */
    int32_t *owner;           /* per point of all ranks: the rank that holds it */
    int32_t *local;           /* per point of all ranks: its index here, -1 elsewhere */
    /* the rows of the copies whose point another rank holds */
    int *scount, *sdispl;     /* bytes to each rank (rows of my points) */
    int *rcount, *rdispl;     /* bytes from each rank (rows of my copies) */
    int32_t *send_pt;         /* my points whose rows go out, grouped by rank */
    long nsend;
    long *recv_link;          /* the link of each row that comes in, grouped by rank */
    long nrecv;
    int any_remote;           /* some rank has such a copy (else no all-to-all) */
    long remote_max;          /* the most such copies of all ranks at any rebuild */
    double *sbuf, *rbuf;
    long ck_offset, ck_total;     /* a checkpoint's rows of points: this rank's first, all */
};

static const struct halo *halo_of(const struct handshake *hs)
{
    return hs->md->halo;
}

int hs_bricks_adopt(struct handshake *hs, const struct halo *h, int32_t *owner, long n,
                    struct err *e)
{
    struct hs_bricks *b = calloc(1, sizeof *b);
    hs->bricks = b;
    int rc = b ? 0 : err_nomem(e, "handshake bricks");
    if (b) {
        b->owner = owner;
        b->par = h->dc.par;
        b->rank = b->par ? b->par->rank : 0;
        b->nranks = b->par ? b->par->size : 1;
        b->npoints = n;
        size_t nr = (size_t)b->nranks;
        b->local = malloc((size_t)(n > 0 ? n : 1) * sizeof *b->local);
        b->scount = calloc(nr, sizeof *b->scount);
        b->sdispl = calloc(nr, sizeof *b->sdispl);
        b->rcount = calloc(nr, sizeof *b->rcount);
        b->rdispl = calloc(nr, sizeof *b->rdispl);
        if (!b->local || !b->scount || !b->sdispl || !b->rcount || !b->rdispl)
            rc = err_nomem(e, "handshake bricks");
        if (!rc && n > INT32_MAX)
            rc = err_set(e, ERR_RUNTIME, "handshake: %ld material points, more than 2^31", n);
    } else {
        free(owner);
    }
    /* this rank's points were added in the order of the build */
    long mine = 0;
    for (long q = 0; !rc && q < n; q++)
        b->local[q] = owner[q] == b->rank ? (int32_t)mine++ : -1;
    if (!rc && mine != hs->mpm.pts.n)
        rc = err_set(e, ERR_RUNTIME, "handshake: rank %d holds %ld points, dealt %ld", b->rank,
                     hs->mpm.pts.n, mine);
    rc = halo_agree(h, rc, e);
    if (!rc)
        rc = mpm_bricks_create_fixed(b->par, &hs->mpm, &b->mb, e);
    return rc;
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
    const struct halo *h = halo_of(hs);
    struct hs_bricks *b = hs->bricks;
    const int nr = b->nranks;
    const long rowb = HS_LINK_ROW * (long)sizeof(double);
    /* my requests: the copies whose point is elsewhere, grouped by owner */
    int *req = calloc((size_t)nr, sizeof *req), *got = calloc((size_t)nr, sizeof *got);
    int *at = calloc((size_t)nr, sizeof *at);
    int rc = req && got && at ? 0 : err_nomem(e, "handshake copies' plan");
    long nreq = 0;
    for (long k = 0; !rc && k < hs->nlink; k++) {
        long q = hs->link_pt[k];
        if (b->local[q] < 0) {
            req[b->owner[q]]++;
            nreq++;
        }
    }
    int64_t *qs = NULL, *theirs = NULL;
    if (!rc && (grow((void **)&b->recv_link, (size_t)nreq * sizeof *b->recv_link) ||
                !(qs = malloc((size_t)(nreq > 0 ? nreq : 1) * sizeof *qs))))
        rc = err_nomem(e, "handshake copies' plan");
    if (!rc && (long)nreq * rowb > INT_MAX)
        rc = err_set(e, ERR_RUNTIME, "handshake: %ld copies' rows exceed MPI's int count", nreq);
    for (int r = 0, s = 0; !rc && r < nr; r++) {
        at[r] = s;
        s += req[r];
    }
    for (long k = 0; !rc && k < hs->nlink; k++) {
        long q = hs->link_pt[k];
        if (b->local[q] >= 0)
            continue;
        int j = at[b->owner[q]]++;
        qs[j] = q;
        b->recv_link[j] = k;
    }
    b->nrecv = nreq;
    rc = halo_agree(h, rc, e);
    /* what every rank asks of me */
    if (!rc)
        rc = parallel_alltoall_int(b->par, req, got, e);
    long nsend = 0;
    for (int r = 0; !rc && r < nr; r++)
        nsend += got[r];
    if (!rc && (grow((void **)&b->send_pt, (size_t)nsend * sizeof *b->send_pt) ||
                !(theirs = malloc((size_t)(nsend > 0 ? nsend : 1) * sizeof *theirs))))
        rc = err_nomem(e, "handshake copies' plan");
    if (!rc && nsend * rowb > INT_MAX)
        rc = err_set(e, ERR_RUNTIME, "handshake: %ld points' rows exceed MPI's int count", nsend);
    rc = halo_agree(h, rc, e);
    /* the requested point numbers, in bytes */
    int *sc = b->scount, *sd = b->sdispl, *rcn = b->rcount, *rd = b->rdispl;
    if (!rc) {
        int so = 0, ro = 0;
        for (int r = 0; r < nr; r++) {
            sc[r] = req[r] * (int)sizeof(int64_t);
            sd[r] = so;
            so += sc[r];
            rcn[r] = got[r] * (int)sizeof(int64_t);
            rd[r] = ro;
            ro += rcn[r];
        }
        rc = parallel_alltoallv_bytes(b->par, qs, sc, sd, theirs, rcn, rd, e);
    }
    for (long j = 0; !rc && j < nsend; j++) {
        long q = (long)theirs[j];
        if (q < 0 || q >= b->npoints || b->local[q] < 0)
            rc = err_set(e, ERR_RUNTIME, "handshake: rank %d asked for material point %ld, "
                                         "which it does not hold",
                         b->rank, q + 1);
        else
            b->send_pt[j] = b->local[q];
    }
    b->nsend = nsend;
    /* from here on the counts are the rows' bytes: mine out, my copies' in */
    if (!rc) {
        int so = 0, ro = 0;
        for (int r = 0; r < nr; r++) {
            sc[r] = got[r] * (int)rowb;
            sd[r] = so;
            so += sc[r];
            rcn[r] = req[r] * (int)rowb;
            rd[r] = ro;
            ro += rcn[r];
        }
        if (grow((void **)&b->sbuf, (size_t)(nsend * rowb)) ||
            grow((void **)&b->rbuf, (size_t)(nreq * rowb)))
            rc = err_nomem(e, "handshake copies' rows");
    }
    free(req);
    free(got);
    free(at);
    free(qs);
    free(theirs);
    rc = halo_agree(h, rc, e);
    if (!rc) {
        double any = (double)nreq;
        halo_sum(h, &any, 1);
        b->any_remote = any > 0;
        if ((long)any > b->remote_max)
            b->remote_max = (long)any;
    }
    return rc;
}

int hs_bricks_link_rows(struct handshake *hs, struct err *e)
{
    struct hs_bricks *b = hs->bricks;
    for (long k = 0; k < hs->nlink; k++) {
        int32_t l = b->local[hs->link_pt[k]];
        if (l >= 0)
            handshake_point_row(hs, l, hs->link_row + HS_LINK_ROW * k);
    }
    if (!b->any_remote)
        return 0;
    for (long j = 0; j < b->nsend; j++)
        handshake_point_row(hs, b->send_pt[j], b->sbuf + HS_LINK_ROW * j);
    int rc = parallel_alltoallv_bytes(b->par, b->sbuf, b->scount, b->sdispl, b->rbuf, b->rcount,
                                      b->rdispl, e);
    if (rc)
        return rc;
    for (long j = 0; j < b->nrecv; j++)
        memcpy(hs->link_row + HS_LINK_ROW * b->recv_link[j], b->rbuf + HS_LINK_ROW * j,
               HS_LINK_ROW * sizeof(double));
    return 0;
}

int hs_bricks_mpm_step(struct handshake *hs, double dt, struct err *e)
{
    struct mpm_bricks *mb = hs->bricks->mb;
    int rc = mpm_bricks_step_map(mb, &hs->mpm, e);
    return rc ? rc : mpm_bricks_step_update(mb, &hs->mpm, dt, e);
}

int hs_bricks_mpm_prepare(struct handshake *hs, struct err *e)
{
    return mpm_bricks_prepare(hs->bricks->mb, &hs->mpm, e);
}

int hs_bricks_map_forces(struct handshake *hs, struct err *e)
{
    return mpm_bricks_map_initial(hs->bricks->mb, &hs->mpm, e);
}

void hs_bricks_mpm_totals(const struct handshake *hs, struct mpm_totals *t)
{
    mpm_bricks_totals(hs->bricks->mb, &hs->mpm, t);
}

/* The rows of a checkpoint's points this rank writes: its first (the
 * points of the lower ranks) and all of them.  Collective. */
int hs_bricks_checkpoint_collect(struct handshake *hs, struct err *e)
{
    struct hs_bricks *b = hs->bricks;
    long *counts = malloc((size_t)b->nranks * sizeof *counts);
    int rc = halo_agree(halo_of(hs), counts ? 0 : err_nomem(e, "checkpoint counts"), e);
    b->ck_offset = b->ck_total = 0;
    if (!rc) {
        parallel_allgather_long(b->par, hs->mpm.pts.n, counts);
        for (int r = 0; r < b->nranks; r++) {
            b->ck_offset += r < b->rank ? counts[r] : 0;
            b->ck_total += counts[r];
        }
    }
    free(counts);
    return rc;
}

long hs_bricks_checkpoint_total(const struct handshake *hs)
{
    return hs->bricks->ck_total;
}

long hs_bricks_checkpoint_offset(const struct handshake *hs)
{
    return hs->bricks->ck_offset;
}

static int dealt_to_me(const void *ctx, const double x[3], int64_t id)
{
    const struct hs_bricks *b = ctx;
    (void)x;
    return id >= 1 && id <= b->npoints && b->owner[id - 1] == b->rank;
}

int hs_bricks_read_points(struct handshake *hs, struct ckpt *ck, long n, struct err *e)
{
    struct hs_bricks *b = hs->bricks;
    struct mpm_points *p = &hs->mpm.pts;
    int rc = 0;
    if (n != b->npoints)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld material points, the case %ld",
                     ck->path, n, b->npoints);
    long want = p->n;
    p->n = 0;
    if (!rc)
        rc = mpm_ckpt_get_points_where(ck, n, p, 1, hs->mpm.nbody, dealt_to_me, b);
    /* in the order of the build (id order), which the links follow */
    if (!rc)
        rc = mpm_bricks_sort_by_id(NULL, &hs->mpm, e);
    if (!rc && p->n != want)
        rc = err_set(e, ERR_INPUT, "%s: rank %d read %ld of its %ld material points", ck->path,
                     b->rank, p->n, want);
    for (long i = 0; !rc && i < p->n; i++)
        if (b->local[p->id[i] - 1] != i)
            rc = err_set(e, ERR_INPUT, "%s: material point id %lld is stored twice", ck->path,
                         (long long)p->id[i]);
    mpm_points_moved(&hs->mpm);
    return halo_agree(halo_of(hs), rc, e);
}

long hs_bricks_remote_copies_max(const struct handshake *hs)
{
    return hs->bricks ? hs->bricks->remote_max : 0;
}

void hs_bricks_shared_counts(const struct handshake *hs, long *nodes_max, long *plans)
{
    mpm_bricks_shared_counts(hs->bricks ? hs->bricks->mb : NULL, nodes_max, plans);
}

void hs_bricks_free(struct handshake *hs)
{
    struct hs_bricks *b = hs->bricks;
    if (!b)
        return;
    mpm_bricks_destroy(&b->mb);
    free(b->owner);
    free(b->local);
    free(b->scount);
    free(b->sdispl);
    free(b->rcount);
    free(b->rdispl);
    free(b->send_pt);
    free(b->recv_link);
    free(b->sbuf);
    free(b->rbuf);
    free(b);
    hs->bricks = NULL;
}
