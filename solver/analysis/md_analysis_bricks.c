/* md_analysis_bricks: the MD analysis of a brick run, each rank on its own
 * atoms (md_analysis_bricks.h). */
#include "analysis/md_analysis_bricks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/sputter_bricks.h"
#include "core/parallel.h"

/* The analysis' latest results and its newest row, as rank 0 sends them. */
struct latest {
    long counts[STRUCT_NCLASSES], displaced, counted;
    struct sputter_stats sputter;
    struct crater_stats crater;
    struct damage_shape shape;
    double row[MDA_MAXCOLS];
};

/* The per-atom fields the analysis fills (md_analysis_attach). */
static int analysis_fields(const struct md_analysis *a, int *f)
{
    int nf = 0;
    f[nf++] = a->f_structure;
    f[nf++] = a->f_displaced;
    if (a->f_sputtered >= 0)
        f[nf++] = a->f_sputtered;
    if (a->f_crater >= 0)
        f[nf++] = a->f_crater;
    return nf;
}

static int by_id(const void *x, const void *y)
{
    int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return (a > b) - (a < b);
}

/* On rank 0: run the serial analysis on `all` (every atom, in id order)
 * and lay out the fields for the scatter: for each id of `ids` (every
 * rank's owned ids, concatenated in rank order) the nf field values. */
static int analyse_all(struct md_analysis *a, struct particles *all, const struct box *box,
                       double time, const int64_t *ids, long nids, const int *f, int nf,
                       double **out, struct latest *l, struct err *e)
{
    int rc = md_analysis_run(a, all, box, time, NULL, e);
    double *buf = rc ? NULL : malloc((size_t)(nids ? nids : 1) * (size_t)nf * sizeof *buf);
    if (!rc && !buf)
        rc = err_nomem(e, "analysis fields");
    /* the gathered set is sorted by id (halo_gather): find each id there */
    for (long k = 0; !rc && k < nids; k++) {
        const int64_t *at = bsearch(&ids[k], all->id, (size_t)all->n_owned, sizeof *all->id,
                                    by_id);
        if (!at) {
            rc = err_set(e, ERR_RUNTIME, "analysis: atom id %lld missing from the gathered set",
                         (long long)ids[k]);
            break;
        }
        long i = at - all->id;
        for (int m = 0; m < nf; m++)
            buf[k * nf + m] = particles_field(all, f[m])[i];
    }
    if (!rc) {
        memcpy(l->counts, a->counts, sizeof l->counts);
        l->displaced = a->displaced;
        l->counted = a->counted;
        l->sputter = a->sputter;
        l->crater = a->crater;
        l->shape = a->shape;
        memcpy(l->row, md_analysis_row(a, a->nrows - 1), (size_t)a->ncols * sizeof *l->row);
    }
    if (rc) {
        free(buf);
        buf = NULL;
    }
    *out = buf;
    return rc;
}

/* The fallback for bricks thinner than the analysis' reach: every atom
 * on rank 0, the serial analysis there (md_analysis_bricks.h). */
