/* mpm: set-up of an MPM run -- materials, bodies, extra sets, observables. */
#include "mpm/mpm.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_view.h"

int mpm_init(struct mpm *m, struct mpm_grid *grid, int nstate, int nthreads, struct err *e)
{
    memset(m, 0, sizeof *m);
    m->grid = *grid;
    memset(grid, 0, sizeof *grid);
    m->algorithm = MPM_MUSL;
    m->small_mass_rel = 1e-12;
    m->fext_scale = 1.0;
    m->sort_every = 50;
    m->fuse = 1;
    m->fused_map_share = -1;
    m->nthreads = nthreads > 0 ? nthreads : 1;
    for (int s = 0; s <= MPM_MAX_EXTRA; s++)
        m->bins[s].blk_step = -1;
    return mpm_points_init(&m->pts, nstate, e);
}

static void bins_free(struct mpm_bins *b)
{
    free(b->blk);
    free(b->order);
    free(b->cell);
    free(b->start);
    free(b->count);
    memset(b, 0, sizeof *b);
    b->blk_step = -1;
}

void mpm_free(struct mpm *m)
{
    mpm_grid_free(&m->grid);
    mpm_points_free(&m->pts);
    for (int i = 0; i < m->nmat; i++)
        mpm_material_destroy(&m->mat[i]);
    for (int s = 0; s <= MPM_MAX_EXTRA; s++)
        bins_free(&m->bins[s]);
    free(m->scratch);
    memset(m, 0, sizeof *m);
}

int mpm_add_material(struct mpm *m, struct mpm_material *mat, struct err *e)
{
    if (m->nmat >= MPM_MAX_MATERIALS) {
        mpm_material_destroy(&mat);
        err_set(e, ERR_INPUT, "at most %d materials", MPM_MAX_MATERIALS);
        return -1;
    }
    if (mat->ops->nstate > m->pts.nstate) {
        mpm_material_destroy(&mat);
        err_set(e, ERR_RUNTIME, "material needs %d state variables, points have %d",
                mat->ops->nstate, m->pts.nstate);
        return -1;
    }
    m->mat[m->nmat] = mat;
    return m->nmat++;
}

int mpm_add_body(struct mpm *m, const struct mpm_body *b, struct err *e)
{
    if (m->nbody >= MPM_MAX_BODIES) {
        err_set(e, ERR_INPUT, "at most %d bodies", MPM_MAX_BODIES);
        return -1;
    }
    if (b->material < 0 || b->material >= m->nmat) {
        err_set(e, ERR_RUNTIME, "body '%s': no material %d", b->name, b->material);
        return -1;
    }
    m->body[m->nbody] = *b;
    return m->nbody++;
}

int mpm_prepare(struct mpm *m, struct err *e)
{
    double mmin = INFINITY;
    for (long p = 0; p < m->pts.n; p++)
        if (m->pts.mass[p] < mmin)
            mmin = m->pts.mass[p];
    if (!(mmin > 0) && m->pts.n > 0)
        return err_set(e, ERR_INPUT, "material points need a positive mass");
    m->small_mass = m->pts.n > 0 ? m->small_mass_rel * mmin : 0.0;
    m->cmax = 0;
    for (int i = 0; i < m->nmat; i++) {
        double c = m->mat[i]->ops->wave_speed(m->mat[i]);
        if (c > m->cmax)
            m->cmax = c;
    }
    for (int b = 0; b < m->nbody; b++)
        m->body[b].npoints = 0;
    double v2 = 0;
    for (long p = 0; p < m->pts.n; p++) {
        const double *v = m->pts.v + 3 * p;
        double s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (s > v2)
            v2 = s;
        m->body[m->pts.body[p]].npoints++;
    }
    m->vmax = sqrt(v2);
    mpm_points_moved(m);
    struct mpm_totals t;
    mpm_totals(m, &t);
    m->ke = t.kinetic;
    m->strain = m->strain_before = t.strain;
    m->ke_centred = t.kinetic;
    if (m->scratch_cap < m->pts.n) {
        free(m->scratch);
        m->scratch = malloc((size_t)(m->pts.n > 0 ? m->pts.n : 1) * sizeof *m->scratch);
        if (!m->scratch)
            return err_nomem(e, "reorder scratch");
        m->scratch_cap = m->pts.n;
    }
    return 0;
}

