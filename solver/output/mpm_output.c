/*
 * mpm_output: thermo rows and HDF5 snapshots of an MPM run, in the case's
 * units (mpm_units.h): material points as a point cloud (/points), grid
 * nodes as a structured grid (/grid, uniform grids) or a point cloud of the
 * nodes (hierarchical grids), both described in the XDMF sidecar.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_bricks.h"
#include "mpm/mpm_hgrid.h"
#include "scenarios/mpm_case.h"
#include "util/mem.h"

#define MAX_COLS MPM_OUTPUT_MAX_COLS

long mpm_probe_means(const struct mpm_case *c, int k, double stress[6], double disp[3])
{
    const struct mpm_points *p = &c->m.pts;
    const struct region *r = &c->probe[k].region;
    long cnt = 0;
    double s[6] = {0}, u[3] = {0};
    for (long i = 0; i < p->n; i++) {
        if (!region_contains(r, p->x0 + 3 * i))
            continue;
        for (int a = 0; a < 6; a++)
            s[a] += p->stress[6 * i + a];
        for (int a = 0; a < 3; a++)
            u[a] += p->x[3 * i + a] - p->x0[3 * i + a];
        cnt++;
    }
    if (c->bricks) {   /* the points of every rank */
        double all[10] = {s[0], s[1], s[2], s[3], s[4], s[5], u[0], u[1], u[2], (double)cnt};
        mpm_bricks_sum(c->bricks, all, 10);
        memcpy(s, all, sizeof s);
        memcpy(u, all + 6, sizeof u);
        cnt = (long)all[9];
    }
    for (int a = 0; a < 6; a++)
        stress[a] = cnt ? s[a] / cnt : 0.0;
    for (int a = 0; a < 3; a++)
        disp[a] = cnt ? u[a] / cnt : 0.0;
    return cnt;
}

static void col(struct mpm_output *o, const char *name, const char *unit)
{
    int k = o->ncols++;
    snprintf(o->col_name[k], sizeof o->col_name[k], "%s", name);
    snprintf(o->col_unit[k], sizeof o->col_unit[k], "%s", unit);
    if (strcmp(unit, "1") == 0)
        snprintf(o->col_head[k], sizeof o->col_head[k], "%s", name);
    else
        snprintf(o->col_head[k], sizeof o->col_head[k], "%s_%s", name, unit);
}

int mpm_output_begin(struct mpm_output *o, struct run *run, struct mpm_case *c, struct err *e)
{
    memset(o, 0, sizeof *o);
    const struct mpm_units *u = &c->u;
    char name[48];
    col(o, "step", "1");
    col(o, "time", u->time_name);
    col(o, "dt", u->time_name);
    col(o, "ke", u->energy_name);
    col(o, "strain_energy", u->energy_name);
    col(o, "etotal", u->energy_name);
    /* time-centred total energy of the previous step (mpm.h) */
    col(o, "etotal_centred", u->energy_name);
    col(o, "px", u->momentum_name);
    col(o, "py", u->momentum_name);
    col(o, "pz", u->momentum_name);
    col(o, "vmax", u->velocity_name);
    for (int b = 0; b < c->m.nbody; b++)
        if (c->m.body[b].rigid)
            for (int d = 0; d < 3; d++) {
                snprintf(name, sizeof name, "%s_f%c", c->m.body[b].name, "xyz"[d]);
                col(o, name, u->force_name);
            }
    static const char *const probe_cols[4] = {"sxx", "syy", "szz", "ux"};
    for (int k = 0; k < c->nprobes; k++)
        for (int q = 0; q < 4; q++) {
            snprintf(name, sizeof name, "%s_%s", c->probe[k].name, probe_cols[q]);
            col(o, name, q < 3 ? u->stress_name : u->length_name);
        }
    const char *heads[MAX_COLS];
    for (int k = 0; k < o->ncols; k++)
        heads[k] = o->col_head[k];
    if (run_thermo_header(run, heads, o->ncols) != 0)
        return err_set(e, ERR_RUNTIME, "%s", run->write_err.msg);
    if (run->h5_open) {
        char desc[256];
        snprintf(desc, sizeof desc,
                 "MPM case in %s units: length %s, time %s, velocity %s, mass %s, energy %s, "
                 "force %s, stress %s",
                 u->name, u->length_name, u->time_name, u->velocity_name, u->mass_name,
                 u->energy_name, u->force_name, u->stress_name);
        h5out_set_units(&run->h5, desc, u->time_name);
    }
    return 0;
}

