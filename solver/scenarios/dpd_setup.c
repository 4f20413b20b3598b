/* dpd_setup: the `dpd` section and building the DPD model. */
#include "scenarios/dpd_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/velocity.h"
#include "md/md_bricks.h"

int dpd_section_read(struct cfg_obj *root, enum dpd_variant default_variant,
                     struct dpd_input *in)
{
    memset(in, 0, sizeof *in);
    struct cfg_obj o, to;
    const char *file;
    int variant, rc;
    if ((rc = cfg_section_required(root, "dpd", &o)) ||
        (rc = cfg_string(&o, "parameters", NULL, &file)) ||
        (rc = cfg_enum(&o, "variant", dpd_variant_names[default_variant], dpd_variant_names,
                       &variant)) ||
        (rc = cfg_real(&o, "gamma", 0.2, CFG_GE(0), &in->set.gamma)) ||
        (rc = cfg_real(&o, "temperature", 298.0, CFG_GE(0), &in->set.temperature)) ||
        (rc = cfg_real(&o, "cutoff", 0.0, CFG_GE(0), &in->set.cutoff)) ||
        (rc = cfg_real(&o, "heat_capacity", 21.0, CFG_GT(0), &in->set.heat_capacity)) ||
        (rc = cfg_real(&o, "timestep", 0.005, CFG_GT(0), &in->dt)) ||
        (rc = cfg_int(&o, "steps", 1000, CFG_GE(0), &in->steps)) ||
        (rc = cfg_real(&o, "skin", 1.0, CFG_GT(0), &in->skin)) ||
        (rc = cfg_real(&o, "initial_temperature", 0.0, CFG_GE(0), &in->t_init)) ||
        (rc = cfg_section(&o, "thermostat", &to)) || (rc = thermostat_read(&to, &in->thermo)))
        return rc;
    /* optional without a default, so that job keys of cases without it do
     * not change: absent means list order (cells on bricks) */
    cfg_allow(&o, "sweep");
    if (json_object_get(o.node, "sweep")) {
        static const char *const sweep_names[] = {"list", "cells", NULL};
        int sweep;
        if ((rc = cfg_enum(&o, "sweep", "list", sweep_names, &sweep)))
            return rc;
        in->set.sweep_cells = sweep == 1;
    }
    if ((rc = cfg_close(&o)))
        return rc;
    in->set.variant = (enum dpd_variant)variant;
    char kp[CFG_PATH_MAX];
    if (in->thermo.style == THERMOSTAT_LANGEVIN) {
        snprintf(kp, sizeof kp, "%s.thermostat.style", o.path);
        return cfg_error_at(o.cfg, kp, "DPD takes no Langevin thermostat: its dissipative and "
                                       "random forces are the thermostat (raise dpd.gamma), or "
                                       "use berendsen");
    }
    if (in->set.variant == DPD_ENERGY && in->set.gamma > 0 && !(in->set.temperature > 0)) {
        snprintf(kp, sizeof kp, "%s.temperature", o.path);
        return cfg_error_at(o.cfg, kp, "DPDE needs a positive reference temperature (the "
                                       "internal energies start at heat_capacity kB T)");
    }
    if (o.cfg->shallow)
        return 0;
    char path[4096];
    snprintf(kp, sizeof kp, "%s.parameters", o.path);
    if (cfg_find_file(o.cfg, file, path, sizeof path) != 0)
        return cfg_error_at(o.cfg, kp, "cannot read DPD parameter file '%s'", file);
    struct err pe = {0};
    if (cg_params_load(path, &in->prm, &pe) != 0)
        return cfg_error_at(o.cfg, kp, "bad DPD parameter file: %s", pe.msg);
    if (in->set.cutoff == 0)
        in->set.cutoff = in->prm.sc.rc;
    double limit = dpd_timestep_limit(&in->prm);
    if (in->dt > limit) {
        snprintf(kp, sizeof kp, "%s.timestep", o.path);
        return cfg_error_at(o.cfg, kp,
                            "time step %g ps is unstable for these parameters: the Einstein "
                            "frequency of the coarse-grained crystal is %.3g rad/ps, so velocity "
                            "Verlet needs dt < %.3g ps",
                            in->dt, sqrt(2.0) / limit, limit);
    }
    return 0;
}

