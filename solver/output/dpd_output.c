/* dpd_output: the DPD run's thermo, snapshots and frames. */
#include "output/dpd_output.h"

#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "output/xyz_write.h"
#include "util/mem.h"

static const char *const cols[DPD_THERMO_COLS] = {"step",      "time_ps", "pe_eV",
                                                  "ke_eV",     "uint_eV", "etotal_eV",
                                                  "temp_K",    "press_GPa"};
static const char *const units[DPD_THERMO_COLS] = {"1", "ps", "eV", "eV", "eV", "eV", "K", "GPa"};

double dpd_total_energy(const struct dpd *d)
{
    return d->epot + dpd_kinetic_energy(d) + dpd_internal_energy(d);
}

int dpd_output_begin(struct dpd_output *o, struct run *run, struct err *e)
{
    memset(o, 0, sizeof *o);
    if (run_thermo_header(run, cols, DPD_THERMO_COLS) != 0)
        return err_set(e, ERR_RUNTIME, "%s", run->write_err.msg);
    return 0;
}

int dpd_output_resume(struct dpd_output *o, struct run *run, const double *rows, long nrows,
                      struct err *e)
{
    if (nrows <= 0)
        return 0;
    double *sr = mem_alloc((size_t)nrows * DPD_THERMO_COLS * sizeof *sr);
    if (!sr)
        return err_nomem(e, "thermo series");
    memcpy(sr, rows, (size_t)nrows * DPD_THERMO_COLS * sizeof *sr);
    free(o->series);
    o->series = sr;
    o->nrows = o->cap = nrows;
    for (long i = 0; i < nrows; i++)
        run_thermo_row(run, rows + i * DPD_THERMO_COLS, DPD_THERMO_COLS);
    return 0;
}

int dpd_output_checkpoint_write(const struct dpd_output *o, struct ckpt *ck)
{
    return ckpt_put_doubles(ck, "thermo_rows", o->series, o->nrows * DPD_THERMO_COLS);
}

int dpd_output_checkpoint_read(struct ckpt *ck, double **rows, long *nrows, struct err *e)
{
    (void)e;   /* ckpt_get_rows reports through the checkpoint's err */
    return ckpt_get_rows(ck, "thermo_rows", DPD_THERMO_COLS, rows, nrows);
}

static int thermo_row(struct dpd_output *o, struct run *run, struct dpd *d)
{
    double P[6];
    dpd_pressure_tensor(d, P);
    double ke = dpd_kinetic_energy(d), u = dpd_internal_energy(d);
    double row[DPD_THERMO_COLS] = {(double)d->step, d->time,          d->epot,
                                   ke,              u,                d->epot + ke + u,
                                   dpd_temperature(d), (P[0] + P[1] + P[2]) / 3.0 * UNITS_EVA3_TO_GPA};
    run_thermo_row(run, row, DPD_THERMO_COLS);
    if (o->nrows >= o->cap) {
        long cap = o->cap ? 2 * o->cap : 256;
        double *s = mem_realloc(o->series, (size_t)cap * DPD_THERMO_COLS * sizeof *s);
        if (!s)
            return ERR_RUNTIME;
        o->series = s;
        o->cap = cap;
    }
    memcpy(o->series + o->nrows * DPD_THERMO_COLS, row, sizeof row);
    o->nrows++;
    return 0;
}

static const char *field_unit(const char *name)
{
    if (strcmp(name, "u_internal") == 0)
        return "eV";
    if (strcmp(name, "x_ref") == 0)
        return "Å";
    return "1";
}

