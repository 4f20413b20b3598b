/* structure: common neighbour analysis, coordination and surface detection. */
#include "analysis/structure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const structure_class_names[STRUCT_NCLASSES] = {
    "other12", "fcc", "hcp", "bcc", "ico", "not12", "surface", "coord4", "not4"};
const char *const structure_ref_names[] = {"fcc", "hcp", "bcc", "diamond", NULL};
const char *const cna_mode_names[] = {"fixed", "adaptive", NULL};

#define MAXN 16   /* largest neighbour set a signature is computed for */

/* r_c / a: halfway between the first two shells of the reference. */
static double cutoff_factor(enum structure_ref ref)
{
    switch (ref) {
    case STRUCT_REF_FCC: return 0.5 * (1.0 + 1.0 / M_SQRT2);
    case STRUCT_REF_HCP: return 0.5 * (1.0 + M_SQRT2);         /* a = nearest-neighbour distance */
    case STRUCT_REF_BCC: return 0.5 * (1.0 + M_SQRT2);         /* between the 2nd and 3rd shells */
    case STRUCT_REF_DIAMOND: return 0.5 * (sqrt(3.0) / 4.0 + 1.0 / M_SQRT2);
    }
    return 1.0;
}

/* R_s / a: between the 3rd and 4th shells. */
static double surface_factor(enum structure_ref ref)
{
    switch (ref) {
    case STRUCT_REF_FCC: return 0.5 * (sqrt(3.0) + 2.0) / M_SQRT2;
    case STRUCT_REF_HCP: return 0.5 * (sqrt(3.0) + 2.0);
    case STRUCT_REF_BCC: return 0.5 * (M_SQRT2 + sqrt(11.0) / 2.0);
    case STRUCT_REF_DIAMOND: return 0.5 * (sqrt(11.0) / 4.0 + 1.0);
    }
    return 1.0;
}

static int ideal_coordination(enum structure_ref ref)
{
    return ref == STRUCT_REF_DIAMOND ? 4 : ref == STRUCT_REF_BCC ? 14 : 12;
}

enum structure_class structure_ideal_class(enum structure_ref ref)
{
    switch (ref) {
    case STRUCT_REF_FCC: return STRUCT_FCC;
    case STRUCT_REF_HCP: return STRUCT_HCP;
    case STRUCT_REF_BCC: return STRUCT_BCC;
    case STRUCT_REF_DIAMOND: return STRUCT_COORD4;
    }
    return STRUCT_FCC;
}

int structure_params_resolve(struct structure_params *p, struct err *e)
{
    double k = cutoff_factor(p->ref);
    if (!(p->cutoff > 0)) {
        if (!(p->a > 0))
            return err_set(e, ERR_INPUT, "structure analysis needs a lattice constant or a cutoff");
        p->cutoff = k * p->a;
    } else if (!(p->a > 0)) {
        p->a = p->cutoff / k;
    }
    if (!(p->search_radius > 0))
        p->search_radius = 1.3 * p->cutoff;
    if (!(p->surface_radius > 0))
        p->surface_radius = surface_factor(p->ref) * p->a;
    if (!(p->surface_offset > 0))
        p->surface_offset = 0.15;
    if (p->nthreads < 1)
        p->nthreads = 1;
    return 0;
}

int structure_params_read(struct cfg_obj *o, const struct structure_params *def,
                          struct structure_params *out)
{
    *out = *def;
    int ref, mode, rc;
    if ((rc = cfg_enum(o, "reference", structure_ref_names[def->ref], structure_ref_names, &ref)) ||
        (rc = cfg_enum(o, "method", cna_mode_names[def->mode], cna_mode_names, &mode)) ||
        (rc = cfg_real(o, "lattice_constant", def->a, CFG_GE(0), &out->a)) ||
        (rc = cfg_real(o, "cutoff", def->cutoff, CFG_GE(0), &out->cutoff)) ||
        (rc = cfg_real(o, "surface_offset", def->surface_offset > 0 ? def->surface_offset : 0.15,
                       CFG_RANGE(0.01, 0.5), &out->surface_offset)))
        return rc;
    out->ref = (enum structure_ref)ref;
    out->mode = (enum cna_mode)mode;
    out->search_radius = 0;
    out->surface_radius = 0;
    if (!(out->a > 0) && !(out->cutoff > 0))
        return cfg_error_at(o->cfg, o->path,
                            "give 'lattice_constant' or 'cutoff' for the structure analysis");
    return structure_params_resolve(out, o->cfg->err);
}

static inline int popcount(uint32_t v) { return __builtin_popcount(v); }

/* Bonds among the m entries of `ent` (bitmask per entry) within rc2.  The
 * owned positions and shifts are gathered once; each distance is the
 * canonical one of frame_vec, so the bond between two neighbours is the
 * neighbour relation they have between themselves, bit for bit. */
