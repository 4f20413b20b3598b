/*
 * mpm_case_read: the `mpm` section of a case file, and building the model.
 *
 *   type: mpm
 *   mpm:
 *     units: metal | si            unit system of every key below (mpm_units.h)
 *     grid:
 *       origin: [0, 0, 0]
 *       cell: h                    edge of the (finest) cubic cell
 *       cells: [nx, ny, nz]        number of (finest) cells
 *       max_nodes: 5e7             bound on the finest grid's nodes, checked
 *                                  before anything is allocated (memory, not
 *                                  physics: not written into the case)
 *       shape: linear | gimp       shape functions (gimp: uniform grids only)
 *       levels:                    hierarchical grid (Guo & Yang 2005), up to 5:
 *         - {coarsen: xyz, region: {...}}   level l where regions 1..l contain
 *       hanging: modified | standard        Eq. (11) (default) or Eq. (9)
 *       faces: {x_lo: free, x_hi: free, y_lo: ..., z_hi: ...}  free | fixed | sliding
 *     materials:                   list; see mpm/mpm_material.h
 *       - {name: al, law: linear_elastic, density: 2700, E: 70e9, nu: 0.3}
 *     bodies:
 *       - name: A
 *         material: al
 *         region: {shape: box, lo: [...], hi: [...]}   (box, sphere, cylinder)
 *         points_per_cell: 2       n: n x n x n points per cell
 *     max_points: 2e7              bound on the material points of all bodies
 *                                  (from the regions' bounding boxes, before
 *                                  they are filled; not written into the case)
 *         velocity: [0, 0, 0]      initial, or prescribed when rigid
 *         rigid: false             moves at `velocity`, imposes it on its nodes
 *     loads:                       tractions on boundary layers of points
 *       - {region: {...}, normal: x, traction: [tx, ty, tz]}
 *     load_ramp: 0                 time to reach the full traction (0: step load)
 *     algorithm: musl | usl
 *     small_mass: 1e-12            nodes lighter than this fraction of the lightest
 *                                  point are skipped (Chen 2014)
 *     damping: 0                   nodal velocity damping (1/time)
 *     steps: 1000
 *     timestep: 0                  fixed step; 0: from the CFL condition
 *     cfl: 0.5                     safety factor on h / (c + |v|max)
 *     adaptive: true               recompute the CFL step every step
 *     sort_every: 50               steps between reorders of the points
 *     fuse: true                   fuse the next step's mapping into the update
 *                                  pass where possible (same results to round-off)
 *     report_steps: []             steps whose kinetic energy becomes a metric
 *     probes: [{name: p1, region: {...}}]   mean stress/displacement series
 *     output_grid: true            grid fields in the HDF5 snapshots
 *     max_energy_change: 1.0       relative change of the total energy that
 *                                  counts as divergence, for closed systems (no
 *                                  rigid body, load, damping or fixed/sliding
 *                                  face); 0: no check
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpm/mpm_bricks.h"
#include "mpm/mpm_build.h"
#include "mpm/mpm_hgrid.h"
#include "scenarios/mpm_case.h"

static void region_scale(struct region *r, double f)
{
    for (int d = 0; d < 3; d++) {
        r->lo[d] *= f;
        r->hi[d] *= f;
        r->center[d] *= f;
    }
    r->radius *= f;
}

static int read_region(struct cfg_obj *o, const char *key, const struct mpm_units *u,
                       struct region *r)
{
    struct cfg_obj ro;
    int rc = cfg_section_required(o, key, &ro);
    if (!rc)
        rc = region_read(&ro, r);
    if (!rc)
        region_scale(r, u->length);
    return rc;
}

static int parse_coarsen(struct cfg_obj *o, unsigned *mask)
{
    static const char *const names[] = {"x", "y", "z", "xy", "xz", "yz", "xyz", NULL};
    static const unsigned bits[] = {1, 2, 4, 3, 5, 6, 7};
    int k, rc = cfg_enum(o, "coarsen", "xyz", names, &k);
    if (!rc)
        *mask = bits[k];
    return rc;
}

/* Default memory bounds: a grid of 5e7 nodes takes a few GB with its
 * nodal fields, 2e7 points about as much; both are far above the paper's
 * runs (0.5 M points) and far below what a typo in `cells` asks for. */
#define MPM_MAX_NODES_DEFAULT 50000000L
#define MPM_MAX_POINTS_DEFAULT 20000000L
#define MPM_MAX_CAP 4000000000L

