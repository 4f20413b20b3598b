/*
 * handshake_step: the coupled time step (Guo & Yang 2005, section 2.2):
 * region I -> MPM (mass, volume, position, velocity, stress), one MUSL
 * step, regions II and III -> MD (displacement coupling), one MD step, all
 * with the same dt.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "couple/handshake.h"
#include "couple/handshake_bricks.h"
#include "couple/handshake_thermal.h"

void handshake_wrap(const struct handshake *hs, double x[3])
{
    const struct box *b = &hs->md->box;
    for (int d = 0; d < 3; d++) {
        if (b->bc[d] != BOUNDARY_PERIODIC)
            continue;
        double L = b->hi[d] - b->lo[d];
        x[d] -= L * floor((x[d] - b->lo[d]) / L);
        if (x[d] >= b->hi[d])   /* round-off of the line above */
            x[d] = b->lo[d];
    }
}

/* Index lists of region I and of the copies, after any reordering. */
static int reindex_local(struct handshake *hs, struct err *e)
{
    struct particles *p = hs->md->p;
    long nI = 0, nl = 0;
    for (int i = 0; i < p->n_owned; i++) {
        nI += (p->mask[i] & HS_MASK_I) != 0;
        nl += (p->mask[i] & (HS_MASK_II | HS_MASK_III)) != 0;
    }
    if (nI != hs->nI || !hs->idxI) {
        size_t n = (size_t)(nI > 0 ? nI : 1);
        int *idx = realloc(hs->idxI, n * sizeof *idx);
        double *x = realloc(hs->xI, 3 * n * sizeof *x);
        if (idx)
            hs->idxI = idx;
        if (x)
            hs->xI = x;
        double *v = realloc(hs->vI, 3 * n * sizeof *v);
        if (v)
            hs->vI = v;
        double *mI = realloc(hs->mI, n * sizeof *mI);
        if (mI)
            hs->mI = mI;
        double *s = realloc(hs->sI, 6 * n * sizeof *s);
        if (s)
            hs->sI = s;
        double *vol = realloc(hs->volI, n * sizeof *vol);
        if (vol)
            hs->volI = vol;
        if (!idx || !x || !v || !mI || !s || !vol)
            return err_nomem(e, "handshake region I");
        hs->nI = nI;
    }
    if (nl != hs->nlink || !hs->link_md) {
        size_t n = (size_t)(nl > 0 ? nl : 1);
        int *lm = realloc(hs->link_md, n * sizeof *lm);
        if (lm)
            hs->link_md = lm;
        long *lp = realloc(hs->link_pt, n * sizeof *lp);
        if (lp)
            hs->link_pt = lp;
        double *lr = realloc(hs->link_row, HS_LINK_ROW * n * sizeof *lr);
        if (lr)
            hs->link_row = lr;
        if (!lm || !lp || !lr)
            return err_nomem(e, "handshake links");
        hs->nlink = nl;
    }
    long kI = 0, kl = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & HS_MASK_I) {
            hs->idxI[kI] = i;
            hs->mI[kI] = p->mass[p->type[i]];
            hs->volI[kI] = hs->omega0;
            kI++;
        }
        if (p->mask[i] & (HS_MASK_II | HS_MASK_III)) {
            long q = (long)(p->id[i] - hs->id_base);
            if (q < 0 || q >= hs->npoints)
                return err_set(e, ERR_RUNTIME, "handshake: copy %lld has no material point",
                               (long long)p->id[i]);
            hs->link_md[kl] = i;
            hs->link_pt[kl] = q;
            kl++;
        }
    }
    hs->seen_builds = hs->md->nrebuilds;
    hs_extra_region_i(hs, hs->nI);
    return 0;
}

void hs_extra_region_i(struct handshake *hs, long n)
{
    hs->extra.n = n;
    hs->extra.x = hs->xI;
    hs->extra.v = hs->vI;
    hs->extra.mass = hs->mI;
    hs->extra.stress = hs->sI;
    hs->extra.volume = hs->volI;
}

