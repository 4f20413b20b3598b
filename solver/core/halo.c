/* halo: ghosts, migration and gathers of a brick decomposition (halo.h). */
#include "core/halo.h"

#include <limits.h>
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

int halo_init_like(struct halo *h, const struct halo *src, struct err *e)
{
    memset(h, 0, sizeof *h);
    h->dc = src->dc;
    for (int d = 0; d < 3; d++) {
        h->dc.frac[d] = NULL;
        if (!src->dc.frac[d])
            continue;
        size_t bytes = (size_t)(src->dc.grid[d] + 1) * sizeof *src->dc.frac[d];
        if (!(h->dc.frac[d] = malloc(bytes))) {
            halo_free(h);
            return err_nomem(e, "halo copy");
        }
        memcpy(h->dc.frac[d], src->dc.frac[d], bytes);
    }
    return 0;
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
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
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

void halo_balance_schedule(struct halo *h, long every, double threshold, int at_first_build)
{
    h->balance_every = every;
    h->balance_threshold = threshold;
    h->balance_next = every;   /* the set-up has cut at the particles, or will */
    h->balance_pending = at_first_build;
}

/* The cuts to the owned particles' present distribution. */
static int shift_cuts(struct halo *h, const struct particles *p, double range, struct err *e)
{
    int rc = collective_rc(h, decomp_shift(&h->dc, p->x, p->n_owned, range, e), e);
    if (!rc)
        h->balance_shifts++;
    return rc;
}

int halo_balance_step(struct halo *h, struct box *b, struct particles *p, double range,
                      long step, struct err *e)
{
    long every = h->balance_every;
    int force = h->balance_pending;
    if (!force && !(every > 0 && step >= h->balance_next))
        return 0;
    h->balance_pending = 0;
    if (every > 0)
        h->balance_next = (step / every + 1) * every;
    particles_clear_ghosts(p);
    int rc = halo_remap(h, b, p, 1, e);
    if (rc)
        return rc;
    if (!force) {
        /* the owned counts, strays included: they have moved less than
         * half a skin since the last migration */
        double most = p->n_owned, total = p->n_owned;
        halo_max(h, &most, 1);
        halo_sum(h, &total, 1);
        double mean = total / halo_nranks(h);
        double imbalance = mean > 0 ? most / mean : 1.0;
        h->balance_checks++;
        if (imbalance > h->balance_worst)
            h->balance_worst = imbalance;
        if (!(imbalance > h->balance_threshold))
            return 0;
    }
    rc = shift_cuts(h, p, range, e);
    return rc ? rc : halo_migrate(h, p, e);
}

int halo_balance_sync(struct halo *h, const struct particles *p, double range, long step,
                      struct err *e)
{
    long every = h->balance_every;
    if (every <= 0)
        return 0;
    h->balance_next = (step / every + 1) * every;
    return shift_cuts(h, p, range, e);
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
                int c = decomp_coord_at(dc, d, p->x + 3 * i);
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

/* Ghost records travel in pieces of at most this many (the build's
 * buffers stay a few hundred kB whatever the face's atom count: memory per
 * rank is what a decomposition is for). */
enum { HALO_CHUNK = 4096 };

/* The widest row a forward or reverse pass moves: the per-atom virial (6)
 * or an extra field. */
static size_t widest_row(const struct particles *p)
{
    int nc = 6;
    for (int k = 0; k < p->nfields; k++)
        if (p->fields[k].ncomp > nc)
            nc = p->fields[k].ncomp;
    return (size_t)nc * sizeof(double);
}

/* The particles of sw->send[0, nsend) to sw->dest as ghost records,
 * shifted by sw->shift along d; what sw->src sends is appended as ghosts.
 * The counts go first, then the records in pieces of HALO_CHUNK. */
static int swap_ghosts(struct halo *h, struct particles *p, struct halo_swap *sw, int d,
                       struct err *e)
{
    const struct decomp *dc = &h->dc;
    size_t rec = halo_ghost_record_size(p);
    long nout = sw->dest >= 0 ? sw->nsend : 0, nin = 0;
    int rc = collective_rc(h, parallel_sendrecv_known(dc->par, sw->dest, &nout, sizeof nout,
                                                      sw->src, &nin, sizeof nin, e), e);
    if (rc)
        return rc;
    if (sw->src < 0)
        nin = 0;
    int at = p->n_owned + p->n_ghost;
    rc = nin < 0 || nin > INT_MAX - at
             ? err_set(e, ERR_RUNTIME, "halo swap: %ld ghosts announced", nin)
             : particles_reserve(p, at + (int)nin, e);
    if (!rc)
        rc = grow(&h->sbuf, &h->scap, rec * HALO_CHUNK, e);
    if (!rc)
        rc = grow(&h->rbuf, &h->rcap, rec * HALO_CHUNK, e);
    if ((rc = collective_rc(h, rc, e)))
        return rc;
    /* the number of pieces differs between ranks: no collective call in
     * the loop (a failure is agreed on after it; a local one -- none is
     * expected with pieces this small -- leaves the records unsent) */
    for (long done_out = 0, done_in = 0; !rc && (done_out < nout || done_in < nin);) {
        long kout = nout - done_out < HALO_CHUNK ? nout - done_out : HALO_CHUNK;
        long kin = nin - done_in < HALO_CHUNK ? nin - done_in : HALO_CHUNK;
        for (long k = 0; k < kout; k++)
            halo_pack_ghost(p, sw->send[done_out + k], d, sw->shift, sw->tilted ? sw->vec : NULL,
                            (unsigned char *)h->sbuf + rec * (size_t)k);
        /* a side that is done takes no part (MPI_PROC_NULL): between two
         * ranks as many pieces travel as the sender has, however many
         * the ranks on either side exchange with their other neighbours */
        /* one neighbour on both sides (a periodic axis of one or two
         * bricks): the counts are symmetric, every piece is a pair */
        int self = sw->dest == sw->src;
        rc = parallel_sendrecv_known(dc->par, kout || self ? sw->dest : -1, h->sbuf,
                                     rec * (size_t)kout, kin || self ? sw->src : -1, h->rbuf,
                                     rec * (size_t)kin, e);
        if (rc)
            break;
        for (long k = 0; k < kin; k++)
            halo_unpack_ghost(p, at + (int)(done_in + k),
                              (const unsigned char *)h->rbuf + rec * (size_t)k);
        done_out += kout;
        done_in += kin;
    }
    if ((rc = collective_rc(h, rc, e)))
        return rc;
    sw->first = at;
    sw->nrecv = (int)nin;
    p->n_ghost += (int)nin;
    return 0;
}

int halo_build(struct halo *h, struct particles *p, double range, struct err *e)
{
    const struct decomp *dc = &h->dc;
    int rc = 0;
    p->n_ghost = 0;
    h->nswap = 0;
    /* an owned particle is its own copy, shifted by no box length; its slot
     * may hold a ghost's shift from before a checkpoint read refilled the
     * slots, and DPD's pair keys read it (dpd_pair_key_pre) */
    memset(p->gshift, 0, (size_t)3 * (size_t)p->n_owned * sizeof *p->gshift);
    /* a free axis shrink-wraps: its bricks may have become thinner than
     * the range since the grid was chosen, and one swap would miss ghosts */
    for (int d = 0; d < 3; d++)
        if ((dc->grid[d] > 1 || dc->periodic[d]) &&
            !(decomp_min_width(dc, d) >= decomp_range_along(dc, d, range)))   /* the same on every rank */
            return err_set(e, ERR_RUNTIME,
                           "the bricks along %c are %g Å thick, thinner than the interaction "
                           "range %g Å (the box shrank): run on fewer ranks along %c",
                           "xyz"[d],
                           decomp_min_width(dc, d) * range / decomp_range_along(dc, d, range),
                           range, "xyz"[d]);
    long widest = 1;   /* the most particles one swap sends or receives */
    for (int d = 0; d < 3 && !rc; d++) {
        if (dc->grid[d] == 1 && !dc->periodic[d])
            continue;
        int nbefore = p->n_owned + p->n_ghost;
        double L = dc->bhi[d] - dc->blo[d];
        double reach = decomp_range_along(dc, d, range);   /* range in an orthogonal box */
        double edge[3];   /* a tilted cell's edge d: (lx 0 0), (xy ly 0), (xz yz lz) */
        struct box cell;
        decomp_box(dc, &cell);
        const int unit[3] = {d == 0, d == 1, d == 2};
        box_image_shift(&cell, unit, edge);
        for (int dir = 0; dir < 2 && !rc; dir++) {
            if (h->half_shell && d == 2 && dir == 1)
                continue;   /* the ghosts below the lower z face: half_shell in halo.h */
            struct halo_swap *sw = &h->swap[h->nswap++];
            sw->dim = d;
            sw->dest = dc->nbr[d][dir];
            sw->src = dc->nbr[d][1 - dir];
            sw->shift = 0;
            if (dc->periodic[d] && dir == 0 && dc->coords[d] == 0)
                sw->shift = L;
            if (dc->periodic[d] && dir == 1 && dc->coords[d] == dc->grid[d] - 1)
                sw->shift = -L;
            sw->tilted = dc->tilted && sw->shift != 0;
            for (int c = 0; c < 3; c++)
                sw->vec[c] = sw->shift > 0 ? edge[c] : -edge[c];
            sw->nsend = 0;
            if (sw->dest >= 0)
                for (int i = 0; i < nbefore && !rc; i++) {
                    double x = dc->tilted ? decomp_cut_coord(dc, d, p->x + 3 * i) : p->x[3 * i + d];
                    if (dir == 0 ? x < dc->lo[d] + reach : x >= dc->hi[d] - reach)
                        rc = push_send(sw, i, e);
                }
            rc = collective_rc(h, rc, e);
            if (!rc)
                rc = swap_ghosts(h, p, sw, d, e);
            if (!rc) {
                if (sw->nsend > widest) widest = sw->nsend;
                if (sw->nrecv > widest) widest = sw->nrecv;
            }
        }
    }
    /* the forward and reverse passes share sbuf: a forward pass packs the
     * sent rows into it and receives into the array, a reverse pass sends
     * from the array and receives the rows into it */
    if (!rc)
        rc = collective_rc(h, grow(&h->sbuf, &h->scap, widest_row(p) * (size_t)widest, e), e);
    return rc;
}

/* One forward pass: values of the sent particles to the received ghosts,
 * coordinate `dim` shifted (with_shift).  Sizes are known from the build
 * (one message per swap), and sbuf was sized there for the widest row
 * passed here (the virial or an extra field) of the largest swap, so this
 * does not allocate (a wider row than that grows it). */
static int forward(struct halo *h, double *arr, int ncomp, int with_shift, struct err *e)
{
    size_t row = (size_t)ncomp * sizeof(double);
    for (int s = 0; s < h->nswap; s++) {
        struct halo_swap *sw = &h->swap[s];
        if (row * (size_t)sw->nsend > h->scap && grow(&h->sbuf, &h->scap, row * (size_t)sw->nsend, e))
            return ERR_RUNTIME;
        double *sb = h->sbuf;
        for (int k = 0; k < sw->nsend; k++) {
            memcpy(sb + (size_t)ncomp * k, arr + (size_t)ncomp * sw->send[k], row);
            if (with_shift && sw->tilted)
                for (int c = 0; c < 3; c++)
                    sb[(size_t)ncomp * k + c] += sw->vec[c];
            else if (with_shift)
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
        if (row * (size_t)sw->nsend > h->scap &&
            grow(&h->sbuf, &h->scap, row * (size_t)sw->nsend, &e))
            return ERR_RUNTIME;
        int rc = parallel_sendrecv_known(h->dc.par, sw->src, arr + (size_t)ncomp * sw->first,
                                         row * (size_t)sw->nrecv, sw->dest, h->sbuf,
                                         row * (size_t)sw->nsend, &e);
        if (rc)
            return rc;
        const double *rb = h->sbuf;
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

void halo_counts(const struct halo *h, const struct particles *p, long *counts)
{
    parallel_allgather_long(h->dc.par, p->n_owned, counts);
}

void halo_allgather_long(const struct halo *h, long v, long *out)
{
    parallel_allgather_long(h->dc.par, v, out);
}
