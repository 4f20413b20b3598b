/* dpd_tensile_setup: the tensile rod, its grips and its stress-strain curve. */
#include "scenarios/dpd_tensile_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "core/velocity.h"
#include "scenarios/dpd_bar.h"
#include "scenarios/dpd_setup.h"
#include "input/md_system.h"

static int read_tensile(struct cfg_obj *root, struct dpd_tensile *k)
{
    static const char *const axes[] = {"x", "y", "z", NULL};
    struct cfg_obj o;
    int rc;
    if ((rc = cfg_section(root, "tensile", &o)) ||
        (rc = cfg_enum(&o, "axis", "x", axes, &k->axis)) ||
        (rc = cfg_real(&o, "grip_length", 15.0, CFG_GT(0), &k->grip)) ||
        (rc = cfg_real(&o, "velocity", 2.169, CFG_GT(0), &k->v)) ||
        (rc = cfg_real(&o, "lattice_constant", 0.0, CFG_GE(0), &k->a)) ||
        (rc = cfg_real(&o, "area", 0.0, CFG_GE(0), &k->area_key)) ||
        (rc = cfg_bool(&o, "velocity_ramp", 1, &k->ramp)) ||
        (rc = cfg_int(&o, "sample_every", 20, CFG_GE(1), &k->sample_every)))
        return rc;
    return cfg_close(&o);
}

int dpd_tensile_read(struct cfg_obj *root, const struct case_common *common, struct dpd *d,
                     struct dpd_tensile *t, struct halo **halo, int sweep)
{
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    struct dpd_input in;
    memset(t, 0, sizeof *t);
    /* Each rank builds (a lattice) or receives (a file) only its brick's
     * particles: the dpd section first, its ranges size the bricks.  With
     * the sweep (dpd_tensile) the bricks are planned on the box; the
     * grid-carried rod (no sweep) on the rod's extent less the skin, the
     * box its first ghost build shrink-wraps to (md_system_split.on_extent:
     * a pass over the lattice's sites that stores none, or rank 0's file). */
    int split = halo != NULL;
    struct halo *mine = NULL;
    int rc;
    if (split) {
        rc = dpd_section_read(root, DPD_ENERGY, &in);
        struct dpd_split_plan plan = {&in, common, root->cfg, !sweep};
        struct md_system_split sp = {dpd_split_plan_bricks, &plan, 0, common->par, !sweep};
        if (!rc)
            rc = md_system_read_split(root, common->seed, root->cfg->shallow ? NULL : &sp, &p,
                                      &box, &info, &mine);
    } else {
        rc = md_system_read(root, common->seed, &p, &box, &info);
        if (!rc)
            rc = dpd_section_read(root, DPD_ENERGY, &in);
    }
    if (mine) {
        *halo = mine;
        p->halo = mine;
        p->par = NULL;   /* no replicated sums: each rank owns its brick */
    }
    if (!rc)
        rc = read_tensile(root, t);
    int axis = t->axis;
    if (!rc && box.bc[axis] == BOUNDARY_PERIODIC)
        rc = cfg_error_at(root->cfg, "system.boundary",
                          "the rod axis %c must not be periodic (its ends are pulled apart)",
                          "xyz"[axis]);
    if (rc || root->cfg->shallow) {
        particles_destroy(&p);
        return rc;
    }
    struct err *e = root->cfg->err;
    double a = t->a > 0 ? t->a : in.prm.lattice_constant, v = t->v;
    struct dpd_bar *bar = &t->bar;
    dpd_bar_measure_over(p, 0, 0.5 * a, mine, bar);   /* over every rank's particles */
    t->L0 = bar->extent[axis];
    if (!(2 * t->grip < bar->face_hi[axis] - bar->face_lo[axis])) {
        particles_destroy(&p);
        return cfg_error_at(root->cfg, "tensile.grip_length",
                            "grips of %g Å at both ends leave nothing of a %g Å rod", t->grip,
                            bar->extent[axis]);
    }
    /* a grip is the material within grip_length of its end of the rod */
    double lo_cut = bar->face_lo[axis] - 0.5 * bar->plane + t->grip;
    double hi_cut = bar->face_hi[axis] + 0.5 * bar->plane - t->grip;
    for (int i = 0; i < p->n_owned; i++) {
        double x = p->x[3 * i + axis];
        if (x < lo_cut)
            p->mask[i] |= DPD_GRIP_LO_BIT;
        else if (x > hi_cut)
            p->mask[i] |= DPD_GRIP_HI_BIT;
    }
    /* the k-th Maxwell draw to the k-th id of all ranks: the serial
     * velocities (to round-off on bricks, bitwise serially) */
    for (int k = 0; k < p->ntypes; k++)
        p->mass[k] = in.prm.mass;
    if (in.t_init > 0)
        rc = velocity_maxwell_split(p, in.t_init, common->seed, 1u, mine, e);
    if (rc) {
        particles_destroy(&p);
        return rc;
    }
    if (t->ramp) {
        double xlo = bar->face_lo[axis], xhi = bar->face_hi[axis];
        for (int i = 0; i < p->n_owned; i++)
            p->v[3 * i + axis] += v * (2 * p->x[3 * i + axis] - xlo - xhi) / (xhi - xlo);
    }
    /* bricks: each rank keeps what it built (a particle a displacement
     * moved just out of its brick migrates at the first list build) */
    if (mine)
        rc = halo_adopt(mine, p, 0, e);
    if (rc) {
        particles_destroy(&p);
        return rc;
    }
    rc = dpd_build(&in, p, &box, common, e, d);
    double vlo[3] = {0, 0, 0}, vhi[3] = {0, 0, 0};
    vlo[axis] = -v;
    vhi[axis] = v;
    if (!rc)
        rc = dpd_add_body(d, DPD_GRIP_LO_BIT, DPD_BODY_PRESCRIBED, vlo, e);
    if (!rc)
        rc = dpd_add_body(d, DPD_GRIP_HI_BIT, DPD_BODY_PRESCRIBED, vhi, e);
    if (rc) {
        dpd_free(d);
        return rc;
    }
    t->steps = in.steps;
    int t1 = (axis + 1) % 3, t2 = (axis + 2) % 3;
    t->area = t->area_key > 0 ? t->area_key : bar->extent[t1] * bar->extent[t2];
    t->ngrip = d->body[0].n + d->body[1].n;
    return 0;
}