void handshake_point_row(const struct handshake *hs, long q, double row[HS_LINK_ROW])
{
    const struct mpm_points *pt = &hs->mpm.pts;
    double x[3] = {pt->x[3 * q], pt->x[3 * q + 1], pt->x[3 * q + 2]};
    if (hs->cr.zeta != 0) {   /* diamond: the sublattice's internal shift */
        double dx[3];
        hs_internal_shift(&hs->lay, hs->axes, hs->cr.zeta,
                          hs_sublattice(&hs->lay, hs->axes, pt->x0 + 3 * q), pt->F + 9 * q, dx);
        for (int d = 0; d < 3; d++)
            x[d] += dx[d];
    }
    handshake_wrap(hs, x);
    for (int d = 0; d < 3; d++) {
        row[d] = x[d];
        row[3 + d] = pt->v[3 * q + d];
    }
    row[6] = pt->eint[q];
}

/* The copies' rows from their points (on bricks, collective: some points
 * are on other ranks). */
static int link_rows(struct handshake *hs, struct err *e)
{
    if (hs->bricks)
        return hs_bricks_link_rows(hs, e);
    for (long k = 0; k < hs->nlink; k++)
        handshake_point_row(hs, hs->link_pt[k], hs->link_row + HS_LINK_ROW * k);
    return 0;
}

/* The lists of this rank, and the copies' rows (after a checkpoint the
 * points changed); on bricks (collective) the plan that brings the rows
 * of points held elsewhere (handshake_bricks.h). */
static int reindex(struct handshake *hs, struct err *e)
{
    int rc = reindex_local(hs, e);
    if (hs->md->halo && !(rc = halo_agree(hs->md->halo, rc, e)))
        rc = hs_bricks_index(hs, e);
    return rc ? rc : link_rows(hs, e);
}

/* Region I at the current time as material points: positions (inside the
 * grid: wrapped along periodic axes), velocities, and the potential part of
 * the virial stress over the atomic volume, so that V sigma = -W_i is the
 * atom's own virial (Chen 2014 Eq. (s3a) with the atom as the point).  The
 * kinetic part m v v is left out: the atoms' momentum reaches the nodes
 * through the mapping of their velocities (s2) already. */
void handshake_region_I_row(const struct handshake *hs, int i, double x[3], double v[3],
                            double s[6])
{
    const struct particles *p = hs->md->p;
    for (int d = 0; d < 3; d++) {
        x[d] = p->x[3 * i + d];
        v[d] = p->v[3 * i + d];
    }
    handshake_wrap(hs, x);
    handshake_atom_stress(hs, i, s);
    if (hs->thermal) {   /* at T: the thermal pressure too (handshake_thermal.h) */
        double mv = p->mass[p->type[i]] * UNITS_MVV2E / hs->omega0;
        s[0] -= mv * v[0] * v[0];
        s[1] -= mv * v[1] * v[1];
        s[2] -= mv * v[2] * v[2];
        s[3] -= mv * v[0] * v[1];
        s[4] -= mv * v[0] * v[2];
        s[5] -= mv * v[1] * v[2];
    }
}

/* Region I as this rank's extra set (on bricks the node sums over the
 * ranks add the other ranks' atoms). */
static void gather_region_I(struct handshake *hs)
{
    for (long k = 0; k < hs->nI; k++)
        handshake_region_I_row(hs, hs->idxI[k], hs->xI + 3 * k, hs->vI + 3 * k, hs->sI + 6 * k);
}

/* Regions II and III to the MD from the copies' rows: positions and (for
 * output) velocities. */
static void sync_copies(struct handshake *hs)
{
    struct particles *p = hs->md->p;
    for (long k = 0; k < hs->nlink; k++) {
        int i = hs->link_md[k];
        if (hs->thermal && (p->mask[i] & HS_MASK_II))
            continue;   /* at T region II moves by MD under the bath */
        const double *row = hs->link_row + HS_LINK_ROW * k;
        for (int d = 0; d < 3; d++) {
            p->x[3 * i + d] = row[d];
            p->v[3 * i + d] = row[3 + d];
        }
    }
}

