/*
 * dpd_fit_case: the MD->DPD hierarchical bridge (`type: dpd_fit`) -- fit
 * the coarse-grained Sutton-Chen parameters to an MD pressure-density
 * isotherm and write the parameter file DPD cases reference (Chen et al.
 * 2014 Sec. 2.2; the fit itself is dpd/cg_fit.h).
 *
 *   isotherm:
 *     temperature: 298          K of the isotherm
 *     points_file: iso.csv      CSV with a header naming the columns
 *                               density_g_cm3, pressure_GPa and optionally
 *                               pressure_sem_GPa (one MD run per row)
 *     densities: [...]          and/or the points inline: g/cm^3,
 *     pressures: [...]          GPa,
 *     pressure_sems: [...]      GPa (optional, same length)
 *     weighted: false           weight residuals by 1 / sem
 *   coarse_grain:
 *     element: Cu
 *     atoms_per_particle: 8     atoms per DPD particle
 *     atom_mass: 63.546         amu
 *     a: 7.23                   Å, length scale of the form (the coarse lattice constant)
 *     cutoff: 10.845            Å (1.5 a: four neighbour shells)
 *     n: 9                      start values (or fixed values) of the form
 *     m: 6
 *     epsilon: 0.099            eV
 *     c: 39.432
 *     fit: [epsilon, c]         which of epsilon, c, n, m, a are fitted
 *     thermal_pressure: true    include the quasi-harmonic thermal pressure in the model
 *   output_file: cu_cg.yaml     parameter file written into the run's output directory
 *
 * Metrics: the fitted parameters (epsilon eV, c, n, m, a Å) with standard
 * errors (*_stderr), residual_rms and residual_max (GPa), chi2, points,
 * iterations; and what the parameters predict for the coarse-grained fcc
 * crystal at the isotherm temperature and zero pressure: lattice_constant
 * (Å), density (g/cm^3), bulk_modulus, c11, c12, c44 (static, GPa),
 * longitudinal_wave_speed sqrt(C11/rho) and bar_wave_speed sqrt(E100/rho)
 * along [100] (m/s).  Series: density, pressure_md, pressure_model,
 * residual (g/cm^3, GPa).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"
#include "core/units.h"
#include "dpd/cg_fit.h"
#include "dpd/cg_lattice.h"
#include "dpd/cg_params.h"
#include "scenarios/case_type.h"

struct fit_case {
    struct cg_fit_spec spec;
    struct cg_fit_point *pts;
    int npts;
    char element[16];
    long atoms_per_particle;
    char output_file[256];
    char source[512];
};

/* Whether a CSV line has an empty field (",,", or a comma first or last):
 * the tokenizer would skip it and read the next column in its place. */
static int csv_empty_field(const char *s)
{
    int prev_comma = 1;   /* the start of the line acts as a comma */
    for (; *s; s++) {
        if (*s == ' ' || *s == '\t' || *s == '\r')
            continue;
        if (*s == ',' && prev_comma)
            return 1;
        prev_comma = *s == ',';
    }
    return prev_comma;
}

