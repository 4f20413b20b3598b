/* halo: ghosts, migration and gathers of a brick decomposition (halo.h). */
#include "core/halo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo_pack.h"
#include "core/parallel.h"

static int grow(void **buf, size_t *cap, size_t n, struct err *e)
{
    if (n <= *cap && *buf)
        return 0;
    size_t c = n + n / 4 + 256;
    void *b = realloc(*buf, c);
    if (!b)
        return err_nomem(e, "halo buffer");
    *buf = b;
    *cap = c;
    return 0;
}

int halo_init(struct halo *h, const struct parallel *par, const int grid[3], const struct box *b,
              struct err *e)
{
    memset(h, 0, sizeof *h);
    return decomp_init(&h->dc, par, grid, b, e);
}

void halo_free(struct halo *h)
{
    decomp_free(&h->dc);
    for (int s = 0; s < 6; s++)
        free(h->swap[s].send);
    free(h->sbuf);
    free(h->rbuf);
    memset(h, 0, sizeof *h);
}

int halo_nranks(const struct halo *h) { return h->dc.par ? h->dc.par->size : 1; }

void halo_sum(const struct halo *h, double *buf, int n) { parallel_sum(h->dc.par, buf, (size_t)n); }
void halo_max(const struct halo *h, double *buf, int n) { parallel_max(h->dc.par, buf, (size_t)n); }
int halo_any(const struct halo *h, int flag) { return parallel_any(h->dc.par, flag); }

static void count_atoms(struct halo *h, const struct particles *p)
{
    double n = p->n_owned;
    halo_sum(h, &n, 1);
    h->natoms = (long)n;
}

/* A failure on one rank becomes a failure on all, so no rank waits for a
 * message that never comes. */
static int collective_rc(const struct halo *h, int rc, struct err *e)
{
    if (halo_any(h, rc != 0) && !rc)
        rc = err_set(e, ERR_RUNTIME, "stopped: another MPI rank failed (its message is in its "
                                     "own output)");
    return rc;
}

int halo_agree(const struct halo *h, int rc, struct err *e)
{
    return collective_rc(h, rc, e);
}

int halo_distribute(struct halo *h, struct particles *p, struct err *e)
{
    unsigned char *keep = malloc((size_t)(p->n_owned ? p->n_owned : 1));
    int rc = keep ? 0 : err_nomem(e, "brick distribution");
    if (!rc) {
        particles_clear_ghosts(p);
        for (int i = 0; i < p->n_owned; i++)
            keep[i] = (unsigned char)decomp_owns(&h->dc, p->x + 3 * i);
        particles_compact(p, keep);
        /* room for the brick's atoms and half as many ghosts (about
         * right for bricks four ranges wide; the arrays grow when needed) */
        rc = particles_fit(p, p->n_owned + p->n_owned / 2 + 1024, e);
    }
    free(keep);
    rc = collective_rc(h, rc, e);
    if (!rc)
        count_atoms(h, p);
    return rc;
}

int halo_adopt(struct halo *h, struct particles *p, int rc, struct err *e)
{
    rc = collective_rc(h, rc, e);
    if (!rc) {
        particles_clear_ghosts(p);
        count_atoms(h, p);
    }
    return rc;
}

int halo_balance(struct halo *h, const struct box *b, struct particles *p, double range,
                 struct err *e)
{
    /* on the box the first list build will shrink-wrap to (the same
     * wrap and extent it computes there) */
    struct box wrapped = *b;
    int rc = halo_remap(h, &wrapped, p, 1, e);
    if (!rc)
        rc = collective_rc(h, decomp_shift(&h->dc, p->x, p->n_owned, range, e), e);
    if (!rc) {
        particles_clear_ghosts(p);
        rc = halo_migrate(h, p, e);
    }
    return rc;
}

