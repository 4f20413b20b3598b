/*
 * handshake_thermal_case: an MD region at a temperature embedded in MPM,
 * `type: handshake_thermal` -- the finite-temperature handshake that Guo &
 * Yang (2005) leave as future work (couple/handshake_thermal.h).
 *
 * The bar of the other handshake case types, unloaded, with the MD region
 * at T: MD and material points on the lattice at a(T), the MPM with the
 * elastic constants at T (both from type: elastic), region II under the
 * Langevin bath.  The MD atoms start at 2T (a perfect lattice started at 2T
 * settles at T by equipartition) and are thermostatted as a whole for
 * `equilibrate` ps; after that no thermostat acts on them and the run
 * measures how well the handshake keeps the MD region at T for md.steps
 * steps.
 *
 *   thermal:
 *     temperature: 300        K
 *     lattice_constant: 0     Å, a(T) (required: lattice_constant of type: elastic)
 *     damping_time: 0.1       ps, the bath on region II (0: no bath)
 *     coarse_cell: 1          lattice constants: the band's friction spares the
 *                             points' velocity field on this grid (0: friction on
 *                             their whole velocity, as before)
 *     equilibrate: 2          ps under a Langevin thermostat on all MD atoms
 *     equilibrate_damping: 0.1   ps, its damping time
 *     block: 1                ps, the temperature block averages
 *     from_potential: {...}   compute a(T) and the constants at T here, by the
 *                             computation of type: elastic (elastic_thermal.h)
 *                             with the keys of its elastic section (temperature:
 *                             this one) and cells; then lattice_constant and the
 *                             elastic section stay out of the case
 *
 * Metrics (the MD region = the core and region I; after the equilibration):
 * temperature_md_mean, temperature_core_mean, temperature_region_II_mean,
 * temperature_block_first, temperature_block_last, temperature_drift (last
 * block over first, - 1), temperature_max_deviation (largest |block / T -
 * 1|), temperature_trend (the least-squares slope of the blocks over the
 * window, relative to T), bath_heat; the block averages as series.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "couple/handshake_thermal.h"
#include "scenarios/elastic_thermal.h"
#include "scenarios/handshake_case.h"

struct thermal_case {
    struct hs_case c;
    struct hs_thermal bath;
    double equilibrate, eq_damping, block;   /* ps */
    long neq, nblock;                        /* steps */
    uint64_t seed;
    /* the read's common settings (threads, ranks, `parallel`) for the
     * rebuild at a(T) of thermal.from_potential; title not kept */
    struct case_common common;
    /* thermal.from_potential: a(T) and the constants at T computed here */
    int from_potential;
    long auto_cells;
    struct elastic_thermal_settings auto_set;
    struct elastic_thermal auto_out;
    /* block sums of the MD region's, the core's and region II's temperature */
    double *blocks;                          /* 3 per block */
    long nblocks, maxblocks, in_block;
    double sum[3];
};
_Static_assert(offsetof(struct thermal_case, c) == 0, "hs_case first");

/* thermal.from_potential: the settings of the a(T) and constants
 * computation (the keys of type: elastic's elastic section and cells). */
static int read_from_potential(struct cfg_obj *o, struct thermal_case *w)
{
    struct cfg_obj fp;
    int rc = cfg_section_listed(o, "from_potential", &fp, &w->from_potential);
    if (rc || !w->from_potential)
        return rc;
    w->auto_set.md.temperature = w->bath.temperature;
    if ((rc = elastic_thermal_read(&fp, 0, &w->auto_set)) ||
        (rc = cfg_int(&fp, "cells", 4, CFG_RANGE(2, 20), &w->auto_cells)))
        return rc;
    return cfg_close(&fp);
}

