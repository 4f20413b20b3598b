/*
 * mpm_shared: the shared nodes of a whole hierarchical grid on bricks
 * (mpm_shared.h).
 */
#include "mpm/mpm_shared.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"
#include "mpm/mpm.h"
#include "mpm/mpm_hgrid.h"
#include "mpm/mpm_view.h"

#define MARK_TOUCHED 1u
#define MARK_SHARED 2u
#define MARK_LOWER 4u   /* a lower rank touches it too */

int mpm_shared_init(struct mpm_shared *s, const struct parallel *par, const struct mpm *m,
                    struct err *e)
{
    memset(s, 0, sizeof *s);
    s->par = par;
    const struct mpm_hgrid *hg = m->grid.hg;
    s->ncell = hg ? hg->ncell : 0;
    s->nnodes = m->grid.nnodes;
    int size = par ? par->size : 1;
    s->cell_mark = calloc((size_t)(s->ncell > 0 ? s->ncell : 1), 1);
    s->node_mark = calloc((size_t)(s->nnodes > 0 ? s->nnodes : 1), 1);
    s->touched = malloc((size_t)(s->nnodes > 0 ? s->nnodes : 1) * sizeof *s->touched);
    s->fresh = malloc((size_t)(s->nnodes > 0 ? s->nnodes : 1) * sizeof *s->fresh);
    s->first = malloc((size_t)(s->nnodes > 0 ? s->nnodes : 1));
    s->count = calloc((size_t)size, sizeof *s->count);
    s->displ = calloc((size_t)size + 1, sizeof *s->displ);
    s->scount = calloc((size_t)size, sizeof *s->scount);
    s->sdispl = calloc((size_t)size, sizeof *s->sdispl);
    s->rcount = calloc((size_t)size, sizeof *s->rcount);
    s->rdispl = calloc((size_t)size, sizeof *s->rdispl);
    if (!s->cell_mark || !s->node_mark || !s->touched || !s->fresh || !s->first || !s->count ||
        !s->displ ||
        !s->scount || !s->sdispl || !s->rcount || !s->rdispl) {
        mpm_shared_free(s);
        return err_nomem(e, "MPM shared nodes");
    }
    return 0;
}

void mpm_shared_free(struct mpm_shared *s)
{
    free(s->cell_mark);
    free(s->node_mark);
    free(s->touched);
    free(s->fresh);
    free(s->first);
    free(s->list);
    free(s->count);
    free(s->displ);
    free(s->uni);
    free(s->sbuf);
    free(s->rbuf);
    free(s->own);
    free(s->scount);
    free(s->sdispl);
    free(s->rcount);
    free(s->rdispl);
    memset(s, 0, sizeof *s);
}

long mpm_shared_nodes(const struct mpm_shared *s)
{
    return s->nuni;
}

/* The touched nodes of this rank's particles, ascending, into s->fresh:
 * the cells of every located particle (material points and extra sets),
 * then their present nodes.  A particle outside the grid has no cell; its
 * set's locate reported it (and stops the step), so it is not marked. */
static void mark_touched(struct mpm_shared *s, const struct mpm *m)
{
    const struct mpm_hgrid *hg = m->grid.hg;
    memset(s->cell_mark, 0, (size_t)s->ncell);
    memset(s->node_mark, 0, (size_t)s->nnodes);
    if (!hg) {   /* a uniform grid: each particle's stencil, from its position */
        struct mpm_view views[1 + MPM_MAX_EXTRA];
        int nv = mpm_views((struct mpm *)m, views);   /* read only */
        const int kind = mpm_stencil_kind(&m->grid);
        for (int k = 0; k < nv; k++)
            for (long i = 0; i < views[k].n; i++) {
                struct mpm_stencil st;
                mpm_stencil_at(m, &views[k], i, kind, &st);
                for (int q = 0; q < st.n; q++)
                    if (st.node[q] >= 0 && st.node[q] < s->nnodes)
                        s->node_mark[st.node[q]] = MARK_TOUCHED;
            }
    }
    for (int k = 0; hg && k <= m->nextra; k++) {
        long n = k == 0 ? m->pts.n : m->extra[k - 1]->n;
        const int32_t *cell = m->bins[k].cell;
        if (!cell)
            continue;
        for (long i = 0; i < n; i++)
            if (cell[i] >= 0 && cell[i] < s->ncell)
                s->cell_mark[cell[i]] = 1;
    }
    for (long c = 0; c < s->ncell; c++) {
        if (!s->cell_mark[c])
            continue;
        const int32_t *node = mpm_hgrid_cell_nodes(hg, c);   /* located: made */
        for (int q = 0; q < 27; q++)
            if (node[q] >= 0)
                s->node_mark[node[q]] = MARK_TOUCHED;
    }
    long n = 0;
    for (long i = 0; i < s->nnodes; i++)
        if (s->node_mark[i])
            s->fresh[n++] = (int32_t)i;
    s->nfresh = n;
}

