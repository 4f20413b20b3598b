/*
 * dpd_tensile_case: a DPD rod pulled apart by its rigid ends (`type:
 * dpd_tensile`), Chen et al. 2014 Sec. 4.1.2: rod 216 x 72.3 x 72.3 Å, the
 * two ends (15 Å each) rigid and moved apart at 2.169 Å/ps each (strain
 * rate 2 v / L = 0.02/ps); the stress-strain curve from the forces on the
 * rigid ends over the cross-section, and its peak.
 *
 *   system:   the rod (md_system.h): read_data of the equilibrated bar, or a lattice
 *   dpd:      dpd_setup.h (default variant dpde)
 *   tensile:
 *     axis: x                   the rod axis
 *     grip_length: 15.0         Å of material at each end held rigid
 *     velocity: 2.169           Å/ps of each end, outward
 *     lattice_constant: 0       Å for the plane spacing a/2 that sets the rod's length
 *                               and cross-section (0: the parameter file's)
 *     area: 0                   Å^2 cross-section (0: measured, (extent + a/2)^2 per axis)
 *     velocity_ramp: true       start the rod at the homogeneous strain rate: every
 *                               free particle gets v (2 x - x_lo - x_hi) / (x_hi - x_lo)
 *                               along the axis on top of its thermal velocity
 *     sample_every: 20          steps per stress-strain point (forces averaged over them)
 *
 * Strain: engineering, 2 v t / L0 with L0 the rod's length (faces + a/2).
 * Stress: (F_left - F_right) / (2 A) along the axis, F the total force of
 * the rest of the rod on each grip (conservative + dissipative + random),
 * tension positive.
 *
 * Without the velocity ramp the ends start at full speed into a rod at rest
 * and the first picoseconds carry its dynamic response instead: the stress
 * jumps to about rho c v (7 GPa for the paper's rod) and waves cross the
 * rod every 2 L / c.  The ramp (the usual start of constant-strain-rate MD
 * tension) removes that jump, so the peak is the rod's strength.
 *
 * Metrics: peak_stress (GPa), strain_at_peak (1), strain_rate (1/ps),
 * strain_final (1), rod_length (Å), area (Å^2), grip_particles (1).
 * Series: strain, stress (GPa), time_ps.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"
#include "scenarios/dpd_bar.h"
#include "scenarios/dpd_output.h"
#include "scenarios/dpd_setup.h"
#include "scenarios/md_system.h"

#define GRIP_LO_BIT (1u << 2)
#define GRIP_HI_BIT (1u << 3)

struct tensile_case {
    struct dpd d;
    long steps;
    int axis;
    double v, L0, area;
    long sample_every, ngrip;
};

struct tensile_keys {
    int axis, ramp;
    double grip, v, a, area;
    long every;
};

static int read_tensile(struct cfg_obj *root, struct tensile_keys *k)
{
    static const char *const axes[] = {"x", "y", "z", NULL};
    struct cfg_obj o;
    int rc;
    if ((rc = cfg_section(root, "tensile", &o)) ||
        (rc = cfg_enum(&o, "axis", "x", axes, &k->axis)) ||
        (rc = cfg_real(&o, "grip_length", 15.0, CFG_GT(0), &k->grip)) ||
        (rc = cfg_real(&o, "velocity", 2.169, CFG_GT(0), &k->v)) ||
        (rc = cfg_real(&o, "lattice_constant", 0.0, CFG_GE(0), &k->a)) ||
        (rc = cfg_real(&o, "area", 0.0, CFG_GE(0), &k->area)) ||
        (rc = cfg_bool(&o, "velocity_ramp", 1, &k->ramp)) ||
        (rc = cfg_int(&o, "sample_every", 20, CFG_GE(1), &k->every)))
        return rc;
    return cfg_close(&o);
}

static int tensile_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box;
    struct md_system_info info;
    struct dpd_input in;
    struct tensile_keys k = {0, 0, 0, 0, 0, 0, 0};
    int rc = md_system_read(root, common->seed, &p, &box, &info);
    if (!rc)
        rc = dpd_section_read(root, DPD_ENERGY, &in);
    if (!rc)
        rc = read_tensile(root, &k);
    int axis = k.axis;
    double grip = k.grip, v = k.v, a = k.a;
    if (!rc && box.bc[axis] == BOUNDARY_PERIODIC)
        rc = cfg_error_at(root->cfg, "system.boundary",
                          "the rod axis %c must not be periodic (its ends are pulled apart)",
                          "xyz"[axis]);
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        return rc;
    }
    struct err *e = root->cfg->err;
    struct tensile_case *c = calloc(1, sizeof *c);
    if (!c) {
        particles_destroy(&p);
        return err_nomem(e, "tensile case");
    }
    if (!(a > 0))
        a = in.prm.lattice_constant;
    struct dpd_bar bar;
    dpd_bar_measure(p, 0, 0.5 * a, &bar);
    c->L0 = bar.extent[axis];
    if (!(2 * grip < bar.face_hi[axis] - bar.face_lo[axis])) {
        particles_destroy(&p);
        free(c);
        return cfg_error_at(root->cfg, "tensile.grip_length",
                            "grips of %g Å at both ends leave nothing of a %g Å rod", grip,
                            bar.extent[axis]);
    }
    /* a grip is the material within grip_length of its end of the rod */
    double lo_cut = bar.face_lo[axis] - 0.5 * bar.plane + grip;
    double hi_cut = bar.face_hi[axis] + 0.5 * bar.plane - grip;
    for (int i = 0; i < p->n_owned; i++) {
        double x = p->x[3 * i + axis];
        if (x < lo_cut)
            p->mask[i] |= GRIP_LO_BIT;
        else if (x > hi_cut)
            p->mask[i] |= GRIP_HI_BIT;
    }
    rc = dpd_init_velocities(&in, p, common, e);
    if (rc) {
        particles_destroy(&p);
        free(c);
        return rc;
    }
    if (k.ramp) {
        double xlo = bar.face_lo[axis], xhi = bar.face_hi[axis];
        for (int i = 0; i < p->n_owned; i++)
            p->v[3 * i + axis] += v * (2 * p->x[3 * i + axis] - xlo - xhi) / (xhi - xlo);
    }
    rc = dpd_build(&in, p, &box, common, e, &c->d);
    double vlo[3] = {0, 0, 0}, vhi[3] = {0, 0, 0};
    vlo[axis] = -v;
    vhi[axis] = v;
    if (!rc)
        rc = dpd_add_body(&c->d, GRIP_LO_BIT, DPD_BODY_PRESCRIBED, vlo, e);
    if (!rc)
        rc = dpd_add_body(&c->d, GRIP_HI_BIT, DPD_BODY_PRESCRIBED, vhi, e);
    if (rc) {
        dpd_free(&c->d);
        free(c);
        return rc;
    }
    c->steps = in.steps;
    c->axis = axis;
    c->v = v;
    int t1 = (axis + 1) % 3, t2 = (axis + 2) % 3;
    c->area = k.area > 0 ? k.area : bar.extent[t1] * bar.extent[t2];
    c->sample_every = k.every;
    c->ngrip = c->d.body[0].n + c->d.body[1].n;
    *state = c;
    return 0;
}