int mpm_attach(struct mpm *m, struct mpm_extra *x, struct err *e)
{
    if (m->nextra >= MPM_MAX_EXTRA)
        return err_set(e, ERR_RUNTIME, "at most %d extra particle sets", MPM_MAX_EXTRA);
    m->extra[m->nextra++] = x;
    return 0;
}

void mpm_detach(struct mpm *m, struct mpm_extra *x)
{
    for (int i = 0; i < m->nextra; i++) {
        if (m->extra[i] != x)
            continue;
        for (int j = i; j + 1 < m->nextra; j++)
            m->extra[j] = m->extra[j + 1];
        m->nextra--;
        bins_free(&m->bins[m->nextra + 1]);
        return;
    }
}

int mpm_views(struct mpm *m, struct mpm_view *views)
{
    struct mpm_view *w = &views[0];
    memset(w, 0, sizeof *w);
    w->n = m->pts.n;
    w->x = m->pts.x;
    w->v = m->pts.v;
    w->mass = m->pts.mass;
    w->stress = m->pts.stress;
    w->vol = m->pts.vol;
    w->force = m->pts.fext;
    w->fscale = m->fext_scale;
    w->body = m->pts.body;
    w->follow = 1;
    w->bins = &m->bins[0];
    for (int i = 0; i < m->nextra; i++) {
        const struct mpm_extra *x = m->extra[i];
        w = &views[1 + i];
        memset(w, 0, sizeof *w);
        w->n = x->n;
        w->x = x->x;
        w->v = x->v;
        w->mass = x->mass;
        w->type = x->type;
        w->type_mass = x->type_mass;
        w->stress = x->stress;
        w->vol = x->volume;
        w->force = x->force;
        w->fscale = 1.0;
        for (int d = 0; d < 3; d++)
            w->lp[d] = x->lp[d] > 0 ? x->lp[d] : 0.25;
        w->follow = x->follow_grid;
        w->bins = &m->bins[1 + i];
    }
    return 1 + m->nextra;
}

int mpm_fusable(const struct mpm *m)
{
    return m->fuse && m->grid.kind == MPM_GRID_UNIFORM && m->grid.shape == MPM_SHAPE_LINEAR &&
           m->nextra == 0 && !m->pts.fext;
}

double mpm_stable_dt(const struct mpm *m)
{
    double c = m->cmax + m->vmax;
    return c > 0 ? mpm_grid_min_cell(&m->grid) / c : INFINITY;
}

void mpm_totals(const struct mpm *m, struct mpm_totals *t)
{
    const struct mpm_points *p = &m->pts;
    double mass = 0, px = 0, py = 0, pz = 0, ke = 0, se = 0, v2max = 0;
    long n = p->n;
#pragma omp parallel for schedule(static) num_threads(m->nthreads) \
    reduction(+ : mass, px, py, pz, ke, se) reduction(max : v2max)
    for (long i = 0; i < n; i++) {
        const double *v = p->v + 3 * i;
        double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        mass += p->mass[i];
        px += p->mass[i] * v[0];
        py += p->mass[i] * v[1];
        pz += p->mass[i] * v[2];
        ke += 0.5 * p->mass[i] * v2;
        se += p->eint[i];
        if (v2 > v2max)
            v2max = v2;
    }
    t->mass = mass;
    t->momentum[0] = px;
    t->momentum[1] = py;
    t->momentum[2] = pz;
    t->kinetic = ke * UNITS_MVV2E;
    t->strain = se;
    t->vmax = sqrt(v2max);
}

double mpm_grid_mass(const struct mpm *m)
{
    double s = 0;
    for (long i = 0; i < m->grid.nnodes; i++)
        s += m->grid.node[i].m;
    return s;
}
