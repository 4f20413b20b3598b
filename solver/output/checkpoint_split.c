/* checkpoint_split: a checkpoint's particles read in blocks, keeping those
 * a predicate selects (checkpoint.h, ckpt_get_particles_where). */
#include "output/checkpoint.h"

#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/mem.h"

/* particles per block: the read's memory beyond the kept particles is one
 * block of every dataset (about 160 bytes a particle for MD) */
#define CKPT_READ_BLOCK 16384

struct column {
    char name[64];
    hid_t memtype;
    size_t elem;
    int ncomp;
    hid_t ds;
    unsigned char *buf;
};

static int where_fail(struct ckpt *c, const char *what, const char *name, int code)
{
    err_set(c->e, code, "%s: checkpoint %s%s%s: %s", c->path, c->where, c->where[0] ? "/" : "",
            name, what);
    return code;
}

/* The same for a rank stopped by another's failure (err.h). */
static int where_fail_elsewhere(struct ckpt *c, const char *name)
{
    int rc = where_fail(c, "stopped: another MPI rank failed to read it", name, ERR_INPUT);
    c->e->elsewhere = 1;
    return rc;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* rows [first, first + count) of a column into its buffer; with dxpl
 * collective every rank calls it (count 0: nothing selected) */
static int read_block(struct ckpt *c, struct column *col, long first, long count, hid_t dxpl)
{
    hsize_t start[1] = {(hsize_t)(first * col->ncomp)},
            len[1] = {(hsize_t)((count > 0 ? count : 1) * col->ncomp)};
    hid_t fs = H5Dget_space(col->ds), ms = H5Screate_simple(1, len, NULL);
    int rc = fs < 0 || ms < 0;
    if (!rc && count > 0)
        rc = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, len, NULL) < 0;
    else if (!rc)
        rc = H5Sselect_none(fs) < 0 || H5Sselect_none(ms) < 0;
    /* a rank whose selection failed still joins a collective transfer */
    rc |= (rc && dxpl == H5P_DEFAULT) || H5Dread(col->ds, col->memtype, ms, fs, dxpl, col->buf) < 0;
    if (ms >= 0)
        H5Sclose(ms);
    if (fs >= 0)
        H5Sclose(fs);
    return rc ? where_fail(c, "unreadable (checksum mismatch: corrupt checkpoint?)", col->name,
                           ERR_INPUT)
              : 0;
}

/* Open each column's dataset, check its length against n rows and give it
 * a buffer of `block` rows; the first failure is returned (the columns
 * opened so far are closed by close_columns). */
static int open_columns(struct ckpt *c, struct column *col, int ncol, long n, long block)
{
    for (int q = 0; q < ncol; q++) {
        long have = ckpt_len(c, col[q].name);
        if (have < 0)
            return ERR_INPUT;
        if (have != n * col[q].ncomp) {
            char what[96];
            snprintf(what, sizeof what, "has %ld values, expected %ld", have, n * col[q].ncomp);
            return where_fail(c, what, col[q].name, ERR_INPUT);
        }
        if ((col[q].ds = H5Dopen2(c->group, col[q].name, H5P_DEFAULT)) < 0)
            return where_fail(c, "unreadable", col[q].name, ERR_INPUT);
        size_t comps = (size_t)(col[q].ncomp > 0 ? col[q].ncomp : 1);
        if (!(col[q].buf = mem_alloc((size_t)block * col[q].elem * comps)))
            return err_nomem(c->e, "checkpoint read");
    }
    return 0;
}

static void close_columns(struct column *col, int ncol)
{
    for (int q = 0; q < ncol; q++) {
        if (col[q].ds >= 0)
            H5Dclose(col[q].ds);
        free(col[q].buf);
    }
}

/* stored particle k of the block into slot i of p */
static void put_particle(struct particles *p, int i, struct column *col, int ncol, long k)
{
    void *dst[9] = {p->x, p->v, p->f, p->type, p->id, p->mask, p->image, p->pe, p->virial};
    for (int q = 0; q < ncol; q++) {
        size_t row = col[q].elem * (size_t)col[q].ncomp;
        unsigned char *to = q < 9 ? (unsigned char *)dst[q]
                                  : (unsigned char *)p->fields[q - 9].data;
        memcpy(to + row * (size_t)i, col[q].buf + row * (size_t)k, row);
    }
    p->origin[i] = i;
}

static int check_particle(struct ckpt *c, const struct particles *p, const struct column *col,
                          long k)
{
    int type = ((const int *)col[3].buf)[k];
    int64_t id = ((const int64_t *)col[4].buf)[k];
    if (type < 0 || type >= p->ntypes)
        return where_fail(c, "type index out of range", "type", ERR_INPUT);
    if (id < 1)
        return where_fail(c, "an id below 1", "id", ERR_INPUT);
    for (int q = 0; q < 3; q++)
        for (int d = 0; d < 3; d++)
            if (!isfinite(((const double *)col[q].buf)[3 * k + d])) {
                char what[96];
                snprintf(what, sizeof what,
                         "a non-finite position, velocity or force (id %lld)", (long long)id);
                return where_fail(c, what, "x/v/f", ERR_INPUT);
            }
    return 0;
}

