/* dpd_impact_setup: the impact section, the flyer, particle copies. */
#include "scenarios/dpd_impact_setup.h"

#include <math.h>
#include <string.h>

#include "core/halo.h"
#include "core/lattice.h"
#include "core/region.h"

int dpd_impact_keys_read(struct cfg_obj *root, struct dpd_impact_keys *k)
{
    static const char *const axes[] = {"x", "y", "z", NULL};
    static const char *const motions[] = {"free", "prescribed", NULL};
    static const double regions[2] = {100.0, 150.0};
    struct cfg_obj o;
    double thick;
    int rc;
    memset(k, 0, sizeof *k);
    if ((rc = cfg_section(root, "impact", &o)) ||
        (rc = cfg_enum(&o, "axis", "x", axes, &k->axis)) ||
        (rc = cfg_real(&o, "flyer_thickness", 15.0, CFG_GT(0), &k->thickness)) ||
        (rc = cfg_real(&o, "flyer_velocity", 5.0, CFG_ANY, &k->velocity)) ||
        (rc = cfg_enum(&o, "flyer_motion", "free", motions, &k->motion)) ||
        (rc = cfg_real(&o, "lattice_constant", 0.0, CFG_GE(0), &k->a)) ||
        (rc = cfg_real(&o, "gap", 0.0, CFG_GE(0), &k->gap)) ||
        (rc = cfg_reals(&o, "regions", 2, regions, CFG_GT(0), k->regions)) ||
        (rc = cfg_real(&o, "region_thickness", 6.0, CFG_GT(0), &thick)) ||
        (rc = cfg_real(&o, "arrival_threshold", 0.01, CFG_GT(0), &k->threshold)) ||
        (rc = cfg_bool(&o, "reference", 1, &k->reference)) ||
        (rc = cfg_int(&o, "sample_every", 1, CFG_GE(1), &k->sample_every)) ||
        (rc = cfg_real_list(&o, "profile_times", 0, CFG_GE(0), &k->ptimes, &k->nptimes)) ||
        (rc = cfg_real(&o, "profile_bin", 0.0, CFG_GE(0), &k->bin)) || (rc = cfg_close(&o)))
        return rc;
    k->half = 0.5 * thick;
    if (!(k->regions[1] > k->regions[0]))
        return cfg_error_at(o.cfg, "impact.regions",
                            "the second region (%g Å) must lie beyond the first (%g Å)",
                            k->regions[1], k->regions[0]);
    return 0;
}

/* Append the flyer: (100) planes of an fcc lattice continuing the target's
 * stacking below its impact face, across the target's cross-section. */
/* Bricks: a flyer site is this rank's when its place after the gap shift
 * lies in the brick. */
struct flyer_keep {
    const struct decomp *dc;
    int axis;
    double gap;
};

static int flyer_in_brick(const void *ctx, const double x[3])
{
    const struct flyer_keep *f = ctx;
    double y[3] = {x[0], x[1], x[2]};
    y[f->axis] -= f->gap;
    return decomp_owns(f->dc, y);
}

int dpd_impact_add_flyer(struct particles *p, const struct dpd_bar *bar,
                         const struct dpd_impact_keys *k, double a, long *nadded, struct err *e)
{
    return dpd_impact_add_flyer_over(p, bar, k, a, NULL, nadded, e);
}

