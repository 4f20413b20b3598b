/*
 * sutton_chen: the analytic Sutton-Chen many-body potential (core/sc_form.h).
 *
 * Case keys (defaults: copper, Sutton & Chen 1990): elements [Cu],
 * epsilon 1.2382e-2 eV, c 39.432, n 9, m 6, a 3.61 Å, cutoff (default 3a,
 * shifted-force truncation), masses.
 */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "core/ghost.h"
#include "core/sc_density.h"
#include "core/sc_form.h"
#include "md/potential.h"
#include "md/potential_common.h"

struct sutton_chen {
    struct potential base;
    struct sc_params sc;
    double *rho, *fp;
    int cap;
    struct thread_accum rho_acc;
    struct pair_scratch scratch;
};

static int sc_compute(struct potential *pot, struct particles *p, const struct nlist *nl, int flags,
                      struct force_result *out, struct err *e)
{
    struct sutton_chen *s = (struct sutton_chen *)pot;
    const struct sc_params *sc = &s->sc;
    int nt = pot->nthreads < 1 ? 1 : pot->nthreads;
    int ntot = p->n_owned + p->n_ghost;
    if (ntot > s->cap) {
        int cap = ntot + ntot / 4 + 64;
        double *r = realloc(s->rho, (size_t)cap * sizeof *r);
        if (r)
            s->rho = r;
        double *f = realloc(s->fp, (size_t)cap * sizeof *f);
        if (f)
            s->fp = f;
        if (!r || !f)
            return err_nomem(e, "Sutton-Chen densities");
        s->cap = cap;
    }
    int rc = thread_accum_reserve(&s->rho_acc, nt, (size_t)ntot, e);
    if (!rc)
        rc = pair_scratch_begin(&s->scratch, p, flags, nt, e);
    if (rc)
        return rc;
    const double rc2 = sc->rc * sc->rc;
    double embed = sc_density_embed(sc, p, nl, &s->rho_acc, nt, s->rho, s->fp,
                                    (flags & POT_PERATOM) ? p->pe : NULL);

    const double *fp = s->fp;
#pragma omp parallel num_threads(nt)
    {
        int tid = omp_get_thread_num();
        struct pair_target t = pair_scratch_target(&s->scratch, p, tid);
        double esum = 0, w[6] = {0};
#pragma omp for schedule(static)
        for (int i = 0; i < p->n_owned; i++) {
            const double xi = p->x[3 * i], yi = p->x[3 * i + 1], zi = p->x[3 * i + 2];
            double fxi = 0, fyi = 0, fzi = 0;
            for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
                int j = nl->neigh[k];
                double dx = xi - p->x[3 * j], dy = yi - p->x[3 * j + 1], dz = zi - p->x[3 * j + 2];
                double r2 = dx * dx + dy * dy + dz * dz;
                if (r2 >= rc2)
                    continue;
                double r = sqrt(r2), v, dv, rr, drr;
                sc_pair_terms(sc, r, &v, &dv, &rr, &drr);
                double epair = sc->eps * v;
                double dEdr = sc->eps * dv + (fp[i] + fp[j]) * drr;
                double fpair = -dEdr / r;
                fxi += dx * fpair;
                fyi += dy * fpair;
                fzi += dz * fpair;
                t.f[3 * j] -= dx * fpair;
                t.f[3 * j + 1] -= dy * fpair;
                t.f[3 * j + 2] -= dz * fpair;
                esum += epair;
                pair_tally_virial(w, dx, dy, dz, fpair);
                if (t.pe)
                    pair_tally_peratom(&t, i, j, epair, dx, dy, dz, fpair);
            }
            t.f[3 * i] += fxi;
            t.f[3 * i + 1] += fyi;
            t.f[3 * i + 2] += fzi;
        }
        pair_scratch_store_sums(&s->scratch, tid, esum, w);
    }
    pair_scratch_end(&s->scratch, p, out);
    out->energy += embed;
    return 0;
}

static void sc_destroy(struct potential *pot)
{
    struct sutton_chen *s = (struct sutton_chen *)pot;
    thread_accum_free(&s->rho_acc);
    pair_scratch_free(&s->scratch);
    free(s->rho);
    free(s->fp);
    free(s);
}

static const struct potential_ops sc_ops = {"sutton_chen", sc_compute, sc_destroy};

/* Read the Sutton-Chen parameters (shared with the coarse-grained DPD
 * potential, which takes the same keys with fitted values). */
int sc_params_read(struct cfg_obj *o, struct sc_params *sc)
{
    int rc;
    if ((rc = cfg_real(o, "epsilon", 1.2382e-2, CFG_GT(0), &sc->eps)) ||
        (rc = cfg_real(o, "c", 39.432, CFG_GT(0), &sc->c)) ||
        (rc = cfg_real(o, "n", 9.0, CFG_GT(0), &sc->n)) ||
        (rc = cfg_real(o, "m", 6.0, CFG_GT(0), &sc->m)) ||
        (rc = cfg_real(o, "a", 3.61, CFG_GT(0), &sc->a)) ||
        (rc = cfg_real(o, "cutoff", 3.0 * sc->a, CFG_GT(0), &sc->rc)))
        return rc;
    if (!(sc->n > sc->m))
        return cfg_error_at(o->cfg, o->path,
                            "the repulsive exponent n = %g must exceed the density exponent m = %g",
                            sc->n, sc->m);
    if (sc->rc < 0.8 * sc->a)
        return cfg_error_at(o->cfg, o->path, "cutoff %g Å is shorter than 0.8 a = %g Å", sc->rc,
                            0.8 * sc->a);
    sc_params_finish(sc);
    return 0;
}

int sutton_chen_create(struct cfg_obj *o, struct potential **out)
{
    struct sutton_chen *s = calloc(1, sizeof *s);
    if (!s)
        return err_nomem(o->cfg->err, "sutton_chen");
    s->base.ops = &sc_ops;
    s->base.list_kind = NLIST_HALF;
    /* a single element: default copper */
    if (!json_object_get(o->node, "elements"))
        json_object_set_new(o->node, "elements", json_pack("[s]", "Cu"));
    int rc = potential_read_elements(o, &s->base);
    if (!rc && s->base.nelements != 1)
        rc = cfg_error_at(o->cfg, o->path, "sutton_chen takes one element, found %d",
                          s->base.nelements);
    if (!rc)
        rc = sc_params_read(o, &s->sc);
    if (rc) {
        free(s);
        return rc;
    }
    s->base.cutoff = s->sc.rc;
    snprintf(s->base.description, sizeof s->base.description,
             "Sutton-Chen %g-%g, eps = %g eV, c = %g, a = %g Å, shifted-force cutoff %g Å",
             s->sc.n, s->sc.m, s->sc.eps, s->sc.c, s->sc.a, s->sc.rc);
    *out = &s->base;
    return 0;
}