int halo_remap(struct halo *h, struct box *b, struct particles *p, int shrink, struct err *e)
{
    struct box local = *b;
    int rc = box_remap(&local, p, 0.0, e);
    rc = collective_rc(h, rc, e);
    if (rc)
        return rc;
    double mn[3], mx[3];
    for (int d = 0; d < 3; d++) {
        mn[d] = INFINITY;
        mx[d] = -INFINITY;
    }
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            double x = p->x[3 * i + d];
            if (x < mn[d]) mn[d] = x;
            if (x > mx[d]) mx[d] = x;
        }
    parallel_min(h->dc.par, mn, 3);
    parallel_max(h->dc.par, mx, 3);
    for (int d = 0; d < 3; d++)
        if (shrink && b->bc[d] == BOUNDARY_FREE && isfinite(mn[d]) && isfinite(mx[d])) {
            b->lo[d] = mn[d];
            b->hi[d] = mx[d];
        }
    decomp_set_box(&h->dc, b);
    return 0;
}

/* Send records [0, nup) of sbuf up and [nup, nup + ndown) down along d;
 * append what arrives. */
static int migrate_exchange(struct halo *h, struct particles *p, int d, int nup, int ndown,
                            size_t rec, struct err *e)
{
    for (int dir = 1; dir >= 0; dir--) {
        const unsigned char *s = (const unsigned char *)h->sbuf + (dir ? 0 : rec * (size_t)nup);
        size_t nb = rec * (size_t)(dir ? nup : ndown), got;
        int rc = parallel_sendrecv(h->dc.par, h->dc.nbr[d][dir], s, nb, h->dc.nbr[d][1 - dir],
                                   &h->rbuf, &h->rcap, &got, e);
        if (rc)
            return rc;
        int nin = (int)(got / rec);
        if ((rc = particles_reserve(p, p->n_owned + nin, e)))
            return rc;
        for (int k = 0; k < nin; k++)
            halo_unpack(p, p->n_owned + k, (const unsigned char *)h->rbuf + rec * (size_t)k);
        p->n_owned += nin;
    }
    return 0;
}

int halo_migrate(struct halo *h, struct particles *p, struct err *e)
{
    const struct decomp *dc = &h->dc;
    size_t rec = halo_record_size(p);
    int rc = 0;
    particles_clear_ghosts(p);
    for (int d = 0; d < 3 && !rc; d++) {
        int g = dc->grid[d], me = dc->coords[d];
        if (g == 1)
            continue;
        for (int hop = 0; hop <= g && !rc; hop++) {
            /* direction of each leaving particle: +1 up, -1 down (periodic
             * axes: the shorter way round) */
            signed char *dir = malloc((size_t)(p->n_owned ? p->n_owned : 1));
            unsigned char *keep = malloc((size_t)(p->n_owned ? p->n_owned : 1));
            if (!dir || !keep)
                rc = err_nomem(e, "migration");
            int nup = 0, ndown = 0;
            for (int i = 0; !rc && i < p->n_owned; i++) {
                int c = decomp_coord(dc, d, p->x[3 * i + d]);
                dir[i] = 0;
                if (c != me) {
                    int up = dc->periodic[d] ? (c - me + g) % g <= g / 2 : c > me;
                    dir[i] = up ? 1 : -1;
                    nup += up;
                    ndown += !up;
                }
                keep[i] = dir[i] == 0;
            }
            if (!rc)
                rc = grow(&h->sbuf, &h->scap, rec * (size_t)(nup + ndown), e);
            int moving = !rc && nup + ndown > 0;
            if (moving) {
                int ku = 0, kd = nup;
                for (int i = 0; i < p->n_owned; i++)
                    if (dir[i])
                        halo_pack(p, i, -1, 0.0,
                                  (unsigned char *)h->sbuf + rec * (size_t)(dir[i] > 0 ? ku++ : kd++));
                particles_compact(p, keep);
            }
            free(dir);
            free(keep);
            rc = collective_rc(h, rc, e);
            if (rc || !halo_any(h, moving))
                break;
            rc = collective_rc(h, migrate_exchange(h, p, d, nup, ndown, rec, e), e);
        }
    }
    if (!rc)
        count_atoms(h, p);
    return rc;
}

static int push_send(struct halo_swap *sw, int i, struct err *e)
{
    if (sw->nsend >= sw->cap_send) {
        int cap = sw->cap_send ? 2 * sw->cap_send : 1024;
        int *s = realloc(sw->send, (size_t)cap * sizeof *s);
        if (!s)
            return err_nomem(e, "halo send list");
        sw->send = s;
        sw->cap_send = cap;
    }
    sw->send[sw->nsend++] = i;
    return 0;
}