int mpm_output_thermo(struct mpm_output *o, struct run *run, struct mpm_case *c, double dt,
                      const struct mpm_totals *t, struct err *e)
{
    const struct mpm_units *u = &c->u;
    const struct mpm *m = &c->m;
    double row[MAX_COLS];
    int n = 0;
    row[n++] = (double)m->step;
    row[n++] = m->time / u->time;
    row[n++] = dt / u->time;
    row[n++] = t->kinetic / u->energy;
    row[n++] = t->strain / u->energy;
    row[n++] = (t->kinetic + t->strain) / u->energy;
    row[n++] = (m->step > 0 ? mpm_energy_centred(m) : t->kinetic + t->strain) / u->energy;
    for (int d = 0; d < 3; d++)
        row[n++] = t->momentum[d] / u->momentum;
    row[n++] = t->vmax / u->velocity;
    for (int b = 0; b < m->nbody; b++)
        if (m->body[b].rigid)
            for (int d = 0; d < 3; d++)
                row[n++] = m->body[b].reaction[d] / u->force;
    for (int k = 0; k < c->nprobes; k++) {
        double s[6], disp[3];
        mpm_probe_means(c, k, s, disp);
        row[n++] = s[0] / u->stress;
        row[n++] = s[1] / u->stress;
        row[n++] = s[2] / u->stress;
        row[n++] = disp[0] / u->length;
    }
    run_thermo_row(run, row, n);
    if (o->nrows >= o->rcap) {
        long cap = o->rcap ? 2 * o->rcap : 256;
        double *s = mem_realloc(o->series, (size_t)cap * o->ncols * sizeof *s);
        if (!s)
            return err_nomem(e, "thermo series");
        o->series = s;
        o->rcap = cap;
    }
    memcpy(o->series + o->nrows * o->ncols, row, (size_t)n * sizeof *row);
    o->nrows++;
    return 0;
}

int mpm_output_resume(struct mpm_output *o, struct run *run, const double *rows, long nrows,
                      long ncols, struct err *e)
{
    if (nrows <= 0)
        return 0;
    if (ncols != o->ncols)
        return err_set(e, ERR_INPUT, "checkpoint thermo rows have %ld columns, the case's %d",
                       ncols, o->ncols);
    double *sr = mem_alloc((size_t)nrows * ncols * sizeof *sr);
    if (!sr)
        return err_nomem(e, "thermo series");
    memcpy(sr, rows, (size_t)nrows * ncols * sizeof *sr);
    free(o->series);
    o->series = sr;
    o->nrows = o->rcap = nrows;
    for (long i = 0; i < nrows; i++)
        run_thermo_row(run, rows + i * ncols, (int)ncols);
    return 0;
}

static int reserve(struct mpm_output *o, long n, struct err *e)
{
    if (n > o->cap) {
        double *b = mem_realloc(o->buf, (size_t)n * sizeof *b);
        if (!b)
            return err_nomem(e, "output buffer");
        o->buf = b;
        o->cap = n;
    }
    if (n > o->icap) {
        int64_t *ib = mem_realloc(o->ibuf, (size_t)n * sizeof *ib);
        if (!ib)
            return err_nomem(e, "output buffer");
        o->ibuf = ib;
        o->icap = n;
    }
    return 0;
}

/* Write n x nc values of src times `scale` under name. */
static int put(struct mpm_output *o, struct run *run, hid_t g, const char *name, const double *src,
               long n, int nc, double scale, const char *unit, struct err *e)
{
    for (long k = 0; k < n * nc; k++)
        o->buf[k] = src[k] * scale;
    return h5out_write_doubles(&run->h5, g, name, o->buf, n, nc, unit, e);
}

