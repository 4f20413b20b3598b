/* frame: wrapped positions, periodic images, cells and sorted neighbour lists. */
#include "analysis/frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int frame_reserve(struct frame *f, int n, struct err *e)
{
    if (n <= f->cap)
        return 0;
    int cap = n + n / 4 + 64;
    double *x = realloc(f->x, (size_t)3 * cap * sizeof *x);
    if (x)
        f->x = x;
    int *o = realloc(f->origin, (size_t)cap * sizeof *o);
    if (o)
        f->origin = o;
    int *s = realloc(f->shift, (size_t)3 * cap * sizeof *s);
    if (s)
        f->shift = s;
    if (!x || !o || !s)
        return err_nomem(e, "analysis frame");
    f->cap = cap;
    return 0;
}

static int add_image(struct frame *f, int src, int d, int s, double len, struct err *e)
{
    if (frame_reserve(f, f->ntot + 1, e))
        return ERR_RUNTIME;
    int k = f->ntot++;
    for (int c = 0; c < 3; c++) {
        f->x[3 * k + c] = f->x[3 * src + c];
        f->shift[3 * k + c] = f->shift[3 * src + c];
    }
    f->x[3 * k + d] += s * len;
    f->shift[3 * k + d] += s;
    f->origin[k] = f->origin[src];
    return 0;
}

static int make_images(struct frame *f, const struct box *b, double range, struct err *e)
{
    for (int d = 0; d < 3; d++) {
        if (b->bc[d] != BOUNDARY_PERIODIC)
            continue;
        double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
        int nlayers = (int)ceil(range / len);
        int nsrc = f->ntot;   /* images of earlier axes' images cover edges and corners */
        for (int s = 1; s <= nlayers; s++)
            for (int i = 0; i < nsrc; i++) {
                double x = f->x[3 * i + d];
                if (x + s * len < hi + range && add_image(f, i, d, s, len, e))
                    return ERR_RUNTIME;
                if (x - s * len >= lo - range && add_image(f, i, d, -s, len, e))
                    return ERR_RUNTIME;
            }
    }
    return 0;
}

static int bin_entries(struct frame *f, double width, struct err *e)
{
    double hi[3];
    for (int d = 0; d < 3; d++) {
        f->clo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int i = 0; i < f->ntot; i++)
        for (int d = 0; d < 3; d++) {
            double x = f->x[3 * i + d];
            if (x < f->clo[d]) f->clo[d] = x;
            if (x > hi[d]) hi[d] = x;
        }
    if (f->ntot == 0)
        for (int d = 0; d < 3; d++) {
            f->clo[d] = 0;
            hi[d] = 1;
        }
    /* sparse systems (atoms flying far away): widen the cells until there
     * are no more cells than a few per entry */
    long ncell;
    double w = width * (1.0 + 1e-9) + 1e-12;
    for (;;) {
        ncell = 1;
        for (int d = 0; d < 3; d++) {
            double len = hi[d] - f->clo[d];
            f->nc[d] = (int)floor(len / w);
            if (f->nc[d] < 1)
                f->nc[d] = 1;
            ncell *= f->nc[d];
        }
        if (ncell <= 4L * f->ntot + 4096)
            break;
        w *= 1.26;
    }
    for (int d = 0; d < 3; d++) {
        double len = hi[d] - f->clo[d];
        f->cinv[d] = f->nc[d] / (len > 0 ? len * (1.0 + 1e-12) + 1e-300 : 1.0);
    }
    if (f->cap_cells < ncell + 1) {
        int *cs = realloc(f->cell_start, (size_t)(ncell + 1) * sizeof *cs);
        if (!cs)
            return err_nomem(e, "analysis cells");
        f->cell_start = cs;
        f->cap_cells = ncell + 1;
    }
    if (f->cap_sorted < f->ntot + 1) {
        int *so = realloc(f->cell_sorted, (size_t)(f->ntot + 1) * sizeof *so);
        if (so)
            f->cell_sorted = so;
        double *cx = realloc(f->cell_x, (size_t)3 * (f->ntot + 1) * sizeof *cx);
        if (cx)
            f->cell_x = cx;
        if (!so || !cx)
            return err_nomem(e, "analysis cells");
        f->cap_sorted = f->ntot + 1;
    }
    /* the shifts times the box lengths, only where some are not zero */
    if (f->periodic && f->cap_shifts < f->ntot + 1) {
        double *cs = realloc(f->cell_s, (size_t)3 * (f->ntot + 1) * sizeof *cs);
        if (!cs)
            return err_nomem(e, "analysis cells");
        f->cell_s = cs;
        f->cap_shifts = f->ntot + 1;
    }
    int *cellof = malloc((size_t)(f->ntot + 1) * sizeof *cellof);
    if (!cellof)
        return err_nomem(e, "analysis cells");
    memset(f->cell_start, 0, (size_t)(ncell + 1) * sizeof(int));
    for (int i = 0; i < f->ntot; i++) {
        int c[3];
        for (int d = 0; d < 3; d++) {
            c[d] = (int)((f->x[3 * i + d] - f->clo[d]) * f->cinv[d]);
            if (c[d] >= f->nc[d]) c[d] = f->nc[d] - 1;
            if (c[d] < 0) c[d] = 0;
        }
        cellof[i] = (c[2] * f->nc[1] + c[1]) * f->nc[0] + c[0];
        f->cell_start[cellof[i] + 1]++;
    }
    for (long c = 0; c < ncell; c++)
        f->cell_start[c + 1] += f->cell_start[c];
    for (int i = 0; i < f->ntot; i++)
        f->cell_sorted[f->cell_start[cellof[i]]++] = i;
    for (long c = ncell; c > 0; c--)
        f->cell_start[c] = f->cell_start[c - 1];
    f->cell_start[0] = 0;
    free(cellof);
    for (int k = 0; k < f->ntot; k++) {
        int j = f->cell_sorted[k], o = f->origin[j];
        for (int d = 0; d < 3; d++) {
            f->cell_x[3 * k + d] = f->x[3 * o + d];
            if (f->periodic)
                f->cell_s[3 * k + d] = (double)f->shift[3 * j + d] * f->len[d];
        }
    }
    return 0;
}