int halo_build(struct halo *h, struct particles *p, double range, struct err *e)
{
    const struct decomp *dc = &h->dc;
    size_t rec = halo_ghost_record_size(p);
    int rc = 0;
    p->n_ghost = 0;
    h->nswap = 0;
    /* a free axis shrink-wraps: its bricks may have become thinner than
     * the range since the grid was chosen, and one swap would miss ghosts */
    for (int d = 0; d < 3; d++)
        if ((dc->grid[d] > 1 || dc->periodic[d]) &&
            !(decomp_min_width(dc, d) >= range))   /* the same on every rank */
            return err_set(e, ERR_RUNTIME,
                           "the bricks along %c are %g Å thick, thinner than the interaction "
                           "range %g Å (the box shrank): run on fewer ranks along %c",
                           "xyz"[d], decomp_min_width(dc, d), range, "xyz"[d]);
    for (int d = 0; d < 3 && !rc; d++) {
        if (dc->grid[d] == 1 && !dc->periodic[d])
            continue;
        int nbefore = p->n_owned + p->n_ghost;
        double L = dc->bhi[d] - dc->blo[d];
        for (int dir = 0; dir < 2 && !rc; dir++) {
            struct halo_swap *sw = &h->swap[h->nswap++];
            sw->dim = d;
            sw->dest = dc->nbr[d][dir];
            sw->src = dc->nbr[d][1 - dir];
            sw->shift = 0;
            if (dc->periodic[d] && dir == 0 && dc->coords[d] == 0)
                sw->shift = L;
            if (dc->periodic[d] && dir == 1 && dc->coords[d] == dc->grid[d] - 1)
                sw->shift = -L;
            sw->nsend = 0;
            if (sw->dest >= 0)
                for (int i = 0; i < nbefore && !rc; i++) {
                    double x = p->x[3 * i + d];
                    if (dir == 0 ? x < dc->lo[d] + range : x >= dc->hi[d] - range)
                        rc = push_send(sw, i, e);
                }
            if (!rc)
                rc = grow(&h->sbuf, &h->scap, rec * (size_t)sw->nsend, e);
            if (!rc)   /* the reverse sums receive as much as was sent */
                rc = grow(&h->rbuf, &h->rcap, rec * (size_t)sw->nsend, e);
            for (int k = 0; !rc && k < sw->nsend; k++)
                halo_pack_ghost(p, sw->send[k], d, sw->shift, (unsigned char *)h->sbuf + rec * (size_t)k);
            size_t got = 0;
            rc = collective_rc(h, rc, e);
            if (!rc)
                rc = collective_rc(h, parallel_sendrecv(dc->par, sw->dest, h->sbuf,
                                                        rec * (size_t)sw->nsend, sw->src, &h->rbuf,
                                                        &h->rcap, &got, e), e);
            if (rc)
                break;
            int nin = (int)(got / rec), at = p->n_owned + p->n_ghost;
            rc = collective_rc(h, particles_reserve(p, at + nin, e), e);
            if (!rc)   /* the reverse sums send as much as was received */
                rc = collective_rc(h, grow(&h->sbuf, &h->scap, rec * (size_t)nin, e), e);
            if (rc)
                break;
            for (int k = 0; k < nin; k++)
                halo_unpack_ghost(p, at + k, (const unsigned char *)h->rbuf + rec * (size_t)k);
            sw->first = at;
            sw->nrecv = nin;
            p->n_ghost += nin;
        }
    }
    return rc;
}

/* One forward pass: values of the sent particles to the received ghosts,
 * coordinate `dim` shifted (with_shift).  Sizes are known from the build
 * (one message per swap), and the buffers were sized there for whole
 * ghost records (at least a row of the virial or of any field: the widest
 * arrays passed here), so this cannot run out of memory. */
static int forward(struct halo *h, double *arr, int ncomp, int with_shift, struct err *e)
{
    size_t row = (size_t)ncomp * sizeof(double);
    for (int s = 0; s < h->nswap; s++) {
        struct halo_swap *sw = &h->swap[s];
        double *sb = h->sbuf;
        for (int k = 0; k < sw->nsend; k++) {
            memcpy(sb + (size_t)ncomp * k, arr + (size_t)ncomp * sw->send[k], row);
            if (with_shift)
                sb[(size_t)ncomp * k + sw->dim] += sw->shift;
        }
        int rc = parallel_sendrecv_known(h->dc.par, sw->dest, sb, row * (size_t)sw->nsend, sw->src,
                                         arr + (size_t)ncomp * sw->first,
                                         row * (size_t)sw->nrecv, e);
        if (rc)
            return rc;
    }
    return 0;
}

