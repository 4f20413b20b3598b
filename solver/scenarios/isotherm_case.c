/*
 * isotherm_case: pressure against volume along an isotherm (`type:
 * isotherm`), Guo & Yang 2005, Fig. 11: the 293 K isotherm of copper with
 * the Mishin EAM against diamond-anvil data and first-principles curves.
 *
 *   isotherm:
 *     lattice: fcc            fcc | bcc
 *     element: Cu
 *     a: 3.615                Å at 0 K: the starting guess
 *     temperature: 293        K
 *     cells: 5                periodic cubic cells along each axis
 *     volume_ratios: [1.0, 0.9, 0.8, 0.7, 0.6]   V/V0, V0 the zero-pressure
 *                             volume at the temperature
 *     equilibrate: 1.0        ps of Langevin before averaging
 *     average: 2.0            ps of averaging (Langevin continues)
 *     damping_time: 0.1       ps
 *     reference_b0: 133       GPa  } a room-temperature Vinet fit to experiment
 *     reference_b0p: 5.4           } (copper, diamond-anvil data) for comparison
 *   potential: {...}
 *   md: {timestep: 0.001, skin: 1.0}
 *
 * Each volume is its own periodic crystal, thermalised and averaged under
 * a Langevin bath.  The Vinet form is fitted to the points (analysis/eos.h).
 * Series: v_ratio, pressure_GPa, pressure_reference_GPa, pxx_GPa, pyy_GPa,
 * pzz_GPa, temperature_K.  Metrics: lattice_constant_T, volume_per_atom_T,
 * b0, b0p (Vinet fit), pressure_min_volume (at the smallest ratio) and its
 * deviation from the reference curve.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/eos.h"
#include "core/units.h"
#include "md/md_settings.h"
#include "scenarios/case_type.h"
#include "md/md_timestep.h"
#include "scenarios/thermal_crystal.h"

struct isotherm {
    struct potential *pot;
    struct thermal_spec th;
    double a, ref_b0, ref_b0p;
    double *vr;
    size_t nv;
    long steps_done, natoms;
};

static const char *const ilattices[] = {"fcc", "bcc", NULL};

static void isotherm_destroy(void *state)
{
    struct isotherm *c = state;
    if (!c)
        return;
    potential_destroy(&c->pot);
    free(c->vr);
    free(c);
}

static int isotherm_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct cfg_obj io, po;
    struct md_settings ms;
    int rc, lat;
    const char *element;
    long cells;
    double a, T, teq, tavg, tau, b0, b0p, dt, skin, *vr = NULL;
    size_t nv = 0;
    if ((rc = cfg_section_required(root, "isotherm", &io)) ||
        (rc = cfg_enum(&io, "lattice", "fcc", ilattices, &lat)) ||
        (rc = cfg_string(&io, "element", NULL, &element)) ||
        (rc = cfg_real(&io, "a", CFG_REQUIRED, CFG_GT(0), &a)) ||
        (rc = cfg_real(&io, "temperature", 293.0, CFG_GE(0), &T)) ||
        (rc = cfg_int(&io, "cells", 5, CFG_RANGE(2, 100), &cells)) ||
        (rc = cfg_real_list(&io, "volume_ratios", 1, CFG_RANGE(0.2, 1.5), &vr, &nv)) ||
        (rc = cfg_real(&io, "equilibrate", 1.0, CFG_GE(0), &teq)) ||
        (rc = cfg_real(&io, "average", 2.0, CFG_GT(0), &tavg)) ||
        (rc = cfg_real(&io, "damping_time", 0.1, CFG_GT(0), &tau)) ||
        (rc = cfg_real(&io, "reference_b0", 133.0, CFG_GT(0), &b0)) ||
        (rc = cfg_real(&io, "reference_b0p", 5.4, CFG_ANY, &b0p)) || (rc = cfg_close(&io)) ||
        (rc = md_settings_read(root, MD_KEY_TIMESTEP | MD_KEY_SKIN, &md_settings_defaults, &ms))) {
        free(vr);
        return rc;
    }
    dt = ms.timestep;
    skin = ms.skin;
    struct potential *pot = NULL;
    if ((rc = cfg_section_required(root, "potential", &po)) || (rc = potential_create(&po, &pot))) {
        free(vr);
        return rc;
    }
    if (root->cfg->shallow) {
        potential_destroy(&pot);
        free(vr);
        return 0;
    }
    struct isotherm *c = calloc(1, sizeof *c);
    if (!c) {
        potential_destroy(&pot);
        free(vr);
        return err_nomem(root->cfg->err, "isotherm case");
    }
    c->pot = pot;
    c->th = (struct thermal_spec){lat == 0 ? LATTICE_FCC : LATTICE_BCC, element, {cells, cells, cells},
                                  T, dt, skin, tau, teq, tavg, common->seed, common->nthreads};
    c->a = a;
    c->ref_b0 = b0;
    c->ref_b0p = b0p;
    c->vr = vr;
    c->nv = nv;
    c->natoms = cells * cells * cells * (lat == 0 ? 4 : 2);
    /* the cross-section must hold the cutoff; the time step must be stable
     * at the smallest volume */
    double vmin = 1.0;
    for (size_t k = 0; k < nv; k++)
        vmin = fmin(vmin, vr[k]);
    if (cells * a * cbrt(vmin) < 2.0 * (pot->cutoff + skin)) {
        isotherm_destroy(c);
        return cfg_error_at(root->cfg, "isotherm.cells",
                            "%ld cells (%.1f Å at V/V0 = %g) are fewer than two cutoffs plus skins "
                            "(%.1f Å) across", cells, cells * a * cbrt(vmin), vmin,
                            2.0 * (pot->cutoff + skin));
    }
    struct thermal_spec cold = c->th;
    cold.temperature = 0;
    struct md md;
    rc = thermal_crystal_md(&md, pot, &cold, a * cbrt(vmin), NULL, root->cfg->err);
    if (!rc)
        rc = md_check_timestep(&md, root->cfg, "md.timestep");
    md.pot = NULL;
    md_free(&md);
    if (rc) {
        isotherm_destroy(c);
        return rc;
    }
    *state = c;
    return 0;
}

