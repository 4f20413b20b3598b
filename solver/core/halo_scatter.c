/* halo_scatter: rank 0's particles to their owners in blocks (halo_scatter.h). */
#include "core/halo_scatter.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo_pack.h"

/* What the other ranks need of rank 0's set besides its particles. */
struct scatter_header {
    struct box box;
    long n;
    int ntypes, nfields;
    double mass[PARTICLES_MAX_TYPES];
    char type_name[PARTICLES_MAX_TYPES][16];
    struct {
        char name[32];
        int ncomp, ghost_copy;
    } field[PARTICLES_MAX_FIELDS];
};

/* A failure on one rank fails every rank, so none waits in a collective
 * the failed one will not join. */
static int agree(const struct parallel *par, int rc, struct err *e)
{
    if (parallel_any(par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    return rc;
}

int halo_scatter_header(const struct parallel *par, struct particles *p, struct box *b, long *n,
                        struct err *e)
{
    struct scatter_header h;
    memset(&h, 0, sizeof h);
    if (par->rank == 0) {
        h.box = *b;
        h.n = p->n_owned;
        h.ntypes = p->ntypes;
        h.nfields = p->nfields;
        memcpy(h.mass, p->mass, sizeof h.mass);
        memcpy(h.type_name, p->type_name, sizeof h.type_name);
        for (int k = 0; k < p->nfields; k++) {
            memcpy(h.field[k].name, p->fields[k].name, sizeof h.field[k].name);
            h.field[k].ncomp = p->fields[k].ncomp;
            h.field[k].ghost_copy = p->fields[k].ghost_copy;
        }
    }
    int rc = parallel_bcast_bytes(par, &h, sizeof h, e);
    if (rc)
        return rc;   /* the same on every rank (a size check) */
    *n = h.n;
    if (par->rank != 0) {
        *b = h.box;
        p->ntypes = h.ntypes;
        memcpy(p->mass, h.mass, sizeof p->mass);
        memcpy(p->type_name, h.type_name, sizeof p->type_name);
        for (int k = 0; !rc && k < h.nfields; k++)
            if (particles_add_field(p, h.field[k].name, h.field[k].ncomp, h.field[k].ghost_copy,
                                    e) < 0)
                rc = ERR_RUNTIME;
    }
    return agree(par, rc, e);
}

/* One block [lo, lo + m) of rank 0's particles to their owners: rank 0
 * packs them grouped by rank (its own stay, keep[] marks them); every
 * other rank appends its group to p. */
static int scatter_block(const struct parallel *par, const struct halo *h, struct particles *p,
                         long lo, long m, size_t rec, unsigned char *buf, int *dest,
                         long *bytes, long *at, unsigned char *keep, struct err *e)
{
    int size = par->size;
    if (par->rank == 0) {
        for (int r = 0; r < size; r++)
            bytes[r] = 0;
        for (long k = 0; k < m; k++) {
            dest[k] = decomp_owner(&h->dc, p->x + 3 * (lo + k));
            keep[lo + k] = (unsigned char)(dest[k] == 0);
            bytes[dest[k]] += (long)rec;
        }
        bytes[0] = 0;   /* rank 0's own stay where they are */
        at[0] = 0;
        for (int r = 1; r < size; r++)
            at[r] = at[r - 1] + bytes[r - 1];
        for (long k = 0; k < m; k++)
            if (dest[k] != 0) {
                halo_pack(p, (int)(lo + k), -1, 0.0, buf + at[dest[k]]);
                at[dest[k]] += (long)rec;
            }
    }
    int rc = parallel_bcast_bytes(par, bytes, (size_t)size * sizeof *bytes, e);
    unsigned char none;
    if (!rc)
        rc = parallel_scatter_bytes(par, buf, bytes, par->rank == 0 ? &none : buf, e);
    if (rc || par->rank == 0)
        return rc;
    int got = (int)(bytes[par->rank] / (long)rec);
    /* reserved for every particle of the brick beforehand */
    if (p->n_owned + got > p->capacity)
        return err_set(e, ERR_RUNTIME, "scatter of a configuration: rank %d received more "
                                       "particles than counted", par->rank);
    for (int k = 0; k < got; k++)
        halo_unpack(p, p->n_owned + k, buf + rec * (size_t)k);
    p->n_owned += got;
    return 0;
}

/* One block to every rank (replicated data). */
static int bcast_block(const struct parallel *par, struct particles *p, long lo, long m,
                       size_t rec, unsigned char *buf, struct err *e)
{
    if (par->rank == 0)
        for (long k = 0; k < m; k++)
            halo_pack(p, (int)(lo + k), -1, 0.0, buf + rec * (size_t)k);
    int rc = parallel_bcast_bytes(par, buf, rec * (size_t)m, e);
    if (rc || par->rank == 0)
        return rc;
    if (p->n_owned + m > p->capacity)
        return err_set(e, ERR_RUNTIME, "broadcast of a configuration: rank %d received more "
                                       "particles than counted", par->rank);
    for (long k = 0; k < m; k++)
        halo_unpack(p, p->n_owned + (int)k, buf + rec * (size_t)k);
    p->n_owned += (int)m;
    return 0;
}

int halo_scatter(const struct parallel *par, struct halo *h, struct particles *p, long n,
                 struct err *e)
{
    int size = par->size, me = par->rank;
    size_t rec = halo_record_size(p);
    long *counts = calloc((size_t)size, sizeof *counts);
    long *bytes = calloc((size_t)size, sizeof *bytes);
    long *at = calloc((size_t)size, sizeof *at);
    int rc = counts && bytes && at ? 0 : err_nomem(e, "configuration scatter");
    rc = agree(par, rc, e);
    /* how many particles each rank receives in all, so that it reserves
     * exactly its brick (or, replicated, the whole set) */
    if (!rc && me == 0) {
        for (int r = 0; r < size; r++)
            counts[r] = h ? 0 : n;
        for (long i = 0; h && i < n; i++)
            counts[decomp_owner(&h->dc, p->x + 3 * i)]++;
    }
    if (!rc)
        rc = parallel_bcast_bytes(par, counts, (size_t)size * sizeof *counts, e);
    long block = n < HALO_SCATTER_BLOCK ? (n > 0 ? n : 1) : HALO_SCATTER_BLOCK;
    unsigned char *buf = NULL, *keep = NULL;
    int *dest = NULL;
    if (!rc) {
        buf = malloc(rec * (size_t)block);
        if (!buf)
            rc = err_nomem(e, "configuration scatter block");
        if (!rc && me == 0 && h) {
            dest = malloc((size_t)block * sizeof *dest);
            keep = malloc((size_t)(n > 0 ? n : 1));
            if (!dest || !keep)
                rc = err_nomem(e, "configuration scatter block");
        }
        if (!rc && me != 0 && counts[me] > 0)
            rc = particles_reserve(p, p->n_owned + (int)counts[me], e);
        rc = agree(par, rc, e);
    }
    /* every rank runs the same blocks; a failure in one is agreed at once */
    for (long lo = 0; !rc && lo < n; lo += block) {
        long m = n - lo < block ? n - lo : block;
        rc = h ? scatter_block(par, h, p, lo, m, rec, buf, dest, bytes, at, keep, e)
               : bcast_block(par, p, lo, m, rec, buf, e);
        rc = agree(par, rc, e);
    }
    if (!rc && me == 0 && h) {
        /* rank 0 keeps its brick's, in the file's order, and gives the
         * rest of the whole set's memory back (room for half as many
         * ghosts, as halo_distribute) */
        particles_clear_ghosts(p);
        particles_compact(p, keep);
        rc = particles_fit(p, p->n_owned + p->n_owned / 2 + 1024, e);
    }
    free(buf);
    free(keep);
    free(dest);
    free(counts);
    free(bytes);
    free(at);
    return agree(par, rc, e);
}