int handshake_connect(struct handshake *hs, struct md *md, struct err *e)
{
    hs->md = md;
    md->frozen_mask |= HS_MASK_II | HS_MASK_III | HS_MASK_FIXED;
    md->peratom = 1;
    int rc = md_compute_forces(md, e);
    if (rc)
        return rc;
    /* bricks: the points were dealt out as they were built */
    if (md->halo && !hs->bricks)
        return err_set(e, ERR_RUNTIME, "handshake on bricks without its points dealt out "
                                       "(handshake_add_particles with the halo)");
    memset(&hs->extra, 0, sizeof hs->extra);
    hs->extra.name = "region I";
    hs->extra.follow_grid = 1;
    if ((rc = reindex(hs, e)))
        return rc;
    if ((rc = mpm_attach(&hs->mpm, &hs->extra, e)))
        return rc;
    gather_region_I(hs);
    sync_copies(hs);
    return hs->bricks ? hs_bricks_mpm_prepare(hs, e) : mpm_prepare(&hs->mpm, e);
}

int handshake_advance_mpm(struct handshake *hs, struct err *e)
{
    struct md *md = hs->md;
    struct mpm *m = &hs->mpm;
    int rc;
    /* the band's transfers (region I to the points, the copies to the MD)
     * are timed as coupling; the MPM step times itself */
    if (m->timers)
        timer_start(m->timers, TIMER_COUPLING);
    if (md->nrebuilds != hs->seen_builds && (rc = reindex(hs, e)))
        return rc;
    /* region I to the MPM's extra set, then the bath, which closes the
     * previous step (handshake_thermal.h): it changes region II and the
     * points, not region I */
    gather_region_I(hs);
    rc = hs->thermal ? hs_thermal_bath(hs, e) : 0;
    if (m->timers)
        timer_stop(m->timers, TIMER_COUPLING);
    if (rc)
        return rc;
    double dt = md->dt;
    m->fext_scale = hs->ramp > 0 ? fmin(1.0, (m->time + dt) / hs->ramp) : 1.0;
    if ((rc = hs->bricks ? hs_bricks_mpm_step(hs, dt, e) : mpm_step(m, dt, e)))
        return rc;
    if (m->timers)
        timer_start(m->timers, TIMER_COUPLING);
    rc = link_rows(hs, e);
    if (!rc)
        sync_copies(hs);
    if (m->timers)
        timer_stop(m->timers, TIMER_COUPLING);
    return rc;
}

void handshake_finish_step(struct handshake *hs)
{
    struct md *md = hs->md;
    if (hs->md_damping > 0) {   /* quasi-static runs: -alpha m v on the atoms */
        double f = exp(-hs->md_damping * md->dt);
        struct particles *p = md->p;
        for (int i = 0; i < p->n_owned; i++)
            if (!(p->mask[i] & md->frozen_mask))
                for (int d = 0; d < 3; d++)
                    p->v[3 * i + d] *= f;
    }
    hs->step++;
    hs->time += md->dt;
}

int handshake_step(struct handshake *hs, struct err *e)
{
    int rc = handshake_advance_mpm(hs, e);
    if (!rc)
        rc = md_step(hs->md, e);
    if (rc)
        return rc;
    handshake_finish_step(hs);
    return 0;
}

void handshake_energy(const struct handshake *hs, struct handshake_energy *out)
{
    const struct particles *p = hs->md->p;
    const uint32_t skip = HS_MASK_II | HS_MASK_III | HS_MASK_FIXED;
    double ke = 0, pe = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->mask[i] & skip)
            continue;
        const double *v = p->v + 3 * i;
        ke += p->mass[p->type[i]] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        pe += p->pe[i] - hs->cr.pe_ref;
    }
    if (hs->md->halo) {   /* bricks: each rank's atoms */
        double s[2] = {ke, pe};
        halo_sum(hs->md->halo, s, 2);
        ke = s[0];
        pe = s[1];
    }
    struct mpm_totals t;   /* bricks: over every rank's points */
    if (hs->bricks)
        hs_bricks_mpm_totals(hs, &t);
    else
        mpm_totals(&hs->mpm, &t);
    out->md_kinetic = 0.5 * ke * UNITS_MVV2E;
    out->md_potential = pe;
    out->mpm_kinetic = t.kinetic;
    out->mpm_strain = t.strain;
    out->total = out->md_kinetic + out->md_potential + out->mpm_kinetic + out->mpm_strain;
}

