/* run: output files, timing report and result.json of one simulation. */
#include "output/run.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include "output/lammps_data_write.h"
#include "output/provenance.h"
#include "output/xyz_write.h"
#include "util/canon.h"
#include "util/mem.h"

int output_settings_read(struct cfg_obj *root, struct output_settings *o)
{
    struct cfg_obj s;
    int rc = cfg_section(root, "output", &s);
    if (rc)
        return rc;
    if ((rc = cfg_int(&s, "thermo_every", 100, CFG_GE(0), &o->thermo_every)) ||
        (rc = cfg_int(&s, "snapshot_every", 0, CFG_GE(0), &o->snapshot_every)) ||
        (rc = cfg_int(&s, "xyz_every", 0, CFG_GE(0), &o->xyz_every)) ||
        (rc = cfg_bool(&s, "hdf5", 1, &o->hdf5)))
        return rc;
    /* checkpoint_every enters the canonical case only when set: cases that
     * do not ask for checkpoints keep the job keys they had before it
     * existed (checkpoints change round-off, engine/sim.h, so a run with
     * them is another job) */
    o->checkpoint_every = 0;
    if (json_object_get(s.node, "checkpoint_every")) {
        if ((rc = cfg_int(&s, "checkpoint_every", 0, CFG_GE(0), &o->checkpoint_every)))
            return rc;
        if (o->checkpoint_every == 0)
            json_object_del(s.node, "checkpoint_every");
    }
    int has_final;
    o->final_state = NULL;
    if ((rc = cfg_string_opt(&s, "final_state", &o->final_state, &has_final)))
        return rc;
    if (has_final) {
        const char *dot = strrchr(o->final_state, '.');
        if (strchr(o->final_state, '/') || !dot ||
            (strcmp(dot, ".data") != 0 && strcmp(dot, ".xyz") != 0))
            return cfg_error_at(s.cfg, "output.final_state",
                                "'%s' must be a file name (no directory) ending in .data (LAMMPS "
                                "data) or .xyz (extended XYZ)",
                                o->final_state);
    }
    return cfg_close(&s);
}

static int mkdir_p(const char *dir)
{
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s", dir);
    for (char *s = tmp + 1; *s; s++)
        if (*s == '/') {
            *s = '\0';
            if (wfile_mkdir(tmp, 0777) != 0 && errno != EEXIST)
                return -1;
            *s = '/';
        }
    if (wfile_mkdir(tmp, 0777) != 0 && errno != EEXIST)
        return -1;
    return 0;
}

void run_path(const struct run *r, const char *name, char *out, size_t len)
{
    snprintf(out, len, "%s/%s", r->opt.out_dir, name);
}

void run_log(struct run *r, const char *fmt, ...)
{
    if (!r->log)
        return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(r->log, fmt, ap);
    va_end(ap);
    fputc('\n', r->log);
    fflush(r->log);
}

int run_due(long s, long total, long every)
{
    if (s == 0 || s == total)
        return 1;
    return every > 0 && s % every == 0;
}

int run_open(struct run *r, const struct run_options *opt, const struct output_settings *out,
             json_t *case_doc, uint64_t seed, const char *title, struct err *e)
{
    memset(r, 0, sizeof *r);
    r->opt = *opt;
    r->out = *out;
    r->case_doc = case_doc;
    r->seed = seed;
    snprintf(r->title, sizeof r->title, "%s", title ? title : "");
    r->log = opt->quiet || opt->rank != 0 ? NULL : stderr;
    if (canon_key(case_doc, r->case_key) != 0)
        return err_nomem(e, "case key");
    if (result_init(&r->result) != 0) {
        result_free(&r->result);
        return err_nomem(e, "result");
    }
    timer_start(&r->timers, TIMER_TOTAL);
    if (opt->rank != 0)
        return 0;   /* replicated ranks compute; rank 0 writes */
    if (mkdir_p(opt->out_dir) != 0) {
        int rc = err_set(e, ERR_RUNTIME, "%s: cannot create output directory: %s", opt->out_dir,
                         strerror(errno));
        run_discard(r);
        return rc;
    }
    char path[4096];
    if (out->hdf5) {
        run_path(r, "fields.h5", path, sizeof path);
        int rc = h5out_create(&r->h5, path, case_doc, e);
        if (rc) {
            run_discard(r);
            return rc;
        }
        r->h5_open = 1;
    }
    if (out->xyz_every > 0) {
        run_path(r, "snapshots.xyz", path, sizeof path);
        int rc = wfile_open(&r->xyz_w, path, e);
        if (rc) {
            run_discard(r);
            return rc;
        }
        r->xyz = r->xyz_w.f;
    }
    return 0;
}