static int thermal_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct thermal_case *w = calloc(1, sizeof *w);
    if (!w)
        return err_nomem(root->cfg->err, "handshake_thermal case");
    struct hs_case *c = &w->c;
    double regions[3] = {2, 2, 2};
    memcpy(c->regions, regions, sizeof regions);
    c->cell = 1;
    c->fine = 6;
    c->levels = 1;
    c->coarsen = 7;
    c->layer = 8;
    c->dt = 0.002;
    c->steps = 10000;
    c->skin = 1.0;
    c->slab = 1;
    c->profile_every = 1000;
    c->bar_mpm[0] = c->bar_mpm[1] = 16;
    c->bar_md = 16;
    c->bar_width = 4;
    w->seed = common->seed;
    w->common = *common;
    w->common.title = NULL;
    struct cfg_obj o;
    int rc = hs_case_read(root, c);
    if (!rc && !(rc = cfg_section_required(root, "thermal", &o)) &&
        !(rc = cfg_real(&o, "temperature", 300, CFG_GT(0), &w->bath.temperature)) &&
        !(rc = cfg_real(&o, "lattice_constant", 0, CFG_GE(0), &c->a_given)) &&
        !(rc = cfg_real(&o, "damping_time", HS_THERMAL_DAMPING_TIME, CFG_GE(0),
                        &w->bath.damping_time)) &&
        !(rc = cfg_real(&o, "coarse_cell", HS_THERMAL_COARSE_CELL, CFG_GE(0),
                        &w->bath.coarse_cell)) &&
        !(rc = cfg_real(&o, "equilibrate", 2, CFG_GE(0), &w->equilibrate)) &&
        !(rc = cfg_real(&o, "equilibrate_damping", 0.1, CFG_GT(0), &w->eq_damping)) &&
        !(rc = cfg_real(&o, "block", 1, CFG_GT(0), &w->block)) &&
        !(rc = read_from_potential(&o, w)))
        rc = cfg_close(&o);
    if (!rc && w->from_potential && (c->a_given > 0 || c->c_user[0] > 0))
        rc = cfg_error_at(root->cfg, c->a_given > 0 ? "thermal.lattice_constant" : "elastic",
                          "thermal.from_potential computes a(T) and the constants at T: leave "
                          "out thermal.lattice_constant and elastic's c11, c12, c44");
    /* the MPM at T: its lattice and its constants are those of T, not 0 K
     * (checked in deep reads: check, run; a listing of the keys is shallow) */
    int deep = !root->cfg->shallow;
    if (!rc && deep && !w->from_potential && !(c->a_given > 0))
        rc = cfg_error_at(root->cfg, "thermal.lattice_constant",
                          "give the lattice constant at %g K (the metric lattice_constant of "
                          "type: elastic): the material points sit on the lattice at that "
                          "temperature (or thermal.from_potential: {} to compute it here)",
                          w->bath.temperature);
    if (!rc && deep && !w->from_potential && !(c->c_user[0] > 0))
        rc = cfg_error_at(root->cfg, "elastic",
                          "give c11, c12 and c44 at %g K (the output of type: elastic): the MPM "
                          "needs the elastic constants at the MD temperature (or "
                          "thermal.from_potential: {} to compute them here)",
                          w->bath.temperature);
    if (!rc) {
        w->bath.seed = w->seed;
        w->neq = lround(w->equilibrate / c->dt);
        w->nblock = lround(w->block / c->dt);
        if (w->nblock < 1)
            w->nblock = 1;
        c->steps += w->neq;   /* md.steps is the measured window */
    }
    if (!rc && !root->cfg->shallow)
        rc = hs_case_build(c, MPM_FACE_SLIDING, 0, common);
    if (rc || root->cfg->shallow) {
        hs_case_free(c);
        free(w);
        return rc;
    }
    *state = w;
    return 0;
}

static void thermal_destroy(void *state)
{
    struct thermal_case *w = state;
    if (w)
        free(w->blocks);
    hs_case_destroy(state);
}

/* Temperatures (K) of the MD region (core and I), the core and region II. */
static void temperatures(const struct handshake *hs, double T[3])
{
    const uint32_t band = HS_MASK_I | HS_MASK_II | HS_MASK_III | HS_MASK_FIXED;
    hs_thermal_group(hs, 0, HS_MASK_II | HS_MASK_III | HS_MASK_FIXED, NULL, &T[0], NULL);
    hs_thermal_group(hs, 0, band, NULL, &T[1], NULL);
    hs_thermal_group(hs, HS_MASK_II, 0, NULL, &T[2], NULL);
}

/* The thermostat on the MD atoms during the equilibration only. */
static void interior_thermostat(struct thermal_case *w, long step)
{
    struct thermostat *t = &w->c.md.thermo;
    t->style = step < w->neq ? THERMOSTAT_LANGEVIN : THERMOSTAT_NONE;
    t->temperature = w->bath.temperature;
    t->tau = w->eq_damping;
    t->group_mask = 1u;   /* "all": the atoms, not the copies */
}

