/* md_output: the MD run's thermo, snapshots and frames. */
#include "output/md_output.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "output/decomp_record.h"
#include "output/xyz_write.h"
#include "util/mem.h"
#include "util/wfile.h"

static const char *const thermo_cols[MD_THERMO_COLS] = {
    "step", "time_ps", "pe_eV", "ke_eV", "etotal_eV", "temp_K", "press_GPa",
    "pxx_GPa", "pyy_GPa", "pzz_GPa", "pxy_GPa", "pxz_GPa", "pyz_GPa"};
static const char *const thermo_units[MD_THERMO_COLS] = {
    "1", "ps", "eV", "eV", "eV", "K", "GPa", "GPa", "GPa", "GPa", "GPa", "GPa", "GPa"};

int md_output_begin(struct md_output *o, struct run *run, struct md *md, struct err *e)
{
    memset(o, 0, sizeof *o);
    o->xyz_field = -1;
    (void)md;
    if (run_thermo_header(run, thermo_cols, MD_THERMO_COLS) != 0)
        return err_set(e, ERR_RUNTIME, "%s", run->write_err.msg);
    return 0;
}

static int thermo_row(struct md_output *o, struct run *run, struct md *md)
{
    double P[6];
    md_pressure_tensor(md, P);
    double pe = md->last.energy, ke = md_kinetic_energy(md);
    double row[MD_THERMO_COLS] = {(double)md->step, md->time, pe, ke, pe + ke, md_temperature(md),
                                  (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA};
    for (int k = 0; k < 6; k++)
        row[7 + k] = P[k] * UNITS_EVA3_TO_GPA;
    if (run_thermo_row(run, row, MD_THERMO_COLS) != 0)
        return err_set(&o->err, ERR_RUNTIME, "%s", run->write_err.msg);
    if (o->nrows >= o->cap) {
        long cap = o->cap ? 2 * o->cap : 256;
        double *s = mem_realloc(o->series, (size_t)cap * MD_THERMO_COLS * sizeof *s);
        if (!s)
            return err_nomem(&o->err, "thermo series");
        o->series = s;
        o->cap = cap;
    }
    memcpy(o->series + o->nrows * MD_THERMO_COLS, row, sizeof row);
    o->nrows++;
    return 0;
}

int md_output_resume(struct md_output *o, struct run *run, const double *rows, long nrows,
                     struct err *e)
{
    if (nrows <= 0)
        return 0;
    double *sr = mem_alloc((size_t)nrows * MD_THERMO_COLS * sizeof *sr);
    if (!sr)
        return err_nomem(e, "thermo series");
    memcpy(sr, rows, (size_t)nrows * MD_THERMO_COLS * sizeof *sr);
    free(o->series);
    o->series = sr;
    o->nrows = o->cap = nrows;
    for (long i = 0; i < nrows; i++)
        run_thermo_row(run, rows + i * MD_THERMO_COLS, MD_THERMO_COLS);
    return 0;
}

/* Scratch for n atoms: stresses and ids/types. */
static int grow_atoms(struct md_output *o, long n)
{
    if (n <= o->cap_atoms)
        return 0;
    double *s = mem_realloc(o->stress, (size_t)6 * (n ? n : 1) * sizeof *s);
    if (s)
        o->stress = s;
    int64_t *ib = mem_realloc(o->ibuf, (size_t)(n ? n : 1) * sizeof *ib);
    if (ib)
        o->ibuf = ib;
    if (!s || !ib)
        return err_nomem(&o->err, "per-atom buffers");
    o->cap_atoms = n;
    return 0;
}

static int snapshot_of(struct md_output *o, struct run *run, struct md *md);

/* Bricks: every rank writes its own atoms' rows of each dataset into the
 * one fields.h5, collectively (h5out_par_begin); the same datasets as a
 * serial run writes. */
int md_output_snapshot(struct md_output *o, struct run *run, struct md *md)
{
    if (!md->halo)
        return run->h5_open ? snapshot_of(o, run, md) : 0;
    if (!run->out.hdf5)
        return 0;
    int rc = run_h5_par_begin(run, md->p->n_owned, &o->err);
    if (!rc)
        rc = snapshot_of(o, run, md);
    return run_h5_par_end(run, rc, &o->err);
}

static int snapshot_of(struct md_output *o, struct run *run, struct md *md)
{
    struct particles *p = md->p;
    long n = p->n_owned;
    struct err *ep = &o->err;
    /* collective (bricks): an allocation that failed on one rank stops all */
    if (h5out_par_agree(&run->h5, grow_atoms(o, n), ep) != 0)
        return ERR_RUNTIME;
    hid_t g = h5out_begin_snapshot(&run->h5, "particles", md->step, md->time, n, ep);
    if (g < 0)
        return ERR_RUNTIME;
    int rc = run_snapshot_particles(run, g, p, &md->box, o->ibuf, ep);
    if (!rc && md->peratom) {
        rc = h5out_write_doubles(&run->h5, g, "pe", p->pe, n, 1, "eV", ep);
        md_peratom_stress(md, o->stress);
        for (long k = 0; k < 6 * n; k++)
            o->stress[k] *= UNITS_EVA3_TO_GPA;
        if (!rc)
            rc = h5out_write_doubles(&run->h5, g, "stress", o->stress, n, 6, "GPa", ep);
    }
    for (int k = 0; !rc && k < p->nfields; k++)
        rc = h5out_write_doubles(&run->h5, g, p->fields[k].name, p->fields[k].data, n,
                                 p->fields[k].ncomp, "1", ep);
    h5out_end_snapshot(&run->h5, g);
    return rc;
}

/* With XYZ output on, the last configuration also goes to final.xyz, one
 * frame that system.read_xyz reads back (positions and velocities), so a
 * campaign's preparation job can hand an equilibrated state to later jobs.
 * Written to a temporary name and renamed: never seen half-written. */
static int write_final(struct run *run, struct md *md, struct err *e)
{
    char path[4096];
    run_path(run, "final.xyz", path, sizeof path);
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    if (xyz_write_frame(w.f, md->p, &md->box, md->step, md->time, NULL) != 0) {
        wfile_discard(&w);
        return err_set(e, ERR_RUNTIME, "cannot write %s: write error", path);
    }
    return wfile_commit(&w, e);
}

/* The optional XYZ columns of md's particles: the per-atom energies and
 * stresses when this step computed them (the engine asks for them on XYZ
 * steps; natoms, the whole system's count, gives each atom's volume), and
 * the chosen per-particle field as an integer column. */
static int xyz_columns(struct md_output *o, struct md *md, long natoms, struct xyz_extra *x)
{
    struct particles *p = md->p;
    memset(x, 0, sizeof *x);
    if (o->xyz_field >= 0 && o->xyz_field < p->nfields) {
        int *buf = mem_realloc(o->xyz_buf, (size_t)(p->n_owned + 1) * sizeof *buf);
        if (!buf)
            return err_nomem(&o->err, "XYZ column");
        o->xyz_buf = buf;
        const double *f = particles_field(p, o->xyz_field);
        for (int i = 0; i < p->n_owned; i++)
            buf[i] = (int)f[i];
        x->int_name = p->fields[o->xyz_field].name;
        x->int_values = buf;
    }
    if (md->peratom) {
        if (grow_atoms(o, p->n_owned) != 0)
            return ERR_RUNTIME;
        md_peratom_stress_of(md, natoms, o->stress);
        for (long k = 0; k < 6L * p->n_owned; k++)
            o->stress[k] *= UNITS_EVA3_TO_GPA;
        x->pe = p->pe;
        x->stress = o->stress;
    }
    return 0;
}

/* An extended XYZ frame of md's particles. */
static int xyz_frame(struct md_output *o, struct run *run, struct md *md)
{
    struct xyz_extra x;
    int rc = xyz_columns(o, md, md_natoms(md), &x);
    if (rc)
        return rc;
    if (xyz_write_frame(run->xyz, md->p, &md->box, md->step, md->time, &x) != 0)
        return err_set(&o->err, ERR_RUNTIME, "cannot write %s/snapshots.xyz: write error",
                       run->opt.out_dir);
    return run_xyz_frame_done(run, &o->err);
}

/* Rank 0's writers while the windows of a decomposed run's XYZ step pass. */
struct xyz_walk {
    struct md_output *o;
    struct run *run;
    const struct md *md;
    long natoms;          /* of every rank: the atoms' volume V/N */
    int frame;            /* a frame of snapshots.xyz is due */
    struct wfile *final;  /* final.xyz (the last step), or NULL */
};

static int xyz_window(void *ctx, struct particles *q, struct err *e)
{
    const struct xyz_walk *w = ctx;
    struct md view = *w->md;   /* the window's particles in place of the brick's */
    view.p = q;
    view.halo = NULL;
    (void)e;   /* the messages go to o->err, as the serial frames' */
    if (w->frame) {
        struct xyz_extra x;
        int rc = xyz_columns(w->o, &view, w->natoms, &x);
        if (rc)
            return rc;
        if (xyz_write_particles(w->run->xyz, q, &x) != 0)
            return err_set(&w->o->err, ERR_RUNTIME, "cannot write %s/snapshots.xyz: write error",
                           w->run->opt.out_dir);
    }
    if (w->final && xyz_write_particles(w->final->f, q, NULL) != 0)
        return err_set(&w->o->err, ERR_RUNTIME, "cannot write %s: write error", w->final->path);
    return 0;
}

/* The XYZ frame (and final.xyz at the end) of a decomposed run: rank 0
 * writes the headers with the totals, then the atoms of every rank in id
 * order, a window at a time (halo_gather_windows), so no rank holds them
 * all. */
static int xyz_gathered(struct md_output *o, struct run *run, struct md *md, long total)
{
    double n = (double)md->p->n_owned;
    halo_sum(md->halo, &n, 1);
    struct wfile final = {0};
    struct xyz_walk w = {o, run, md, (long)n, run->xyz && md->step % run->out.xyz_every == 0,
                         NULL};
    int rc = 0;
    if (run->xyz && md->step == total) {   /* rank 0 */
        char path[4096];
        run_path(run, "final.xyz", path, sizeof path);
        rc = wfile_open(&final, path, &o->err);
        if (!rc) {
            w.final = &final;
            xyz_write_header(final.f, (long)n, &md->box, md->step, md->time, 0, 0, NULL);
        }
    }
    if (!rc && w.frame) {
        const struct particles *p = md->p;
        int field = o->xyz_field >= 0 && o->xyz_field < p->nfields;
        xyz_write_header(run->xyz, (long)n, &md->box, md->step, md->time, md->peratom,
                         md->peratom, field ? p->fields[o->xyz_field].name : NULL);
    }
    rc = halo_agree(md->halo, rc, &o->err);
    if (!rc)
        rc = halo_gather_windows(md->halo, md->p, 0, xyz_window, &w, &o->err);
    if (!rc && w.frame)
        rc = run_xyz_frame_done(run, &o->err);
    if (w.final && !rc)
        rc = wfile_commit(&final, &o->err);
    else if (w.final)
        wfile_discard(&final);
    if (o->cap_atoms > md->p->n_owned) {   /* rank 0 keeps no scratch for a window */
        free(o->stress);
        free(o->ibuf);
        o->stress = NULL;
        o->ibuf = NULL;
        o->cap_atoms = 0;
    }
    return rc;
}

int md_output_step(struct md_output *o, struct run *run, struct md *md, long total)
{
    long s = md->step;
    int rc = 0;
    if (md->halo) {   /* every rank takes part in the gathers */
        timer_start(&run->timers, TIMER_OUTPUT);
        /* rank 0 writes: a failure there stops every rank before the next
         * gather, which rank 0 would never join */
        if (run_due(s, total, run->out.thermo_every))
            rc = halo_agree(md->halo, thermo_row(o, run, md), &o->err);
        if (!rc && run_due(s, total, run->out.snapshot_every))
            rc = halo_agree(md->halo, md_output_snapshot(o, run, md), &o->err);
        if (!rc && run->out.xyz_every > 0 && (s % run->out.xyz_every == 0 || s == total))
            rc = halo_agree(md->halo, xyz_gathered(o, run, md, total), &o->err);
        timer_stop(&run->timers, TIMER_OUTPUT);
        return rc;
    }
    timer_start(&run->timers, TIMER_OUTPUT);
    if (run_due(s, total, run->out.thermo_every))
        rc = thermo_row(o, run, md);
    if (!rc && run_due(s, total, run->out.snapshot_every))
        rc = md_output_snapshot(o, run, md);
    if (!rc && run->xyz && run->out.xyz_every > 0 && s % run->out.xyz_every == 0)
        rc = xyz_frame(o, run, md);
    if (!rc && run->xyz && s == total)
        rc = write_final(run, md, &o->err);
    timer_stop(&run->timers, TIMER_OUTPUT);
    return rc;
}

void md_output_decomposition(struct run *run, const struct md *md)
{
    decomp_record_write(run, md->halo, md->p);
}

int md_output_end(struct md_output *o, struct run *run, struct err *e)
{
    int rc = run_write_series_table(run, o->series, o->nrows, MD_THERMO_COLS, thermo_cols, thermo_units, e);
    free(o->series);
    free(o->stress);
    free(o->ibuf);
    free(o->xyz_buf);
    memset(o, 0, sizeof *o);
    return rc;
}