static void bond_masks(const struct frame *f, const int *ent, int m, double rc2, uint32_t *bond)
{
    double xo[MAXN][3];
    int sh[MAXN][3];
    for (int a = 0; a < m; a++) {
        int o = f->origin[ent[a]];
        for (int k = 0; k < 3; k++) {
            xo[a][k] = f->x[3 * o + k];
            sh[a][k] = f->shift[3 * ent[a] + k];
        }
        bond[a] = 0;
    }
    for (int a = 0; a < m; a++)
        for (int b = a + 1; b < m; b++) {
            double r2 = 0;
            for (int k = 0; k < 3; k++) {
                double d = (xo[b][k] - xo[a][k]) + (double)(sh[b][k] - sh[a][k]) * f->len[k];
                r2 += d * d;
            }
            if (r2 < rc2) {
                bond[a] |= 1u << b;
                bond[b] |= 1u << a;
            }
        }
}

/* Bonds in the largest connected group of bonds among `set`. */
static int longest_chain(const uint32_t *bond, uint32_t set)
{
    uint32_t left = set;
    int best = 0;
    while (left) {
        int seed = __builtin_ctz(left);
        uint32_t comp = 1u << seed, frontier = comp;
        while (frontier) {
            int k = __builtin_ctz(frontier);
            frontier &= frontier - 1;
            uint32_t nw = bond[k] & set & ~comp;
            comp |= nw;
            frontier |= nw;
        }
        left &= ~comp;
        int edges = 0;
        for (uint32_t c = comp; c; c &= c - 1)
            edges += popcount(bond[__builtin_ctz(c)] & comp);
        edges /= 2;
        if (edges > best)
            best = edges;
    }
    return best;
}

/* Signature counts of the m neighbours: n421, n422, n555, n666, n444. */
struct sig_counts {
    int s421, s422, s555, s666, s444;
};

static struct sig_counts signatures(const uint32_t *bond, int m)
{
    struct sig_counts s = {0, 0, 0, 0, 0};
    for (int j = 0; j < m; j++) {
        uint32_t common = bond[j];
        int ncn = popcount(common), nb = 0;
        for (uint32_t c = common; c; c &= c - 1)
            nb += popcount(bond[__builtin_ctz(c)] & common);
        nb /= 2;
        int lcb = longest_chain(bond, common);
        if (ncn == 4 && nb == 2 && lcb == 1) s.s421++;
        else if (ncn == 4 && nb == 2 && lcb == 2) s.s422++;
        else if (ncn == 5 && nb == 5 && lcb == 5) s.s555++;
        else if (ncn == 6 && nb == 6 && lcb == 6) s.s666++;
        else if (ncn == 4 && nb == 4 && lcb == 4) s.s444++;
    }
    return s;
}

/* fcc / hcp / ico for 12 neighbours, bcc for 14, else -1. */
static int match_pattern(const struct frame *f, const int *ent, int m, double rc2)
{
    uint32_t bond[MAXN];
    bond_masks(f, ent, m, rc2, bond);
    struct sig_counts s = signatures(bond, m);
    if (m == 12) {
        if (s.s421 == 12) return STRUCT_FCC;
        if (s.s421 == 6 && s.s422 == 6) return STRUCT_HCP;
        if (s.s555 == 12) return STRUCT_ICO;
    } else if (m == 14) {
        if (s.s666 == 8 && s.s444 == 6) return STRUCT_BCC;
    }
    return -1;
}

struct centroid {
    double sum[3];
    const struct frame *f;
    int i, n;
};

static void centroid_cb(void *ctx, int entry, double r2)
{
    (void)r2;
    struct centroid *c = ctx;
    double d[3];
    frame_vec(c->f, c->i, entry, d);
    for (int k = 0; k < 3; k++)
        c->sum[k] += d[k];
    c->n++;
}

static int is_surface(const struct structure_params *p, const struct frame *f, int i)
{
    struct centroid c = {{0, 0, 0}, f, i, 0};
    frame_query(f, i, p->surface_radius, centroid_cb, &c);
    if (c.n == 0)
        return 1;
    double off = sqrt(c.sum[0] * c.sum[0] + c.sum[1] * c.sum[1] + c.sum[2] * c.sum[2]) / c.n;
    return off > p->surface_offset * p->surface_radius;
}

/* The squared distance of entry k of i's list: from r2 for the first
 * LIST_R2_KEPT, recomputed beyond (the same bits: frame.h). */
#define LIST_R2_KEPT 14

static double list_r2(const struct frame *f, int i, const int *nb, const double *r2, int k)
{
    return k < LIST_R2_KEPT ? r2[k] : frame_dist2(f, i, nb[k]);
}

