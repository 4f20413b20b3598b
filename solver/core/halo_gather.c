/* halo_gather: the owned particles of every rank on rank 0, all at once or
 * a window of ids at a time (halo.h). */
#include "core/halo.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo_pack.h"
#include "core/parallel.h"

/* An empty set with p's types, masses and per-particle fields, room for n. */
static int empty_like(const struct particles *p, int n, struct particles **out, struct err *e)
{
    struct particles *q = particles_create(n > 0 ? n : 1);
    int rc = q ? 0 : err_nomem(e, "gathered particles");
    if (!rc) {
        q->ntypes = p->ntypes;
        memcpy(q->mass, p->mass, sizeof q->mass);
        memcpy(q->type_name, p->type_name, sizeof q->type_name);
        for (int k = 0; !rc && k < p->nfields; k++)
            if (particles_add_field(q, p->fields[k].name, p->fields[k].ncomp,
                                    p->fields[k].ghost_copy, e) < 0)
                rc = ERR_RUNTIME;
    }
    if (!rc)
        rc = particles_reserve(q, n, e);
    if (rc)
        particles_destroy(&q);
    *out = q;
    return rc;
}

/* The n records of buf into q (emptied first), sorted by id. */
static int unpack_sorted(struct particles *q, const void *buf, size_t rec, int n, struct err *e)
{
    int rc = particles_reserve(q, n, e);
    if (rc)
        return rc;
    for (int i = 0; i < n; i++)
        halo_unpack(q, i, (const unsigned char *)buf + rec * (size_t)i);
    q->n_owned = n;
    q->n_ghost = 0;
    return halo_sort_by_id(q, e);
}

int halo_gather(struct halo *h, const struct particles *p, struct particles **out, struct err *e)
{
    *out = NULL;
    size_t rec = halo_record_size(p);
    /* a buffer of its own: the brick's every atom, given back at once
     * (sbuf stays the size of a swap) */
    unsigned char *mine = malloc(rec * (size_t)(p->n_owned ? p->n_owned : 1));
    int rc = mine ? 0 : err_nomem(e, "gather buffer");
    for (int i = 0; !rc && i < p->n_owned; i++)
        halo_pack(p, i, -1, 0.0, mine + rec * (size_t)i);
    rc = halo_agree(h, rc, e);
    void *all = NULL;
    size_t bytes = 0;
    if (!rc)
        rc = parallel_gather_bytes(h->dc.par, mine, rec * (size_t)p->n_owned, &all, &bytes, e);
    free(mine);
    if (rc || !all)
        return rc;
    int n = (int)(bytes / rec);
    struct particles *q = NULL;
    rc = empty_like(p, n, &q, e);
    if (!rc)
        rc = unpack_sorted(q, all, rec, n, e);
    free(all);
    if (rc)
        particles_destroy(&q);
    *out = q;
    return rc;
}

struct id_at {
    int64_t id;
    int i;
};

static int cmp_id_at(const void *a, const void *b)
{
    int64_t x = ((const struct id_at *)a)->id, y = ((const struct id_at *)b)->id;
    return (x > y) - (x < y);
}

/* How many of the sorted s[from..n) have an id below `end`. */
static long below(const struct id_at *s, long from, long n, double end)
{
    long a = from, b = n;
    while (a < b) {
        long mid = a + (b - a) / 2;
        if ((double)s[mid].id < end)
            a = mid + 1;
        else
            b = mid;
    }
    return a - from;
}

/* The ids of all ranks in [lo, end) not yet sent (every rank's cursor is
 * at lo or beyond); the same on every rank. */
static double count_window(const struct halo *h, const struct id_at *s, long next, long n,
                           double end)
{
    double c = (double)below(s, next, n, end);
    halo_sum(h, &c, 1);
    return c;
}

int halo_gather_windows(struct halo *h, const struct particles *p, long window,
                        int (*visit)(void *ctx, struct particles *q, struct err *e),
                        void *ctx, struct err *e)
{
    if (window <= 0)
        window = HALO_GATHER_WINDOW;
    long n = p->n_owned;
    int root = h->dc.par ? h->dc.par->rank == 0 : 1;
    size_t rec = halo_record_size(p);
    long most = n < window ? n : window;
    struct id_at *s = malloc((size_t)(n > 0 ? n : 1) * sizeof *s);
    unsigned char *buf = malloc(rec * (size_t)(most > 0 ? most : 1));
    struct particles *q = NULL;
    int rc = s && buf ? 0 : err_nomem(e, "gather windows");
    if (!rc && root)
        rc = empty_like(p, (int)window, &q, e);
    rc = halo_agree(h, rc, e);
    for (long i = 0; !rc && i < n; i++) {
        s[i].id = p->id[i];
        s[i].i = (int)i;
    }
    if (!rc && n > 1)
        qsort(s, (size_t)n, sizeof *s, cmp_id_at);
    long next = 0;
    while (!rc) {
        /* the window starts at the smallest id not yet sent, anywhere
         * (a gap in the ids costs nothing), and ends before the id that
         * would take it beyond `window` particles: a bisection over ids
         * with the counts summed over the ranks (ids are exact in a double
         * below 2^53) */
        double range[2] = {next < n ? -(double)s[next].id : -INFINITY,
                           n > 0 ? (double)s[n - 1].id + 1 : -INFINITY};
        halo_max(h, range, 2);
        if (range[0] == -INFINITY)
            break;
        double lo = -range[0], a = lo + 1, b = range[1], end = b;
        if (count_window(h, s, next, n, b) > (double)window) {
            while (b - a > 1) {
                double mid = floor(a + (b - a) / 2);
                if (count_window(h, s, next, n, mid) <= (double)window)
                    a = mid;
                else
                    b = mid;
            }
            end = a;
        }
        long k = below(s, next, n, end);
        if (k > most) {   /* only with an id given twice: a window of one id */
            unsigned char *more = realloc(buf, rec * (size_t)k);
            if (more) {
                buf = more;
                most = k;
            } else {   /* this rank sends nothing; the agreement below stops all */
                rc = err_nomem(e, "gather windows");
            }
        }
        long send = rc ? 0 : k;
        for (long j = 0; j < send; j++)
            halo_pack(p, s[next + j].i, -1, 0.0, buf + rec * (size_t)j);
        next += k;
        void *all = NULL;
        size_t bytes = 0;
        int rg = parallel_gather_bytes(h->dc.par, buf, rec * (size_t)send, &all, &bytes, e);
        rc = rc ? rc : rg;
        if (!rc && root)
            rc = unpack_sorted(q, all, rec, (int)(bytes / rec), e);
        if (!rc && root)
            rc = visit(ctx, q, e);
        free(all);
        rc = halo_agree(h, rc, e);
    }
    particles_destroy(&q);
    free(buf);
    free(s);
    return rc;
}
