/* md_analysis: structure, displaced, sputtered and crater analysis of MD runs. */
#include "analysis/md_analysis.h"

#include <stdlib.h>
#include <string.h>

static const char *const class_cols[STRUCT_NCLASSES] = {
    "n_other12", "n_fcc", "n_hcp", "n_bcc", "n_ico", "n_not12", "n_surface", "n_coord4", "n_not4"};

int md_analysis_read(struct cfg_obj *root, const struct structure_params *def, long def_every,
                     struct md_analysis *a)
{
    memset(a, 0, sizeof *a);
    struct cfg_obj ao, so;
    int rc;
    if ((rc = cfg_section(root, "analysis", &ao)) ||
        (rc = cfg_int(&ao, "every", def_every, CFG_GE(0), &a->every)) ||
        (rc = cfg_section(&ao, "structure", &so)) ||
        (rc = structure_params_read(&so, def, &a->sp)) || (rc = cfg_close(&so)))
        return rc;
    return cfg_close(&ao);
}

static void add_col(struct md_analysis *a, const char *name, const char *unit)
{
    a->cols[a->ncols] = name;
    a->units[a->ncols] = unit;
    a->ncols++;
}

int md_analysis_attach(struct md_analysis *a, struct particles *p,
                       const struct md_analysis_opts *o, int nthreads, struct err *e)
{
    a->o = *o;
    a->sp.nthreads = nthreads;
    if ((a->f_structure = particles_add_field(p, "structure", 1, 0, e)) < 0 ||
        (a->f_displaced = particles_add_field(p, "displaced", 1, 0, e)) < 0)
        return ERR_RUNTIME;
    a->f_sputtered = a->f_crater = -1;
    if (o->sputter && (a->f_sputtered = particles_add_field(p, "sputtered", 1, 0, e)) < 0)
        return ERR_RUNTIME;
    if (o->crater && (a->f_crater = particles_add_field(p, "crater", 1, 0, e)) < 0)
        return ERR_RUNTIME;
    a->ncols = 0;
    add_col(a, "analysis_time_ps", "ps");
    for (int k = 0; k < STRUCT_NCLASSES; k++)
        add_col(a, class_cols[k], "1");
    add_col(a, "displaced", "1");
    if (o->sputter) {
        add_col(a, "sputtered_atoms", "1");
        add_col(a, "sputtered_clusters", "1");
    }
    if (o->crater) {
        add_col(a, "crater_depth_A", "Å");
        add_col(a, "crater_volume_A3", "Å^3");
        add_col(a, "crater_extent_100_A", "Å");
        add_col(a, "crater_extent_110_A", "Å");
        add_col(a, "rim_height_A", "Å");
    }
    if (o->damage_shape) {
        add_col(a, "damage_atoms", "1");
        add_col(a, "damage_lmax_A2", "Å^2");
        add_col(a, "damage_lmin_A2", "Å^2");
        add_col(a, "damage_eig_ratio", "1");
        add_col(a, "damage_axis_deg", "deg");
        add_col(a, "damage_extent_100_A", "Å");
        add_col(a, "damage_extent_110_A", "Å");
        add_col(a, "damage_extent_ratio", "1");
    }
    return 0;
}

int md_analysis_due(const struct md_analysis *a, const struct run *run, long s, long total)
{
    if (run_due(s, total, run->out.snapshot_every))
        return 1;
    return a->every > 0 && s % a->every == 0;
}

int md_analysis_column(const struct md_analysis *a, const char *name)
{
    for (int k = 0; k < a->ncols; k++)
        if (strcmp(a->cols[k], name) == 0)
            return k;
    return -1;
}

int md_analysis_reserve(struct md_analysis *a, int n, struct err *e)
{
    if (n <= a->cap)
        return 0;
    int cap = n + n / 4 + 16;
    int *c = realloc(a->cls, (size_t)cap * sizeof *c);
    if (c)
        a->cls = c;
    unsigned char *s1 = realloc(a->sel, (size_t)cap), *s2 = realloc(a->sput, (size_t)cap),
                  *s3 = realloc(a->floor_atom, (size_t)cap), *s4 = realloc(a->damaged, (size_t)cap);
    if (s1) a->sel = s1;
    if (s2) a->sput = s2;
    if (s3) a->floor_atom = s3;
    if (s4) a->damaged = s4;
    double *m = realloc(a->mass, (size_t)cap * sizeof *m);
    if (m)
        a->mass = m;
    double *sc = realloc(a->shape_scratch, (size_t)(2 * cap) * sizeof *sc);
    if (sc)
        a->shape_scratch = sc;
    if (!c || !s1 || !s2 || !s3 || !s4 || !m || !sc)
        return err_nomem(e, "analysis buffers");
    a->cap = cap;
    return 0;
}

void md_analysis_mark(struct md_analysis *a, struct particles *p)
{
    int n = p->n_owned;
    for (int i = 0; i < n; i++) {
        a->sel[i] = (unsigned char)!(p->mask[i] & a->o.exclude_mask);
        a->mass[i] = p->mass[p->type[i]];
    }
    a->counted = structure_count(a->cls, n, a->sel, a->counts);
    a->displaced = 0;
    double *fs = particles_field(p, a->f_structure), *fd = particles_field(p, a->f_displaced);
    for (int i = 0; i < n; i++) {
        int disp = a->sel[i] && structure_is_displaced(a->sp.ref, a->cls[i]);
        a->displaced += disp;
        fs[i] = a->cls[i];
        fd[i] = disp;
        /* the damage below the surface: not the rim, not what flies off */
        a->damaged[i] = (unsigned char)(disp && p->x[3 * i + 2] < a->o.surface - a->o.crater_threshold);
    }
}