static int classify_one(const struct structure_params *p, const struct frame *f, int i)
{
    const int *nb = f->nbr + f->offset[i];
    int m = f->offset[i + 1] - f->offset[i];
    /* the squared distances of the first 14 (the most any rule below
     * reads; the coordination counts go on with list_r2) */
    double r2[LIST_R2_KEPT];
    for (int k = 0; k < m && k < LIST_R2_KEPT; k++)
        r2[k] = frame_dist2(f, i, nb[k]);
    int ncoord, cls = -1;
    if (p->ref == STRUCT_REF_DIAMOND) {
        double rc2 = p->cutoff * p->cutoff;
        if (p->mode == CNA_ADAPTIVE && m >= 1) {
            /* local cutoff from the first-shell distances among the 4
             * nearest: those within the cutoff ratio of the nearest one,
             * so that an under-coordinated atom does not stretch its
             * cutoff into the second shell */
            double k_rc = cutoff_factor(STRUCT_REF_DIAMOND) / (sqrt(3.0) / 4.0);
            double r1 = sqrt(r2[0]), mean = 0;
            int nm = 0;
            for (int k = 0; k < 4 && k < m; k++)
                if (sqrt(r2[k]) < k_rc * r1) {
                    mean += sqrt(r2[k]);
                    nm++;
                }
            double rc = k_rc * mean / nm;
            rc2 = rc * rc;
        }
        ncoord = 0;
        while (ncoord < m && list_r2(f, i, nb, r2, ncoord) < rc2)
            ncoord++;
        if (ncoord == 4)
            return STRUCT_COORD4;
        cls = STRUCT_NOT4;
    } else if (p->mode == CNA_FIXED) {
        ncoord = m;   /* the list radius is the cutoff */
        double rc2 = p->cutoff * p->cutoff;
        if (m == 12 || m == 14)
            cls = match_pattern(f, nb, m, rc2);
        if (cls >= 0)
            return cls;
        cls = m == 12 ? STRUCT_OTHER12 : STRUCT_NOT12;
    } else {
        double rc2 = p->cutoff * p->cutoff;
        if (m >= 12) {
            double mean = 0;
            for (int k = 0; k < 12; k++)
                mean += sqrt(r2[k]);
            double rc = 0.5 * (1.0 + M_SQRT2) * mean / 12.0;   /* Stukowski 2012, Eq. (3) */
            rc2 = rc * rc;
            cls = match_pattern(f, nb, 12, rc2);
            if (cls >= 0)
                return cls;
        }
        if (m >= 14) {
            double m1 = 0, m2 = 0;
            for (int k = 0; k < 8; k++)
                m1 += sqrt(r2[k]);
            for (int k = 8; k < 14; k++)
                m2 += sqrt(r2[k]);
            double rc = 0.5 * (1.0 + M_SQRT2) * 0.5 * (2.0 / sqrt(3.0) * m1 / 8.0 + m2 / 6.0);
            cls = match_pattern(f, nb, 14, rc * rc);   /* Stukowski 2012, Eq. (4) */
            if (cls >= 0)
                return cls;
        }
        ncoord = 0;
        while (ncoord < m && list_r2(f, i, nb, r2, ncoord) < rc2)
            ncoord++;
        cls = ncoord == 12 ? STRUCT_OTHER12 : STRUCT_NOT12;
    }
    if (ncoord < ideal_coordination(p->ref) && is_surface(p, f, i))
        return STRUCT_SURFACE;
    return cls;
}

int structure_classify(const struct structure_params *p, const double *x, int n,
                       const struct box *b, struct frame *f, int *cls, struct err *e)
{
    double radius = p->mode == CNA_ADAPTIVE ? p->search_radius : p->cutoff;
    int rc = frame_build(f, x, n, b, radius, structure_range(p), p->nthreads, e);
    if (rc)
        return rc;
#pragma omp parallel for num_threads(p->nthreads) schedule(dynamic, 256)
    for (int i = 0; i < n; i++)
        cls[i] = classify_one(p, f, i);
    return 0;
}

double structure_range(const struct structure_params *p)
{
    double radius = p->mode == CNA_ADAPTIVE ? p->search_radius : p->cutoff;
    return radius > p->surface_radius ? radius : p->surface_radius;
}

int structure_classify_particles(const struct structure_params *p, const struct particles *ps,
                                 const struct box *b, struct frame *f, int *cls, struct err *e)
{
    return structure_classify(p, ps->x, ps->n_owned, b, f, cls, e);
}

long structure_count(const int *cls, int n, const unsigned char *sel, long counts[STRUCT_NCLASSES])
{
    long total = 0;
    memset(counts, 0, STRUCT_NCLASSES * sizeof(long));
    for (int i = 0; i < n; i++) {
        if (sel && !sel[i])
            continue;
        if (cls[i] >= 0 && cls[i] < STRUCT_NCLASSES)
            counts[cls[i]]++;
        total++;
    }
    return total;
}