int run_write_final_state(struct run *r, const struct particles *p, const struct box *b,
                          long step, double time, struct err *e)
{
    const char *name = r->out.final_state;
    /* replicated data: every rank holds the state, rank 0 writes it (two
     * ranks renaming one temporary file failed) */
    if (!name || r->opt.rank != 0)
        return 0;
    char path[4096];
    run_path(r, name, path, sizeof path);
    const char *dot = strrchr(name, '.');
    int rc = 0;
    if (dot && strcmp(dot, ".xyz") == 0) {
        struct wfile w;
        rc = wfile_open(&w, path, e);
        if (rc)
            return rc;
        if (xyz_write_frame(w.f, p, b, step, time, NULL) != 0) {
            wfile_discard(&w);
            return err_set(e, ERR_RUNTIME, "cannot write %s: write error", path);
        }
        rc = wfile_commit(&w, e);
    } else {
        char title[512];
        run_final_state_title(r, step, time, title, sizeof title);
        rc = lammps_data_write(path, p, b, title, e);
    }
    if (!rc)
        run_final_state_recorded(r);
    return rc;
}

void run_final_state_title(const struct run *r, long step, double time, char *out, size_t len)
{
    snprintf(out, len, "cascade-solver final state: case %s, step %ld, time %g ps", r->case_key,
             step, time);
}

void run_final_state_recorded(struct run *r)
{
    result_artifact(&r->result, "final_state", r->out.final_state);
}

int run_thermo_header(struct run *r, const char *const *columns, int n)
{
    if (r->opt.rank != 0)
        return 0;
    char path[4096];
    run_path(r, "thermo.csv", path, sizeof path);
    if (wfile_open(&r->thermo_w, path, &r->write_err) != 0)
        return -1;
    r->thermo_csv = r->thermo_w.f;
    /* provenance as a comment line (gnuplot, numpy and pandas skip '#') */
    fprintf(r->thermo_csv, "# cascade-solver %s (git %s), case key %s\n", provenance_version(),
            provenance_git_hash(), r->case_key);
    for (int k = 0; k < n; k++)
        fprintf(r->thermo_csv, "%s%s", k ? "," : "", columns[k]);
    fputc('\n', r->thermo_csv);
    return 0;
}

/* A stream's write failed (wfile discarded it): keep the first error. */
static int stream_failed(struct run *r, FILE **alias, const struct err *e)
{
    *alias = NULL;
    if (!r->write_err.code)
        r->write_err = *e;
    return ERR_RUNTIME;
}

int run_thermo_row(struct run *r, const double *values, int n)
{
    if (!r->thermo_csv)
        return r->write_err.code ? ERR_RUNTIME : 0;
    for (int k = 0; k < n; k++)
        fprintf(r->thermo_csv, "%s%.10g", k ? "," : "", values[k]);
    fputc('\n', r->thermo_csv);
    struct err e = {0};
    if (wfile_flush(&r->thermo_w, &e) != 0)
        return stream_failed(r, &r->thermo_csv, &e);
    return 0;
}