static int points_snapshot(struct mpm_output *o, struct run *run, struct mpm_case *c,
                           struct err *e)
{
    const struct mpm_units *u = &c->u;
    struct mpm *m = &c->m;
    struct mpm_points *p = &m->pts;
    long n = p->n;
    /* collective (bricks): an allocation that failed on one rank stops all */
    int rc = h5out_par_agree(&run->h5, reserve(o, 9 * n, e), e);
    if (rc)
        return rc;
    hid_t g = h5out_begin_snapshot(&run->h5, "points", m->step, m->time / u->time, n, e);
    if (g < 0)
        return ERR_RUNTIME;
    rc = put(o, run, g, "position", p->x, n, 3, 1.0 / u->length, u->length_name, e);
    if (!rc) {
        for (long k = 0; k < 3 * n; k++)
            o->buf[k] = (p->x[k] - p->x0[k]) / u->length;
        rc = h5out_write_doubles(&run->h5, g, "displacement", o->buf, n, 3, u->length_name, e);
    }
    if (!rc)
        rc = put(o, run, g, "velocity", p->v, n, 3, 1.0 / u->velocity, u->velocity_name, e);
    if (!rc)
        rc = put(o, run, g, "stress", p->stress, n, 6, 1.0 / u->stress, u->stress_name, e);
    if (!rc) {   /* logarithmic strain from F */
        for (long i = 0; i < n; i++)
            mpm_points_strain(p, i, o->buf + 6 * i);
        rc = h5out_write_doubles(&run->h5, g, "strain", o->buf, n, 6, "1", e);
    }
    if (!rc)
        rc = put(o, run, g, "deformation_gradient", p->F, n, 9, 1.0, "1", e);
    if (!rc)
        rc = put(o, run, g, "volume", p->vol, n, 1, 1.0 / (u->length * u->length * u->length),
                 u->volume_name, e);
    if (!rc)
        rc = put(o, run, g, "mass", p->mass, n, 1, 1.0 / u->mass, u->mass_name, e);
    if (!rc)
        rc = put(o, run, g, "strain_energy", p->eint, n, 1, 1.0 / u->energy, u->energy_name, e);
    for (int k = 0; !rc && k < p->nstate; k++) {
        for (long i = 0; i < n; i++)
            o->buf[i] = p->state[(long)p->nstate * i + k];
        char name[32];
        snprintf(name, sizeof name, k == 0 ? "plastic_strain" : "state_%d", k);
        rc = h5out_write_doubles(&run->h5, g, name, o->buf, n, 1, "1", e);
    }
    for (long i = 0; !rc && i < n; i++)
        o->ibuf[i] = p->body[i];
    if (!rc)
        rc = h5out_write_ints(&run->h5, g, "body", o->ibuf, n, "1", e);
    for (long i = 0; !rc && i < n; i++)
        o->ibuf[i] = p->id[i];
    if (!rc)
        rc = h5out_write_ints(&run->h5, g, "id", o->ibuf, n, "1", e);
    h5out_end_snapshot(&run->h5, g);
    return rc;
}

enum grid_field { GRID_MASS, GRID_VELOCITY, GRID_FORCE };

/* One node field (mass; velocity; force) of the uniform grid's nodes
 * [lo, hi) (the grid's global node indices, x fastest), or of every node
 * of a hierarchical grid, times `scale` into out (1 or 3 values a node);
 * one field at a time, so a snapshot needs 3 doubles a node beyond the
 * grid. */
static long grid_field(struct mpm_case *c, const long lo[3], const long hi[3],
                       enum grid_field field, double scale, int fresh, double *out)
{
    struct mpm *m = &c->m;
    const struct mpm_grid *g = &m->grid;
    int musl = m->algorithm == MPM_MUSL, uniform = g->kind == MPM_GRID_UNIFORM;
    long nx = uniform ? hi[0] - lo[0] : g->nnodes, ny = uniform ? hi[1] - lo[1] : 1,
         nz = uniform ? hi[2] - lo[2] : 1;
    long k = 0;
    for (long z = 0; z < nz; z++)
        for (long y = 0; y < ny; y++)
            for (long x = 0; x < nx; x++, k++) {
                long i = !uniform ? x
                                  : (lo[0] + x - g->lo[0] + g->halo) +
                                        (lo[1] + y - g->lo[1] + g->halo) * g->dim[0] +
                                        (lo[2] + z - g->lo[2] + g->halo) * g->dim[0] * g->dim[1];
                const struct mpm_node *nd = &g->node[i];
                double mi = nd->m;
                if (field == GRID_MASS) {
                    out[k] = mi * scale;
                    continue;
                }
                for (int d = 0; d < 3; d++) {
                    double v;
                    if (fresh)   /* just mapped: momentum and force */
                        v = field == GRID_VELOCITY ? (mi > m->small_mass ? nd->q[d] / mi : 0.0)
                                                   : nd->f[d];
                    else         /* after a step: velocity and acceleration */
                        v = field == GRID_VELOCITY ? (musl ? g->r[4 * i + d] : nd->q[d])
                                                   : mi * nd->f[d] * UNITS_MVV2E;
                    out[3 * k + d] = v * scale;
                }
            }
    return k;
}