struct sputter_params md_analysis_sputter_params(const struct md_analysis *a)
{
    /* connection and margin: the surface radius (about three neighbour
     * shells), so hot rim atoms with stretched bonds stay attached */
    return (struct sputter_params){2, a->o.surface, a->sp.surface_radius, a->sp.surface_radius};
}

struct crater_params md_analysis_crater_params(const struct md_analysis *a)
{
    return (struct crater_params){a->o.surface, {a->o.center[0], a->o.center[1]},
                                  {a->o.lat_lo[0], a->o.lat_lo[1]},
                                  {a->o.lat_hi[0], a->o.lat_hi[1]},
                                  a->o.crater_bin, a->o.crater_threshold};
}

int md_analysis_push_latest(struct md_analysis *a, double time, struct err *e)
{
    double row[MDA_MAXCOLS];
    int k = 0;
    row[k++] = time;
    for (int c = 0; c < STRUCT_NCLASSES; c++)
        row[k++] = (double)a->counts[c];
    row[k++] = (double)a->displaced;
    if (a->o.sputter) {
        row[k++] = (double)a->sputter.atoms;
        row[k++] = (double)a->sputter.clusters;
    }
    if (a->o.crater) {
        row[k++] = a->crater.depth;
        row[k++] = a->crater.volume;
        row[k++] = 0.5 * (a->crater.extent[0] + a->crater.extent[1]);
        row[k++] = 0.5 * (a->crater.extent[2] + a->crater.extent[3]);
        row[k++] = a->crater.rim;
    }
    if (a->o.damage_shape) {
        const struct damage_shape *ds = &a->shape;
        row[k++] = (double)ds->n;
        row[k++] = ds->lmax;
        row[k++] = ds->lmin;
        row[k++] = ds->eig_ratio;
        row[k++] = ds->axis_deg;
        row[k++] = ds->extent_100;
        row[k++] = ds->extent_110;
        row[k++] = ds->extent_ratio;
    }
    return md_analysis_push_row(a, row, e);
}

int md_analysis_run(struct md_analysis *a, struct particles *p, const struct box *box, double time,
                    struct timers *timers, struct err *e)
{
    int n = p->n_owned;
    if (timers)
        timer_start(timers, TIMER_ANALYSIS);
    int rc = md_analysis_reserve(a, n, e);
    if (!rc)
        rc = structure_classify_particles(&a->sp, p, box, &a->fr, a->cls, e);
    if (rc)
        goto out;
    md_analysis_mark(a, p);
    if (a->o.damage_shape &&
        (rc = damage_shape_measure(p->x, n, a->damaged, a->shape_scratch, &a->shape, e)))
        goto out;
    if (a->o.sputter) {
        struct sputter_params spp = md_analysis_sputter_params(a);
        if ((rc = sputter_find(&a->fr, p->v, a->mass, &spp, a->sput, &a->sputter, e)))
            goto out;
        double *f = particles_field(p, a->f_sputtered);
        for (int i = 0; i < n; i++)
            f[i] = a->sput[i] == SPUTTER_LEFT;
    }
    if (a->o.crater) {
        struct crater_params cp = md_analysis_crater_params(a);
        /* the target: the largest connected group (not the incoming
         * projectile, not what flew off) */
        for (int i = 0; i < n; i++)
            a->sel[i] = a->o.sputter ? a->sput[i] == SPUTTER_TARGET : 1;
        if ((rc = crater_measure(p->x, n, a->sel, &cp, a->floor_atom, &a->crater, e)))
            goto out;
        double *f = particles_field(p, a->f_crater);
        for (int i = 0; i < n; i++)
            f[i] = a->floor_atom[i];
    }
    rc = md_analysis_push_latest(a, time, e);
out:
    if (timers)
        timer_stop(timers, TIMER_ANALYSIS);
    return rc;
}

int md_analysis_push_row(struct md_analysis *a, const double *row, struct err *e)
{
    if (a->nrows >= a->caprows) {
        long cap = a->caprows ? 2 * a->caprows : 128;
        double *r = realloc(a->rows, (size_t)cap * a->ncols * sizeof *r);
        if (!r)
            return err_nomem(e, "analysis series");
        a->rows = r;
        a->caprows = cap;
    }
    memcpy(a->rows + a->nrows * a->ncols, row, (size_t)a->ncols * sizeof *row);
    a->nrows++;
    return 0;
}

void md_analysis_release(struct md_analysis *a)
{
    frame_free(&a->fr);
    free(a->cls);
    free(a->sel);
    free(a->sput);
    free(a->floor_atom);
    free(a->damaged);
    free(a->mass);
    free(a->shape_scratch);
    a->cls = NULL;
    a->sel = a->sput = a->floor_atom = a->damaged = NULL;
    a->mass = a->shape_scratch = NULL;
    a->cap = 0;
}

int md_analysis_finish(struct md_analysis *a, struct run *run, struct err *e)
{
    int rc = 0;
    if (a->nrows == 0)
        return 0;
    double *col = malloc((size_t)a->nrows * sizeof *col);
    if (!col)
        return err_nomem(e, "analysis series");
    for (int k = 0; k < a->ncols && !rc; k++) {
        for (long r = 0; r < a->nrows; r++)
            col[r] = a->rows[r * a->ncols + k];
        result_series(&run->result, a->cols[k], col, (int)a->nrows, a->units[k]);
        if (run->h5_open)
            rc = h5out_write_series(&run->h5, a->cols[k], col, a->nrows, a->units[k], e);
    }
    free(col);
    return rc;
}

void md_analysis_free(struct md_analysis *a)
{
    md_analysis_release(a);
    free(a->rows);
    memset(a, 0, sizeof *a);
}