int run_xyz_frame_done(struct run *r, struct err *e)
{
    if (!r->xyz)
        return 0;
    struct err e2 = {0};
    if (wfile_flush(&r->xyz_w, &e2) != 0) {
        stream_failed(r, &r->xyz, &e2);
        return err_set(e, ERR_RUNTIME, "%s", e2.msg);
    }
    return 0;
}

int run_h5_par_begin(struct run *r, long n_local, struct err *e)
{
    if (r->opt.rank != 0 && !r->h5.path[0]) {   /* the other ranks name the file once */
        char path[4096];
        run_path(r, "fields.h5", path, sizeof path);
        h5out_par_attach(&r->h5, path);
    }
    return h5out_par_begin(&r->h5, n_local, e);
}

int run_h5_par_end(struct run *r, int rc, struct err *e)
{
    return h5out_par_end(&r->h5, rc, e);
}

int run_snapshot_cell(struct run *r, hid_t g, const struct box *b, struct err *e)
{
    int pbc[3];
    char boundary[64];
    snprintf(boundary, sizeof boundary, "%s %s %s", boundary_names[b->bc[0]],
             boundary_names[b->bc[1]], boundary_names[b->bc[2]]);
    for (int d = 0; d < 3; d++)
        pbc[d] = b->bc[d] == BOUNDARY_PERIODIC;
    return h5out_snapshot_cell(&r->h5, g, b->lo, b->hi, b->tilt, pbc, boundary, e);
}

int run_snapshot_particles(struct run *r, hid_t g, const struct particles *p,
                           const struct box *b, int64_t *ibuf, struct err *e)
{
    long n = p->n_owned;
    int rc = run_snapshot_cell(r, g, b, e);
    if (!rc)
        rc = h5out_write_doubles(&r->h5, g, "position", p->x, n, 3, "Å", e);
    if (!rc)
        rc = h5out_write_doubles(&r->h5, g, "velocity", p->v, n, 3, "Å/ps", e);
    if (!rc)
        rc = h5out_write_doubles(&r->h5, g, "force", p->f, n, 3, "eV/Å", e);
    for (long i = 0; !rc && i < n; i++)
        ibuf[i] = p->id[i];
    if (!rc)
        rc = h5out_write_ints(&r->h5, g, "id", ibuf, n, "1", e);
    for (long i = 0; !rc && i < n; i++)
        ibuf[i] = p->type[i];
    if (!rc)
        rc = h5out_write_ints(&r->h5, g, "type", ibuf, n, "1", e);
    return rc;
}

int run_write_series_table(struct run *r, const double *rows, long nrows, int ncols,
                           const char *const *names, const char *const *units, struct err *e)
{
    if (!r->h5_open || nrows <= 0)
        return 0;
    double *col = mem_alloc((size_t)nrows * sizeof *col);
    if (!col)
        return err_nomem(e, "thermo series");
    int rc = 0;
    for (int k = 0; k < ncols && !rc; k++) {
        for (long i = 0; i < nrows; i++)
            col[i] = rows[i * ncols + k];
        rc = h5out_write_series(&r->h5, names[k], col, nrows, units[k], e);
    }
    free(col);
    return rc;
}

static double peak_rss_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0;   /* Linux: kB */
}

void run_discard(struct run *r)
{
    wfile_discard(&r->thermo_w);
    wfile_discard(&r->xyz_w);
    r->thermo_csv = r->xyz = NULL;
    if (r->h5_open)
        h5out_discard(&r->h5);
    r->h5_open = 0;
    result_free(&r->result);
}