/* The grid snapshot of nodes [lo, hi) of a uniform grid whose whole has
 * dims nodes from origin (the grid's units), or of every node of a
 * hierarchical grid.  block: inside a collective snapshot, this rank's
 * block of the uniform grid (h5out_par_grid_block); failures agreed. */
static int grid_write(struct mpm_output *o, struct run *run, struct mpm_case *c, const long lo[3],
                      const long hi[3], const long dims[3], const double origin[3], int block,
                      struct err *e)
{
    const struct mpm_units *u = &c->u;
    struct mpm *m = &c->m;
    const struct mpm_grid *g = &m->grid;
    /* after a step the nodes hold the updated velocities and accelerations
     * (s5), or, when mpm_step fused them, the fresh mapping of the next step */
    int fresh = m->step == 0 || m->grid_fresh;
    int structured = g->kind == MPM_GRID_UNIFORM;
    long n = structured ? (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]) : g->nnodes;
    int rc = h5out_par_agree(&run->h5, reserve(o, 3 * n, e), e);
    if (rc)
        return rc;
    hid_t gr = -1;
    if (structured) {
        double o_len[3], spacing[3];
        for (int d = 0; d < 3; d++) {
            o_len[d] = origin[d] / u->length;
            spacing[d] = g->h / u->length;
        }
        gr = h5out_begin_grid_snapshot(&run->h5, "grid", m->step, m->time / u->time, dims, o_len,
                                       spacing, e);
        if (gr >= 0 && block) {
            long count[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
            h5out_par_grid_block(&run->h5, lo, count);
        }
    } else {
        gr = h5out_begin_snapshot(&run->h5, "grid", m->step, m->time / u->time, n, e);
        if (gr >= 0) {
            for (long i = 0; i < n; i++)
                mpm_grid_node_position(g, i, o->buf + 3 * i);
            for (long k = 0; k < 3 * n; k++)
                o->buf[k] /= u->length;
            rc = h5out_write_doubles(&run->h5, gr, "position", o->buf, n, 3, u->length_name, e);
        }
    }
    if (gr < 0 && !rc)
        rc = ERR_RUNTIME;
    static const struct {
        const char *name;
        enum grid_field field;
        int nc;
    } fields[] = {{"mass", GRID_MASS, 1}, {"velocity", GRID_VELOCITY, 3}, {"force", GRID_FORCE, 3}};
    const double scale[] = {1.0 / u->mass, 1.0 / u->velocity, 1.0 / u->force};
    const char *unit[] = {u->mass_name, u->velocity_name, u->force_name};
    for (int f = 0; !rc && f < 3; f++) {
        grid_field(c, lo, hi, fields[f].field, scale[f], fresh, o->buf);
        rc = structured ? h5out_write_grid_doubles(&run->h5, gr, fields[f].name, o->buf,
                                                   fields[f].nc, unit[f], e)
                        : h5out_write_doubles(&run->h5, gr, fields[f].name, o->buf, n,
                                              fields[f].nc, unit[f], e);
    }
    if (gr >= 0)
        h5out_end_snapshot(&run->h5, gr);
    return rc;
}

/* The whole grid of this process (serial, or rank 0 of a hierarchical
 * grid on bricks). */