/* The entries of cells [k0, k1) of the sorted order within rr of (xi, yi,
 * zi), owned entry i excluded.  shifted: add the image shifts (the pair
 * vector of frame_vec, (x_o - x_i) + s L); without, every shift is zero
 * and the vector is (x_o - x_i), the same bits. */
static inline void query_range(const struct frame *f, int k0, int k1, int i, double xi,
                               double yi, double zi, double rr, const int shifted,
                               void (*fn)(void *ctx, int entry, double r2), void *ctx)
{
    for (int k = k0; k < k1; k++) {
        const double *cx = f->cell_x + 3 * k;
        double dx = cx[0] - xi, dy = cx[1] - yi, dz = cx[2] - zi;
        if (shifted) {
            const double *cs = f->cell_s + 3 * k;
            dx += cs[0];
            dy += cs[1];
            dz += cs[2];
        }
        double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 < rr) {
            int j = f->cell_sorted[k];
            if (j != i)
                fn(ctx, j, r2);
        }
    }
}

void frame_query(const struct frame *f, int i, double radius,
                 void (*fn)(void *ctx, int entry, double r2), void *ctx)
{
    int c[3], reach[3];
    for (int d = 0; d < 3; d++) {
        c[d] = (int)((f->x[3 * i + d] - f->clo[d]) * f->cinv[d]);
        if (c[d] >= f->nc[d]) c[d] = f->nc[d] - 1;
        if (c[d] < 0) c[d] = 0;
        reach[d] = (int)ceil(radius * f->cinv[d] * (1.0 + 1e-12));
        if (reach[d] < 1) reach[d] = 1;
    }
    const double rr = radius * radius;
    const double xi = f->x[3 * i], yi = f->x[3 * i + 1], zi = f->x[3 * i + 2];
    for (int z = c[2] - reach[2]; z <= c[2] + reach[2]; z++) {
        if (z < 0 || z >= f->nc[2]) continue;
        for (int y = c[1] - reach[1]; y <= c[1] + reach[1]; y++) {
            if (y < 0 || y >= f->nc[1]) continue;
            int x0 = c[0] - reach[0] < 0 ? 0 : c[0] - reach[0];
            int x1 = c[0] + reach[0] >= f->nc[0] ? f->nc[0] - 1 : c[0] + reach[0];
            /* the cells of one row are consecutive: one contiguous range */
            int row = (z * f->nc[1] + y) * f->nc[0];
            int k0 = f->cell_start[row + x0], k1 = f->cell_start[row + x1 + 1];
            if (f->periodic)
                query_range(f, k0, k1, i, xi, yi, zi, rr, 1, fn, ctx);
            else
                query_range(f, k0, k1, i, xi, yi, zi, rr, 0, fn, ctx);
        }
    }
}

/* Lists longer than this sort with their distances recomputed at each
 * comparison instead of from a buffer on the stack. */
#define SORT_STACK 256

struct collect {
    const struct frame *f;
    int *nbr;
    double *r2;   /* SORT_STACK squared distances, as the query gives them */
    int n;
};

static void count_cb(void *ctx, int entry, double r2)
{
    (void)entry;
    (void)r2;
    ((struct collect *)ctx)->n++;
}

static void fill_cb(void *ctx, int entry, double r2)
{
    struct collect *c = ctx;
    if (c->n < SORT_STACK)
        c->r2[c->n] = r2;
    c->nbr[c->n++] = entry;
}