/* Read a points CSV: a header line naming the columns, then numbers. */
static int read_points_csv(const char *path, struct cg_fit_point **pts, int *npts, struct err *e)
{
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    int cd = -1, cp = -1, cs = -1, ncol = 0;
    while (textfile_next_line(&t) == 0) {
        const char *s = t.buf + strspn(t.buf, " \t");
        if (*s && *s != '#')
            break;
    }
    if (t.eof) {
        rc = textfile_error(&t, e, "no header line (density_g_cm3,pressure_GPa[,pressure_sem_GPa])");
        goto done;
    }
    char hdr[4096];
    snprintf(hdr, sizeof hdr, "%s", t.buf);
    char *save = NULL;
    for (char *tok = strtok_r(hdr, ", \t\r", &save); tok; tok = strtok_r(NULL, ", \t\r", &save)) {
        if (strcmp(tok, "density_g_cm3") == 0)
            cd = ncol;
        else if (strcmp(tok, "pressure_GPa") == 0)
            cp = ncol;
        else if (strcmp(tok, "pressure_sem_GPa") == 0)
            cs = ncol;
        ncol++;
    }
    if (cd < 0 || cp < 0) {
        rc = textfile_error(&t, e, "header must name the columns density_g_cm3 and pressure_GPa");
        goto done;
    }
    while (textfile_next_line(&t) == 0) {
        const char *s = t.buf + strspn(t.buf, " \t\r");
        if (!*s || *s == '#')
            continue;
        if (strchr(s, ',') && csv_empty_field(s)) {
            rc = textfile_error(&t, e, "empty column");
            goto done;
        }
        double v[32];
        int nv = 0;
        char *save2 = NULL;
        for (char *tok = strtok_r(t.buf, ", \t\r", &save2); tok;
             tok = strtok_r(NULL, ", \t\r", &save2)) {
            char ex[TEXT_EXCERPT_SIZE];
            if (nv >= ncol || nv >= 32) {
                rc = textfile_error(&t, e, "more columns than the %d of the header", ncol);
                goto done;
            }
            /* the whole field, decimal and finite: "1.5x" is not 1.5 */
            if (text_parse_real(tok, &v[nv]) != 0) {
                rc = textfile_error(&t, e, "column %d: '%s' is not a finite decimal number",
                                    nv + 1, text_excerpt(tok, ex));
                goto done;
            }
            nv++;
        }
        if (nv <= cd || nv <= cp || (cs >= 0 && nv <= cs)) {
            rc = textfile_error(&t, e, "%d columns, the header has %d", nv, ncol);
            goto done;
        }
        if (!(v[cd] > 0)) {
            rc = textfile_error(&t, e, "density %g must be positive", v[cd]);
            goto done;
        }
        struct cg_fit_point *np = realloc(*pts, (size_t)(*npts + 1) * sizeof *np);
        if (!np) {
            rc = err_nomem(e, "isotherm points");
            goto done;
        }
        *pts = np;
        np[*npts] = (struct cg_fit_point){v[cd], v[cp], cs >= 0 ? v[cs] : 0};
        (*npts)++;
    }
done:
    textfile_close(&t);
    return rc;
}

static int read_isotherm(struct cfg_obj *root, struct fit_case *c, int *weighted, double *T)
{
    struct cfg_obj o;
    const char *file = NULL;
    int has_file, rc;
    double *dens = NULL, *pres = NULL, *sems = NULL;
    size_t nd = 0, np = 0, ns = 0;
    if ((rc = cfg_section_required(root, "isotherm", &o)) ||
        (rc = cfg_real(&o, "temperature", CFG_REQUIRED, CFG_GE(0), T)) ||
        (rc = cfg_string_opt(&o, "points_file", &file, &has_file)) ||
        (rc = cfg_real_list(&o, "densities", 0, CFG_GT(0), &dens, &nd)) ||
        (rc = cfg_real_list(&o, "pressures", 0, CFG_ANY, &pres, &np)) ||
        (rc = cfg_real_list(&o, "pressure_sems", 0, CFG_GE(0), &sems, &ns)) ||
        (rc = cfg_bool(&o, "weighted", 0, weighted)) || (rc = cfg_close(&o)))
        goto out;
    if (nd != np || (ns && ns != nd)) {
        rc = cfg_error_at(o.cfg, "isotherm.pressures",
                          "densities (%zu), pressures (%zu) and pressure_sems (%zu) must have "
                          "the same length",
                          nd, np, ns);
        goto out;
    }
    if (!has_file && nd == 0) {
        rc = cfg_error_at(o.cfg, "isotherm", "give the isotherm as points_file or as densities "
                                             "and pressures");
        goto out;
    }
    if (o.cfg->shallow)
        goto out;
    if (has_file) {
        char path[4096];
        if (cfg_find_file(o.cfg, file, path, sizeof path) != 0) {
            rc = cfg_error_at(o.cfg, "isotherm.points_file", "cannot read '%s'", file);
            goto out;
        }
        struct err fe = {0};
        if (read_points_csv(path, &c->pts, &c->npts, &fe) != 0) {
            rc = cfg_error_at(o.cfg, "isotherm.points_file", "%s", fe.msg);
            goto out;
        }
        snprintf(c->source, sizeof c->source, "%s", file);
    }
    if (nd) {
        struct cg_fit_point *q = realloc(c->pts, (c->npts + nd) * sizeof *q);
        if (!q) {
            rc = err_nomem(o.cfg->err, "isotherm points");
            goto out;
        }
        c->pts = q;
        for (size_t k = 0; k < nd; k++)
            c->pts[c->npts++] = (struct cg_fit_point){dens[k], pres[k], ns ? sems[k] : 0};
        if (!c->source[0])
            snprintf(c->source, sizeof c->source, "inline points");
    }
out:
    free(dens);
    free(pres);
    free(sems);
    return rc;
}