int dpd_init_velocities(const struct dpd_input *in, struct particles *p,
                        const struct case_common *common, struct err *e)
{
    for (int t = 0; t < p->ntypes; t++)
        p->mass[t] = in->prm.mass;
    if (in->t_init > 0)
        return velocity_maxwell(p, in->t_init, common->seed, 1u, e);
    return 0;
}

int dpd_build(const struct dpd_input *in, struct particles *p, const struct box *box,
              const struct case_common *common, struct err *e, struct dpd *d)
{
    int rc = dpd_init(d, p, box, &in->prm, &in->set, in->dt, in->skin, common->nthreads,
                      common->seed, e);
    d->thermo = in->thermo;
    return rc;
}

int dpd_bricks_plan(const struct dpd_input *in, const struct box *box,
                    const struct case_common *common, struct cfg *cfg, int sweep,
                    struct halo **out)
{
    double rd = in->set.cutoff, reach = dpd_sweep_cells_range(box, rd, in->skin);
    double range = fmax(in->prm.sc.rc, rd) + in->skin;
    /* Without a sweep too: the DPD model's first ghost build (dpd_init,
     * before a grid model marks its particles as carried by the grid)
     * takes the sweep's reach where the box has one, so a plan on the
     * list's range alone let `auto` take bricks that build then refused
     * ("the box shrank") instead of falling back to replicated data. */
    if (sweep || reach > 0)
        range = fmax(range, reach);
    int rc = md_bricks_plan(common->par, &common->parallel, box, range, cfg, out);
    if (rc || !*out)
        return rc;
    if (sweep && !(reach > 0)) {
        halo_free(*out);
        free(*out);
        *out = NULL;
        return cfg_error_at(cfg, "parallel", "the DPD sweep on bricks needs every periodic axis "
                                             "at least 3 r_d = %g Å long: run without mpirun, or "
                                             "with decomposition: replicated",
                            3 * rd);
    }
    return 0;
}

/* A box's non-periodic axes less `skin` at both ends where they are
 * longer than 2 skin (the first ghost build's shrink-wrap, nearly). */
static void skin_box(const struct box *box, double skin, struct box *plan)
{
    *plan = *box;
    for (int d = 0; d < 3; d++) {
        if (box->bc[d] == BOUNDARY_PERIODIC || !(box->hi[d] - box->lo[d] > 2 * skin))
            continue;
        plan->lo[d] = box->lo[d] + skin;
        plan->hi[d] = box->hi[d] - skin;
    }
}

int dpd_split_plan_bricks(void *ctx, const struct box *b, struct halo **out)
{
    const struct dpd_split_plan *pl = ctx;
    if (!pl->grid_carried)
        return dpd_bricks_plan(pl->in, b, pl->common, pl->cfg, 1, out);
    struct box plan;
    skin_box(b, pl->in->skin, &plan);
    return dpd_bricks_plan(pl->in, &plan, pl->common, pl->cfg, 0, out);
}

int dpd_bricks(const struct dpd_input *in, const struct box *box, struct particles *p,
               const struct case_common *common, struct cfg *cfg, int sweep,
               struct halo **out)
{
    int rc = dpd_bricks_plan(in, box, common, cfg, sweep, out);
    if (rc || !*out)
        return rc;
    p->halo = *out;
    p->par = NULL;   /* no replicated sums: each rank owns its brick */
    return halo_distribute(*out, p, cfg->err);
}

void dpd_bricks_plan_box(const struct box *box, const struct particles *p, uint32_t skip,
                         double skin, struct box *plan)
{
    *plan = *box;
    for (int d = 0; d < 3; d++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < p->n_owned; i++) {
            if (p->mask[i] & skip)
                continue;
            lo = fmin(lo, p->x[3 * i + d]);
            hi = fmax(hi, p->x[3 * i + d]);
        }
        if (box->bc[d] == BOUNDARY_PERIODIC || !(hi - lo > 2 * skin))
            continue;
        plan->lo[d] = lo + skin;
        plan->hi[d] = hi - skin;
    }
}
