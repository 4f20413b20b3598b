/* handshake_case: common sections, the bar model and the outputs of the
 * MPM/MD handshake case types (see handshake_case.h). */
#include "scenarios/handshake_case.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "core/halo.h"
#include "core/parallel.h"
#include "md/md_bricks.h"
#include "output/decomp_record.h"
#include "scenarios/handshake_record.h"
#include "mpm/mpm_hgrid.h"
#include "md/md_settings.h"
#include "md/md_timestep.h"

static const char *const coarsen_names[] = {"x", "y", "xy", "z", "xz", "yz", "xyz", NULL};

int hs_case_read(struct cfg_obj *root, struct hs_case *c)
{
    struct cfg_obj o;
    int rc;
    const char *element;
    int lattice = HS_LATTICE_FCC;
    long orient = 100;
    c->cfg = root->cfg;
    if ((rc = cfg_section_required(root, "crystal", &o)) ||
        (rc = cfg_enum(&o, "lattice", "fcc", hs_lattice_names, &lattice)) ||
        (rc = cfg_int(&o, "orientation", 100, CFG_ANY, &orient)) ||
        (rc = cfg_string(&o, "element", "Cu", &element)) ||
        (rc = cfg_real(&o, "a_min", CFG_REQUIRED, CFG_GT(0), &c->a_min)) ||
        (rc = cfg_real(&o, "a_max", CFG_REQUIRED, CFG_GT(0), &c->a_max)) || (rc = cfg_close(&o)))
        return rc;
    snprintf(c->element, sizeof c->element, "%s", element);
    c->lattice = (enum hs_lattice)lattice;
    if (orient != 100 && orient != 110)
        return cfg_error_at(root->cfg, "crystal.orientation",
                            "orientation %ld: 100 (cube axes along x, y, z) or 110 (x along "
                            "[110], y along [-110], z along [001])",
                            orient);
    c->orient = orient == 110 ? HS_ORIENT_110 : HS_ORIENT_100;
    if (!(c->a_max > c->a_min))
        return cfg_error_at(root->cfg, "crystal.a_max", "a_max = %g must exceed a_min = %g",
                            c->a_max, c->a_min);
    if ((rc = cfg_section_required(root, "potential", &o)) || (rc = potential_create(&o, &c->pot)))
        return rc;
    if ((rc = cfg_section(root, "elastic", &o)) ||
        (rc = cfg_real(&o, "c11", 0, CFG_GE(0), &c->c_user[0])) ||
        (rc = cfg_real(&o, "c12", 0, CFG_GE(0), &c->c_user[1])) ||
        (rc = cfg_real(&o, "c44", 0, CFG_GE(0), &c->c_user[2])) ||
        (rc = cfg_real(&o, "c11_scale", 1, CFG_GT(0), &c->c11_scale)) || (rc = cfg_close(&o)))
        return rc;
    int given = (c->c_user[0] > 0) + (c->c_user[1] > 0) + (c->c_user[2] > 0);
    if (given != 0 && given != 3)
        return cfg_error_at(root->cfg, "elastic",
                            "give all of c11, c12, c44 or none (none: from the potential at 0 K)");
    double regions_def[3] = {c->regions[0], c->regions[1], c->regions[2]};
    int ci = 6;
    for (int k = 0; coarsen_names[k]; k++)
        if ((unsigned)(k + 1) == (unsigned)c->coarsen)
            ci = k;
    if ((rc = cfg_section(root, "handshake", &o)) ||
        (rc = cfg_reals(&o, "regions", 3, regions_def, CFG_GT(0), c->regions)) ||
        (rc = cfg_real(&o, "cell", c->cell, CFG_GT(0), &c->cell)) ||
        (rc = cfg_real(&o, "fine", c->fine, CFG_GE(0), &c->fine)) ||
        (rc = cfg_int(&o, "levels", c->levels, CFG_RANGE(0, MPM_MAX_LEVELS), &c->levels)) ||
        (rc = cfg_enum(&o, "coarsen", coarsen_names[ci], coarsen_names, &ci)) ||
        (rc = cfg_real(&o, "layer", c->layer, CFG_GT(0), &c->layer)) || (rc = cfg_close(&o)))
        return rc;
    c->coarsen = ci + 1;
    /* the shared md reader; each handshake case type declares its own
     * defaults (time step, steps, skin) in c before this */
    struct md_settings def = md_settings_defaults, ms;
    def.timestep = c->dt;
    def.steps = c->steps;
    def.skin = c->skin;
    if ((rc = md_settings_read(root, MD_KEY_TIMESTEP | MD_KEY_STEPS | MD_KEY_SKIN, &def, &ms)))
        return rc;
    c->dt = ms.timestep;
    c->steps = ms.steps;
    c->skin = ms.skin;
    if ((rc = cfg_section(root, "profile", &o)) ||
        (rc = cfg_real(&o, "slab", c->slab, CFG_GT(0), &c->slab)) ||
        (rc = cfg_int(&o, "every", c->profile_every, CFG_GE(1), &c->profile_every)) ||
        (rc = cfg_close(&o)))
        return rc;
    double mpm_def[2] = {c->bar_mpm[0], c->bar_mpm[1]};
    if ((rc = cfg_section(root, "bar", &o)) ||
        (rc = cfg_reals(&o, "mpm", 2, mpm_def, CFG_GE(0), c->bar_mpm)) ||
        (rc = cfg_real(&o, "md", c->bar_md, CFG_GT(0), &c->bar_md)) ||
        (rc = cfg_real(&o, "width", c->bar_width, CFG_GT(0), &c->bar_width)) ||
        (rc = cfg_close(&o)))
        return rc;
    return 0;
}

