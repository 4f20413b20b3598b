/*
 * elastic_case: cubic elastic constants at a temperature from MD
 * (`type: elastic`), by finite-strain averages -- the constants the MPM
 * side of the MPM/MD handshake needs when the MD region is not at 0 K
 * (Guo & Yang 2005, section 2.2: the constants "can be derived from the
 * atomic potential and then are used in the MPM region").
 *
 *   crystal:  {lattice: fcc, element: Cu, a_min: 3.5, a_max: 3.7, cells: 4}
 *   potential: {...}
 *   elastic:
 *     temperature: 300     K
 *     strain: 0.01         amplitude of the +- strains
 *     timestep: 0.002      ps
 *     tau: 0.5             ps, Langevin damping time
 *     equilibrate: 2000    steps before each average
 *     sample: 6000         steps averaged (a pressure sample every 5)
 *     lattice_iterations: 3
 *     repeats: 1           independent runs (other velocities) per strain
 *
 * 1. The 0 K lattice constant a0 and constants (crystal.h).
 * 2. The lattice constant at T: a <- a (1 + P / (3 B)) from the mean
 *    pressure of an NVT run, `lattice_iterations` times, B the 0 K bulk
 *    modulus (the thermal pressure is removed to the statistical error).
 * 3. At that a, NVT runs under uniaxial strains +-eps along [100] give
 *    C11 = -dP_xx/deps and C12 = -dP_yy/deps, and along [110] (crystal
 *    oriented [110] [-110] [001]) C'11 = (C11 + C12 + 2 C44) / 2, so
 *    C44 = C'11 - (C11 + C12) / 2 -- central differences of time averages,
 *    the same construction as at 0 K.  The errors are standard errors
 *    carried through the differences: with repeats >= 2 from the spread of
 *    the independent runs, else block-averaged within the one run (which
 *    underestimates them: the slow acoustic modes of a small periodic
 *    crystal outlast the blocks).  These are the isothermal constants of
 *    the crystal at its zero-pressure volume at T.
 */
#include <math.h>
#include <stdlib.h>

#include "analysis/block_average.h"
#include "core/units.h"
#include "scenarios/crystal_range.h"
#include "scenarios/crystal_thermal.h"
#include "scenarios/case_type.h"

struct elastic_case {
    struct potential *pot;
    struct crystal_spec spec;
    char element[16];
    double a_min, a_max;
    struct crystal_md md;
    double strain;
    long iterations;
    long repeats;
};

static int elastic_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    static const char *const cubic[] = {"sc", "bcc", "fcc", "diamond", NULL};
    struct cfg_obj co, po, eo;
    int style, rc;
    const char *element;
    long cells, equil, sample, iters, repeats;
    double amin, amax, T, strain, dt, tau;
    if ((rc = cfg_section_required(root, "crystal", &co)) ||
        (rc = cfg_enum(&co, "lattice", "fcc", cubic, &style)) ||
        (rc = cfg_string(&co, "element", NULL, &element)) ||
        (rc = cfg_real(&co, "a_min", CFG_REQUIRED, CFG_GT(0), &amin)) ||
        (rc = cfg_real(&co, "a_max", CFG_REQUIRED, CFG_GT(0), &amax)) ||
        (rc = cfg_int(&co, "cells", 4, CFG_RANGE(2, 20), &cells)) || (rc = cfg_close(&co)))
        return rc;
    if (!(amax > amin))
        return cfg_error_at(co.cfg, "crystal.a_max", "a_max = %g must exceed a_min = %g", amax,
                            amin);
    if ((rc = cfg_section(root, "elastic", &eo)) ||
        (rc = cfg_real(&eo, "temperature", 300, CFG_GE(0), &T)) ||
        (rc = cfg_real(&eo, "strain", 0.01, CFG_RANGE(1e-5, 0.05), &strain)) ||
        (rc = cfg_real(&eo, "timestep", 0.002, CFG_GT(0), &dt)) ||
        (rc = cfg_real(&eo, "tau", 0.5, CFG_GT(0), &tau)) ||
        (rc = cfg_int(&eo, "equilibrate", 2000, CFG_GE(0), &equil)) ||
        (rc = cfg_int(&eo, "sample", 6000, CFG_GE(10), &sample)) ||
        (rc = cfg_int(&eo, "lattice_iterations", 3, CFG_RANGE(0, 20), &iters)) ||
        (rc = cfg_int(&eo, "repeats", 1, CFG_RANGE(1, 100), &repeats)) ||
        (rc = cfg_close(&eo)))
        return rc;
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot)))
        return rc;
    struct crystal_spec smallest = {(enum lattice_style)style, element, 0, cells};
    /* the skin of the MD the case runs (crystal_thermal.c: 1.0 Å) */
    if (!root->cfg->shallow &&
        (rc = crystal_check_range(root, &po, pot, &smallest, amin, 1.0))) {
        potential_destroy(&pot);
        return rc;
    }
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        return 0;
    }
    struct elastic_case *c = calloc(1, sizeof *c);
    if (!c) {
        potential_destroy(&pot);
        return err_nomem(root->cfg->err, "elastic case");
    }
    snprintf(c->element, sizeof c->element, "%s", element);
    c->pot = pot;
    c->spec.style = (enum lattice_style)style;
    c->spec.element = c->element;
    c->spec.cells = cells;
    c->a_min = amin;
    c->a_max = amax;
    c->strain = strain;
    c->iterations = iters;
    c->repeats = repeats;
    c->md.temperature = T;
    c->md.dt = dt;
    c->md.tau = tau;
    c->md.equilibrate = equil;
    c->md.sample = sample;
    c->md.sample_every = 5;
    c->md.seed = common->seed;
    c->md.nthreads = common->nthreads;
    *state = c;
    return 0;
}