int run_close(struct run *r, const char *status, const char *message, long steps, long particles,
              struct err *e)
{
    int rc = 0;
    timer_stop(&r->timers, TIMER_TOTAL);
    /* The streams become their files only now (written as NAME.tmp so far),
     * and only for a run that ended as a result (ok, or diverged: its
     * history shows how); a run that failed keeps none of them, so no
     * reader takes a stream cut short for a run's output. */
    struct err e2 = {0};
    int keep = strcmp(status, "failed") != 0;
    if (r->write_err.code) {
        rc = err_set(e, ERR_RUNTIME, "%s", r->write_err.msg);
        keep = 0;
    }
    if (keep && wfile_commit(&r->thermo_w, &e2) != 0) {
        rc = err_set(e, ERR_RUNTIME, "%s", e2.msg);
        keep = 0;
    }
    if (keep && wfile_commit(&r->xyz_w, &e2) != 0) {
        rc = err_set(e, ERR_RUNTIME, "%s", e2.msg);
        keep = 0;
    }
    wfile_discard(&r->thermo_w);
    wfile_discard(&r->xyz_w);
    r->thermo_csv = r->xyz = NULL;
    if (r->h5_open && keep && h5out_close(&r->h5, &e2) != 0)
        rc = err_set(e, ERR_RUNTIME, "%s", e2.msg);
    else if (r->h5_open && !keep)
        h5out_discard(&r->h5);
    r->h5_open = 0;
    /* result.json must not say ok when a file of the run is missing */
    if (rc && strcmp(status, "ok") == 0) {
        status = "failed";
        message = e->msg;
    }
    /* timing per phase: seconds and µs per particle-step */
    json_t *timing = json_object();
    if (!timing) {
        result_free(&r->result);
        return rc ? rc : err_nomem(e, "result.json");
    }
    double denom = (double)steps * (double)particles;
    for (int t = 0; t < TIMER_COUNT; t++) {
        if (r->timers.calls[t] == 0 && t != TIMER_TOTAL)
            continue;
        json_t *row = json_pack("{s:f, s:I}", "seconds", r->timers.total[t], "calls",
                                (json_int_t)r->timers.calls[t]);
        if (denom > 0)
            json_object_set_new(row, "us_per_particle_step",
                                json_real(1e6 * r->timers.total[t] / denom));
        json_object_set_new(timing, timer_keys[t], row);
    }
    /* CPU seconds of the run and the loop, apart from the timer rows (whose
     * "calls","seconds" layout the bench scripts read as text) */
    json_t *cpu = json_object();
    for (int t = 0; cpu && t < TIMER_COUNT; t++)
        if (timer_counts_cpu(t) && (r->timers.calls[t] > 0 || t == TIMER_TOTAL))
            json_object_set_new(cpu, timer_keys[t], json_real(r->timers.cpu[t]));
    if (cpu)
        json_object_set_new(timing, "cpu_seconds", cpu);
    json_object_set_new(timing, "peak_rss_mib", json_real(peak_rss_mib()));
    json_object_set_new(timing, "threads", json_integer(r->opt.nthreads));
    json_object_set_new(r->result.root, "timing", timing);
    json_object_set_new(r->result.root, "provenance", provenance_json());
    json_object_set_new(r->result.root, "case_key", json_string(r->case_key));
    json_object_set_new(r->result.root, "case", json_deep_copy(r->case_doc));
    json_object_set_new(r->result.root, "steps", json_integer(steps));
    json_object_set_new(r->result.root, "particles", json_integer(particles));
    result_set_status(&r->result, status, message);
    if (r->log && steps > 0 && particles > 0) {
        run_log(r, "timing (%ld steps x %ld particles):", steps, particles);
        for (int t = 0; t < TIMER_COUNT; t++)
            if (r->timers.calls[t] > 0 || t == TIMER_TOTAL)
                run_log(r, "  %-16s %10.3f s  %9.4f us/particle-step", timer_names[t],
                        r->timers.total[t], 1e6 * r->timers.total[t] / denom);
        run_log(r, "  peak memory      %10.1f MiB", peak_rss_mib());
    }
    char path[4096];
    run_path(r, "result.json", path, sizeof path);
    struct err e3 = {0};
    if (r->opt.rank == 0 && result_write(&r->result, path, &e3) != 0 && !rc)
        rc = err_set(e, ERR_RUNTIME, "%s", e3.msg);
    result_free(&r->result);
    return rc;
}