static int thermal_begin(void *state, struct sim *s, struct err *e)
{
    struct thermal_case *w = state;
    struct hs_case *c = &w->c;
    static const char *const cols[] = {"T_md_K", "T_core_K", "T_region_II_K", "bath_heat_eV"};
    int rc = hs_case_output_begin(c, s->run, cols, 4, e);
    if (rc)
        return rc;
    interior_thermostat(w, s->step);
    run_log(s->run,
            "handshake_thermal: %ld atoms, %ld material points, %g K, a(T) = %.5f Å, bath "
            "damping time %g ps, %g ps equilibration then %g ps without a thermostat",
            c->hs.counts[HS_CORE] + c->hs.counts[HS_I], c->hs.npoints, w->bath.temperature,
            c->a, w->bath.damping_time, w->equilibrate, (c->steps - w->neq) * c->dt);
    return 0;
}

static int thermal_after_step(void *state, struct sim *s, struct err *e)
{
    struct thermal_case *w = state;
    interior_thermostat(w, s->step);
    if (s->step <= w->neq)
        return 0;
    double T[3];
    temperatures(&w->c.hs, T);
    for (int k = 0; k < 3; k++)
        w->sum[k] += T[k];
    if (++w->in_block < w->nblock)
        return 0;
    if (w->nblocks >= w->maxblocks) {
        long n = w->maxblocks ? 2 * w->maxblocks : 64;
        double *b = realloc(w->blocks, (size_t)n * 3 * sizeof *b);
        if (!b)
            return err_nomem(e, "temperature blocks");
        w->blocks = b;
        w->maxblocks = n;
    }
    for (int k = 0; k < 3; k++) {
        w->blocks[3 * w->nblocks + k] = w->sum[k] / (double)w->in_block;
        w->sum[k] = 0;
    }
    w->nblocks++;
    w->in_block = 0;
    return 0;
}

static int thermal_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct thermal_case *w = state;
    int rc = 0;
    if (due & SIM_DUE_THERMO) {
        double row[4];
        temperatures(&w->c.hs, row);
        row[3] = w->bath.heat;
        rc = hs_case_thermo(&w->c, s->run, row, 4, e);
    }
    if (!rc && (due & SIM_DUE_SNAPSHOT))
        rc = hs_case_snapshot(&w->c, s->run, e);
    return rc;
}

static int thermal_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct thermal_case *w = state;
    struct hs_case *c = &w->c;
    struct result *res = &s->run->result;
    const double T0 = w->bath.temperature;
    double mean[3] = {0, 0, 0}, dev = 0;
    long nb = w->nblocks;
    double *series = malloc((size_t)(nb > 0 ? nb : 1) * 4 * sizeof *series);
    if (!series)
        return err_nomem(e, "temperature series");
    for (long b = 0; b < nb; b++) {
        for (int k = 0; k < 3; k++) {
            mean[k] += w->blocks[3 * b + k] / (double)nb;
            series[(k + 1) * nb + b] = w->blocks[3 * b + k];
        }
        series[b] = w->equilibrate + (b + 0.5) * w->nblock * c->dt;
        dev = fmax(dev, fabs(w->blocks[3 * b] / T0 - 1));
    }
    double first = nb > 0 ? w->blocks[0] : NAN, last = nb > 0 ? w->blocks[3 * (nb - 1)] : NAN;
    /* the trend: least-squares slope of the blocks times the window, over
     * T (the blocks' canonical fluctuation, about sqrt(2 / 3N) per sample,
     * enters the largest deviation but averages out of the slope) */
    double tm = 0, sxy = 0, sxx = 0;
    for (long b = 0; b < nb; b++)
        tm += (double)b / (double)nb;
    for (long b = 0; b < nb; b++) {
        sxy += ((double)b - tm) * (w->blocks[3 * b] - mean[0]);
        sxx += ((double)b - tm) * ((double)b - tm);
    }
    double trend = nb > 1 ? sxy / sxx * (double)nb / T0 : NAN;
    double window = (double)(c->steps - w->neq) * c->dt;
    result_metric(res, "temperature", T0, "K");
    result_metric(res, "lattice_constant_T", c->a, "Å");
    result_metric(res, "from_potential", w->from_potential, "1");
    if (w->from_potential)   /* what the computation gave, with its errors */
        elastic_thermal_report(&w->auto_out, &w->auto_set, res);
    result_metric(res, "damping_time", w->bath.damping_time, "ps");
    result_metric(res, "bath_coarse_cell", w->bath.coarse_cell, "1");
    result_metric(res, "equilibrate", w->equilibrate, "ps");
    result_metric(res, "measured_time", window, "ps");
    result_metric(res, "temperature_blocks", (double)nb, "1");
    result_metric(res, "temperature_md_mean", nb ? mean[0] : NAN, "K");
    result_metric(res, "temperature_core_mean", nb ? mean[1] : NAN, "K");
    result_metric(res, "temperature_region_II_mean", nb ? mean[2] : NAN, "K");
    result_metric(res, "temperature_block_first", first, "K");
    result_metric(res, "temperature_block_last", last, "K");
    result_metric(res, "temperature_drift", nb ? last / first - 1 : NAN, "1");
    result_metric(res, "temperature_max_deviation", nb ? dev : NAN, "1");
    result_metric(res, "temperature_trend", trend, "1");
    result_metric(res, "bath_heat", w->bath.heat, "eV");
    result_series(res, "block_time", series, (int)nb, "ps");
    result_series(res, "block_temperature_md", series + nb, (int)nb, "K");
    result_series(res, "block_temperature_core", series + 2 * nb, (int)nb, "K");
    result_series(res, "block_temperature_region_II", series + 3 * nb, (int)nb, "K");
    free(series);
    (void)run_rc;
    return hs_case_output_end(c, s->run, e);
}