static int run_gathered(struct md_analysis *a, struct halo *h, struct particles *p,
                        const struct box *box, double time, struct err *e)
{
    const struct parallel *par = h->dc.par;
    int root = !par || par->rank == 0, nr = halo_nranks(h), n = p->n_owned;
    int f[4], nf = analysis_fields(a, f);
    long *counts = malloc((size_t)nr * sizeof *counts);
    long *bytes = malloc((size_t)nr * sizeof *bytes);
    double *vals = malloc((size_t)(n ? n : 1) * (size_t)nf * sizeof *vals);
    int rc = halo_agree(h, counts && bytes && vals ? 0 : err_nomem(e, "analysis"), e);
    struct particles *all = NULL;
    void *ids = NULL;
    size_t idbytes = 0;
    double *sbuf = NULL;
    struct latest l;
    memset(&l, 0, sizeof l);
    if (!rc) {
        halo_counts(h, p, counts);
        rc = halo_agree(h, halo_gather(h, p, &all, e), e);
    }
    /* every rank's ids in rank order: where each field value goes back */
    if (!rc)
        rc = parallel_gather_bytes(par, p->id, (size_t)n * sizeof *p->id, &ids, &idbytes, e);
    if (!rc && root)
        rc = analyse_all(a, all, box, time, ids, (long)(idbytes / sizeof(int64_t)), f, nf, &sbuf,
                         &l, e);
    particles_destroy(&all);
    free(ids);
    if (root)   /* rank 0 held every atom: give the analysis' scratch back */
        md_analysis_release(a);
    rc = halo_agree(h, rc, e);
    if (!rc)
        rc = parallel_bcast_bytes(par, &l, sizeof l, e);
    if (!rc && !root) {
        memcpy(a->counts, l.counts, sizeof a->counts);
        a->displaced = l.displaced;
        a->counted = l.counted;
        a->sputter = l.sputter;
        a->crater = l.crater;
        a->shape = l.shape;
        rc = md_analysis_push_row(a, l.row, e);
    }
    rc = halo_agree(h, rc, e);
    if (!rc) {
        for (int r = 0; r < nr; r++)
            bytes[r] = counts[r] * nf * (long)sizeof(double);
        rc = parallel_scatter_bytes(par, sbuf, bytes, vals, e);
    }
    for (int i = 0; !rc && i < n; i++)
        for (int m = 0; m < nf; m++)
            particles_field(p, f[m])[i] = vals[(long)i * nf + m];
    free(sbuf);
    free(vals);
    free(counts);
    free(bytes);
    return rc;
}

/* --- the distributed analysis ------------------------------------------- */

/* This rank's owned atoms, without fields: the set the analysis' ghosts
 * are added to (the MD's own ghosts stay as they are). */
static struct particles *copy_owned(const struct particles *p)
{
    int n = p->n_owned;
    struct particles *q = particles_create(n + n / 4 + 64);
    if (!q)
        return NULL;
    q->ntypes = p->ntypes;
    memcpy(q->mass, p->mass, sizeof q->mass);
    memcpy(q->type_name, p->type_name, sizeof q->type_name);
    /* what the analysis and the ghost exchange read, written array by
     * array: forces, energies and virials are never read here, and their
     * pages (80 of a particle's 172 bytes) stay unwritten, so not
     * resident (docs/parallel.md, "The paper-scale run") */
    memcpy(q->x, p->x, (size_t)n * 3 * sizeof *q->x);
    memcpy(q->v, p->v, (size_t)n * 3 * sizeof *q->v);
    memcpy(q->type, p->type, (size_t)n * sizeof *q->type);
    memcpy(q->id, p->id, (size_t)n * sizeof *q->id);
    memcpy(q->mask, p->mask, (size_t)n * sizeof *q->mask);
    memset(q->image, 0, (size_t)n * 3 * sizeof *q->image);
    memset(q->gshift, 0, (size_t)n * 3 * sizeof *q->gshift);
    for (int i = 0; i < n; i++)
        q->origin[i] = i;
    q->n_owned = n;
    return q;
}

/* The farthest an owned atom lies outside its brick, towards a face with
 * a neighbour rank, over all ranks (atoms migrate at list builds only). */
static double max_outside(const struct halo *h, const struct particles *p)
{
    const struct decomp *dc = &h->dc;
    double dmax = 0;
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            double x = p->x[3 * i + d];
            if (dc->nbr[d][0] >= 0)
                dmax = fmax(dmax, dc->lo[d] - x);
            if (dc->nbr[d][1] >= 0)
                dmax = fmax(dmax, x - dc->hi[d]);
        }
    halo_max(h, &dmax, 1);
    return dmax;
}

/* Every axis with an exchange has bricks at least `width` thick. */
static int bricks_wide(const struct halo *h, double width)
{
    const struct decomp *dc = &h->dc;
    for (int d = 0; d < 3; d++)
        if ((dc->grid[d] > 1 || dc->periodic[d]) && !(decomp_min_width(dc, d) >= width))
            return 0;
    return 1;
}