int halo_update_positions(struct halo *h, struct particles *p)
{
    struct err e = {0};
    int rc = forward(h, p->x, 3, 1, &e);
    for (int k = 0; !rc && k < p->nfields; k++)
        if (p->fields[k].ghost_copy)
            rc = forward(h, p->fields[k].data, p->fields[k].ncomp, 0, &e);
    return rc;
}

int halo_forward(struct halo *h, const struct particles *p, double *arr, int ncomp)
{
    (void)p;
    struct err e = {0};
    return forward(h, arr, ncomp, 0, &e);
}

int halo_reverse_add(struct halo *h, const struct particles *p, double *arr, int ncomp)
{
    (void)p;
    struct err e = {0};
    size_t row = (size_t)ncomp * sizeof(double);
    for (int s = h->nswap - 1; s >= 0; s--) {
        struct halo_swap *sw = &h->swap[s];
        int rc = parallel_sendrecv_known(h->dc.par, sw->src, arr + (size_t)ncomp * sw->first,
                                         row * (size_t)sw->nrecv, sw->dest, h->rbuf,
                                         row * (size_t)sw->nsend, &e);
        if (rc)
            return rc;
        const double *rb = h->rbuf;
        for (int k = 0; k < sw->nsend; k++)
            for (int c = 0; c < ncomp; c++)
                arr[(size_t)ncomp * sw->send[k] + c] += rb[(size_t)ncomp * k + c];
    }
    return 0;
}

struct id_index {
    int64_t id;
    int i;
};

static int cmp_id(const void *a, const void *b)
{
    int64_t x = ((const struct id_index *)a)->id, y = ((const struct id_index *)b)->id;
    return (x > y) - (x < y);
}

int halo_sort_by_id(struct particles *p, struct err *e)
{
    int n = p->n_owned;
    particles_clear_ghosts(p);
    struct id_index *t = malloc((size_t)(n ? n : 1) * sizeof *t);
    int *perm = malloc((size_t)(n ? n : 1) * sizeof *perm);
    int rc = t && perm ? 0 : err_nomem(e, "sort by id");
    if (!rc) {
        for (int i = 0; i < n; i++)
            t[i] = (struct id_index){p->id[i], i};
        qsort(t, (size_t)n, sizeof *t, cmp_id);
        for (int i = 0; i < n; i++)
            perm[i] = t[i].i;
        rc = particles_permute(p, perm, e);
    }
    free(t);
    free(perm);
    return rc;
}

int halo_gather(struct halo *h, const struct particles *p, struct particles **out, struct err *e)
{
    *out = NULL;
    size_t rec = halo_record_size(p);
    int rc = grow(&h->sbuf, &h->scap, rec * (size_t)p->n_owned, e);
    for (int i = 0; !rc && i < p->n_owned; i++)
        halo_pack(p, i, -1, 0.0, (unsigned char *)h->sbuf + rec * (size_t)i);
    rc = collective_rc(h, rc, e);
    void *all = NULL;
    size_t bytes = 0;
    if (!rc)
        rc = parallel_gather_bytes(h->dc.par, h->sbuf, rec * (size_t)p->n_owned, &all, &bytes, e);
    if (rc || !all)
        return rc;
    int n = (int)(bytes / rec);
    struct particles *q = particles_create(n);
    rc = q ? 0 : err_nomem(e, "gathered particles");
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
    if (!rc) {
        for (int i = 0; i < n; i++)
            halo_unpack(q, i, (const unsigned char *)all + rec * (size_t)i);
        q->n_owned = n;
        rc = halo_sort_by_id(q, e);
    }
    free(all);
    if (rc)
        particles_destroy(&q);
    *out = q;
    return rc;
}

void halo_counts(const struct halo *h, const struct particles *p, long *counts)
{
    parallel_allgather_long(h->dc.par, p->n_owned, counts);
}

void halo_allgather_long(const struct halo *h, long v, long *out)
{
    parallel_allgather_long(h->dc.par, v, out);
}