/* Mean pressure tensor and its block standard error over one run. */
static int run_pressure(struct elastic_case *c, double a, const int (*orient)[3],
                        const double eps[3], double P[6], double err[6], struct err *e)
{
    long cap = c->md.sample / c->md.sample_every + 1, n;
    double *s = malloc((size_t)cap * 7 * sizeof *s);
    if (!s)
        return err_nomem(e, "pressure samples");
    double *col = s + 6 * cap;
    int rc = crystal_pressure_md(c->pot, &c->spec, a, orient, eps, &c->md, s, &n, e);
    for (int k = 0; k < 6 && !rc; k++) {
        for (long i = 0; i < n; i++)
            col[i] = s[6 * i + k];
        P[k] = block_average(col, n, 10, &err[k]);
        if (!isfinite(err[k]))
            err[k] = 0;
    }
    free(s);
    c->md.seed += 7919;   /* the next run draws other velocities */
    return rc;
}

/* Over `repeats` independent runs: the mean, and the standard error from
 * their spread (one run: its block error). */
static int mean_pressure(struct elastic_case *c, double a, const int (*orient)[3],
                         const double eps[3], double P[6], double err[6], struct err *e)
{
    double sum[6] = {0}, sum2[6] = {0}, p[6], pe[6];
    long R = c->repeats;
    for (long r = 0; r < R; r++) {
        int rc = run_pressure(c, a, orient, eps, p, pe, e);
        if (rc)
            return rc;
        for (int k = 0; k < 6; k++) {
            sum[k] += p[k];
            sum2[k] += p[k] * p[k];
        }
    }
    for (int k = 0; k < 6; k++) {
        P[k] = sum[k] / R;
        err[k] = R > 1 ? sqrt(fmax(0.0, (sum2[k] / R - P[k] * P[k]) * R / (R - 1)) / R) : pe[k];
    }
    return 0;
}

