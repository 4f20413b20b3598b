/* dpd_sweep_bodies: the free bodies' pairs of the cell-coloured sweep, in
 * one global order on every rank (dpd_sweep_bodies.h). */
#include "dpd/dpd_sweep_bodies.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/parallel.h"
#include "dpd/dpd_ou.h"
#include "dpd/dpd_pair.h"

/* Every rank's records on every rank (*all: a new buffer). */
static int gather_all(const struct halo *h, const struct dpd_body_pair *mine, long n,
                      struct dpd_body_pair **all, long *nall, struct err *e)
{
    size_t bytes = (size_t)n * sizeof *mine;
    if (!h || halo_nranks(h) <= 1) {
        *all = malloc(bytes ? bytes : 1);
        if (!*all)
            return err_nomem(e, "DPD body pairs");
        if (bytes)
            memcpy(*all, mine, bytes);
        *nall = n;
        return 0;
    }
    const struct parallel *par = h->dc.par;
    void *buf = NULL;
    size_t total = 0;
    /* to rank 0, then its buffer to every rank */
    int rc = parallel_gather_bytes(par, mine, bytes, &buf, &total, e);
    if (halo_any(h, rc != 0)) {
        free(buf);
        return rc ? rc : err_set_elsewhere(e, ERR_RUNTIME, "DPD body pairs: another rank failed");
    }
    long t = (long)total;
    rc = parallel_bcast_bytes(par, &t, sizeof t, e);
    if (!rc && par->rank != 0 && !(buf = malloc(t > 0 ? (size_t)t : 1)))
        rc = err_nomem(e, "DPD body pairs");
    if (halo_any(h, rc != 0)) {
        free(buf);
        return rc ? rc : err_set_elsewhere(e, ERR_RUNTIME, "DPD body pairs: another rank failed");
    }
    if ((rc = parallel_bcast_bytes(par, buf, (size_t)t, e))) {
        free(buf);
        return rc;
    }
    *all = buf;
    *nall = t / (long)sizeof **all;
    return 0;
}

static int cmp_rec(const void *x, const void *y)
{
    const struct dpd_body_pair *p = x, *q = y;
    if (p->cell != q->cell)
        return p->cell < q->cell ? -1 : 1;
    for (int k = 0; k < 2; k++)
        if (p->id[k] != q->id[k])
            return p->id[k] < q->id[k] ? -1 : 1;
    return (p->image > q->image) - (p->image < q->image);
}

/* A particle's state while the pairs are swept: the value of its first
 * record (every copy of a particle holds the same bits). */
struct slot {
    int64_t id;
    double v[3], u;
};

static int cmp_slot(const void *x, const void *y)
{
    const struct slot *p = x, *q = y;
    return (p->id > q->id) - (p->id < q->id);
}

static struct slot *find(struct slot *s, long n, int64_t id)
{
    long lo = 0, hi = n - 1;
    while (lo <= hi) {
        long mid = (lo + hi) / 2;
        if (s[mid].id == id)
            return s + mid;
        if (s[mid].id < id)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return NULL;
}

int dpd_sweep_bodies(struct dpd *d, const struct dpd_ou *ou, const struct dpd_body_pair *mine,
                     long n, double imp[DPD_MAX_BODIES][3], struct err *e)
{
    struct particles *p = d->p;
    struct dpd_body_pair *r = NULL;
    long nr = 0;
    int rc = gather_all(p->halo, mine, n, &r, &nr, e);
    if (rc)
        return rc;
    if (nr == 0) {
        free(r);
        return 0;
    }
    qsort(r, (size_t)nr, sizeof *r, cmp_rec);
    struct slot *s = malloc((size_t)(2 * nr) * sizeof *s);
    if (!s) {
        free(r);
        return err_nomem(e, "DPD body pairs");
    }
    long ns = 0;
    for (long k = 0; k < nr; k++)
        for (int q = 0; q < 2; q++) {
            s[ns].id = r[k].id[q];
            memcpy(s[ns].v, r[k].v[q], sizeof s[ns].v);
            s[ns++].u = r[k].u[q];
        }
    /* stable enough: equal ids hold equal values */
    qsort(s, (size_t)ns, sizeof *s, cmp_slot);
    long m = 0;
    for (long k = 0; k < ns; k++)
        if (m == 0 || s[k].id != s[m - 1].id)
            s[m++] = s[k];
    ns = m;
    const int dpde = d->set.variant == DPD_ENERGY;
    int64_t bad = -1;
    double badu = 0;
    for (long k = 0; k < nr && bad < 0; k++) {
        const struct dpd_body_pair *q = r + k;
        struct slot *sa = find(s, ns, q->id[0]), *sb = find(s, ns, q->id[1]);
        double *va = q->body[0] >= 0 ? d->body[q->body[0]].v : sa->v;
        double *vb = q->body[1] >= 0 ? d->body[q->body[1]].v : sb->v;
        double invmu = q->winv[0] + q->winv[1], mu = 1.0 / invmu;
        const double ex = q->e[0], ey = q->e[1], ez = q->e[2];
        struct dpd_ou_pair op;
        dpd_ou_pair_set(ou, &op, q->wr, invmu, q->xi);
        double urel = ex * (va[0] - vb[0]) + ey * (va[1] - vb[1]) + ez * (va[2] - vb[2]);
        double unew = dpd_ou_unew(ou, &op, urel, sa->u, sb->u);
        double du = unew - urel;
        double aa = du * (q->winv[0] * mu), ab = du * (q->winv[1] * mu);
        dpd_ou_kick(va, vb, aa, ab, ex, ey, ez);
        double J = du * mu;   /* amu Å/ps along e, +J on the anchor */
        for (int c = 0; c < 3; c++) {
            if (q->body[0] >= 0)
                imp[q->body[0]][c] += J * q->e[c];
            if (q->body[1] >= 0)
                imp[q->body[1]][c] -= J * q->e[c];
        }
        if (dpde) {
            double dE4 = du * ((unew + urel) * (mu * (0.25 * UNITS_MVV2E)));   /* eV, per side */
            sa->u -= dE4;
            sb->u -= dE4;
            if (!(sa->u > 0) || !(sb->u > 0)) {
                bad = sa->u > 0 ? sb->id : sa->id;
                badu = sa->u > 0 ? sb->u : sa->u;
            }
        }
    }
    /* every copy this rank holds (owned and ghost) takes the new values;
     * a body's particles take its velocity */
    double *u = d->ufield >= 0 ? particles_field(p, d->ufield) : NULL;
    const int ntot = p->n_owned + p->n_ghost;
    for (int i = 0; i < ntot; i++) {
        const struct slot *t = find(s, ns, p->id[i]);
        if (!t)
            continue;
        int b = dpd_body_of(d, i);
        memcpy(p->v + 3 * i, b >= 0 ? d->body[b].v : t->v, 3 * sizeof(double));
        if (u)
            u[i] = t->u;
    }
    free(s);
    free(r);
    if (bad >= 0)
        return err_set(e, ERR_DIVERGED,
                       "internal energy of particle %lld became %.3g eV at step %ld (time step "
                       "too large for the heat exchanged?)",
                       (long long)bad, badu, d->step);
    return 0;
}