double hs_case_wave_speed(const struct hs_case *c, double cl)
{
    return sqrt(cl / c->hs.rho * UNITS_FTM2V);
}

/* Whether the bar runs on bricks (*halo, new) or not (NULL): under mpirun
 * with bricks asked for or chosen (`parallel`, md_bricks_plan: refusals
 * name the case file, line and key). */
static int plan_bricks(const struct case_common *common, const struct handshake_layout *L,
                       double range, struct cfg *cfg, struct halo **halo)
{
    *halo = NULL;
    if (!common->par || !common->par->mpi)
        return 0;
    struct box box;
    handshake_md_box(L, &box);
    return md_bricks_plan(common->par, &common->parallel, &box, range, cfg, halo);
}

int hs_case_build(struct hs_case *c, enum mpm_face_bc x_hi_face, int end_margin,
                  const struct case_common *common)
{
    const int nthreads = common->nthreads;
    struct cfg *cfg = c->cfg;
    struct err *e = cfg->err;
    double a;
    int rc = handshake_crystal_of_lattice(c->pot, c->lattice, c->element, c->a_min, c->a_max,
                                          &c->md_cr, &a, e);
    if (rc)
        return cfg_error_at(cfg, "crystal", "%s", e->msg);
    if (c->a_given > 0)
        a = c->a_given;
    c->a = a;
    struct handshake_crystal cr = c->md_cr;
    /* at a given a (an MD region at T): diamond's copies of region III
     * take the internal shift of the crystal at that a */
    if (c->a_given > 0 &&
        (rc = handshake_crystal_zeta_at(c->pot, c->lattice, &c->md_cr, a, &cr.zeta, e)))
        return cfg_error_at(cfg, "crystal", "%s", e->msg);
    if (c->c_user[0] > 0) {
        cr.c11 = c->c_user[0] / UNITS_EVA3_TO_GPA;
        cr.c12 = c->c_user[1] / UNITS_EVA3_TO_GPA;
        cr.c44 = c->c_user[2] / UNITS_EVA3_TO_GPA;
    }
    cr.c11 *= c->c11_scale;   /* Guo & Yang Fig. 5: C11 of the MPM doubled */
    struct handshake_layout L;
    memset(&L, 0, sizeof L);
    L.lattice = c->lattice;
    L.orient = c->orient;
    L.a = a;
    /* lengths in edges of the oriented cell along each axis (a along [100]) */
    handshake_layout_period(&L, c->unit);
    const double *u = c->unit;
    double cxy;
    hs_oriented_moduli(c->orient, cr.c11, cr.c12, cr.c44, &c->cl, &cxy, &c->cxz);
    hs_oriented_moduli(c->orient, c->md_cr.c11, c->md_cr.c12, c->md_cr.c44, &c->cl_md, &cxy,
                       &c->cxz_md);
    double len = c->bar_mpm[0] + c->bar_md + c->bar_mpm[1];
    /* empty cells beyond a loaded end, room to stretch: one coarsest cell */
    double margin = 0;
    if (end_margin) {
        margin = c->cell;
        if (c->coarsen & 1)
            for (long l = 0; l < c->levels; l++)
                margin *= 2;
    }
    for (int d = 0; d < 3; d++) {
        L.lat_origin[d] = hs_cell_offset(c->lattice, c->orient, d) * u[d];
        L.dom_lo[d] = L.mat_lo[d] = 0;
        L.mat_hi[d] = (d == 0 ? len : c->bar_width) * u[d];
        L.dom_hi[d] = (d == 0 ? len + margin : c->bar_width) * u[d];
        L.md_lo[d] = d == 0 ? c->bar_mpm[0] * u[d] : 0;
        L.md_hi[d] = d == 0 ? (c->bar_mpm[0] + c->bar_md) * u[d] : c->bar_width * u[d];
        L.md_periodic[d] = d != 0;
        L.w[d] = c->regions[d] * u[0];   /* across the x interfaces */
    }
    L.h = c->cell * u[0];
    L.fine = c->fine * u[0];
    L.nlevels = (int)c->levels;
    L.coarsen = (unsigned)c->coarsen;
    L.layer = c->layer * u[0];
    for (int f = 0; f < 6; f++)
        L.face[f] = MPM_FACE_SLIDING;
    L.face[1] = x_hi_face;
    enum hs_layout_key key;
    char why[512];
    static const char *const key_path[HS_KEY_COUNT] = {
        "handshake.regions", "handshake.cell", "handshake.fine",
        "handshake.levels",  "handshake.layer", "bar.mpm",       "bar.md"};
    if (handshake_layout_check(&L, c->pot->cutoff, &key, why, sizeof why))
        return cfg_error_at(cfg, key_path[key], "%s", why);
    struct halo *halo = NULL;
    if ((rc = plan_bricks(common, &L, c->pot->cutoff + c->skin, cfg, &halo)))
        return rc;
    struct potential *pot = c->pot;
    c->pot = NULL;   /* the md owns it from here, even on failure */
    rc = halo ? handshake_setup_bricks(&c->hs, &c->md, &L, &cr, pot, c->dt, c->skin, nthreads,
                                       halo, common->parallel.balance == BALANCE_SHIFT, e)
              : handshake_setup(&c->hs, &c->md, &L, &cr, pot, c->dt, c->skin, nthreads, e);
    c->built = 1;
    if (rc)
        return rc;
    /* moved again during the run when asked: the copies follow the atoms,
     * the points stay where they were dealt (couple/handshake_bricks.h) */
    if (halo && common->parallel.balance_every > 0)
        halo_balance_schedule(c->md.halo, common->parallel.balance_every,
                              common->parallel.balance_threshold, 0);
    if ((rc = md_check_timestep(&c->md, cfg, "md.timestep")))
        return rc;
    return hs_profile_init(&c->prof, &c->hs, 0, c->slab * u[0], e);
}