static int elastic_run(void *state, struct run *run, struct err *e)
{
    struct elastic_case *c = state;
    const double G = UNITS_EVA3_TO_GPA;
    double a0, ec, c0[3];
    int rc = crystal_equilibrium(c->pot, &c->spec, c->a_min, c->a_max, &a0, &ec, e);
    if (!rc)
        rc = crystal_elastic_cubic(c->pot, &c->spec, a0, &c0[0], &c0[1], &c0[2], e);
    if (rc)
        return rc;
    double B = (c0[0] + 2 * c0[1]) / 3, a = a0, P[6], Pe[6];
    double p_mean = 0, p_err = 0;
    timer_start(&run->timers, TIMER_LOOP);
    /* lattice constant at T: remove the thermal pressure */
    for (long it = 0; it < c->iterations && c->md.temperature > 0 && !rc; it++) {
        rc = mean_pressure(c, a, NULL, NULL, P, Pe, e);
        if (rc)
            break;
        p_mean = (P[0] + P[1] + P[2]) / 3;
        p_err = sqrt(Pe[0] * Pe[0] + Pe[1] * Pe[1] + Pe[2] * Pe[2]) / 3;
        a *= 1 + p_mean / (3 * B);
        run_log(run, "elastic: iteration %ld: P = %.4f +- %.4f GPa -> a = %.6f Å", it + 1,
                p_mean * G, p_err * G, a);
    }
    /* strains along [100] and [110] */
    static const int rot[3][3] = {{1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
    double ep[3] = {c->strain, 0, 0}, em[3] = {-c->strain, 0, 0};
    double Pp[6], Pm[6], Ep[6], Em[6], Rp[6], Rm[6], REp[6], REm[6];
    if (!rc)
        rc = mean_pressure(c, a, NULL, ep, Pp, Ep, e);
    if (!rc)
        rc = mean_pressure(c, a, NULL, em, Pm, Em, e);
    if (!rc)
        rc = mean_pressure(c, a, rot, ep, Rp, REp, e);
    if (!rc)
        rc = mean_pressure(c, a, rot, em, Rm, REm, e);
    timer_stop(&run->timers, TIMER_LOOP);
    if (rc)
        return rc;
    double h2 = 2 * c->strain;
    double c11 = -(Pp[0] - Pm[0]) / h2, c12 = -(Pp[1] - Pm[1]) / h2;
    double c11e = hypot(Ep[0], Em[0]) / h2, c12e = hypot(Ep[1], Em[1]) / h2;
    double c11r = -(Rp[0] - Rm[0]) / h2, c11re = hypot(REp[0], REm[0]) / h2;
    double c44 = c11r - 0.5 * (c11 + c12);
    double c44e = sqrt(c11re * c11re + 0.25 * (c11e * c11e + c12e * c12e));
    struct result *r = &run->result;
    result_metric(r, "temperature", c->md.temperature, "K");
    result_metric(r, "lattice_constant", a, "Å");
    result_metric(r, "lattice_constant_0K", a0, "Å");
    result_metric(r, "thermal_expansion", a / a0 - 1, "1");
    result_metric(r, "pressure_last_iteration", p_mean * G, "GPa");
    result_metric(r, "pressure_last_iteration_err", p_err * G, "GPa");
    result_metric(r, "c11", c11 * G, "GPa");
    result_metric(r, "c12", c12 * G, "GPa");
    result_metric(r, "c44", c44 * G, "GPa");
    result_metric(r, "c11_err", c11e * G, "GPa");
    result_metric(r, "c12_err", c12e * G, "GPa");
    result_metric(r, "c44_err", c44e * G, "GPa");
    result_metric(r, "bulk_modulus", (c11 + 2 * c12) / 3 * G, "GPa");
    result_metric(r, "c11_0K", c0[0] * G, "GPa");
    result_metric(r, "c12_0K", c0[1] * G, "GPa");
    result_metric(r, "c44_0K", c0[2] * G, "GPa");
    run_log(run,
            "elastic at %g K: a = %.5f Å, C11 = %.1f +- %.1f, C12 = %.1f +- %.1f, C44 = %.1f +- "
            "%.1f GPa (0 K: %.1f, %.1f, %.1f)",
            c->md.temperature, a, c11 * G, c11e * G, c12 * G, c12e * G, c44 * G, c44e * G,
            c0[0] * G, c0[1] * G, c0[2] * G);
    return 0;
}

static void elastic_destroy(void *state)
{
    struct elastic_case *c = state;
    if (!c)
        return;
    potential_destroy(&c->pot);
    free(c);
}

static long elastic_particles(const void *state)
{
    const struct elastic_case *c = state;
    if (!c)
        return 0;
    struct lattice l = {c->spec.style, 1.0, {0, 0, 0}, {{0}}};
    double basis[8][3];
    long n = c->spec.cells;
    return lattice_basis(&l, basis) * n * n * n;
}

static long elastic_steps(const void *state)
{
    const struct elastic_case *c = state;
    if (!c)
        return 0;
    long runs = (4 + (c->md.temperature > 0 ? c->iterations : 0)) * c->repeats;
    return runs * (c->md.equilibrate + c->md.sample);
}

const struct case_type elastic_case_type = {
    "elastic",
    "cubic elastic constants at a temperature from MD finite-strain averages (for the MPM side "
    "of the handshake)",
    elastic_read, elastic_run, elastic_destroy, elastic_particles, elastic_steps,
    .checkpoints = 0,
};
