/* elastic_thermal: a(T) and the cubic elastic constants at T by MD
 * finite-strain averages (see elastic_thermal.h). */
#include "scenarios/elastic_thermal.h"

#include <math.h>
#include <stdlib.h>

#include "analysis/block_average.h"
#include "core/units.h"
#include "output/result.h"

int elastic_thermal_read(struct cfg_obj *o, int with_temperature,
                         struct elastic_thermal_settings *s)
{
    long equil, sample;
    int rc;
    if ((with_temperature &&
         (rc = cfg_real(o, "temperature", 300, CFG_GE(0), &s->md.temperature))) ||
        (rc = cfg_real(o, "strain", 0.01, CFG_RANGE(1e-5, 0.05), &s->strain)) ||
        (rc = cfg_real(o, "timestep", 0.002, CFG_GT(0), &s->md.dt)) ||
        (rc = cfg_real(o, "tau", 0.5, CFG_GT(0), &s->md.tau)) ||
        (rc = cfg_int(o, "equilibrate", 2000, CFG_GE(0), &equil)) ||
        (rc = cfg_int(o, "sample", 6000, CFG_GE(10), &sample)) ||
        (rc = cfg_int(o, "lattice_iterations", 3, CFG_RANGE(0, 20), &s->iterations)) ||
        (rc = cfg_int(o, "repeats", 1, CFG_RANGE(1, 100), &s->repeats)))
        return rc;
    s->md.equilibrate = equil;
    s->md.sample = sample;
    s->md.sample_every = 5;
    return 0;
}

long elastic_thermal_steps(const struct elastic_thermal_settings *s)
{
    long runs = (4 + (s->md.temperature > 0 ? s->iterations : 0)) * s->repeats;
    return runs * (s->md.equilibrate + s->md.sample);
}

/* Mean pressure tensor and its block standard error over one run; the
 * next run draws other velocities (md->seed advances). */
static int run_pressure(struct potential *pot, const struct crystal_spec *spec,
                        struct crystal_md *md, double a, const int (*orient)[3],
                        const double eps[3], double P[6], double err[6], struct err *e)
{
    long cap = md->sample / md->sample_every + 1, n;
    double *s = malloc((size_t)cap * 7 * sizeof *s);
    if (!s)
        return err_nomem(e, "pressure samples");
    double *col = s + 6 * cap;
    int rc = crystal_pressure_md(pot, spec, a, orient, eps, md, s, &n, e);
    for (int k = 0; k < 6 && !rc; k++) {
        for (long i = 0; i < n; i++)
            col[i] = s[6 * i + k];
        P[k] = block_average(col, n, 10, &err[k]);
        if (!isfinite(err[k]))
            err[k] = 0;
    }
    free(s);
    md->seed += 7919;
    return rc;
}

/* Over `repeats` independent runs: the mean, and the standard error from
 * their spread (one run: its block error). */