static int read_coarse_grain(struct cfg_obj *root, struct fit_case *c)
{
    struct cfg_obj o;
    const char *element, *names[CG_FIT_NPAR];
    static const char *const def_free[] = {"epsilon", "c"};
    double atom_mass;
    int nfree, rc;
    struct sc_params *sc = &c->spec.start;
    if ((rc = cfg_section(root, "coarse_grain", &o)) ||
        (rc = cfg_string(&o, "element", "Cu", &element)) ||
        (rc = cfg_int(&o, "atoms_per_particle", 8, CFG_RANGE(1, 1000000), &c->atoms_per_particle)) ||
        (rc = cfg_real(&o, "atom_mass", 63.546, CFG_GT(0), &atom_mass)) ||
        (rc = cfg_real(&o, "a", 7.23, CFG_GT(0), &sc->a)) ||
        (rc = cfg_real(&o, "cutoff", 10.845, CFG_GT(0), &sc->rc)) ||
        (rc = cfg_real(&o, "n", 9.0, CFG_RANGE(1, 60), &sc->n)) ||
        (rc = cfg_real(&o, "m", 6.0, CFG_RANGE(1, 60), &sc->m)) ||
        (rc = cfg_real(&o, "epsilon", 8 * 1.2382e-2, CFG_GT(0), &sc->eps)) ||
        (rc = cfg_real(&o, "c", 39.432, CFG_GT(0), &sc->c)) ||
        (rc = cfg_bool(&o, "thermal_pressure", 1, &c->spec.thermal)))
        return rc;
    if (!json_object_get(o.node, "fit"))
        json_object_set_new(o.node, "fit", json_pack("[ss]", def_free[0], def_free[1]));
    if ((rc = cfg_strings(&o, "fit", 1, names, CG_FIT_NPAR, &nfree)) || (rc = cfg_close(&o)))
        return rc;
    for (int k = 0; k < nfree; k++) {
        int found = -1;
        for (int q = 0; q < CG_FIT_NPAR; q++)
            if (strcmp(names[k], cg_fit_param_names[q]) == 0)
                found = q;
        char kp[CFG_PATH_MAX];
        snprintf(kp, sizeof kp, "coarse_grain.fit[%d]", k);
        if (found < 0)
            return cfg_error_at(o.cfg, kp, "'%s' is not a parameter of the form (epsilon, c, n, "
                                           "m, a)",
                                names[k]);
        c->spec.free[found] = 1;
    }
    if (c->spec.free[CG_FIT_C] && c->spec.free[CG_FIT_A])
        return cfg_error_at(o.cfg, "coarse_grain.fit", "c and a cannot both be fitted: both only "
                                                       "set the equilibrium lattice constant");
    if (!(sc->n > sc->m))
        return cfg_error_at(o.cfg, "coarse_grain.n", "n = %g must exceed m = %g", sc->n, sc->m);
    if (!(sc->rc > sc->a / sqrt(2.0)))
        return cfg_error_at(o.cfg, "coarse_grain.cutoff",
                            "cutoff %g Å does not reach the nearest neighbours (%g Å)", sc->rc,
                            sc->a / sqrt(2.0));
    snprintf(c->element, sizeof c->element, "%s", element);
    c->spec.mass = c->atoms_per_particle * atom_mass;
    sc_params_finish(sc);
    return 0;
}