static int grid_snapshot(struct mpm_output *o, struct run *run, struct mpm_case *c, struct err *e)
{
    struct mpm *m = &c->m;
    const struct mpm_grid *g = &m->grid;
    if (m->step == 0 && !c->bricks) {   /* nothing mapped yet: map the initial state (s1-s3);
                                           bricks: mapped by the caller */
        int rc = mpm_locate_particles(m, e);
        if (rc)
            return rc;
        mpm_clear_grid(m);
        mpm_map_to_grid(m, MPM_MAP_ALL);
    }
    long lo[3], hi[3], dims[3];
    double origin[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = g->lo[d];
        hi[d] = g->lo[d] + g->nn[d];
        dims[d] = g->nn[d];
        origin[d] = g->origin[d] + g->lo[d] * g->h;
    }
    return grid_write(o, run, c, lo, hi, dims, origin, 0, e);
}

/* Bricks: every rank writes its own points' rows of each dataset into the
 * one fields.h5, collectively (h5out_par_begin; rank 0's points, then rank
 * 1's, ...: the serial datasets, as MD's atoms), and, on a uniform grid,
 * its own block of nodes into the whole grid's datasets (the serial
 * layout: no rank holds the whole grid).  A hierarchical grid is whole on
 * every rank (mpm_bricks.h): rank 0 writes it with the serial code.
 * Collective. */
static int bricks_snapshot(struct mpm_output *o, struct run *run, struct mpm_case *c,
                           struct err *e)
{
    struct mpm *m = &c->m;
    struct mpm_bricks *b = c->bricks;
    int rc = 0, root = mpm_bricks_rank(b) == 0;
    if (!run->out.hdf5)   /* the setting every rank knows (rank 0 alone opens the file) */
        return 0;
    if (c->output_grid && m->step == 0)   /* the initial mapping, as a serial snapshot */
        rc = mpm_bricks_map_initial(b, m, e);
    if (rc)
        return rc;
    rc = run_h5_par_begin(run, m->pts.n, e);
    if (!rc)
        rc = points_snapshot(o, run, c, e);
    if (!rc && c->output_grid && !b->whole) {
        long lo[3], hi[3], dims[3];
        mpm_bricks_node_block(b, lo, hi);
        double origin[3];
        for (int d = 0; d < 3; d++) {   /* the whole grid's nodes 0 .. ncell */
            dims[d] = b->ncell[d] + 1;
            origin[d] = m->grid.origin[d];
        }
        rc = grid_write(o, run, c, lo, hi, dims, origin, 1, e);
    }
    rc = run_h5_par_end(run, rc, e);
    if (rc || !c->output_grid || !b->whole)
        return rc;
    /* only the shared nodes were summed: complete copies for the writer */
    struct mpm_node *cnode = NULL;
    double *cr = NULL;
    rc = mpm_bricks_complete_grid(b, m, &cnode, &cr, e);
    if (!rc && root && run->h5_open) {
        struct mpm_grid patch = m->grid;
        if (cnode) {   /* none on one rank: its grid is complete */
            m->grid.node = cnode;
            m->grid.r = cr;
        }
        rc = grid_snapshot(o, run, c, e);
        m->grid = patch;
    }
    free(cnode);
    free(cr);
    return mpm_bricks_agree(b, rc, e);
}

int mpm_output_snapshot(struct mpm_output *o, struct run *run, struct mpm_case *c, struct err *e)
{
    if (c->bricks)
        return bricks_snapshot(o, run, c, e);
    if (!run->h5_open)
        return 0;
    int rc = points_snapshot(o, run, c, e);
    if (!rc && c->output_grid)
        rc = grid_snapshot(o, run, c, e);
    return rc;
}

int mpm_output_end(struct mpm_output *o, struct run *run, struct err *e)
{
    int rc = 0;
    if (run->h5_open && o->nrows > 0) {
        double *vals = mem_alloc((size_t)o->nrows * sizeof *vals);
        if (!vals)
            rc = err_nomem(e, "thermo series");
        for (int k = 0; k < o->ncols && !rc; k++) {
            for (long r = 0; r < o->nrows; r++)
                vals[r] = o->series[r * o->ncols + k];
            rc = h5out_write_series(&run->h5, o->col_name[k], vals, o->nrows, o->col_unit[k], e);
        }
        free(vals);
    }
    free(o->buf);
    free(o->ibuf);
    free(o->series);
    memset(o, 0, sizeof *o);
    return rc;
}