struct grid_spec {
    double origin[3], h;
    long cells[3];
    int shape, hanging, nlevels;
    struct mpm_hlevel level[MPM_MAX_LEVELS];
    enum mpm_face_bc face[6];
    long max_points;          /* mpm.max_points, checked by build() */
    int max_points_given;
};

static int read_grid(struct cfg_obj *mo, const struct mpm_units *u, struct grid_spec *g)
{
    static const char *const shapes[] = {"linear", "gimp", NULL};
    static const char *const hang[] = {"modified", "standard", NULL};
    static const char *const bcs[] = {"free", "fixed", "sliding", NULL};
    static const char *const face_keys[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
    static const double zero[3] = {0, 0, 0};
    struct cfg_obj go, fo;
    int rc;
    if ((rc = cfg_section_required(mo, "grid", &go)) ||
        (rc = cfg_reals(&go, "origin", 3, zero, CFG_ANY, g->origin)) ||
        (rc = cfg_real(&go, "cell", CFG_REQUIRED, CFG_GT(0), &g->h)) ||
        (rc = cfg_ints(&go, "cells", 3, NULL, CFG_RANGE(1, 1 << 20), g->cells)) ||
        (rc = cfg_enum(&go, "shape", "linear", shapes, &g->shape)) ||
        (rc = cfg_enum(&go, "hanging", "modified", hang, &g->hanging)))
        return rc;
    long max_nodes = MPM_MAX_NODES_DEFAULT;
    int given;
    if ((rc = cfg_int_opt(&go, "max_nodes", CFG_RANGE(1, MPM_MAX_CAP), &max_nodes, &given)))
        return rc;
    double nodes = (double)(g->cells[0] + 1) * (double)(g->cells[1] + 1) * (double)(g->cells[2] + 1);
    if (nodes > (double)max_nodes)
        return mpm_key_error(&go, "cells",
                             "%ld x %ld x %ld cells make %.4g grid nodes, more than "
                             "%s.max_nodes = %ld%s",
                             g->cells[0], g->cells[1], g->cells[2], nodes, go.path, max_nodes,
                             given ? "" : " (the default; set it to allow more)");
    for (int d = 0; d < 3; d++)
        g->origin[d] *= u->length;
    g->h *= u->length;
    size_t nl = 0;
    if ((rc = cfg_list(&go, "levels", 0, &nl)))
        return rc;
    if (nl > MPM_MAX_LEVELS)
        return mpm_key_error(&go, "levels", "%zu levels given, at most %d", nl, MPM_MAX_LEVELS);
    g->nlevels = (int)nl;
    for (size_t i = 0; i < nl; i++) {
        struct cfg_obj lo;
        if ((rc = cfg_list_item(&go, "levels", i, &lo)) ||
            (rc = parse_coarsen(&lo, &g->level[i].coarsen)) ||
            (rc = read_region(&lo, "region", u, &g->level[i].region)) || (rc = cfg_close(&lo)))
            return rc;
    }
    if (nl > 0 && g->shape == 1)
        return mpm_key_error(&go, "shape", "GIMP needs a uniform grid (no levels)");
    if ((rc = cfg_section(&go, "faces", &fo)))
        return rc;
    for (int f = 0; f < 6; f++) {
        int k;
        if ((rc = cfg_enum(&fo, face_keys[f], "free", bcs, &k)))
            return rc;
        g->face[f] = (enum mpm_face_bc)k;
    }
    if ((rc = cfg_close(&fo)))
        return rc;
    return cfg_close(&go);
}

struct body_spec {
    struct mpm_body b;
    struct region region;
    long ppc;
    char path[CFG_PATH_MAX];
};

struct load_spec {
    struct region region;
    int normal;
    double traction[3];   /* eV/Å^3 */
    char path[CFG_PATH_MAX];
};

void mpm_case_free(struct mpm_case *c)
{
    if (!c)
        return;
    mpm_free(&c->m);
    mpm_bricks_destroy(&c->bricks);
    free(c->out.buf);
    free(c->out.ibuf);
    free(c->out.series);
    free(c->restored_rows);
    free(c);
}

/* Distribute each traction over the point layers of its region:
 * f_p = t V_p / (k l), k layers of spacing l, so the layers carry t x area.
 * On bricks the layers' extent and count are taken over every rank's
 * points; the spacing is that of the last body with points in the region,
 * as in a serial run, where the bodies' points come in body order. */
static int apply_loads(struct mpm_case *c, const struct load_spec *ls, int nloads, struct cfg *cfg)
{
    struct mpm *m = &c->m;
    struct mpm_points *p = &m->pts;
    for (int k = 0; k < nloads; k++) {
        const struct load_spec *L = &ls[k];
        int a = L->normal;
        double ext[3] = {INFINITY, -INFINITY, -1};   /* -lo, hi, last body */
        double cnt = 0;
        for (long i = 0; i < p->n; i++) {
            if (!region_contains(&L->region, p->x + 3 * i) || m->body[p->body[i]].rigid)
                continue;
            double xa = p->x[3 * i + a];
            ext[0] = fmin(ext[0], xa);
            ext[1] = fmax(ext[1], xa);
            ext[2] = fmax(ext[2], (double)p->body[i]);
            cnt++;
        }
        ext[0] = -ext[0];
        mpm_bricks_max(c->bricks, ext, 3);
        mpm_bricks_sum(c->bricks, &cnt, 1);
        if (cnt == 0)
            return cfg_error_at(cfg, L->path, "load region holds no deformable material point");
        if (mpm_bricks_agree(c->bricks, mpm_points_enable_fext(p, cfg->err), cfg->err))
            return ERR_RUNTIME;
        double lo = -ext[0], hi = ext[1];
        double spacing = 2.0 * m->body[(int)ext[2]].lp[a] * m->grid.h;   /* cell / n */
        double layers = floor((hi - lo) / spacing + 0.5) + 1.0;
        for (long i = 0; i < p->n; i++) {
            if (!region_contains(&L->region, p->x + 3 * i) || m->body[p->body[i]].rigid)
                continue;
            double area = p->vol0[i] / (layers * spacing);
            for (int d = 0; d < 3; d++)
                p->fext[3 * i + d] += L->traction[d] * area;
        }
    }
    return 0;
}

static int check_time_step(struct mpm_case *c, struct cfg *cfg)
{
    struct mpm *m = &c->m;
    double stable = mpm_stable_dt(m);
    const struct mpm_units *u = &c->u;
    if (c->dt_fixed > 0 && c->dt_fixed > stable)
        return cfg_error_at(cfg, "mpm.timestep",
                            "time step %g %s is unstable: the explicit limit h / (c + |v|max) is "
                            "%g %s (cell %g %s, wave speed %g %s, largest speed %g %s)",
                            c->dt_fixed / u->time, u->time_name, stable / u->time, u->time_name,
                            mpm_grid_min_cell(&m->grid) / u->length, u->length_name,
                            m->cmax / u->velocity, u->velocity_name, m->vmax / u->velocity,
                            u->velocity_name);
    return 0;
}

/* What the first pass over a body's points finds (every rank visits every
 * point of the case, so every rank finds the same). */
struct body_scan {
    const struct mpm_case *c;
    const struct body_spec *bs;
    int body;                    /* the body whose points are visited */
    int overlap;                 /* the first earlier body holding one of its points, or -1 */
    double at[3];                /* that point */
    struct mpm_bricks_hist *hist;   /* the bricks' balance, or NULL */
};

static int scan_point(void *ctx, const double x[3], double vol)
{
    struct body_scan *s = ctx;
    (void)vol;
    for (int o = 0; o < s->body && s->overlap < 0; o++)
        if (region_contains(&s->bs[o].region, x)) {
            s->overlap = o;
            memcpy(s->at, x, sizeof s->at);
        }
    if (s->hist)
        mpm_bricks_hist_add(s->c->bricks, &s->c->m.grid, s->hist, x);
    return 0;
}

/* The bodies' material points in two passes.  The first visits every point
 * of every body, on every rank: the counts and the checks (the bound on the
 * points, a body without points, bodies that overlap) and, for shifted
 * bricks, the points along each axis, from which the cuts are set.  The
 * second makes the points, each rank only its brick's, with the ids of a
 * serial run (the place of a point in the case's order). */
static int make_bodies(struct mpm_case *c, const struct grid_spec *gs, struct body_spec *bs,
                       int nbody, struct mpm_bricks_hist *hist, struct cfg *cfg)
{
    struct err *e = cfg->err;
    struct mpm *m = &c->m;
    const struct mpm_units *u = &c->u;
    double glo[3], ghi[3];
    mpm_grid_bounds(&m->grid, glo, ghi);
    long first[MPM_MAX_BODIES + 1];
    int idx[MPM_MAX_BODIES];
    long total = 0;
    for (int b = 0; b < nbody; b++) {
        struct body_spec *B = &bs[b];
        char rpath[CFG_PATH_MAX + 8];
        snprintf(rpath, sizeof rpath, "%s.region", B->path);
        double rlo[3], rhi[3];
        region_bounds(&B->region, rlo, rhi);
        for (int d = 0; d < 3; d++) {
            if (!isfinite(rlo[d]) || !isfinite(rhi[d]))
                return cfg_error_at(cfg, rpath,
                                    "body '%s': its region must be bounded (box, sphere or "
                                    "cylinder, side: in)",
                                    B->b.name);
            if (rlo[d] < glo[d] - 1e-9 * gs->h || rhi[d] > ghi[d] + 1e-9 * gs->h)
                return cfg_error_at(cfg, rpath,
                                    "body '%s' has points outside the grid: its region spans "
                                    "%c = [%g, %g] %s but the grid spans [%g, %g] %s",
                                    B->b.name, "xyz"[d], rlo[d] / u->length, rhi[d] / u->length,
                                    u->length_name, glo[d] / u->length, ghi[d] / u->length,
                                    u->length_name);
        }
        if ((idx[b] = mpm_add_body(m, &B->b, e)) < 0)
            return ERR_RUNTIME;
        first[b] = total;
        /* on a uniform grid the region's bounding box bounds the points it
         * can get; refuse before visiting them (hierarchical grids put fewer
         * points in coarse cells: checked after the visit) */
        double upto = (double)total;
        if (gs->nlevels == 0) {
            double cells = 1;
            for (int d = 0; d < 3; d++)
                cells *= ceil((rhi[d] - rlo[d]) / gs->h) + 1;
            upto += cells * (double)(B->ppc * B->ppc * B->ppc);
        }
        struct body_scan scan = {c, bs, b, -1, {0, 0, 0}, hist};
        long added = 0;
        if (upto <= (double)gs->max_points) {
            mpm_region_visit(m, &B->region, (int)B->ppc, scan_point, &scan, &added);
            upto = (double)(total + added);
        }
        if (upto > (double)gs->max_points)
            return cfg_error_at(cfg, rpath,
                                "body '%s' brings the material points to up to %.4g, more than "
                                "mpm.max_points = %ld%s",
                                B->b.name, upto, gs->max_points,
                                gs->max_points_given ? "" : " (the default; set it to allow more)");
        if (added == 0)
            return cfg_error_at(cfg, rpath,
                                "body '%s' has no material point: its region holds no point of "
                                "the %ld^3 per cell",
                                B->b.name, B->ppc);
        if (scan.overlap >= 0)
            return cfg_error_at(cfg, rpath,
                                "body '%s' overlaps body '%s' (both contain the point "
                                "%g %g %g %s)",
                                B->b.name, bs[scan.overlap].b.name, scan.at[0] / u->length,
                                scan.at[1] / u->length, scan.at[2] / u->length, u->length_name);
        total += added;
    }
    first[nbody] = total;
    c->npoints_total = total;
    struct mpm_bricks_owner mine = {c->bricks, &m->grid};
    struct mpm_fill_owner keep;
    if (c->bricks) {
        if (hist)
            mpm_bricks_shift_cuts(c->bricks, hist);
        keep = mpm_bricks_fill_owner(&mine);
    }
    int rc = 0;
    for (int b = 0; b < nbody && !rc; b++) {
        long added, kept;
        rc = mpm_fill_region(m, &bs[b].region, idx[b], (int)bs[b].ppc,
                             c->bricks ? &keep : NULL, (int64_t)first[b] + 1, &added, &kept, e);
        if (!rc && added != first[b + 1] - first[b])
            rc = err_set(e, ERR_RUNTIME, "body '%s': %ld points made, %ld counted", bs[b].b.name,
                         added, first[b + 1] - first[b]);
    }
    return mpm_bricks_agree(c->bricks, rc, e);
}

static int build(struct mpm_case *c, const struct case_common *common, const struct grid_spec *gs,
                 struct mpm_material **mats, int nmat, struct body_spec *bs, int nbody,
                 const struct load_spec *ls, int nloads, struct cfg *cfg)
{
    struct err *e = cfg->err;
    struct mpm_grid grid;
    int rc;
    if (gs->nlevels > 0) {
        struct mpm_hgrid *hg;
        rc = mpm_hgrid_build(&hg, gs->origin, gs->h, gs->cells, gs->level, gs->nlevels,
                             (enum mpm_hanging)gs->hanging, e);
        if (rc)
            return rc == ERR_INPUT ? cfg_error_at(cfg, "mpm.grid.levels", "%s", e->msg) : rc;
        rc = mpm_grid_init_hier(&grid, hg, e);
    } else {
        rc = mpm_grid_init_uniform(&grid, gs->origin, gs->h, gs->cells,
                                   (enum mpm_shape_kind)gs->shape, e);
    }
    if (!rc)
        rc = mpm_grid_set_faces(&grid, gs->face, e);
    if (rc) {
        mpm_grid_free(&grid);
        return rc;
    }
    int nstate = 0;
    for (int i = 0; i < nmat; i++)
        if (mats[i]->ops->nstate > nstate)
            nstate = mats[i]->ops->nstate;
    struct mpm *m = &c->m;
    if ((rc = mpm_init(m, &grid, nstate, common->nthreads, e)))
        return rc;
    for (int i = 0; i < nmat; i++) {
        struct mpm_material *mat = mats[i];
        mats[i] = NULL;   /* owned by m from here, even on failure */
        if (mpm_add_material(m, mat, e) < 0)
            return ERR_RUNTIME;
    }
    /* under mpirun: the grid's bricks, planned before the points are made
     * so that each rank stores only its own (docs/parallel.md) */
    if ((rc = mpm_bricks_plan(common->par, &common->parallel, &m->grid, gs->nlevels > 0, cfg,
                              &c->bricks)))
        return rc;
    struct mpm_bricks_hist hist = {{NULL, NULL, NULL}, 0};
    if (c->bricks && c->bricks->shift && (rc = mpm_bricks_hist_init(c->bricks, &hist, e)))
        return rc;
    rc = make_bodies(c, gs, bs, nbody, c->bricks && c->bricks->shift ? &hist : NULL, cfg);
    mpm_bricks_hist_free(&hist);
    if (rc)
        return rc;
    if ((rc = apply_loads(c, ls, nloads, cfg)))
        return rc;
    if ((rc = mpm_bricks_agree(c->bricks, mpm_prepare(m, e), e)))
        return rc;
    mpm_bricks_max(c->bricks, &m->vmax, 1);   /* the fastest point of every rank */
    return check_time_step(c, cfg);
}

int mpm_case_read(struct cfg_obj *root, const struct case_common *common, struct mpm_case **out)
{
    static const char *const unit_names[] = {"metal", "si", NULL};
    static const char *const algos[] = {"musl", "usl", NULL};
    static const char *const axes[] = {"x", "y", "z", NULL};
    static const double zero[3] = {0, 0, 0};
    struct cfg *cfg = root->cfg;
    struct cfg_obj mo;
    int rc, usys;
    *out = NULL;
    if ((rc = cfg_section_required(root, "mpm", &mo)) ||
        (rc = cfg_enum(&mo, "units", "metal", unit_names, &usys)))
        return rc;
    struct mpm_case *c = calloc(1, sizeof *c);
    struct grid_spec *gs = calloc(1, sizeof *gs);
    struct body_spec *bs = calloc(MPM_MAX_BODIES, sizeof *bs);
    struct load_spec *ls = NULL;
    struct mpm_material *mats[MPM_MAX_MATERIALS] = {0};
    int nmat = 0, nbody = 0, nloads = 0;
    if (!c || !gs || !bs) {
        rc = err_nomem(cfg->err, "mpm case");
        goto done;
    }
    mpm_units_init(&c->u, (enum mpm_unit_system)usys);
    const struct mpm_units *u = &c->u;
    if ((rc = read_grid(&mo, u, gs)))
        goto done;
    /* materials */
    size_t n;
    if ((rc = cfg_list(&mo, "materials", 1, &n)))
        goto done;
    if (n > MPM_MAX_MATERIALS) {
        rc = mpm_key_error(&mo, "materials", "%zu materials, at most %d", n, MPM_MAX_MATERIALS);
        goto done;
    }
    const char *mat_names[MPM_MAX_MATERIALS];
    for (size_t i = 0; i < n; i++) {
        struct cfg_obj o;
        if ((rc = cfg_list_item(&mo, "materials", i, &o)) ||
            (rc = mpm_material_create(&o, u, &mats[nmat])))
            goto done;
        const char *nm = NULL;
        cfg_string(&o, "name", NULL, &nm);   /* already validated */
        for (int k = 0; k < nmat; k++)
            if (strcmp(mat_names[k], nm) == 0) {
                rc = mpm_key_error(&o, "name", "material '%s' is defined twice", nm);
                goto done;
            }
        mat_names[nmat++] = nm;
    }
    /* bodies */
    if ((rc = cfg_list(&mo, "bodies", 1, &n)))
        goto done;
    if (n > MPM_MAX_BODIES) {
        rc = mpm_key_error(&mo, "bodies", "%zu bodies, at most %d", n, MPM_MAX_BODIES);
        goto done;
    }
    for (size_t i = 0; i < n; i++) {
        struct cfg_obj o;
        struct body_spec *B = &bs[nbody];
        const char *name, *mat;
        int rigid;
        if ((rc = cfg_list_item(&mo, "bodies", i, &o)) ||
            (rc = cfg_string(&o, "name", NULL, &name)) ||
            (rc = cfg_string(&o, "material", NULL, &mat)) ||
            (rc = read_region(&o, "region", u, &B->region)) ||
            (rc = cfg_int(&o, "points_per_cell", 2, CFG_RANGE(1, 8), &B->ppc)) ||
            (rc = cfg_reals(&o, "velocity", 3, zero, CFG_ANY, B->b.velocity)) ||
            (rc = cfg_bool(&o, "rigid", 0, &rigid)) || (rc = cfg_close(&o)))
            goto done;
        snprintf(B->path, sizeof B->path, "%s", o.path);
        if (strlen(name) == 0 || strlen(name) >= sizeof B->b.name) {
            rc = mpm_key_error(&o, "name", "body name must have 1 to 31 characters");
            goto done;
        }
        snprintf(B->b.name, sizeof B->b.name, "%s", name);
        B->b.rigid = rigid;
        B->b.material = -1;
        for (int k = 0; k < nmat; k++)
            if (strcmp(mat_names[k], mat) == 0)
                B->b.material = k;
        if (B->b.material < 0) {
            rc = mpm_key_error(&o, "material", "no material named '%s' in mpm.materials", mat);
            goto done;
        }
        for (int k = 0; k < nbody; k++)
            if (strcmp(bs[k].b.name, name) == 0) {
                rc = mpm_key_error(&o, "name", "body '%s' is defined twice", name);
                goto done;
            }
        for (int d = 0; d < 3; d++)
            B->b.velocity[d] *= u->velocity;
        nbody++;
    }
    gs->max_points = MPM_MAX_POINTS_DEFAULT;
    if ((rc = cfg_int_opt(&mo, "max_points", CFG_RANGE(1, MPM_MAX_CAP), &gs->max_points,
                          &gs->max_points_given)))
        goto done;
    /* loads */
    if ((rc = cfg_list(&mo, "loads", 0, &n)))
        goto done;
    ls = calloc(n > 0 ? n : 1, sizeof *ls);
    if (!ls) {
        rc = err_nomem(cfg->err, "mpm loads");
        goto done;
    }
    for (size_t i = 0; i < n; i++) {
        struct cfg_obj o;
        struct load_spec *L = &ls[nloads];
        if ((rc = cfg_list_item(&mo, "loads", i, &o)) ||
            (rc = read_region(&o, "region", u, &L->region)) ||
            (rc = cfg_enum(&o, "normal", NULL, axes, &L->normal)) ||
            (rc = cfg_reals(&o, "traction", 3, NULL, CFG_ANY, L->traction)) ||
            (rc = cfg_close(&o)))
            goto done;
        snprintf(L->path, sizeof L->path, "%s.region", o.path);
        for (int d = 0; d < 3; d++)
            L->traction[d] *= u->stress;
        nloads++;
    }
    /* integration */
    int algo, adaptive, output_grid, fuse;
    long sort_every;
    double small, damping, ramp, dt, cfl, max_de;
    if ((rc = cfg_real(&mo, "load_ramp", 0.0, CFG_GE(0), &ramp)) ||
        (rc = cfg_enum(&mo, "algorithm", "musl", algos, &algo)) ||
        (rc = cfg_real(&mo, "small_mass", 1e-12, CFG_RANGE(0, 0.5), &small)) ||
        (rc = cfg_real(&mo, "damping", 0.0, CFG_GE(0), &damping)) ||
        (rc = cfg_int(&mo, "steps", 1000, CFG_GE(0), &c->steps)) ||
        (rc = cfg_real(&mo, "timestep", 0.0, CFG_GE(0), &dt)) ||
        (rc = cfg_real(&mo, "cfl", 0.5, ((struct cfg_bound){0, 1, 1, 0}), &cfl)) ||
        (rc = cfg_bool(&mo, "adaptive", 1, &adaptive)) ||
        (rc = cfg_int(&mo, "sort_every", 50, CFG_GE(0), &sort_every)) ||
        (rc = cfg_bool(&mo, "output_grid", 1, &output_grid)) ||
        (rc = cfg_bool(&mo, "fuse", 1, &fuse)) ||
        (rc = cfg_real(&mo, "max_energy_change", 1.0, CFG_GE(0), &max_de)))
        goto done;
    double *rs = NULL;
    size_t nrs = 0;
    if ((rc = cfg_real_list(&mo, "report_steps", 0, CFG_GE(0), &rs, &nrs)))
        goto done;
    if (nrs > MPM_CASE_MAX_REPORT) {
        free(rs);
        rc = mpm_key_error(&mo, "report_steps", "at most %d report steps", MPM_CASE_MAX_REPORT);
        goto done;
    }
    for (size_t i = 0; i < nrs; i++) {
        /* bounded before the cast: a double beyond long's range is undefined
         * behaviour to convert (found by the case fuzzer) */
        if (rs[i] != floor(rs[i]) || rs[i] > 1e15) {
            free(rs);
            rc = mpm_key_error(&mo, "report_steps", "steps must be integers from 0 to 1e15");
            goto done;
        }
        c->report_steps[c->nreport++] = (long)rs[i];
    }
    free(rs);
    if ((rc = cfg_list(&mo, "probes", 0, &n)))
        goto done;
    if (n > MPM_CASE_MAX_PROBES) {
        rc = mpm_key_error(&mo, "probes", "at most %d probes", MPM_CASE_MAX_PROBES);
        goto done;
    }
    for (size_t i = 0; i < n; i++) {
        struct cfg_obj o;
        const char *name;
        struct mpm_probe *P = &c->probe[c->nprobes];
        if ((rc = cfg_list_item(&mo, "probes", i, &o)) ||
            (rc = cfg_string(&o, "name", NULL, &name)) ||
            (rc = read_region(&o, "region", u, &P->region)) || (rc = cfg_close(&o)))
            goto done;
        snprintf(P->name, sizeof P->name, "%s", name);
        c->nprobes++;
    }
    if ((rc = cfg_close(&mo)))
        goto done;
    c->dt_fixed = dt * u->time;
    c->cfl = cfl;
    c->adaptive = adaptive;
    c->load_ramp = ramp * u->time;
    c->output_grid = output_grid;
    c->energy_tolerance = max_de;
    if (cfg->shallow)
        goto done;
    rc = build(c, common, gs, mats, nmat, bs, nbody, ls, nloads, cfg);
    if (!rc) {
        c->m.algorithm = algo == 0 ? MPM_MUSL : MPM_USL;
        c->m.small_mass_rel = small;
        c->m.damping = damping / u->time;
        c->m.sort_every = (int)sort_every;
        c->m.fuse = fuse;
        rc = mpm_bricks_agree(c->bricks, mpm_prepare(&c->m, cfg->err), cfg->err);
    }
    /* under mpirun: the grid patch of each rank's brick (docs/parallel.md) */
    if (!rc && c->bricks)
        rc = mpm_bricks_distribute(c->bricks, &c->m, cfg->err);
    if (!rc && c->bricks)
        rc = mpm_bricks_prepare(c->bricks, &c->m, cfg->err);
    if (!rc && c->bricks && common->parallel.balance_every > 0)
        mpm_bricks_balance_schedule(c->bricks, common->parallel.balance_every,
                                    common->parallel.balance_threshold);
    if (!rc) {
        *out = c;
        c = NULL;
    }
done:
    for (int i = 0; i < nmat; i++)
        mpm_material_destroy(&mats[i]);
    free(gs);
    free(bs);
    free(ls);
    mpm_case_free(c);
    return rc;
}