static int fit_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    (void)common;
    struct fit_case *c = calloc(1, sizeof *c);
    if (!c)
        return err_nomem(root->cfg->err, "fit case");
    int weighted = 0, rc;
    double T = 0;
    const char *outfile;
    if ((rc = read_isotherm(root, c, &weighted, &T)) || (rc = read_coarse_grain(root, c)) ||
        (rc = cfg_string(root, "output_file", "cg_params.yaml", &outfile)))
        goto fail;
    if (strchr(outfile, '/') || strlen(outfile) >= sizeof c->output_file) {
        rc = cfg_error_at(root->cfg, "output_file", "'%s' must be a short file name (written "
                                                    "into the run's output directory)",
                          outfile);
        goto fail;
    }
    snprintf(c->output_file, sizeof c->output_file, "%s", outfile);
    c->spec.temperature = T;
    c->spec.weighted = weighted;
    c->spec.max_iter = 500;
    if (root->cfg->shallow) {
        free(c->pts);
        free(c);
        return 0;
    }
    int nfree = 0;
    for (int k = 0; k < CG_FIT_NPAR; k++)
        nfree += c->spec.free[k];
    if (c->npts < nfree) {
        rc = cfg_error_at(root->cfg, "isotherm", "%d points cannot determine %d parameters",
                          c->npts, nfree);
        goto fail;
    }
    *state = c;
    return 0;
fail:
    free(c->pts);
    free(c);
    return rc;
}