/* Order: distance, then owned index, then image shift (total and
 * reproducible, so the k nearest are well defined even for exact ties). */
static int before(const struct frame *f, int a, double ra, int b, double rb)
{
    if (ra != rb)
        return ra < rb;
    if (f->origin[a] != f->origin[b])
        return f->origin[a] < f->origin[b];
    for (int k = 0; k < 3; k++)
        if (f->shift[3 * a + k] != f->shift[3 * b + k])
            return f->shift[3 * a + k] < f->shift[3 * b + k];
    return 0;
}

static void sort_list_by(const struct frame *f, int *nbr, double *r2, int n)
{
    for (int i = 1; i < n; i++) {
        int a = nbr[i];
        double ra = r2[i];
        int j = i - 1;
        while (j >= 0 && before(f, a, ra, nbr[j], r2[j])) {
            nbr[j + 1] = nbr[j];
            r2[j + 1] = r2[j];
            j--;
        }
        nbr[j + 1] = a;
        r2[j + 1] = ra;
    }
}

/* Owned entry i's list by distance, then owned index, then image shift.
 * r2: the query's squared distances of the first SORT_STACK entries,
 * the bits frame_dist2 gives a reader of the list (the same pair vector,
 * the same operations; C11 contracts no multiply-add). */
static void sort_list(const struct frame *f, int i, int *nbr, double *r2, int n)
{
    if (n <= SORT_STACK) {
        sort_list_by(f, nbr, r2, n);
        return;
    }
    for (int k = 1; k < n; k++) {
        int a = nbr[k];
        double ra = frame_dist2(f, i, a);
        int j = k - 1;
        while (j >= 0 && before(f, a, ra, nbr[j], frame_dist2(f, i, nbr[j]))) {
            nbr[j + 1] = nbr[j];
            j--;
        }
        nbr[j + 1] = a;
    }
}

int frame_build(struct frame *f, const double *x, int n, const struct box *b, double radius,
                double range, int nthreads, struct err *e)
{
    if (range < radius)
        range = radius;
    f->n = n;
    f->ntot = 0;
    f->radius = radius;
    f->range = range;
    f->nthreads = nthreads < 1 ? 1 : nthreads;
    if (frame_reserve(f, n, e))
        return ERR_RUNTIME;
    f->periodic = 0;
    for (int d = 0; d < 3; d++) {
        f->len[d] = b->bc[d] == BOUNDARY_PERIODIC ? box_length(b, d) : 0.0;
        f->periodic |= f->len[d] > 0;
    }
    for (int i = 0; i < n; i++) {
        for (int d = 0; d < 3; d++) {
            double v = x[3 * i + d];
            if (b->bc[d] == BOUNDARY_PERIODIC) {
                double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
                if (v < lo || v >= hi) {
                    v -= floor((v - lo) / len) * len;
                    if (v >= hi)
                        v = lo;
                }
            }
            f->x[3 * i + d] = v;
            f->shift[3 * i + d] = 0;
        }
        f->origin[i] = i;
    }
    f->ntot = n;
    int rc = make_images(f, b, range, e);
    if (!rc)
        rc = bin_entries(f, radius, e);
    if (rc)
        return rc;
    if (f->cap_offset < n + 1) {
        int *o = realloc(f->offset, (size_t)(n + 1) * sizeof *o);
        if (!o)
            return err_nomem(e, "analysis neighbours");
        f->offset = o;
        f->cap_offset = n + 1;
    }
    /* count, prefix sum, fill, sort */
#pragma omp parallel for num_threads(f->nthreads) schedule(static)
    for (int i = 0; i < n; i++) {
        struct collect c = {f, NULL, NULL, 0};
        frame_query(f, i, radius, count_cb, &c);
        f->offset[i + 1] = c.n;
    }
    f->offset[0] = 0;
    for (int i = 0; i < n; i++)
        f->offset[i + 1] += f->offset[i];
    long total = f->offset[n];
    if (f->cap_nbr < total + 1) {
        int *nb = realloc(f->nbr, (size_t)(total + 1) * sizeof *nb);
        if (!nb)
            return err_nomem(e, "analysis neighbours");
        f->nbr = nb;
        f->cap_nbr = total + 1;
    }
#pragma omp parallel for num_threads(f->nthreads) schedule(static)
    for (int i = 0; i < n; i++) {
        double r2[SORT_STACK];
        struct collect c = {f, f->nbr + f->offset[i], r2, 0};
        frame_query(f, i, radius, fill_cb, &c);
        sort_list(f, i, c.nbr, r2, c.n);
    }
    return 0;
}

void frame_free(struct frame *f)
{
    free(f->x);
    free(f->origin);
    free(f->shift);
    free(f->cell_start);
    free(f->cell_sorted);
    free(f->cell_x);
    free(f->cell_s);
    free(f->offset);
    free(f->nbr);
    memset(f, 0, sizeof *f);
}