int handshake_apply_strain(struct handshake *hs, const double eps[3], const double origin[3],
                           struct err *e)
{
    struct md *md = hs->md;
    struct particles *p = md->p;
    const double *x0 = p->fields[hs->f_x0].data;
    /* diamond: each sublattice at its relaxed place (hs_internal_shift),
     * the atoms as the copies */
    const double Fd[9] = {1 + eps[0], 0, 0, 0, 1 + eps[1], 0, 0, 0, 1 + eps[2]};
    for (int i = 0; i < p->n_owned; i++) {
        double dx[3];
        hs_internal_shift(&hs->lay, hs->axes, hs->cr.zeta,
                          hs_sublattice(&hs->lay, hs->axes, x0 + 3 * i), Fd, dx);
        for (int d = 0; d < 3; d++)
            p->x[3 * i + d] = origin[d] + (1 + eps[d]) * (x0[3 * i + d] - origin[d]) + dx[d];
    }
    for (int d = 0; d < 3; d++)
        if (md->box.bc[d] == BOUNDARY_PERIODIC) {
            md->box.lo[d] = origin[d] + (1 + eps[d]) * (md->box.lo[d] - origin[d]);
            md->box.hi[d] = origin[d] + (1 + eps[d]) * (md->box.hi[d] - origin[d]);
        }
    struct mpm *m = &hs->mpm;
    struct mpm_points *pt = &m->pts;
    /* logarithmic strain: what the rate form integrates to along this path */
    double de[6] = {log1p(eps[0]), log1p(eps[1]), log1p(eps[2]), 0, 0, 0};
    double J = (1 + eps[0]) * (1 + eps[1]) * (1 + eps[2]);
    for (long q = 0; q < pt->n; q++) {
        const struct mpm_material *mat = m->mat[m->body[pt->body[q]].material];
        for (int d = 0; d < 3; d++)
            pt->x[3 * q + d] = origin[d] + (1 + eps[d]) * (pt->x0[3 * q + d] - origin[d]);
        double *F = pt->F + 9 * q, *s = pt->stress + 6 * q;
        memset(F, 0, 9 * sizeof *F);
        memset(s, 0, 6 * sizeof *s);
        for (int d = 0; d < 3; d++)
            F[4 * d] = 1 + eps[d];
        mat->ops->update(mat, s, de, pt->state ? pt->state + pt->nstate * q : NULL);
        pt->vol[q] = pt->vol0[q] * J;
    }
    mpm_points_moved(m);
    md->nl->nbuilds = 0;   /* the box changed: rebuild ghosts and lists */
    int rc = md_compute_forces(md, e);
    if (!rc && md->nrebuilds != hs->seen_builds)
        rc = reindex(hs, e);
    return rc;
}

int handshake_map_forces(struct handshake *hs, struct err *e)
{
    int rc;
    if (hs->md->nrebuilds != hs->seen_builds && (rc = reindex(hs, e)))
        return rc;
    gather_region_I(hs);
    if (hs->bricks)
        return hs_bricks_map_forces(hs, e);
    struct mpm *m = &hs->mpm;
    if ((rc = mpm_locate_particles(m, e)))
        return rc;
    mpm_clear_grid(m);
    mpm_map_to_grid(m, MPM_MAP_ALL);
    return 0;
}

void handshake_free(struct handshake *hs)
{
    hs_bricks_free(hs);
    mpm_free(&hs->mpm);
    free(hs->idxI);
    free(hs->xI);
    free(hs->vI);
    free(hs->mI);
    free(hs->sI);
    free(hs->volI);
    free(hs->link_md);
    free(hs->link_pt);
    free(hs->link_row);
    memset(hs, 0, sizeof *hs);
}
