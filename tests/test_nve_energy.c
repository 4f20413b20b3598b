/*
 * NVE energy of velocity Verlet, as the md case reports it: the drift as
 * the slope of a least-squares line through the total energy per atom
 * against time (energy_drift_rate, eV/atom/ps), and the fluctuation as the
 * RMS deviation from that line (energy_fluctuation, eV/atom).  Verlet is
 * symplectic: its energy error oscillates with an amplitude of O(dt^2) and
 * does not drift, so the fluctuation must grow fourfold when the time step
 * doubles, and the drift over the run must stay below the fluctuation.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>

#include "helpers/th.h"

static void nve(double dt, double *rate, double *fluct)
{
    char yaml[1024], name[64], dir[1024];
    snprintf(yaml, sizeof yaml,
             "seed: 3\n"
             "system: {lattice: {style: fcc, a: 3.61, cells: [4, 4, 4]}, element: Cu}\n"
             "potential: {style: sutton_chen}\n"
             "md: {timestep: %g, steps: %ld, temperature: 600}\n"
             "output: {hdf5: false, thermo_every: 0}\n",
             dt, lround(2.0 / dt));
    snprintf(name, sizeof name, "nve-%g.yaml", dt);
    const char *path = th_write_temp(1, name, yaml);
    snprintf(dir, sizeof dir, "%s/nve-%g", th_temp_dir(), dt);
    const char *argv[] = {th_solver(), "run", path, "--out", dir, "--quiet", NULL};
    char out[4096];
    cr_assert_eq(th_run(argv, out, sizeof out), 0, "%s", out);
    char rp[1100];
    snprintf(rp, sizeof rp, "%s/result.json", dir);
    json_t *r = json_load_file(rp, 0, NULL);
    cr_assert_not_null(r);
    json_t *m = json_object_get(r, "metrics");
    *rate = json_number_value(json_object_get(json_object_get(m, "energy_drift_rate"), "value"));
    *fluct = json_number_value(json_object_get(json_object_get(m, "energy_fluctuation"), "value"));
    cr_assert_str_eq(json_string_value(json_object_get(json_object_get(m, "energy_drift_rate"),
                                                       "unit")),
                     "eV/atom/ps");
    json_decref(r);
}

Test(nve_energy, fluctuation_scales_as_dt_squared_without_drift, .timeout = 120)
{
    double r1, f1, r2, f2, r4, f4;
    nve(0.001, &r1, &f1);
    nve(0.002, &r2, &f2);
    nve(0.004, &r4, &f4);
    cr_log_info("dt 1/2/4 fs: fluctuation %.3g %.3g %.3g eV/atom, drift %.3g %.3g %.3g eV/atom/ps",
                f1, f2, f4, r1, r2, r4);
    /* O(dt^2): a ratio of 4 per doubling (measured 4.02 and 4.06) */
    cr_assert(f2 / f1 > 3.6 && f2 / f1 < 4.4, "fluctuation ratio 2 fs / 1 fs = %g", f2 / f1);
    cr_assert(f4 / f2 > 3.6 && f4 / f2 < 4.4, "fluctuation ratio 4 fs / 2 fs = %g", f4 / f2);
    /* no drift: over the 2 ps run the fitted line moves less than the
     * fluctuation about it */
    cr_assert_lt(fabs(r1) * 2.0, f1, "drift %g eV/atom/ps against fluctuation %g", r1, f1);
    cr_assert_lt(fabs(r2) * 2.0, f2, "drift %g eV/atom/ps against fluctuation %g", r2, f2);
    cr_assert_gt(f1, 0.0);
}