static int tensile_run(void *state, struct run *run, struct err *e)
{
    struct tensile_case *c = state;
    struct dpd *d = &c->d;
    d->timers = &run->timers;
    struct dpd_output out;
    int rc = dpd_output_begin(&out, run, e);
    if (rc)
        return rc;
    long nmax = c->steps / c->sample_every + 2;
    double *strain = malloc((size_t)nmax * sizeof *strain);
    double *stress = malloc((size_t)nmax * sizeof *stress);
    double *times = malloc((size_t)nmax * sizeof *times);
    long ns = 0;
    if (!strain || !stress || !times) {
        rc = err_nomem(e, "stress-strain samples");
        goto done;
    }
    d->peratom = run_due(0, c->steps, run->out.snapshot_every);
    if ((rc = dpd_compute_forces(d, e)) || (rc = dpd_output_step(&out, run, d, c->steps)))
        goto done;
    progress_start(&run->progress, stderr, c->steps, d->dt, run->opt.progress && !run->opt.quiet);
    timer_start(&run->timers, TIMER_LOOP);
    double fsum = 0, tsum = 0;
    long nacc = 0;
    for (long s = 1; s <= c->steps && !rc; s++) {
        d->peratom = run_due(s, c->steps, run->out.snapshot_every);
        if ((rc = dpd_step(d, e)))
            break;
        if (!isfinite(d->epot)) {
            rc = err_set(e, ERR_DIVERGED, "diverged: non-finite energy at step %ld", s);
            break;
        }
        /* Chen 2014 Sec. 4.1.2: stress from the rigid-end forces */
        fsum += 0.5 * (d->body[0].force[c->axis] - d->body[1].force[c->axis]);
        tsum += d->time;
        nacc++;
        if (nacc == c->sample_every || s == c->steps) {
            double t = tsum / nacc;
            times[ns] = t;
            strain[ns] = 2.0 * c->v * t / c->L0;
            stress[ns] = fsum / nacc / c->area * UNITS_EVA3_TO_GPA;
            ns++;
            fsum = tsum = 0;
            nacc = 0;
        }
        rc = dpd_output_step(&out, run, d, c->steps);
        progress_update(&run->progress, s);
    }
    timer_stop(&run->timers, TIMER_LOOP);
    progress_finish(&run->progress, d->step);
    {
        struct result *res = &run->result;
        long kpk = -1;
        for (long k = 0; k < ns; k++)
            if (kpk < 0 || stress[k] > stress[kpk])
                kpk = k;
        result_metric(res, "peak_stress", kpk >= 0 ? stress[kpk] : NAN, "GPa");
        result_metric(res, "strain_at_peak", kpk >= 0 ? strain[kpk] : NAN, "1");
        result_metric(res, "strain_rate", 2.0 * c->v / c->L0, "1/ps");
        result_metric(res, "strain_final", 2.0 * c->v * d->time / c->L0, "1");
        result_metric(res, "rod_length", c->L0, "Å");
        result_metric(res, "area", c->area, "Å^2");
        result_metric(res, "particles", (double)d->p->n_owned, "1");
        result_metric(res, "grip_particles", (double)c->ngrip, "1");
        result_metric(res, "temperature", dpd_temperature(d), "K");
        result_series(res, "time_ps", times, (int)ns, "ps");
        result_series(res, "strain", strain, (int)ns, "1");
        result_series(res, "stress", stress, (int)ns, "GPa");
        if (kpk >= 0)
            run_log(run, "peak stress %.3f GPa at strain %.4f", stress[kpk], strain[kpk]);
    }
done:
    free(strain);
    free(stress);
    free(times);
    {
        int rc2 = dpd_output_end(&out, run, e);
        if (!rc && !rc2)
            rc2 = run_write_final_state(run, d->p, &d->box, d->step, d->time, e);
        return rc ? rc : rc2;
    }
}

static void tensile_destroy(void *state)
{
    struct tensile_case *c = state;
    if (!c)
        return;
    dpd_free(&c->d);
    free(c);
}

static long tensile_particles(const void *state)
{
    const struct tensile_case *c = state;
    return c->d.p ? c->d.p->n_owned : 0;
}

static long tensile_steps(const void *state)
{
    const struct tensile_case *c = state;
    return c->steps;
}

const struct case_type dpd_tensile_case_type = {
    "dpd_tensile", "DPD tensile rod pulled by rigid ends: stress-strain curve and peak stress",
    tensile_read, tensile_run, tensile_destroy, tensile_particles, tensile_steps,
};