int dpd_impact_add_flyer_over(struct particles *p, const struct dpd_bar *bar,
                              const struct dpd_impact_keys *k, double a, const struct halo *h,
                              long *nadded, struct err *e)
{
    const int ax = k->axis, t1 = (ax + 1) % 3, t2 = (ax + 2) % 3;
    const double dpl = 0.5 * a, tol = 0.25 * dpl;
    long nplanes = lround(k->thickness / dpl);
    if (nplanes < 1)
        nplanes = 1;
    long ncell = (nplanes + 1) / 2 + 1;
    struct lattice lat = {LATTICE_FCC, a, {0, 0, 0}, {{0}}};
    long cells[3];
    lat.origin[ax] = bar->face_lo[ax] - ncell * a;
    cells[ax] = ncell;
    struct region box;
    memset(&box, 0, sizeof box);
    box.shape = REGION_BOX;
    box.lo[ax] = bar->face_lo[ax] - nplanes * dpl - tol;
    box.hi[ax] = bar->face_lo[ax] - dpl + tol;
    /* Stacking: a (100) plane holds the sites whose two transverse
     * coordinates, in half cells from the lattice origin, add up to an even
     * (A) or odd (B) number.  The flyer's plane next to the face must be of
     * the other kind, so find the face plane's kind from its particle
     * nearest the transverse corner. */
    int best = -1;
    double bestd = INFINITY;
    for (int i = 0; i < p->n_owned; i++) {
        if (p->x[3 * i + ax] > bar->face_lo[ax] + 0.5 * dpl)
            continue;
        double dd = p->x[3 * i + t1] - bar->face_lo[t1] + p->x[3 * i + t2] - bar->face_lo[t2];
        if (dd < bestd) {
            bestd = dd;
            best = i;
        }
    }
    long parity = 0;
    if (best >= 0)
        parity = lround((p->x[3 * best + t1] - bar->face_lo[t1]) / dpl) +
                 lround((p->x[3 * best + t2] - bar->face_lo[t2]) / dpl);
    if (h) {   /* the particle nearest the corner over every rank: the lowest distance wins */
        double near[2] = {-bestd, 0};
        halo_max(h, near, 1);
        near[1] = best >= 0 && -bestd == near[0] ? (double)(parity & 1) : -1.0;
        halo_max(h, near + 1, 1);
        parity = near[1] > 0 ? 1 : 0;
    }
    for (int q = 0; q < 2; q++) {
        int t = q ? t2 : t1;
        /* one spare cell on each side; the region keeps the cross-section */
        lat.origin[t] = bar->face_lo[t] - a + (q == 0 && (parity & 1) ? dpl : 0.0);
        cells[t] = lround((bar->face_hi[t] - bar->face_lo[t]) / a) + 3;
        box.lo[t] = bar->face_lo[t] - tol;
        box.hi[t] = bar->face_hi[t] + tol;
    }
    int64_t next_id = 1;
    for (int i = 0; i < p->n_owned; i++)
        if (p->id[i] >= next_id)
            next_id = p->id[i] + 1;
    if (h) {   /* after the largest id of every rank */
        double top = (double)next_id;
        halo_max(h, &top, 1);
        next_id = (int64_t)top;
    }
    int n0 = p->n_owned;
    struct flyer_keep keep = {h ? &h->dc : NULL, ax, k->gap};
    long added = lattice_fill_where(&lat, cells, &box, h ? flyer_in_brick : NULL, &keep, p, 0,
                                    &next_id, e);
    if (added < 0)
        return ERR_RUNTIME;
    for (int i = n0; i < p->n_owned; i++) {
        p->mask[i] |= DPD_FLYER_BIT;
        p->x[3 * i + ax] -= k->gap;
    }
    *nadded = added;
    return 0;
}

/* A copy of the owned particles (positions, velocities, types, ids, masks). */
struct particles *dpd_particles_clone(const struct particles *p, struct err *e)
{
    struct particles *q = particles_create(p->n_owned > 0 ? p->n_owned : 1);
    if (!q) {
        err_nomem(e, "reference particles");
        return NULL;
    }
    for (int t = 0; t < p->ntypes; t++)
        particles_type_index(q, p->type_name[t], p->mass[t]);
    for (int i = 0; i < p->n_owned; i++) {
        int k = particles_add(q, p->x + 3 * i, p->v + 3 * i, p->type[i], p->id[i]);
        if (k < 0) {
            particles_destroy(&q);
            err_nomem(e, "reference particles");
            return NULL;
        }
        q->mask[k] = p->mask[i];
        for (int c = 0; c < 3; c++)
            q->image[3 * k + c] = p->image[3 * i + c];
    }
    return q;
}