/* The damage shape of the damaged owned atoms of every rank: their (id, x,
 * y) on rank 0 in id order (a few per cent of the atoms), measured there,
 * the result broadcast.  A quantile needs every value, not a sum. */
struct damaged_xy {
    int64_t id;
    double x, y;
};

static int by_id_xy(const void *x, const void *y)
{
    int64_t a = ((const struct damaged_xy *)x)->id, b = ((const struct damaged_xy *)y)->id;
    return (a > b) - (a < b);
}

static int shape_bricks(struct md_analysis *a, struct halo *h, const struct particles *p,
                        struct err *e)
{
    const struct parallel *par = h->dc.par;
    int n = p->n_owned, m = 0;
    struct damaged_xy *mine = malloc((size_t)(n ? n : 1) * sizeof *mine);
    int rc = halo_agree(h, mine ? 0 : err_nomem(e, "damage shape"), e);
    for (int i = 0; !rc && i < n; i++)
        if (a->damaged[i])
            mine[m++] = (struct damaged_xy){p->id[i], p->x[3 * i], p->x[3 * i + 1]};
    void *all = NULL;
    size_t bytes = 0;
    if (!rc)
        rc = parallel_gather_bytes(par, mine, (size_t)m * sizeof *mine, &all, &bytes, e);
    free(mine);
    if (!rc && (!par || par->rank == 0)) {
        long k = (long)(bytes / sizeof(struct damaged_xy));
        struct damaged_xy *d = all;
        qsort(d, (size_t)k, sizeof *d, by_id_xy);
        double *x = malloc((size_t)(3 * k + 3) * sizeof *x);
        rc = x ? 0 : err_nomem(e, "damage shape");
        for (long i = 0; !rc && i < k; i++) {
            x[3 * i] = d[i].x;
            x[3 * i + 1] = d[i].y;
            x[3 * i + 2] = 0;
        }
        if (!rc)
            rc = damage_shape_measure(x, (int)k, NULL, NULL, &a->shape, e);
        free(x);
    }
    free(all);
    rc = halo_agree(h, rc, e);
    return rc ? rc : parallel_bcast_bytes(par, &a->shape, sizeof a->shape, e);
}

/* The crater of the target atoms of every rank: the height maps reduced
 * (highest atom of each column and the smallest id at that height, the
 * rim), every rank floods the same map, and marks its own floor atoms. */
static int crater_bricks(struct md_analysis *a, struct halo *h, struct particles *p,
                         struct err *e)
{
    struct crater_params cp = md_analysis_crater_params(a);
    struct crater_map m;
    int n = p->n_owned, rc = crater_map_init(&m, &cp, e);
    if (rc)
        return halo_agree(h, rc, e);
    long nc = (long)m.nx * m.ny;
    double *mine = malloc((size_t)nc * sizeof *mine), *who = malloc((size_t)nc * sizeof *who);
    unsigned char *in = malloc((size_t)nc);
    rc = halo_agree(h, mine && who && in ? 0 : err_nomem(e, "crater height map"), e);
    if (!rc) {
        crater_map_add(&m, p->x, n, a->sel, p->id, &cp);
        memcpy(mine, m.top, (size_t)nc * sizeof *mine);
        halo_max(h, m.top, (int)nc);
        halo_max(h, &m.rim, 1);
        /* ids below 2^53 are exact doubles; the smallest id as the
         * largest negated one */
        for (long c = 0; c < nc; c++)
            who[c] = m.who[c] >= 0 && mine[c] == m.top[c] ? -(double)m.who[c] : -INFINITY;
        halo_max(h, who, (int)nc);
        for (long c = 0; c < nc; c++)
            m.who[c] = isfinite(who[c]) ? (int64_t)-who[c] : -1;
        rc = halo_agree(h, crater_flood(&m, &cp, in, &a->crater, e), e);
    }
    double *f = particles_field(p, a->f_crater);
    for (int i = 0; !rc && i < n; i++) {
        long c = a->sel[i] ? crater_column(&m, &cp, p->x + 3 * i) : -1;
        f[i] = c >= 0 && in[c] && m.who[c] == p->id[i];
    }
    free(mine); free(who); free(in);
    crater_map_free(&m);
    return rc;
}