/* First index of a[0..n) at or above v. */
static long lower_bound(const int32_t *a, long n, long v)
{
    long lo = 0, hi = n;
    while (lo < hi) {
        long mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static int reserve_list(struct mpm_shared *s, long n, struct err *e)
{
    if (n <= s->cap_list)
        return 0;
    int32_t *p = realloc(s->list, (size_t)n * sizeof *p);
    if (!p)
        return err_nomem(e, "MPM shared nodes");
    s->list = p;
    s->cap_list = n;
    return 0;
}

/* Byte counts and offsets fitting an int (the all-to-all's types). */
static int to_int_bytes(long n, size_t unit, int *out, struct err *e)
{
    if (n < 0 || (size_t)n > (size_t)INT_MAX / unit)
        return err_set(e, ERR_RUNTIME, "MPM shared nodes: %ld records are too many for one "
                                       "message", n);
    *out = (int)((size_t)n * unit);
    return 0;
}

static int reserve(double **buf, size_t *cap, size_t n, struct err *e)
{
    if (n <= *cap)
        return 0;
    double *p = realloc(*buf, n * sizeof *p);
    if (!p)
        return err_nomem(e, "MPM shared nodes");
    *buf = p;
    *cap = n;
    return 0;
}

/* rc made collective: an error on one rank stops every rank. */
static int agree(const struct parallel *par, int rc, struct err *e)
{
    if (parallel_any(par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    return rc;
}

/* What goes to every rank r: this rank's touched nodes within r's index
 * range [lo[r], hi[r]] (a contiguous run of s->touched). */
static int plan_counts(struct mpm_shared *s, const long *lo, const long *hi, struct err *e)
{
    int me = s->par->rank;
    long nt = s->ntouched;
    long mylo = lo[me], myhi = hi[me];
    int rc = 0;
    for (int r = 0; !rc && r < s->par->size; r++) {
        long a = 0, b = 0;
        if (r != me && lo[r] <= hi[r] && mylo <= myhi && lo[r] <= myhi && mylo <= hi[r]) {
            a = lower_bound(s->touched, nt, lo[r]);
            b = lower_bound(s->touched, nt, hi[r] + 1);
        }
        rc = to_int_bytes(b - a, sizeof(int32_t), &s->scount[r], e);
        if (!rc)
            rc = to_int_bytes(a, sizeof(int32_t), &s->sdispl[r], e);
    }
    return rc;
}

/* The shared lists from what every rank r sent (its touched nodes within
 * my range): those I touch too.  Rank r computes the same intersection
 * from its side, so both hold the same list in the same order. */
static int plan_lists(struct mpm_shared *s, const int32_t *theirs, long nrecv, struct err *e)
{
    int rc = reserve_list(s, nrecv > 0 ? nrecv : 1, e);
    long n = 0;
    for (int r = 0; !rc && r < s->par->size; r++) {
        s->displ[r] = n;
        const int32_t *t = theirs + s->rdispl[r] / (long)sizeof(int32_t);
        long nr = s->rcount[r] / (long)sizeof(int32_t);
        for (long j = 0; j < nr; j++)
            if (t[j] >= 0 && t[j] < s->nnodes && (s->node_mark[t[j]] & MARK_TOUCHED)) {
                s->list[n++] = t[j];
                s->node_mark[t[j]] |= MARK_SHARED;
            }
        s->count[r] = n - s->displ[r];
    }
    if (rc)
        return rc;
    s->displ[s->par->size] = n;
    s->nlist = n;
    /* the union, ascending, for this rank's own contributions */
    long nu = 0;
    for (long i = 0; i < s->ntouched; i++)
        nu += (s->node_mark[s->touched[i]] & MARK_SHARED) != 0;
    int32_t *u = realloc(s->uni, (size_t)(nu > 0 ? nu : 1) * sizeof *u);
    if (!u)
        return err_nomem(e, "MPM shared nodes");
    s->uni = u;
    nu = 0;
    for (long i = 0; i < s->ntouched; i++)
        if (s->node_mark[s->touched[i]] & MARK_SHARED)
            u[nu++] = s->touched[i];
    s->nuni = nu;
    /* which touched nodes this rank is the lowest toucher of: the one
     * place a sum over nodes (a rigid body's reaction) counts them */
    for (int r = 0; r < s->par->rank; r++)
        for (long j = 0; j < s->count[r]; j++)
            s->node_mark[s->list[s->displ[r] + j]] |= MARK_LOWER;
    for (long i = 0; i < s->ntouched; i++)
        s->first[i] = !(s->node_mark[s->touched[i]] & MARK_LOWER);
    /* the sums' buffers for up to MPM_SHARED_MAX_NC doubles a node, here
     * so that a sum cannot fail on one rank alone */
    int bytes;
    rc = to_int_bytes(n, MPM_SHARED_MAX_NC * sizeof(double), &bytes, e);
    if (!rc)
        rc = reserve(&s->sbuf, &s->sbuf_cap, (size_t)(n > 0 ? n : 1) * MPM_SHARED_MAX_NC, e);
    if (!rc)
        rc = reserve(&s->rbuf, &s->rbuf_cap, (size_t)(n > 0 ? n : 1) * MPM_SHARED_MAX_NC, e);
    if (!rc)
        rc = reserve(&s->own, &s->own_cap, (size_t)(nu > 0 ? nu : 1) * MPM_SHARED_MAX_NC, e);
    return rc;
}

/* The new plan from s->touched (this rank's set, already in place). */
static int make_plan(struct mpm_shared *s, struct err *e)
{
    const struct parallel *par = s->par;
    int size = par->size;
    long *lo = malloc((size_t)size * sizeof *lo), *hi = malloc((size_t)size * sizeof *hi);
    int rc = agree(par, lo && hi ? 0 : err_nomem(e, "MPM shared nodes"), e);
    long nt = s->ntouched;
    if (!rc) {   /* an empty set has an empty range (lo > hi) */
        parallel_allgather_long(par, nt > 0 ? s->touched[0] : 1, lo);
        parallel_allgather_long(par, nt > 0 ? s->touched[nt - 1] : 0, hi);
        rc = agree(par, plan_counts(s, lo, hi, e), e);
    }
    free(lo);
    free(hi);
    if (!rc)
        rc = parallel_alltoall_int(par, s->scount, s->rcount, e);
    long nrecv = 0;
    for (int r = 0; !rc && r < size; r++) {
        s->rdispl[r] = (int)(nrecv * (long)sizeof(int32_t));
        nrecv += s->rcount[r] / (long)sizeof(int32_t);
    }
    int32_t *theirs = NULL;
    if (!rc) {
        theirs = malloc((size_t)(nrecv > 0 ? nrecv : 1) * sizeof *theirs);
        rc = agree(par, theirs ? 0 : err_nomem(e, "MPM shared nodes"), e);
    }
    if (!rc)
        rc = parallel_alltoallv_bytes(par, s->touched, s->scount, s->sdispl, theirs, s->rcount,
                                      s->rdispl, e);
    if (!rc)
        rc = agree(par, plan_lists(s, theirs, nrecv, e), e);
    free(theirs);
    s->valid = !rc;
    s->rebuilds += !rc;
    return rc;
}

int mpm_shared_plan(struct mpm_shared *s, const struct mpm *m, struct err *e)
{
    mark_touched(s, m);
    int changed = !s->valid || s->nfresh != s->ntouched ||
                  memcmp(s->fresh, s->touched, (size_t)s->nfresh * sizeof *s->fresh) != 0;
    if (!parallel_any(s->par, changed))
        return 0;
    int32_t *t = s->touched;   /* the fresh set becomes the plan's */
    s->touched = s->fresh;
    s->fresh = t;
    s->ntouched = s->nfresh;
    return make_plan(s, e);
}

/* v += w, the last of nc values a maximum when aux_max. */
static inline void add_row(double *v, const double *w, int nc, int aux_max)
{
    int nsum = aux_max ? nc - 1 : nc;
    for (int c = 0; c < nsum; c++)
        v[c] += w[c];
    if (aux_max && w[nc - 1] > v[nc - 1])
        v[nc - 1] = w[nc - 1];
}

int mpm_shared_sum(struct mpm_shared *s, double *base, int nc, int aux_max, struct err *e)
{
    const struct parallel *par = s->par;
    if (!par || par->size < 2)
        return 0;
    /* the same on every rank: no rank stops alone */
    if (!s->valid || nc < 1 || nc > MPM_SHARED_MAX_NC)
        return err_set(e, ERR_RUNTIME, "MPM shared nodes: a sum of %d values without a plan "
                                       "for it", nc);
    int size = par->size, me = par->rank;
    size_t row = (size_t)nc * sizeof(double);
    for (int r = 0; r < size; r++) {   /* checked against 8 doubles a node by the plan */
        s->scount[r] = s->rcount[r] = (int)(s->count[r] * (long)row);
        s->sdispl[r] = s->rdispl[r] = (int)(s->displ[r] * (long)row);
    }
    for (long j = 0; j < s->nlist; j++)
        memcpy(s->sbuf + j * nc, base + (long)s->list[j] * nc, row);
    for (long j = 0; j < s->nuni; j++) {   /* my own, then the shared nodes from zero */
        double *v = base + (long)s->uni[j] * nc;
        memcpy(s->own + j * nc, v, row);
        memset(v, 0, row);
    }
    int rc = parallel_alltoallv_bytes(par, s->sbuf, s->scount, s->sdispl, s->rbuf, s->rcount,
                                      s->rdispl, e);
    if (rc)
        return rc;
    /* in ascending rank order, this rank's own at its place: the same
     * additions in the same order on every rank that holds the node */
    for (int r = 0; r < size; r++) {
        if (r == me) {
            for (long j = 0; j < s->nuni; j++)
                add_row(base + (long)s->uni[j] * nc, s->own + j * nc, nc, aux_max);
            continue;
        }
        const int32_t *l = s->list + s->displ[r];
        const double *in = s->rbuf + s->displ[r] * nc;
        for (long j = 0; j < s->count[r]; j++)
            add_row(base + (long)l[j] * nc, in + j * nc, nc, aux_max);
    }
    return 0;
}

/* Node indices a window of the gather spans: with 8 doubles and the index
 * a record, at most 2.4 MB sent by a rank a window. */
#define GATHER_WINDOW_NODES 32768L

int mpm_shared_gather_root(struct mpm_shared *s, const double *base, int nc, double *out,
                           struct err *e)
{
    const struct parallel *par = s->par;
    int root = !par || par->rank == 0;
    if (root)   /* rank 0 is the lowest toucher of every node it touches */
        memcpy(out, base, (size_t)s->nnodes * (size_t)nc * sizeof *out);
    if (!par || par->size < 2)
        return 0;
    int rc = s->valid ? 0 : err_set(e, ERR_RUNTIME, "MPM shared nodes: a gather without a plan");
    double *pack =
        root ? NULL : malloc((size_t)GATHER_WINDOW_NODES * (size_t)(nc + 1) * sizeof *pack);
    if (!rc && !root && !pack)
        rc = err_nomem(e, "MPM grid gather");
    if (parallel_any(par, rc != 0)) {
        free(pack);
        return rc ? rc : err_set_elsewhere(e, ERR_RUNTIME, "MPM grid gather: another rank failed");
    }
    long j = 0;   /* cursor into the touched nodes (ascending) */
    for (long lo = 0; lo < s->nnodes && !rc; lo += GATHER_WINDOW_NODES) {
        long hi = lo + GATHER_WINDOW_NODES < s->nnodes ? lo + GATHER_WINDOW_NODES : s->nnodes;
        size_t n = 0;
        if (!root)
            for (; j < s->ntouched && s->touched[j] < hi; j++) {
                if (!s->first[j])
                    continue;   /* a lower rank gives it */
                double *rec = pack + n++ * (size_t)(nc + 1);
                rec[0] = (double)s->touched[j];
                memcpy(rec + 1, base + (size_t)s->touched[j] * (size_t)nc,
                       (size_t)nc * sizeof *rec);
            }
        void *rbuf = NULL;
        size_t rbytes = 0;
        rc = parallel_gather_bytes(par, pack, n * (size_t)(nc + 1) * sizeof *pack, &rbuf,
                                   &rbytes, e);
        const double *in = rbuf;
        size_t nin = rbytes / ((size_t)(nc + 1) * sizeof *in);
        for (size_t k = 0; !rc && k < nin; k++) {
            const double *rec = in + k * (size_t)(nc + 1);
            memcpy(out + (size_t)rec[0] * (size_t)nc, rec + 1, (size_t)nc * sizeof *out);
        }
        free(rbuf);
    }
    free(pack);
    return rc;
}