int dpd_tensile_curve_init(struct dpd_tensile_curve *cv, const struct dpd_tensile *t,
                           struct err *e)
{
    memset(cv, 0, sizeof *cv);
    cv->cap = t->steps / t->sample_every + 2;
    cv->strain = malloc((size_t)cv->cap * sizeof *cv->strain);
    cv->stress = malloc((size_t)cv->cap * sizeof *cv->stress);
    cv->times = malloc((size_t)cv->cap * sizeof *cv->times);
    if (!cv->strain || !cv->stress || !cv->times) {
        dpd_tensile_curve_free(cv);
        return err_nomem(e, "stress-strain samples");
    }
    return 0;
}

void dpd_tensile_curve_add(struct dpd_tensile_curve *cv, const struct dpd_tensile *c,
                           const struct dpd *d, int last)
{
    /* Chen 2014 Sec. 4.1.2: stress from the rigid-end forces */
    cv->fsum += 0.5 * (d->body[0].force[c->axis] - d->body[1].force[c->axis]);
    cv->tsum += d->time;
    cv->nacc++;
    if (cv->nacc == c->sample_every || last) {
        double t = cv->tsum / cv->nacc;
        cv->times[cv->n] = t;
        cv->strain[cv->n] = 2.0 * c->v * t / c->L0;
        cv->stress[cv->n] = cv->fsum / cv->nacc / c->area * UNITS_EVA3_TO_GPA;
        cv->n++;
        cv->fsum = cv->tsum = 0;
        cv->nacc = 0;
    }
}

void dpd_tensile_curve_report(const struct dpd_tensile_curve *cv, const struct dpd_tensile *c,
                              const struct dpd *d, struct run *run)
{
    struct result *res = &run->result;
    const long ns = cv->n;
    const double *strain = cv->strain, *stress = cv->stress;
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
    result_metric(res, "particles", (double)dpd_nparticles(d), "1");
    result_metric(res, "grip_particles", (double)c->ngrip, "1");
    result_metric(res, "temperature", dpd_temperature(d), "K");
    result_series(res, "time_ps", cv->times, (int)ns, "ps");
    result_series(res, "strain", strain, (int)ns, "1");
    result_series(res, "stress", stress, (int)ns, "GPa");
    if (kpk >= 0)
        run_log(run, "peak stress %.3f GPa at strain %.4f", stress[kpk], strain[kpk]);
}

int dpd_tensile_curve_checkpoint_write(const struct dpd_tensile_curve *cv, struct ckpt *ck)
{
    int rc = ckpt_put_doubles(ck, "strain", cv->strain, cv->n);
    if (!rc) rc = ckpt_put_doubles(ck, "stress", cv->stress, cv->n);
    if (!rc) rc = ckpt_put_doubles(ck, "time", cv->times, cv->n);
    if (!rc) rc = ckpt_put_double(ck, "force_sum", cv->fsum);
    if (!rc) rc = ckpt_put_double(ck, "time_sum", cv->tsum);
    if (!rc) rc = ckpt_put_long(ck, "steps_summed", cv->nacc);
    return rc;
}

int dpd_tensile_curve_checkpoint_read(struct dpd_tensile_curve *cv, struct ckpt *ck,
                                      struct err *e)
{
    long n = ckpt_len(ck, "strain");
    int rc = n < 0 ? ERR_INPUT : 0;
    if (!rc && n > cv->cap)
        rc = err_set(e, ERR_INPUT, "%s: checkpoint has %ld stress-strain points, at most %ld fit",
                     ck->path, n, cv->cap);
    if (!rc) rc = ckpt_get_doubles(ck, "strain", cv->strain, n);
    if (!rc) rc = ckpt_get_doubles(ck, "stress", cv->stress, n);
    if (!rc) rc = ckpt_get_doubles(ck, "time", cv->times, n);
    if (!rc) rc = ckpt_get_double(ck, "force_sum", &cv->fsum);
    if (!rc) rc = ckpt_get_double(ck, "time_sum", &cv->tsum);
    if (!rc) rc = ckpt_get_long(ck, "steps_summed", &cv->nacc);
    if (!rc)
        cv->n = n;
    return rc;
}

void dpd_tensile_curve_free(struct dpd_tensile_curve *cv)
{
    free(cv->strain);
    free(cv->stress);
    free(cv->times);
    memset(cv, 0, sizeof *cv);
}