/* Classes, counts, sputtered groups, crater and damage shape over the
 * ranks, each on its own atoms and the ghosts within the analysis' reach
 * (q, ah). */
static int run_distributed(struct md_analysis *a, struct halo *h, struct halo *ah,
                           struct particles *p, struct particles *q, double reach,
                           const struct box *box, double time, struct err *e)
{
    int n = p->n_owned;
    int rc = halo_build(ah, q, reach, e);
    int ntot = q->n_owned + q->n_ghost;
    /* the ghosts carry the periodic images: no images of the frame's own */
    struct box open = *box;
    for (int d = 0; d < 3; d++)
        open.bc[d] = BOUNDARY_FREE;
    if (!rc)
        rc = md_analysis_reserve(a, ntot, e);
    if (!rc)
        rc = structure_classify(&a->sp, q->x, ntot, &open, &a->fr, a->cls, e);
    if ((rc = halo_agree(h, rc, e)))
        return rc;
    md_analysis_mark(a, p);   /* a->cls[0, n) are p's owned atoms, in order */
    double sums[STRUCT_NCLASSES + 2];
    for (int k = 0; k < STRUCT_NCLASSES; k++)
        sums[k] = (double)a->counts[k];
    sums[STRUCT_NCLASSES] = (double)a->displaced;
    sums[STRUCT_NCLASSES + 1] = (double)a->counted;
    halo_sum(h, sums, STRUCT_NCLASSES + 2);
    for (int k = 0; k < STRUCT_NCLASSES; k++)
        a->counts[k] = (long)sums[k];
    a->displaced = (long)sums[STRUCT_NCLASSES];
    a->counted = (long)sums[STRUCT_NCLASSES + 1];
    if (a->o.damage_shape && (rc = shape_bricks(a, h, p, e)))
        return rc;
    if (a->o.sputter) {
        struct sputter_params spp = md_analysis_sputter_params(a);
        if ((rc = sputter_find_bricks(ah, q, &a->fr, a->mass, &spp, a->sput, &a->sputter, e)))
            return rc;
        double *f = particles_field(p, a->f_sputtered);
        for (int i = 0; i < n; i++)
            f[i] = a->sput[i] == SPUTTER_LEFT;
    }
    if (a->o.crater) {
        for (int i = 0; i < n; i++)
            a->sel[i] = a->o.sputter ? a->sput[i] == SPUTTER_TARGET : 1;
        if ((rc = crater_bricks(a, h, p, e)))
            return rc;
    }
    return halo_agree(h, md_analysis_push_latest(a, time, e), e);
}

int md_analysis_run_bricks(struct md_analysis *a, struct halo *h, struct particles *p,
                           const struct box *box, double time, struct timers *timers,
                           struct err *e)
{
    if (timers)
        timer_start(timers, TIMER_ANALYSIS);
    /* every atom within the analysis' reach of an owned atom must be here:
     * the reach plus how far owned atoms strayed from their bricks since
     * the last migration (on both sides of a face, so the bricks must be
     * that much thicker: one hop along an axis) */
    double dmax = max_outside(h, p);
    double reach = structure_range(&a->sp) * (1 + 1e-9) + dmax + 1e-9;
    int rc;
    if (!bricks_wide(h, reach + dmax)) {
        rc = run_gathered(a, h, p, box, time, e);
    } else {
        struct halo ah;
        struct particles *q = copy_owned(p);
        rc = halo_agree(h, q ? halo_init_like(&ah, h, e) : err_nomem(e, "analysis atoms"), e);
        if (!rc) {
            rc = run_distributed(a, h, &ah, p, q, reach, box, time, e);
            halo_free(&ah);
        } else if (q) {
            halo_free(&ah);
        }
        particles_destroy(&q);
        /* the frame and the scratch hold the brick and its ghosts: given
         * back until the next analysis */
        md_analysis_release(a);
    }
    if (timers)
        timer_stop(timers, TIMER_ANALYSIS);
    return rc;
}