static int mean_pressure(struct potential *pot, const struct crystal_spec *spec,
                         struct crystal_md *md, long R, double a, const int (*orient)[3],
                         const double eps[3], double P[6], double err[6], struct err *e)
{
    double sum[6] = {0}, sum2[6] = {0}, p[6], pe[6];
    for (long r = 0; r < R; r++) {
        int rc = run_pressure(pot, spec, md, a, orient, eps, p, pe, e);
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

int elastic_thermal_compute(struct potential *pot, const struct crystal_spec *spec, double a_min,
                            double a_max, const struct elastic_thermal_settings *s,
                            struct run *run, struct elastic_thermal *out, struct err *e)
{
    const double G = UNITS_EVA3_TO_GPA;
    struct crystal_md md = s->md;
    double ec;
    int rc = crystal_equilibrium(pot, spec, a_min, a_max, &out->a0, &ec, e);
    if (!rc)
        rc = crystal_elastic_cubic(pot, spec, out->a0, &out->c0[0], &out->c0[1], &out->c0[2], e);
    if (rc)
        return rc;
    double B = (out->c0[0] + 2 * out->c0[1]) / 3, a = out->a0, P[6], Pe[6];
    out->p_mean = out->p_err = 0;
    /* lattice constant at T: remove the thermal pressure */
    for (long it = 0; it < s->iterations && md.temperature > 0 && !rc; it++) {
        rc = mean_pressure(pot, spec, &md, s->repeats, a, NULL, NULL, P, Pe, e);
        if (rc)
            break;
        out->p_mean = (P[0] + P[1] + P[2]) / 3;
        out->p_err = sqrt(Pe[0] * Pe[0] + Pe[1] * Pe[1] + Pe[2] * Pe[2]) / 3;
        a *= 1 + out->p_mean / (3 * B);
        if (run)
            run_log(run, "elastic: iteration %ld: P = %.4f +- %.4f GPa -> a = %.6f Å", it + 1,
                    out->p_mean * G, out->p_err * G, a);
    }
    out->a = a;
    /* strains along [100] and [110] */
    static const int rot[3][3] = {{1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
    double ep[3] = {s->strain, 0, 0}, em[3] = {-s->strain, 0, 0};
    double Pp[6], Pm[6], Ep[6], Em[6], Rp[6], Rm[6], REp[6], REm[6];
    long R = s->repeats;
    if (!rc)
        rc = mean_pressure(pot, spec, &md, R, a, NULL, ep, Pp, Ep, e);
    if (!rc)
        rc = mean_pressure(pot, spec, &md, R, a, NULL, em, Pm, Em, e);
    if (!rc)
        rc = mean_pressure(pot, spec, &md, R, a, rot, ep, Rp, REp, e);
    if (!rc)
        rc = mean_pressure(pot, spec, &md, R, a, rot, em, Rm, REm, e);
    if (rc)
        return rc;
    double h2 = 2 * s->strain;
    double c11 = -(Pp[0] - Pm[0]) / h2, c12 = -(Pp[1] - Pm[1]) / h2;
    double c11e = hypot(Ep[0], Em[0]) / h2, c12e = hypot(Ep[1], Em[1]) / h2;
    double c11r = -(Rp[0] - Rm[0]) / h2, c11re = hypot(REp[0], REm[0]) / h2;
    out->c[0] = c11;
    out->c[1] = c12;
    out->c[2] = c11r - 0.5 * (c11 + c12);
    out->c_err[0] = c11e;
    out->c_err[1] = c12e;
    out->c_err[2] = sqrt(c11re * c11re + 0.25 * (c11e * c11e + c12e * c12e));
    return 0;
}

int elastic_thermal_compute_logged(const char *who, struct potential *pot,
                                   const struct crystal_spec *spec, double a_min, double a_max,
                                   const struct elastic_thermal_settings *s, struct run *run,
                                   struct elastic_thermal *out, struct err *e)
{
    const double G = UNITS_EVA3_TO_GPA;
    long per_cell = spec->style == LATTICE_DIAMOND ? 8 : spec->style == LATTICE_BCC ? 2 : 4;
    run_log(run, "%s: computing a(T) and the constants at %g K (%ld MD steps of %ld atoms, "
                 "type: elastic's computation)",
            who, s->md.temperature, elastic_thermal_steps(s),
            per_cell * spec->cells * spec->cells * spec->cells);
    int rc = elastic_thermal_compute(pot, spec, a_min, a_max, s, run, out, e);
    if (!rc)
        run_log(run, "%s: at %g K a = %.5f Å, C11 = %.2f +- %.2f, C12 = %.2f +- %.2f, "
                     "C44 = %.2f +- %.2f GPa",
                who, s->md.temperature, out->a, out->c[0] * G, out->c_err[0] * G,
                out->c[1] * G, out->c_err[1] * G, out->c[2] * G, out->c_err[2] * G);
    return rc;
}

void elastic_thermal_report(const struct elastic_thermal *out,
                            const struct elastic_thermal_settings *s, struct result *r)
{
    const double G = UNITS_EVA3_TO_GPA;
    result_metric(r, "thermal_expansion", out->a / out->a0 - 1, "1");
    result_metric(r, "c11_T_err", out->c_err[0] * G, "GPa");
    result_metric(r, "c12_T_err", out->c_err[1] * G, "GPa");
    result_metric(r, "c44_T_err", out->c_err[2] * G, "GPa");
    result_metric(r, "from_potential_md_steps", (double)elastic_thermal_steps(s), "1");
}
