/* sputter_bricks: groups across brick faces by label propagation (sputter_bricks.h). */
#include "analysis/sputter_bricks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"

/* Label every particle of q (owned and ghosts) by the smallest id of its
 * group over all ranks.  lab: ntot doubles (ids < 2^53 are exact). */
static int propagate(struct halo *h, const struct particles *q, const int *root, double *lab,
                     struct err *e)
{
    int n = q->n_owned, ntot = q->n_owned + q->n_ghost;
    double *rmin = malloc((size_t)(ntot ? ntot : 1) * sizeof *rmin);
    int rc = halo_agree(h, rmin ? 0 : err_nomem(e, "sputter labels"), e);
    for (int i = 0; !rc && i < ntot; i++)
        lab[i] = (double)q->id[i];
    while (!rc) {
        for (int i = 0; i < ntot; i++)
            rmin[i] = INFINITY;
        for (int i = 0; i < ntot; i++)
            rmin[root[i]] = fmin(rmin[root[i]], lab[i]);
        int changed = 0;
        for (int i = 0; i < n; i++)
            if (lab[i] != rmin[root[i]]) {
                lab[i] = rmin[root[i]];
                changed = 1;
            }
        if (!halo_any(h, changed))
            break;   /* labels fall and are ids: the rounds end */
        rc = halo_agree(h, halo_forward(h, q, lab, 1)
                               ? err_set(e, ERR_RUNTIME, "sputter labels: exchange failed")
                               : 0, e);
    }
    free(rmin);
    return rc;
}

struct tagged {
    double label;
    int i;
};

static int by_label(const void *x, const void *y)
{
    double a = ((const struct tagged *)x)->label, b = ((const struct tagged *)y)->label;
    return (a > b) - (a < b);
}

static int group_by_label(const void *x, const void *y)
{
    int64_t a = ((const struct sputter_group *)x)->label, b = ((const struct sputter_group *)y)->label;
    return (a > b) - (a < b);
}

static int by_int64(const void *x, const void *y)
{
    int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return (a > b) - (a < b);
}

/* This rank's share of every group it holds atoms of, in label order. */
static long local_groups(const struct particles *q, const double *lab, const double *mass, int axis,
                         struct tagged *t, struct sputter_group *g)
{
    int n = q->n_owned;
    for (int i = 0; i < n; i++)
        t[i] = (struct tagged){lab[i], i};
    qsort(t, (size_t)n, sizeof *t, by_label);
    long ng = 0;
    for (int k = 0; k < n; k++) {
        int i = t[k].i;
        if (k == 0 || t[k].label != t[k - 1].label)
            g[ng++] = (struct sputter_group){(int64_t)t[k].label, 0, 0.0, 0.0, INFINITY, 0};
        struct sputter_group *gi = &g[ng - 1];
        double m = mass ? mass[i] : 1.0, z = q->x[3 * i + axis];
        gi->size++;
        gi->mass += m;
        gi->momentum += m * q->v[3 * i + axis];
        if (z < gi->zmin)
            gi->zmin = z;
    }
    return ng;
}

/* The verdict rank 0 broadcasts. */
struct verdict {
    struct sputter_stats stats;
    int64_t target;   /* label of the target (-1: none) */
    long nleft;       /* labels of the groups that left, sent next */
};

/* On rank 0: merge the ranks' tables (all, ng rows) by label and judge. */
static int judge_all(struct sputter_group *all, long ng, const struct sputter_params *p,
                     struct verdict *v, int64_t **left, struct err *e)
{
    qsort(all, (size_t)ng, sizeof *all, group_by_label);
    long m = 0;
    for (long k = 0; k < ng; k++) {
        if (m > 0 && all[m - 1].label == all[k].label) {
            struct sputter_group *g = &all[m - 1];
            g->size += all[k].size;
            g->mass += all[k].mass;
            g->momentum += all[k].momentum;
            g->zmin = fmin(g->zmin, all[k].zmin);
        } else {
            all[m++] = all[k];
        }
    }
    long target = sputter_judge(all, m, p, &v->stats);
    v->target = target >= 0 ? all[target].label : -1;
    v->nleft = v->stats.clusters;
    *left = malloc((size_t)(v->nleft ? v->nleft : 1) * sizeof **left);
    if (!*left)
        return err_nomem(e, "sputter groups");
    long k = 0;
    for (long g = 0; g < m; g++)
        if (all[g].left)
            (*left)[k++] = all[g].label;   /* in label order: bsearch below */
    return 0;
}

int sputter_find_bricks(struct halo *h, struct particles *q, const struct frame *f,
                        const double *mass, const struct sputter_params *p, unsigned char *state,
                        struct sputter_stats *out, struct err *e)
{
    const struct parallel *par = h->dc.par;
    int root0 = !par || par->rank == 0;
    int n = q->n_owned, ntot = q->n_owned + q->n_ghost;
    memset(out, 0, sizeof *out);
    int *root = malloc((size_t)(ntot ? ntot : 1) * sizeof *root);
    double *lab = malloc((size_t)(ntot ? ntot : 1) * sizeof *lab);
    struct tagged *t = malloc((size_t)(n ? n : 1) * sizeof *t);
    struct sputter_group *g = malloc((size_t)(n ? n : 1) * sizeof *g);
    int rc = root && lab && t && g ? sputter_link(f, p->cutoff, root, e)
                                   : err_nomem(e, "sputter groups");
    rc = halo_agree(h, rc, e);
    if (!rc)
        rc = propagate(h, q, root, lab, e);
    long ng = rc ? 0 : local_groups(q, lab, mass, p->axis, t, g);
    void *all = NULL;
    size_t allbytes = 0;
    if (!rc)
        rc = parallel_gather_bytes(par, g, (size_t)ng * sizeof *g, &all, &allbytes, e);
    struct verdict v;
    memset(&v, 0, sizeof v);
    int64_t *left = NULL;
    if (!rc && root0)
        rc = judge_all(all, (long)(allbytes / sizeof *g), p, &v, &left, e);
    free(all);
    rc = halo_agree(h, rc, e);
    if (!rc)
        rc = parallel_bcast_bytes(par, &v, sizeof v, e);
    if (!rc && !root0 && !(left = malloc((size_t)(v.nleft ? v.nleft : 1) * sizeof *left)))
        rc = err_nomem(e, "sputter groups");
    rc = halo_agree(h, rc, e);
    if (!rc)
        rc = parallel_bcast_bytes(par, left, (size_t)v.nleft * sizeof *left, e);
    for (int i = 0; !rc && i < n; i++) {
        int64_t l = (int64_t)lab[i];
        state[i] = l == v.target ? SPUTTER_TARGET
                   : bsearch(&l, left, (size_t)v.nleft, sizeof *left, by_int64) ? SPUTTER_LEFT
                                                                                 : SPUTTER_DETACHED;
    }
    if (!rc)
        *out = v.stats;
    free(left); free(root); free(lab); free(t); free(g);
    return rc;
}
