/* potential_common: threaded output arrays and element lists for kernels. */
#include "md/potential_common.h"

#include <stdlib.h>
#include <string.h>

int pair_scratch_begin(struct pair_scratch *ps, struct particles *p, int flags, int nthreads,
                       struct err *e)
{
    size_t n = (size_t)(p->n_owned + p->n_ghost);
    ps->ntot = n;
    ps->nthreads = nthreads < 1 ? 1 : nthreads;
    ps->peratom = (flags & POT_PERATOM) != 0;
    memset(p->f, 0, 3 * n * sizeof(double));
    if (ps->peratom) {
        memset(p->pe, 0, n * sizeof(double));
        memset(p->virial, 0, 6 * n * sizeof(double));
    }
    int rc = thread_accum_reserve(&ps->f, ps->nthreads, 3 * n, e);
    if (!rc && ps->peratom)
        rc = thread_accum_reserve(&ps->pe, ps->nthreads, n, e);
    if (!rc && ps->peratom)
        rc = thread_accum_reserve(&ps->vir, ps->nthreads, 6 * n, e);
    return rc;
}

struct pair_target pair_scratch_target(struct pair_scratch *ps, struct particles *p, int tid)
{
    struct pair_target t = {NULL, NULL, NULL};
    t.f = thread_accum_target(&ps->f, tid, p->f, 3 * ps->ntot);
    if (ps->peratom) {
        t.pe = thread_accum_target(&ps->pe, tid, p->pe, ps->ntot);
        t.vir = thread_accum_target(&ps->vir, tid, p->virial, 6 * ps->ntot);
    }
    return t;
}

void pair_scratch_store_sums(struct pair_scratch *ps, int tid, double esum, const double w[6])
{
    ps->esum[tid] = esum;
    for (int c = 0; c < 6; c++)
        ps->w[tid][c] = w[c];
}

void pair_scratch_end(struct pair_scratch *ps, struct particles *p, struct force_result *out)
{
    thread_accum_reduce(&ps->f, p->f, 3 * ps->ntot);
    if (ps->peratom) {
        thread_accum_reduce(&ps->pe, p->pe, ps->ntot);
        thread_accum_reduce(&ps->vir, p->virial, 6 * ps->ntot);
    }
    out->energy = 0;
    memset(out->virial, 0, sizeof out->virial);
    for (int t = 0; t < ps->nthreads; t++) {
        out->energy += ps->esum[t];
        for (int c = 0; c < 6; c++)
            out->virial[c] += ps->w[t][c];
    }
}

void pair_scratch_free(struct pair_scratch *ps)
{
    thread_accum_free(&ps->f);
    thread_accum_free(&ps->pe);
    thread_accum_free(&ps->vir);
}

int potential_read_elements(struct cfg_obj *o, struct potential *base)
{
    const char *names[PARTICLES_MAX_TYPES];
    int n, rc = cfg_strings(o, "elements", 1, names, PARTICLES_MAX_TYPES, &n);
    if (rc)
        return rc;
    base->nelements = n;
    for (int k = 0; k < n; k++) {
        snprintf(base->element[k], sizeof base->element[k], "%s", names[k]);
        base->mass[k] = element_mass(names[k]);
    }
    double *m = NULL;
    size_t nm = 0;
    if ((rc = cfg_real_list(o, "masses", 0, CFG_GT(0), &m, &nm)))
        return rc;
    if (m && (int)nm != n) {
        free(m);
        return cfg_error_at(o->cfg, o->path, "masses needs one value per element (%d), got %zu", n,
                            nm);
    }
    for (size_t k = 0; k < nm; k++)
        base->mass[k] = m[k];
    free(m);
    for (int k = 0; k < n; k++)
        if (!(base->mass[k] > 0))
            return cfg_error_at(o->cfg, o->path,
                                "no standard mass known for element '%s'; give 'masses'",
                                base->element[k]);
    return 0;
}

void pair_virial_fdotr(const struct particles *p, double w[6])
{
    double s[6] = {0, 0, 0, 0, 0, 0};
    int n = p->n_owned + p->n_ghost;
    for (int i = 0; i < n; i++) {
        const double *x = p->x + 3 * i, *f = p->f + 3 * i;
        s[0] += x[0] * f[0];
        s[1] += x[1] * f[1];
        s[2] += x[2] * f[2];
        s[3] += x[0] * f[1];
        s[4] += x[0] * f[2];
        s[5] += x[1] * f[2];
    }
    for (int c = 0; c < 6; c++)
        w[c] = s[c];
}