void hs_case_free(struct hs_case *c)
{
    if (c->built) {
        handshake_free(&c->hs);
        md_free(&c->md);
    }
    potential_destroy(&c->pot);
    hs_profile_free(&c->prof);
    wfile_discard(&c->profile_w);   /* a run that did not end well: no profile.csv */
    c->profile_csv = NULL;
    free(c->ibuf);
    free(c->dbuf);
    free(c->thermo);
    free(c->profile);
}

void hs_case_destroy(void *state)
{
    if (!state)
        return;
    hs_case_free(state);   /* the first member: same address */
    free(state);
}

long hs_case_particles(const void *state)
{
    const struct hs_case *c = state;
    /* on bricks md_natoms counts every rank's atoms and copies, npoints
     * every rank's points */
    return c ? md_natoms(&c->md) + c->hs.npoints : 0;
}

long hs_case_steps(const void *state)
{
    const struct hs_case *c = state;
    return c ? c->steps : 0;
}

/* --- loads ------------------------------------------------------------------ */

/* A traction t (eV/Å^3, along +x) on the points of the last cell layer at
 * the x_hi end: f_p = t V_p / l with l the layer's thickness, so that the
 * layer carries t x cross-section (Guo & Yang: "forces on boundary are
 * applied on material points along [100]"). */