static int isotherm_run(void *state, struct run *run, struct err *e)
{
    struct isotherm *c = state;
    double a_T = c->a, p_left = 0;
    int rc = 0;
    timer_start(&run->timers, TIMER_LOOP);
    if (c->th.temperature > 0) {
        rc = thermal_lattice_constant(c->pot, &c->th, c->a, 0.02 / UNITS_EVA3_TO_GPA, &a_T, &p_left, e);
        if (rc)
            goto done;
    }
    run_log(run, "V0 at %g K: lattice constant %.5f Å (pressure left %.3f GPa)", c->th.temperature,
            a_T, p_left * UNITS_EVA3_TO_GPA);
    size_t n = c->nv;
    double *col = calloc(7 * (n + 1), sizeof *col);
    if (!col) {
        rc = err_nomem(e, "isotherm series");
        goto done;
    }
    double *vr = col, *pp = col + n, *pref = col + 2 * n, *pxx = col + 3 * n, *pyy = col + 4 * n,
           *pzz = col + 5 * n, *tt = col + 6 * n;
    const double g = UNITS_EVA3_TO_GPA;
    for (size_t k = 0; k < n && !rc; k++) {
        struct md md;
        double P[6], T;
        rc = thermal_crystal_md(&md, c->pot, &c->th, a_T * cbrt(c->vr[k]), NULL, e);
        md.timers = &run->timers;
        if (!rc)
            rc = thermal_average(&md, c->th.t_eq + c->th.t_avg, c->th.t_avg, P, &T, e);
        c->steps_done += md.step;
        md.pot = NULL;
        md_free(&md);
        if (rc)
            break;
        vr[k] = c->vr[k];
        pp[k] = (P[0] + P[1] + P[2]) / 3.0 * g;
        pref[k] = c->vr[k] < 1.0 ? eos_vinet_pressure(c->vr[k], c->ref_b0, c->ref_b0p) : 0.0;
        pxx[k] = P[0] * g;
        pyy[k] = P[1] * g;
        pzz[k] = P[2] * g;
        tt[k] = T;
        run_log(run, "V/V0 = %.3f: P = %8.2f GPa (reference %8.2f), T = %.0f K", vr[k], pp[k],
                pref[k], T);
    }
    if (!rc) {
        static const char *const names[7] = {"v_ratio", "pressure_GPa", "pressure_reference_GPa",
                                             "pxx_GPa", "pyy_GPa", "pzz_GPa", "temperature_K"};
        static const char *const units[7] = {"1", "GPa", "GPa", "GPa", "GPa", "GPa", "K"};
        for (int q = 0; q < 7 && !rc; q++) {
            result_series(&run->result, names[q], col + q * n, (int)n, units[q]);
            if (run->h5_open)
                rc = h5out_write_series(&run->h5, names[q], col + q * n, (long)n, units[q], e);
        }
        struct result *r = &run->result;
        result_metric(r, "lattice_constant_T", a_T, "Å");
        double atoms_per_cell = c->th.style == LATTICE_FCC ? 4.0 : 2.0;
        result_metric(r, "volume_per_atom_T", a_T * a_T * a_T / atoms_per_cell, "Å^3");
        size_t kmin = 0;
        for (size_t k = 1; k < n; k++)
            if (vr[k] < vr[kmin])
                kmin = k;
        result_metric(r, "v_ratio_min", vr[kmin], "1");
        result_metric(r, "pressure_min_volume", pp[kmin], "GPa");
        if (pref[kmin] > 0)
            result_metric(r, "pressure_min_volume_deviation", pp[kmin] / pref[kmin] - 1.0, "1");
        double b0, b0p;
        struct err fe = {0};
        if (eos_fit_vinet(vr, pp, (int)n, &b0, &b0p, &fe) == 0) {
            result_metric(r, "b0", b0, "GPa");
            result_metric(r, "b0p", b0p, "1");
            run_log(run, "Vinet fit: B0 = %.1f GPa, B0' = %.2f (reference %.1f GPa, %.2f)", b0, b0p,
                    c->ref_b0, c->ref_b0p);
        } else {
            run_log(run, "no Vinet fit: %s", fe.msg);
        }
    }
    free(col);
done:
    timer_stop(&run->timers, TIMER_LOOP);
    run->steps_run = c->steps_done;
    return rc;
}

static long isotherm_particles(const void *state)
{
    const struct isotherm *c = state;
    return c ? c->natoms : 0;
}

const struct case_type isotherm_case_type = {
    "isotherm", "pressure-volume isotherm of a crystal at a temperature, with a Vinet fit",
    isotherm_read, isotherm_run, isotherm_destroy, isotherm_particles, NULL,
    .checkpoints = 0,
};