/* The stored particles [lo, hi) (hi < 0: all) that keep selects, in
 * blocks; collective transfers when the file is open on every rank. */
static int get_rows(struct ckpt *c, const char *name, struct particles *p,
                    int (*keep)(const void *ctx, const double x[3]), const void *ctx,
                    const char *keep_field, int rank, int nranks)
{
    int rc = ckpt_enter(c, name);
    long n = 0;
    if (!rc)
        rc = ckpt_get_long(c, "n", &n);
    if (!rc && (n < 0 || n > 2000000000L))
        rc = where_fail(c, "impossible particle count", "n", ERR_INPUT);
    long nt = rc ? 0 : ckpt_len(c, "type_mass");
    if (!rc && nt != p->ntypes) {
        char what[96];
        snprintf(what, sizeof what, "has %ld particle types, the case has %d", nt, p->ntypes);
        rc = where_fail(c, what, "type_mass", ERR_INPUT);
    }
    if (rc)
        return rc;
    struct column col[9 + PARTICLES_MAX_FIELDS] = {
        {"x", H5T_NATIVE_DOUBLE, sizeof(double), 3, -1, NULL},
        {"v", H5T_NATIVE_DOUBLE, sizeof(double), 3, -1, NULL},
        {"f", H5T_NATIVE_DOUBLE, sizeof(double), 3, -1, NULL},
        {"type", H5T_NATIVE_INT, sizeof(int), 1, -1, NULL},
        {"id", H5T_NATIVE_INT64, sizeof(int64_t), 1, -1, NULL},
        {"mask", H5T_NATIVE_UINT32, sizeof(uint32_t), 1, -1, NULL},
        {"image", H5T_NATIVE_INT, sizeof(int), 3, -1, NULL},
        {"pe", H5T_NATIVE_DOUBLE, sizeof(double), 1, -1, NULL},
        {"virial", H5T_NATIVE_DOUBLE, sizeof(double), 6, -1, NULL},
    };
    int ncol = 9 + p->nfields;
    for (int k = 0; k < p->nfields; k++)
        col[9 + k] = (struct column){"", H5T_NATIVE_DOUBLE, sizeof(double),
                                     p->fields[k].ncomp, -1, NULL};
    for (int k = 0; k < p->nfields; k++)
        snprintf(col[9 + k].name, sizeof col[9 + k].name, "field_%s", p->fields[k].name);
    /* the column keep() sees: the positions, or a field of 3 components */
    int kc = 0;
    if (keep_field) {
        int k = particles_find_field(p, keep_field);
        if (k < 0 || p->fields[k].ncomp != 3)
            rc = err_set(c->e, ERR_RUNTIME,
                         "checkpoint read: no field %s of 3 components to select by",
                         keep_field);
        else
            kc = 9 + k;
    }
    long lo = nranks > 0 ? n * rank / nranks : 0;
    long hi = nranks > 0 ? n * (rank + 1) / nranks : n;
    long block = n < CKPT_READ_BLOCK ? (n > 0 ? n : 1) : CKPT_READ_BLOCK;
    if (!rc)
        rc = open_columns(c, col, ncol, n, block);
    particles_clear_ghosts(p);
    p->n_owned = 0;
    /* parallel: every rank takes part in as many transfers as the rank
     * with the most blocks (the others select nothing) */
    long nblocks = (hi - lo + block - 1) / block;
    hid_t dxpl = H5P_DEFAULT;
    if (c->par) {
        int any = rc != 0, anyall = 0;
        MPI_Allreduce(&any, &anyall, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        if (anyall && !rc)
            rc = where_fail_elsewhere(c, name);
        MPI_Allreduce(MPI_IN_PLACE, &nblocks, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
        if (anyall)   /* a set-up failed somewhere: no rank starts the transfers */
            nblocks = 0;
        dxpl = H5Pcreate(H5P_DATASET_XFER);
        H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
    }
    for (long b = 0; b < nblocks && (!rc || c->par); b++) {
        long first = lo + b * block;
        long count = first >= hi ? 0 : hi - first < block ? hi - first : block;
        if (rc)   /* parallel: a rank that failed still joins the transfers */
            count = 0;
        for (int q = 0; q < ncol && (!rc || c->par); q++) {
            int r = col[q].ds >= 0 ? read_block(c, &col[q], first, count, dxpl) : ERR_INPUT;
            rc = rc ? rc : r;
        }
        for (long k = 0; !rc && k < count; k++) {
            if ((rc = check_particle(c, p, col, k)))
                break;
            const double *sel = (const double *)col[kc].buf + 3 * k;
            if (kc > 0 && !(isfinite(sel[0]) && isfinite(sel[1]) && isfinite(sel[2]))) {
                char what[128];
                snprintf(what, sizeof what,
                         "a non-finite value of the field it selects by (id %lld)",
                         (long long)((const int64_t *)col[4].buf)[k]);
                rc = where_fail(c, what, col[kc].name, ERR_INPUT);
                break;
            }
            if (keep && !keep(ctx, sel))
                continue;
            if ((rc = particles_reserve(p, p->n_owned + 1, c->e)))
                break;
            put_particle(p, p->n_owned, col, ncol, k);
            p->n_owned++;
        }
    }
    if (dxpl != H5P_DEFAULT)
        H5Pclose(dxpl);
    close_columns(col, ncol);
    /* ids unique among the kept ones */
    int m = p->n_owned;
    int64_t *ids = rc || m == 0 ? NULL : mem_alloc((size_t)m * sizeof *ids);
    if (!rc && m > 0 && !ids)
        rc = err_nomem(c->e, "checkpoint ids");
    if (ids) {
        memcpy(ids, p->id, (size_t)m * sizeof *ids);
        qsort(ids, (size_t)m, sizeof *ids, cmp_i64);
        for (int i = 1; !rc && i < m; i++)
            if (ids[i] == ids[i - 1]) {
                char what[64];
                snprintf(what, sizeof what, "id %lld given twice", (long long)ids[i]);
                rc = where_fail(c, what, "id", ERR_INPUT);
            }
        free(ids);
    }
    if (rc)
        p->n_owned = 0;
    return rc;
}

int ckpt_get_particles_where(struct ckpt *c, const char *name, struct particles *p,
                             int (*keep)(const void *ctx, const double x[3]), const void *ctx)
{
    return get_rows(c, name, p, keep, ctx, NULL, 0, 0);
}

int ckpt_get_particles_where_field(struct ckpt *c, const char *name, struct particles *p,
                                   const char *field,
                                   int (*keep)(const void *ctx, const double x[3]),
                                   const void *ctx)
{
    return get_rows(c, name, p, keep, ctx, field, 0, 0);
}

int ckpt_get_particles_part(struct ckpt *c, const char *name, struct particles *p, int rank,
                            int nranks)
{
    return get_rows(c, name, p, NULL, NULL, NULL, rank, nranks);
}

/* Whether any rank's *rc is an error; this rank's becomes one too.
 * Collective. */
static int any_rank_failed(struct ckpt *c, int *rc, const char *name)
{
    int any = *rc != 0, anyall = 0;
    MPI_Allreduce(&any, &anyall, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (anyall && !*rc)
        *rc = where_fail_elsewhere(c, name);
    return anyall;
}

int ckpt_get_columns_blocks(struct ckpt *c, const struct ckpt_col *cols, int ncol, long n,
                            int (*take)(void *ctx, const void *const *buf, long k), void *ctx)
{
    enum { MAXCOL = 32 };
    if (ncol > MAXCOL)
        return err_set(c->e, ERR_RUNTIME, "checkpoint read: %d columns, at most %d", ncol, MAXCOL);
    struct column col[MAXCOL];
    const void *buf[MAXCOL];
    long block = n < CKPT_READ_BLOCK ? (n > 0 ? n : 1) : CKPT_READ_BLOCK;
    for (int q = 0; q < ncol; q++) {
        col[q] = (struct column){"", cols[q].memtype, H5Tget_size(cols[q].memtype), cols[q].ncomp,
                                 -1, NULL};
        snprintf(col[q].name, sizeof col[q].name, "%s", cols[q].name);
    }
    int rc = open_columns(c, col, ncol, n, block);
    for (int q = 0; q < ncol; q++)
        buf[q] = col[q].buf;
    long nblocks = (n + block - 1) / block;
    hid_t dxpl = H5P_DEFAULT;
    if (c->par) {   /* every rank reads every block: the same transfers everywhere */
        if (any_rank_failed(c, &rc, cols[0].name))
            nblocks = 0;
        dxpl = H5Pcreate(H5P_DATASET_XFER);
        H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
    }
    for (long b = 0; b < nblocks && (!rc || c->par); b++) {
        long first = b * block;
        long count = n - first < block ? n - first : block;
        if (rc)   /* parallel: a rank that failed still joins the transfers */
            count = 0;
        for (int q = 0; q < ncol && (!rc || c->par); q++) {
            if (col[q].ncomp == 0)
                continue;   /* an empty column (no state variables) */
            int r = read_block(c, &col[q], first, count, dxpl);
            rc = rc ? rc : r;
        }
        for (long k = 0; !rc && k < count; k++)
            rc = take(ctx, buf, k);
        if (c->par && any_rank_failed(c, &rc, cols[0].name))
            break;   /* a rank that stopped makes every rank stop */
    }
    if (dxpl != H5P_DEFAULT)
        H5Pclose(dxpl);
    close_columns(col, ncol);
    return rc;
}