int hs_apply_end_traction(struct handshake *hs, double t, struct err *e)
{
    struct mpm *m = &hs->mpm;
    struct mpm_points *pt = &m->pts;
    const double xe = hs->lay.mat_hi[0];
    /* the thickness of the end layer: x extent of the cell holding a point
     * next to the end */
    double lo[3], hi[3], thick = 0;
    mpm_grid_bounds(&m->grid, lo, hi);
    double xmax = -INFINITY;
    for (long q = 0; q < pt->n; q++)
        xmax = fmax(xmax, pt->x0[3 * q]);
    if (hs->md->halo)   /* bricks: over every rank's points (collective) */
        halo_max(hs->md->halo, &xmax, 1);
    double cell = m->grid.h;
    if (m->grid.kind == MPM_GRID_HIER) {
        double probe[3] = {xmax, 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
        long k = mpm_hgrid_find(m->grid.hg, probe);
        if (k >= 0)
            cell = (double)(1L << m->grid.hg->cell[k].lg[0]) * m->grid.h;
    }
    thick = cell;
    int rc = mpm_points_enable_fext(pt, e);
    if (rc)
        return rc;
    long n = 0;
    for (long q = 0; q < pt->n; q++) {
        if (pt->x0[3 * q] < xe - thick)
            continue;
        pt->fext[3 * q] = t * pt->vol0[q] / thick;
        n++;
    }
    if (hs->md->halo) {   /* bricks: the loaded points of every rank */
        double nall = (double)n;
        halo_sum(hs->md->halo, &nall, 1);
        n = (long)nall;
    }
    if (n == 0)
        return err_set(e, ERR_RUNTIME, "no material point at the loaded end");
    mpm_points_moved(m);
    return 0;
}

/* --- the run on the engine ---------------------------------------------------- */

int hs_case_run(struct hs_case *c, struct run *run, const struct sim_case_ops *ops, void *state,
                struct err *e)
{
    c->md.timers = &run->timers;
    c->hs.mpm.timers = &run->timers;
    c->model = (struct handshake_model){.hs = &c->hs};
    struct sim s;
    sim_init(&s, run, c->steps, c->md.dt);
    s.case_ops = ops;
    s.case_state = state;
    int rc = sim_add_model(&s, &sim_model_handshake, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

/* Append a row of n values to a table of n-value rows. */
static int keep_row(double **rows, long *nrows, long *cap, const double *row, int n,
                    struct err *e)
{
    if (*nrows >= *cap) {
        long nc = *cap ? 2 * *cap : 256;
        double *r = realloc(*rows, (size_t)nc * n * sizeof *r);
        if (!r)
            return err_nomem(e, "handshake output rows");
        *rows = r;
        *cap = nc;
    }
    memcpy(*rows + *nrows * n, row, (size_t)n * sizeof *row);
    (*nrows)++;
    return 0;
}

int hs_case_checkpoint_write(const struct hs_case *c, struct ckpt *ck)
{
    int rc = ckpt_put_long(ck, "thermo_columns", c->ncols);
    if (!rc) rc = ckpt_put_doubles(ck, "thermo_rows", c->thermo, c->nthermo * c->ncols);
    if (!rc) rc = ckpt_put_doubles(ck, "profile_rows", c->profile, c->nprofile * HS_PROFILE_COLS);
    return rc;
}

/* A stored table of rows of n values into *rows (replacing it). */
static int get_rows(struct ckpt *ck, const char *name, int n, double **rows, long *nrows,
                    long *cap, struct err *e)
{
    (void)e;   /* ckpt_get_rows reports through the checkpoint's err */
    int rc = ckpt_get_rows(ck, name, n, rows, nrows);
    if (!rc)
        *cap = *nrows;
    return rc;
}

int hs_case_checkpoint_read(struct hs_case *c, struct ckpt *ck, struct err *e)
{
    long ncols = 0;
    int rc = ckpt_get_long(ck, "thermo_columns", &ncols);
    if (!rc && (ncols < 1 || ncols > 64))
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld thermo columns", ck->path, ncols);
    if (!rc) {
        c->ncols = (int)ncols;
        rc = get_rows(ck, "thermo_rows", c->ncols, &c->thermo, &c->nthermo, &c->thermo_cap, e);
    }
    if (!rc)
        rc = get_rows(ck, "profile_rows", HS_PROFILE_COLS, &c->profile, &c->nprofile,
                      &c->profile_cap, e);
    return rc;
}

/* --- outputs ---------------------------------------------------------------- */

static void print_profile_row(FILE *f, const double *r)
{
    fprintf(f, "%ld,%.6g,%.6g,%d,%ld,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g\n", (long)r[0],
            r[1], r[2], (int)r[3], (long)r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12],
            r[13]);
}

#define HS_BASE_COLS 7
#define HS_MAX_COLS HS_THERMO_MAX_COLS
static const char *const base_cols[HS_BASE_COLS] = {
    "step", "time_ps", "md_ke_eV", "md_pe_eV", "mpm_ke_eV", "mpm_strain_eV", "etotal_eV"};

int hs_case_output_begin(struct hs_case *c, struct run *run, const char *const *extra, int nextra,
                         struct err *e)
{
    const char *cols[HS_MAX_COLS];
    int n = 0;
    for (int k = 0; k < HS_BASE_COLS; k++)
        cols[n++] = base_cols[k];
    for (int k = 0; k < nextra && n < HS_MAX_COLS; k++)
        cols[n++] = extra[k];
    if (run_thermo_header(run, cols, n) != 0)
        return err_set(e, ERR_RUNTIME, "%s", run->write_err.msg);
    /* the rows of a restored checkpoint have this case's columns */
    if (c->nthermo > 0 && c->ncols != n)
        return err_set(e, ERR_INPUT, "checkpoint thermo rows have %d columns, the case writes %d",
                       c->ncols, n);
    c->ncols = n;
    memcpy(c->thermo_names, cols, (size_t)n * sizeof *cols);
    for (long i = 0; i < c->nthermo; i++)
        run_thermo_row(run, c->thermo + i * n, n);
    if (run->opt.rank == 0) {
        char path[4096];
        run_path(run, "profile.csv", path, sizeof path);
        int rc = wfile_open(&c->profile_w, path, e);
        if (rc)
            return rc;
        c->profile_csv = c->profile_w.f;
        fprintf(c->profile_csv,
                "# stress along the bar: MD slabs (source 0: per-atom virial stress) and MPM "
                "slabs (source 1: material point stress), slab %g Å\n"
                "step,time_ps,x_A,source,count,sxx_GPa,syy_GPa,szz_GPa,sxy_GPa,sxz_GPa,syz_GPa,"
                "ux_A,vx_A_ps,sxx_analytic_GPa\n",
                c->prof.width);
        for (long i = 0; i < c->nprofile; i++)
            print_profile_row(c->profile_csv, c->profile + i * HS_PROFILE_COLS);
    }
    return 0;
}

int hs_case_thermo(struct hs_case *c, struct run *run, const double *extra, int nextra,
                   struct err *e)
{
    struct handshake_energy en;
    handshake_energy(&c->hs, &en);
    double row[HS_MAX_COLS] = {(double)c->hs.step, c->hs.time, en.md_kinetic, en.md_potential,
                               en.mpm_kinetic, en.mpm_strain, en.total};
    int n = HS_BASE_COLS;
    for (int k = 0; k < nextra && n < HS_MAX_COLS; k++)
        row[n++] = extra[k];
    run_thermo_row(run, row, n);
    return keep_row(&c->thermo, &c->nthermo, &c->thermo_cap, row, n, e);
}

static int grow(struct hs_case *c, long n, struct err *e)
{
    if (n <= c->cap)
        return 0;
    int64_t *ib = realloc(c->ibuf, (size_t)n * sizeof *ib);
    if (ib)
        c->ibuf = ib;
    double *db = realloc(c->dbuf, (size_t)6 * n * sizeof *db);
    if (db)
        c->dbuf = db;
    if (!ib || !db)
        return err_nomem(e, "handshake output");
    c->cap = n;
    return 0;
}

/* Level of the grid cell a point started in (0 on a uniform grid). */
static int point_level(const struct handshake *hs, const struct mpm_points *pt, long q)
{
    const struct mpm_grid *g = &hs->mpm.grid;
    if (g->kind != MPM_GRID_HIER)
        return 0;
    long cell = mpm_hgrid_find(g->hg, pt->x0 + 3 * q);
    return cell >= 0 ? g->hg->cell[cell].level : -1;
}

/* The MD particles of the snapshot (on bricks each rank its own, inside
 * a collective snapshot). */
static int snapshot_particles(struct hs_case *c, struct run *run, struct err *e)
{
    struct handshake *hs = &c->hs;
    struct particles *p = c->md.p;
    long n = p->n_owned;
    struct h5out *h = &run->h5;
    /* collective on bricks: an allocation that failed on one rank stops all */
    int rc = c->md.halo ? h5out_par_agree(h, grow(c, n, e), e) : grow(c, n, e);
    if (rc)
        return rc;
    hid_t g = h5out_begin_snapshot(h, "particles", hs->step, hs->time, n, e);
    if (g < 0)
        return ERR_RUNTIME;
    rc = run_snapshot_particles(run, g, p, &c->md.box, c->ibuf, e);
    if (!rc)
        rc = h5out_write_doubles(h, g, "pe", p->pe, n, 1, "eV", e);
    for (long i = 0; i < n; i++) {   /* virial stress over the atomic volume */
        const double *v = p->v + 3 * i, *w = p->virial + 6 * i;
        double m = p->mass[p->type[i]] * UNITS_MVV2E;
        double kv[6] = {v[0] * v[0], v[1] * v[1], v[2] * v[2], v[0] * v[1], v[0] * v[2], v[1] * v[2]};
        for (int k = 0; k < 6; k++)
            c->dbuf[6 * i + k] = -(w[k] + m * kv[k]) / hs->omega0 * UNITS_EVA3_TO_GPA;
    }
    if (!rc)
        rc = h5out_write_doubles(h, g, "stress", c->dbuf, n, 6, "GPa", e);
    for (long i = 0; i < n; i++)
        c->ibuf[i] = (int64_t)p->fields[hs->f_region].data[i];
    if (!rc)
        rc = h5out_write_ints(h, g, "region", c->ibuf, n, "1", e);
    h5out_end_snapshot(h, g);
    return rc;
}

/* The material points pt of this rank (on bricks inside a collective
 * snapshot: each rank writes its own rows). */
static int snapshot_points(struct hs_case *c, struct run *run, const struct mpm_points *pt,
                           struct err *e)
{
    struct handshake *hs = &c->hs;
    struct h5out *h = &run->h5;
    long np = pt->n;
    int rc = c->md.halo ? h5out_par_agree(h, grow(c, np, e), e) : grow(c, np, e);
    if (rc)
        return rc;
    hid_t g = h5out_begin_snapshot(h, "points", hs->step, hs->time, np, e);
    if (g < 0)
        return ERR_RUNTIME;
    rc = h5out_write_doubles(h, g, "position", pt->x, np, 3, "Å", e);
    for (long q = 0; q < np; q++)
        for (int d = 0; d < 3; d++)
            c->dbuf[3 * q + d] = pt->x[3 * q + d] - pt->x0[3 * q + d];
    if (!rc)
        rc = h5out_write_doubles(h, g, "displacement", c->dbuf, np, 3, "Å", e);
    if (!rc)
        rc = h5out_write_doubles(h, g, "velocity", pt->v, np, 3, "Å/ps", e);
    for (long k = 0; k < 6 * np; k++)
        c->dbuf[k] = pt->stress[k] * UNITS_EVA3_TO_GPA;
    if (!rc)
        rc = h5out_write_doubles(h, g, "stress", c->dbuf, np, 6, "GPa", e);
    if (!rc)
        rc = h5out_write_doubles(h, g, "mass", pt->mass, np, 1, "amu", e);
    if (!rc)
        rc = h5out_write_doubles(h, g, "volume", pt->vol, np, 1, "Å^3", e);
    /* the points' ids (1-based, the order of the build): on bricks each
     * rank writes its own rows, so the rows follow the ranks */
    if (!rc)
        rc = h5out_write_ints(h, g, "id", pt->id, np, "1", e);
    for (long q = 0; q < np; q++)
        c->ibuf[q] = pt->mask[q] & HS_MASK_II ? HS_II : pt->mask[q] & HS_MASK_III ? HS_III : HS_MPM;
    if (!rc)
        rc = h5out_write_ints(h, g, "region", c->ibuf, np, "1", e);
    for (long q = 0; q < np; q++)
        c->ibuf[q] = point_level(hs, pt, q);
    if (!rc)
        rc = h5out_write_ints(h, g, "level", c->ibuf, np, "1", e);
    h5out_end_snapshot(h, g);
    return rc;
}

int hs_case_snapshot(struct hs_case *c, struct run *run, struct err *e)
{
    if (c->md.halo) {   /* bricks: the atoms collectively, then the points */
        if (!run->out.hdf5)
            return 0;
        int rc = run_h5_par_begin(run, c->md.p->n_owned, e);
        if (!rc)
            rc = snapshot_particles(c, run, e);
        rc = run_h5_par_end(run, rc, e);
        /* the points as the atoms: each rank writes the rows it holds */
        if (!rc) {
            rc = run_h5_par_begin(run, c->hs.mpm.pts.n, e);
            if (!rc)
                rc = snapshot_points(c, run, &c->hs.mpm.pts, e);
            rc = run_h5_par_end(run, rc, e);
        }
        return halo_agree(c->md.halo, rc, e);
    }
    if (!run->h5_open)
        return 0;
    int rc = snapshot_particles(c, run, e);
    return rc ? rc : snapshot_points(c, run, &c->hs.mpm.pts, e);
}

int hs_case_profile(struct hs_case *c, struct run *run, double (*analytic)(const void *, double),
                    const void *ctx, struct err *e)
{
    struct hs_profile *pr = &c->prof;
    hs_profile_compute(pr, &c->hs);
    const double G = UNITS_EVA3_TO_GPA;
    long nrow = 0;
    for (long k = 0; k < pr->nbins; k++)
        nrow += (pr->md[k].n > 0) + (pr->mpm[k].n > 0);
    int rc = grow(c, nrow, e);
    double *x = rc ? NULL : malloc((size_t)(nrow ? nrow : 1) * 10 * sizeof *x);
    if (!rc && !x)
        rc = err_nomem(e, "profile");
    if (rc)   /* bricks: every rank stops at this step */
        return c->md.halo ? halo_agree(c->md.halo, rc, e) : rc;
    double *s6 = x + nrow, *u = s6 + 6 * nrow, *v = u + nrow, *an = v + nrow;
    long r = 0;
    for (long k = 0; k < pr->nbins; k++)
        for (int src = 0; src < 2; src++) {
            const struct hs_slab *s = src == HS_SRC_MD ? &pr->md[k] : &pr->mpm[k];
            if (s->n == 0)
                continue;
            x[r] = hs_profile_x(pr, k);
            c->ibuf[r] = src;
            for (int q = 0; q < 6; q++)
                s6[6 * r + q] = s->stress[q] * G;
            u[r] = s->u;
            v[r] = s->v;
            an[r] = analytic ? analytic(ctx, x[r]) * G : NAN;
            double row[HS_PROFILE_COLS] = {(double)c->hs.step, c->hs.time, x[r], src,
                                           (double)s->n, s6[6 * r], s6[6 * r + 1],
                                           s6[6 * r + 2], s6[6 * r + 3], s6[6 * r + 4],
                                           s6[6 * r + 5], u[r], v[r], an[r]};
            if (c->profile_csv)
                print_profile_row(c->profile_csv, row);
            if (!rc)
                rc = keep_row(&c->profile, &c->nprofile, &c->profile_cap, row,
                              HS_PROFILE_COLS, e);
            r++;
        }
    if (run->h5_open) {
        hid_t g = h5out_begin_snapshot(&run->h5, "profiles", c->hs.step, c->hs.time, nrow, e);
        if (g < 0)
            rc = ERR_RUNTIME;
        if (!rc)
            rc = h5out_write_doubles(&run->h5, g, "x", x, nrow, 1, "Å", e);
        if (!rc)
            rc = h5out_write_ints(&run->h5, g, "source", c->ibuf, nrow, "0 MD, 1 MPM", e);
        if (!rc)
            rc = h5out_write_doubles(&run->h5, g, "stress", s6, nrow, 6, "GPa", e);
        if (!rc)
            rc = h5out_write_doubles(&run->h5, g, "displacement_x", u, nrow, 1, "Å", e);
        if (!rc)
            rc = h5out_write_doubles(&run->h5, g, "velocity_x", v, nrow, 1, "Å/ps", e);
        if (!rc && analytic)
            rc = h5out_write_doubles(&run->h5, g, "sxx_analytic", an, nrow, 1, "GPa", e);
        if (g >= 0)
            h5out_end_snapshot(&run->h5, g);
    }
    free(x);
    if (!rc && c->profile_csv && wfile_flush(&c->profile_w, e) != 0) {
        c->profile_csv = NULL;
        rc = ERR_RUNTIME;
    }
    /* bricks: rank 0 wrote; the others stop with it at the same step */
    return c->md.halo ? halo_agree(c->md.halo, rc, e) : rc;
}

int hs_case_output_end(struct hs_case *c, struct run *run, struct err *e)
{
    struct handshake *hs = &c->hs;
    struct result *res = &run->result;
    const struct handshake_layout *L = &hs->lay;
    const double G = UNITS_EVA3_TO_GPA;
    result_metric(res, "atoms", (double)(hs->counts[HS_CORE] + hs->counts[HS_I] +
                                         hs->counts[HS_FIXED]), "1");
    result_metric(res, "atoms_region_I", (double)hs->counts[HS_I], "1");
    result_metric(res, "points", (double)hs->npoints, "1");
    result_metric(res, "points_region_II", (double)hs->counts[HS_II], "1");
    result_metric(res, "points_region_III", (double)hs->counts[HS_III], "1");
    /* the MD copies of the lattice-site points of regions II and III (every
     * such point with a cell of one lattice constant, every site point with
     * half-constant cells) */
    result_metric(res, "copies_region_II_III", (double)hs->ncopies, "1");
    result_metric(res, "nodes", (double)hs->mpm.grid.nnodes, "1");
    /* lattice sites the MPM domain holds outside the MD region: the atoms a
     * full MD model would need there */
    double vd = 1, vb = 1;
    for (int d = 0; d < 3; d++) {
        vd *= L->mat_hi[d] - L->mat_lo[d];
        vb *= L->md_hi[d] - L->md_lo[d];
    }
    double replaced = (vd - vb) / hs->omega0;
    result_metric(res, "atoms_replaced", replaced, "1");
    result_metric(res, "atoms_per_point", hs->npoints ? replaced / hs->npoints : 0, "1");
    double coarse = L->h;
    for (int l = 0; l < L->nlevels; l++)
        coarse *= 2;
    result_metric(res, "finest_cell", L->h, "Å");
    result_metric(res, "coarse_cell", L->nlevels > 0 ? coarse : L->h, "Å");
    result_metric(res, "lattice_constant", c->a, "Å");
    result_metric(res, "c11_md", c->md_cr.c11 * G, "GPa");
    result_metric(res, "c12_md", c->md_cr.c12 * G, "GPa");
    result_metric(res, "c44_md", c->md_cr.c44 * G, "GPa");
    /* diamond: C44 with the sublattices held, and the internal shift's
     * parameter that places regions II and III (handshake.h) */
    result_metric(res, "c44_unrelaxed_md", c->md_cr.c44_unrelaxed * G, "GPa");
    result_metric(res, "kleinman_zeta", c->md_cr.zeta, "1");
    result_metric(res, "kleinman_zeta_mpm", hs->cr.zeta, "1");   /* at a(T) when given */
    result_metric(res, "c11_mpm", hs->cr.c11 * G, "GPa");
    result_metric(res, "c12_mpm", hs->cr.c12 * G, "GPa");
    result_metric(res, "c44_mpm", hs->cr.c44 * G, "GPa");
    /* the bar's direction and its longitudinal modulus (C11 along [100];
     * (C11 + C12 + 2 C44) / 2 along [110]) */
    result_metric(res, "orientation", c->orient == HS_ORIENT_110 ? 110 : 100, "1");
    result_metric(res, "cl_md", c->cl_md * G, "GPa");
    result_metric(res, "cl_mpm", c->cl * G, "GPa");
    result_metric(res, "steps_done", (double)hs->step, "1");
    result_metric(res, "time", hs->time, "ps");
    result_metric(res, "timestep", c->md.dt, "ps");
    struct handshake_energy en;
    handshake_energy(hs, &en);
    result_metric(res, "md_ke", en.md_kinetic, "eV");
    result_metric(res, "md_pe", en.md_potential, "eV");
    result_metric(res, "mpm_ke", en.mpm_kinetic, "eV");
    result_metric(res, "mpm_strain_energy", en.mpm_strain, "eV");
    result_metric(res, "etotal", en.total, "eV");
    /* the last profile as series (x, source, sxx, szz) */
    struct hs_profile *pr = &c->prof;
    hs_profile_compute(pr, hs);
    long nrow = 0;
    for (long k = 0; k < pr->nbins; k++)
        nrow += (pr->md[k].n > 0) + (pr->mpm[k].n > 0);
    double *buf = malloc((size_t)(nrow ? nrow : 1) * 4 * sizeof *buf);
    if (!buf)
        return err_nomem(e, "profile series");
    long r = 0;
    for (long k = 0; k < pr->nbins; k++)
        for (int src = 0; src < 2; src++) {
            const struct hs_slab *s = src == HS_SRC_MD ? &pr->md[k] : &pr->mpm[k];
            if (s->n == 0)
                continue;
            buf[r] = hs_profile_x(pr, k);
            buf[nrow + r] = src;
            buf[2 * nrow + r] = s->stress[0] * G;
            buf[3 * nrow + r] = s->stress[2] * G;
            r++;
        }
    result_series(res, "profile_x", buf, (int)nrow, "Å");
    result_series(res, "profile_source", buf + nrow, (int)nrow, "0 MD, 1 MPM");
    result_series(res, "profile_sxx", buf + 2 * nrow, (int)nrow, "GPa");
    result_series(res, "profile_szz", buf + 3 * nrow, (int)nrow, "GPa");
    free(buf);
    if (c->md.halo) {   /* the grid, every rank's particles and points, peak memory */
        decomp_record_write(run, c->md.halo, c->md.p);
        handshake_record_parallel(&c->hs, res);
    }
    /* the thermo rows as series under /series of fields.h5, as an MD run's:
     * the unit is the column name's suffix (step: 1) */
    const char *units[HS_MAX_COLS];
    for (int k = 0; k < c->ncols; k++) {
        const char *u = strrchr(c->thermo_names[k], '_');
        units[k] = u ? u + 1 : "1";
    }
    int rc = run_write_series_table(run, c->thermo, c->nthermo, c->ncols, c->thermo_names, units,
                                    e);
    c->profile_csv = NULL;
    int rc2 = wfile_commit(&c->profile_w, e);
    rc = rc ? rc : rc2;
    /* bricks: rank 0 wrote; every rank returns its verdict */
    return c->md.halo ? halo_agree(c->md.halo, rc, e) : rc;
}