static int fit_run(void *state, struct run *run, struct err *e)
{
    struct fit_case *c = state;
    struct cg_fit_result fr;
    int rc = cg_fit_isotherm(&c->spec, c->pts, c->npts, &fr, e);
    if (rc)
        return rc;
    const struct sc_params *sc = &fr.sc;
    const double T = c->spec.temperature, M = c->spec.mass, g = UNITS_EVA3_TO_GPA;
    int th = c->spec.thermal;
    /* the coarse-grained crystal at T and zero pressure */
    double aL = NAN;
    if (cg_lattice_solve_pressure(sc, T, th, 0.0, 0.8 * sc->a, 1.3 * sc->a, &aL) != 0)
        run_log(run, "warning: the fitted model has no zero-pressure state in [0.8 a, 1.3 a]");
    double rho = 4.0 * M / (aL * aL * aL) * UNITS_AMU_A3_TO_KG_M3 / 1000.0;   /* g/cm^3 */
    double h = 1e-4 * aL;
    double dPda = (cg_lattice_pressure(sc, aL + h, T, th) - cg_lattice_pressure(sc, aL - h, T, th)) /
                  (2 * h);
    double B = -aL / 3.0 * dPda;   /* -V dP/dV with V ~ aL^3 */
    double c11, c12, c44;
    cg_lattice_elastic(sc, aL, &c11, &c12, &c44);
    double e100 = (c11 - c12) * (c11 + 2 * c12) / (c11 + c12);
    double rho_si = rho * 1000.0;   /* kg/m^3 */
    double cl = sqrt(c11 * g * 1e9 / rho_si), cb = sqrt(e100 * g * 1e9 / rho_si);

    struct result *res = &run->result;
    for (int k = 0; k < CG_FIT_NPAR; k++) {
        const double vals[CG_FIT_NPAR] = {sc->eps, sc->c, sc->n, sc->m, sc->a};
        const char *units[CG_FIT_NPAR] = {"eV", "1", "1", "1", "Å"};
        result_metric(res, cg_fit_param_names[k], vals[k], units[k]);
        if (c->spec.free[k]) {
            char name[64];
            snprintf(name, sizeof name, "%s_stderr", cg_fit_param_names[k]);
            result_metric(res, name, fr.stderr_par[k], units[k]);
        }
    }
    result_metric(res, "cutoff", sc->rc, "Å");
    result_metric(res, "mass", M, "amu");
    result_metric(res, "residual_rms", fr.rms, "GPa");
    result_metric(res, "residual_max", fr.max_abs, "GPa");
    result_metric(res, "chi2", fr.chi2, "1");
    result_metric(res, "points", (double)c->npts, "1");
    result_metric(res, "iterations", (double)fr.iterations, "1");
    result_metric(res, "lattice_constant", aL, "Å");
    result_metric(res, "density", rho, "g/cm^3");
    result_metric(res, "bulk_modulus", B * g, "GPa");
    result_metric(res, "c11", c11 * g, "GPa");
    result_metric(res, "c12", c12 * g, "GPa");
    result_metric(res, "c44", c44 * g, "GPa");
    result_metric(res, "longitudinal_wave_speed", cl, "m/s");
    result_metric(res, "bar_wave_speed", cb, "m/s");
    double *col = malloc((size_t)4 * c->npts * sizeof *col);
    if (!col)
        return err_nomem(e, "fit series");
    for (int i = 0; i < c->npts; i++) {
        double Pm = cg_fit_model_pressure(sc, M, T, th, c->pts[i].density);
        col[i] = c->pts[i].density;
        col[c->npts + i] = c->pts[i].pressure;
        col[2 * c->npts + i] = Pm;
        col[3 * c->npts + i] = Pm - c->pts[i].pressure;
    }
    result_series(res, "density", col, c->npts, "g/cm^3");
    result_series(res, "pressure_md", col + c->npts, c->npts, "GPa");
    result_series(res, "pressure_model", col + 2 * c->npts, c->npts, "GPa");
    result_series(res, "residual", col + 3 * c->npts, c->npts, "GPa");
    free(col);
    run_log(run, "fit (%s, %ld iterations): epsilon = %.6g eV, c = %.6g, n = %g, m = %g, "
                 "a = %g Å; rms residual %.4g GPa, max %.4g GPa",
            fr.stop, fr.iterations, sc->eps, sc->c, sc->n, sc->m, sc->a, fr.rms, fr.max_abs);
    run_log(run, "at %g K and zero pressure: lattice constant %.5f Å, B = %.1f GPa, C11 = %.1f, "
                 "C12 = %.1f, C44 = %.1f GPa",
            T, aL, B * g, c11 * g, c12 * g, c44 * g);

    /* the parameter file */
    struct cg_params prm;
    memset(&prm, 0, sizeof prm);
    snprintf(prm.element, sizeof prm.element, "%s", c->element);
    prm.sc = *sc;
    prm.mass = M;
    prm.atoms_per_particle = c->atoms_per_particle;
    prm.lattice_constant = aL;
    json_t *fit = json_object();
    json_object_set_new(fit, "temperature_K", json_real(T));
    json_object_set_new(fit, "points", json_integer(c->npts));
    json_object_set_new(fit, "source", json_string(c->source));
    json_object_set_new(fit, "residual_rms_GPa", json_real(fr.rms));
    json_object_set_new(fit, "residual_max_GPa", json_real(fr.max_abs));
    json_object_set_new(fit, "thermal_pressure", json_boolean(th));
    json_t *freed = json_array();
    for (int k = 0; k < CG_FIT_NPAR; k++)
        if (c->spec.free[k])
            json_array_append_new(freed, json_string(cg_fit_param_names[k]));
    json_object_set_new(fit, "fitted", freed);
    json_object_set_new(fit, "bulk_modulus_GPa", json_real(B * g));
    json_object_set_new(fit, "case_key", json_string(run->case_key));
    char path[4096];
    run_path(run, c->output_file, path, sizeof path);
    rc = cg_params_write(path, &prm,
                         "Coarse-grained Sutton-Chen parameters for DPD, fitted by cascade-solver "
                         "(type: dpd_fit)\nto an MD pressure-density isotherm (Chen et al. 2014, "
                         "Sec. 2.2).",
                         fit, e);
    json_decref(fit);
    if (!rc)
        result_artifact(res, "parameters", c->output_file);
    return rc;
}

static void fit_destroy(void *state)
{
    struct fit_case *c = state;
    if (!c)
        return;
    free(c->pts);
    free(c);
}

static long fit_particles(const void *state)
{
    (void)state;
    return 0;
}

const struct case_type dpd_fit_case_type = {
    "dpd_fit", "fit coarse-grained Sutton-Chen DPD parameters to an MD pressure-density isotherm",
    fit_read, fit_run, fit_destroy, fit_particles, NULL,
    .checkpoints = 0,
};
