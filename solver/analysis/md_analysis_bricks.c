/* md_analysis_bricks: the MD analysis of a brick run, on rank 0 (md_analysis_bricks.h). */
#include "analysis/md_analysis_bricks.h"

#include <stdlib.h>
#include <string.h>

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

int md_analysis_run_bricks(struct md_analysis *a, struct halo *h, struct particles *p,
                           const struct box *box, double time, struct timers *timers,
                           struct err *e)
{
    if (timers)
        timer_start(timers, TIMER_ANALYSIS);
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
    if (timers)
        timer_stop(timers, TIMER_ANALYSIS);
    return rc;
}