static int snapshot_of(struct dpd_output *o, struct run *run, struct dpd *d)
{
    struct particles *p = d->p;
    long n = p->n_owned;
    struct err e = {0};
    int grow = 0;
    if (n > o->cap_atoms) {
        int64_t *ib = mem_realloc(o->ibuf, (size_t)(n ? n : 1) * sizeof *ib);
        if (ib) {
            o->ibuf = ib;
            o->cap_atoms = n;
        }
        grow = ib ? 0 : ERR_RUNTIME;
    }
    /* collective (bricks): an allocation that failed on one rank stops all */
    if (h5out_par_agree(&run->h5, grow, &e) != 0)
        return ERR_RUNTIME;
    hid_t g = h5out_begin_snapshot(&run->h5, "particles", d->step, d->time, n, &e);
    if (g < 0)
        return ERR_RUNTIME;
    int rc = run_snapshot_particles(run, g, p, &d->box, o->ibuf, &e);
    if (!rc && d->peratom)
        rc = h5out_write_doubles(&run->h5, g, "pe", p->pe, n, 1, "eV", &e);
    for (int k = 0; !rc && k < p->nfields; k++)
        rc = h5out_write_doubles(&run->h5, g, p->fields[k].name, p->fields[k].data, n,
                                 p->fields[k].ncomp, field_unit(p->fields[k].name), &e);
    h5out_end_snapshot(&run->h5, g);
    return rc;
}

/* Bricks: every rank writes its own particles' rows into the one
 * fields.h5, collectively (h5out_par_begin). */
int dpd_output_snapshot(struct dpd_output *o, struct run *run, struct dpd *d)
{
    if (!d->p->halo)
        return run->h5_open ? snapshot_of(o, run, d) : 0;
    if (!run->out.hdf5)
        return 0;
    struct err e = {0};
    int rc = run_h5_par_begin(run, d->p->n_owned, &e);
    if (!rc)
        rc = snapshot_of(o, run, d);
    return run_h5_par_end(run, rc, &e) ? ERR_RUNTIME : 0;
}

static int xyz_window(void *ctx, struct particles *q, struct err *e)
{
    FILE *f = ctx;
    (void)e;
    return xyz_write_particles(f, q, NULL) ? ERR_RUNTIME : 0;
}

/* Bricks: the XYZ frame written by rank 0 as a serial run writes its own
 * (the particles of every rank in id order), a window at a time
 * (halo_gather_windows), so no rank holds them all.  Collective. */
static int xyz_windows(struct run *run, const struct dpd *d)
{
    double n = (double)d->p->n_owned;
    halo_sum(d->p->halo, &n, 1);
    if (run->xyz)   /* rank 0 */
        xyz_write_header(run->xyz, (long)n, &d->box, d->step, d->time, 0, 0, NULL);
    struct err e = {0};
    int rc = halo_gather_windows(d->p->halo, d->p, 0, xyz_window, run->xyz, &e);
    if (!rc && run->xyz)
        rc = run_xyz_frame_done(run, NULL);
    return halo_agree(d->p->halo, rc, &e);
}

int dpd_output_step(struct dpd_output *o, struct run *run, struct dpd *d, long total)
{
    long s = d->step;
    int rc = 0;
    timer_start(&run->timers, TIMER_OUTPUT);
    if (run_due(s, total, run->out.thermo_every))
        rc = thermo_row(o, run, d);
    int snap = run_due(s, total, run->out.snapshot_every);
    int frame = run->out.xyz_every > 0 && s % run->out.xyz_every == 0;
    if (!rc && snap)   /* bricks: collective, every rank */
        rc = dpd_output_snapshot(o, run, d);
    if (!rc && frame && d->p->halo)   /* bricks: every rank takes part */
        rc = xyz_windows(run, d);
    else if (!rc && frame && run->xyz)
        rc = xyz_write_frame(run->xyz, d->p, &d->box, s, d->time, NULL)
                 ? ERR_RUNTIME
                 : run_xyz_frame_done(run, NULL);
    timer_stop(&run->timers, TIMER_OUTPUT);
    return rc;
}

int dpd_output_end(struct dpd_output *o, struct run *run, struct err *e)
{
    int rc = run_write_series_table(run, o->series, o->nrows, DPD_THERMO_COLS, cols, units, e);
    free(o->series);
    free(o->ibuf);
    memset(o, 0, sizeof *o);
    return rc;
}