static const struct sim_case_ops thermal_ops = {
    .begin = thermal_begin,
    .after_step = thermal_after_step,
    .output = thermal_output,
    .report = thermal_report,
};

/* thermal.from_potential: a(T) and the constants at T by type: elastic's
 * computation (elastic_thermal.h) with the case's potential, then the bar
 * rebuilt on the lattice at a(T) with those constants (read built it at the
 * 0 K lattice constant: that build checked the layout and counted the
 * particles, which do not change).  The computation borrows the potential
 * from the MD of the first build and hands it to the second. */
static int compute_at_temperature(struct thermal_case *w, struct run *run, struct err *e)
{
    struct hs_case *c = &w->c;
    const double G = UNITS_EVA3_TO_GPA;
    struct elastic_thermal_settings s = w->auto_set;
    s.md.temperature = w->bath.temperature;
    s.md.seed = w->seed;
    s.md.nthreads = w->common.nthreads;
    enum lattice_style style = c->lattice == HS_LATTICE_BCC       ? LATTICE_BCC
                               : c->lattice == HS_LATTICE_DIAMOND ? LATTICE_DIAMOND
                                                                  : LATTICE_FCC;
    struct crystal_spec spec = {style, c->element, 0, w->auto_cells};
    struct elastic_thermal *r = &w->auto_out;
    int rc = elastic_thermal_compute_logged("handshake_thermal", c->md.pot, &spec, c->a_min,
                                            c->a_max, &s, run, r, e);
    if (rc)
        return rc;
    /* rebuild: the potential leaves the old MD for the new bar */
    struct potential *pot = c->md.pot;
    c->md.pot = NULL;
    handshake_free(&c->hs);
    md_free(&c->md);
    hs_profile_free(&c->prof);
    c->built = 0;
    c->pot = pot;
    c->a_given = r->a;
    for (int k = 0; k < 3; k++)
        c->c_user[k] = r->c[k] * G;
    /* the read's cfg is gone: build errors name the case type */
    struct cfg cfg = {"handshake_thermal (from_potential)", NULL, e, NULL, 0};
    c->cfg = &cfg;
    rc = hs_case_build(c, MPM_FACE_SLIDING, 0, &w->common);
    c->cfg = NULL;
    return rc;
}

static int thermal_run(void *state, struct run *run, struct err *e)
{
    struct thermal_case *w = state;
    struct hs_case *c = &w->c;
    struct handshake *hs = &c->hs;
    const double T0 = w->bath.temperature;
    int rc;
    if (w->from_potential && (rc = compute_at_temperature(w, run, e)))
        return rc;
    /* a perfect lattice started at 2T settles at T (equipartition) */
    hs_thermal_velocities(hs, 2 * T0, w->seed, HS_MASK_II | HS_MASK_III | HS_MASK_FIXED);
    hs_thermal_attach(hs, &w->bath, 2 * T0);
    c->md.seed = w->seed;
    return hs_case_run(c, run, &thermal_ops, w, e);
}

const struct case_type handshake_thermal_case_type = {
    "handshake_thermal",
    "MPM/MD handshake at a temperature: an MD region at T in MPM, region II under a Langevin "
    "bath (the future work of Guo & Yang 2005)",
    thermal_read, thermal_run, thermal_destroy, hs_case_particles, hs_case_steps,
    .checkpoints = 0,   /* the block sums are not stored: docs/handshake.md, Limits */
    .decomposes = 1,    /* the MD on bricks, the MPM whole (docs/parallel.md) */
    .balances = 1,
};
