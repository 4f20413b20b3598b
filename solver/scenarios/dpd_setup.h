/*
 * dpd_setup: the `dpd` section shared by the DPD case types, and building
 * the DPD model from it.
 *
 *   dpd:
 *     parameters: cu_cg_298K.yaml  coarse-grained parameter file (dpd/cg_params.h),
 *                                  relative to the case file; required
 *     variant: dpd                 dpd (isothermal) | dpde (energy-conserving)
 *     gamma: 0.2                   amu/ps, dissipation strength (Chen 2014)
 *     temperature: 298             K: bath temperature (dpd) or the reference
 *                                  temperature fixing sigma^2 = 2 gamma kB T and the
 *                                  initial internal temperature (dpde)
 *     cutoff: 0                    Å: r_d of w^R = 1 - r/r_d (0: the conservative cutoff)
 *     heat_capacity: 21            kB per particle, internal heat capacity (dpde);
 *                                  21 = 3 (8 - 1): the vibrations of 8 atoms less the
 *                                  particle's own 3 translational degrees of freedom
 *     timestep: 0.005              ps
 *     steps: 1000
 *     skin: 1.0                    Å, neighbour-list skin
 *     initial_temperature: 0       K: Maxwell-Boltzmann velocities (0: keep the input's)
 *     sweep: list                  order of the Shardlow pair sweep: list (neighbour-list
 *                                  order) | cells (cell-colour order, the same on any
 *                                  rank count: docs/dpd.md); absent: list, and cells
 *                                  when the run is decomposed into bricks
 *     thermostat: {style: none | berendsen, temperature, tau}
 *                                  Berendsen rescaling on top of the DPD forces
 *                                  (the equilibration of Chen 2014, Sec. 4.1.1)
 *
 * The time step is refused when it exceeds the stability bound
 * sqrt(2) / omega_E of the coarse-grained crystal (dpd_timestep_limit).
 */
#ifndef CASCADE_DPD_SETUP_H
#define CASCADE_DPD_SETUP_H

#include "core/thermostat.h"
#include "dpd/dpd.h"
#include "scenarios/case_type.h"
#include "util/cfg.h"

struct dpd_input {
    struct cg_params prm;       /* loaded unless shallow */
    struct dpd_settings set;
    double dt, skin, t_init;
    long steps;
    struct thermostat thermo;
};

/* Read the `dpd` section (loading the parameter file unless shallow). */
int dpd_section_read(struct cfg_obj *root, enum dpd_variant default_variant,
                     struct dpd_input *in);

/* Give p the parameter file's mass and, when dpd.initial_temperature asks
 * for it, Maxwell-Boltzmann velocities (to the particles present: call
 * before adding flyers or other bodies). */
int dpd_init_velocities(const struct dpd_input *in, struct particles *p,
                        const struct case_common *common, struct err *e);

/* dpd_init (which takes p, also on failure: dpd_free(d) then) and the
 * thermostat. */
/* Under mpirun, when the `parallel` section and the box give bricks
 * (md_bricks_plan): *out a new halo (the caller owns it), p keeps its
 * brick's particles (every rank built them all; dpd_bricks_plan below
 * for a set-up that builds only its brick's).  The ghost shell covers
 * the list (cutoff + skin) and, with `sweep` (the DPD step sweeps pairs;
 * not the grid-carried models), the cell sweep's reach
 * (dpd_sweep_cells_range): a periodic axis shorter than 3 r_d is then
 * refused naming `parallel`.  Without `sweep` the bricks are still planned
 * on that reach where the box has one (the model's first ghost build
 * takes it).  *out NULL: serial or replicated data. */
int dpd_bricks(const struct dpd_input *in, const struct box *box, struct particles *p,
               const struct case_common *common, struct cfg *cfg, int sweep,
               struct halo **out);

/* The plan callback of md_system_read_split (input/md_system.h) for a DPD
 * case whose particles are built or received brick by brick: the DPD
 * bricks of the box the builder has just sized, with the cell sweep's
 * reach (dpd_bricks_plan with sweep).  ctx: a struct dpd_split_plan.
 * grid_carried: a grid-carried body (no sweep), given its extent
 * (md_system_split.on_extent): the bricks are planned without the sweep,
 * on that extent less the skin at both ends of each non-periodic axis,
 * as dpd_bricks_plan_box gives it from the particles. */
struct dpd_split_plan {
    const struct dpd_input *in;
    const struct case_common *common;
    struct cfg *cfg;
    int grid_carried;
};
int dpd_split_plan_bricks(void *ctx, const struct box *b, struct halo **out);

/* The plan alone (no particle moves): *out as dpd_bricks gives it, for a
 * set-up that builds or receives only its brick's particles
 * (md_system_read_split); on the sweep's refusal *out is NULL. */
int dpd_bricks_plan(const struct dpd_input *in, const struct box *box,
                    const struct case_common *common, struct cfg *cfg, int sweep,
                    struct halo **out);

/* The box to plan a body's bricks on: *box with each axis that is not
 * periodic cut to the extent of the particles without a bit of `skip`,
 * less `skin` at both ends -- the box the first ghost build shrink-wraps
 * to, or nearly (the surfaces relax by less than the skin), so that
 * `auto` takes bricks only where they stay thicker than the range. */
void dpd_bricks_plan_box(const struct box *box, const struct particles *p, uint32_t skip,
                         double skin, struct box *plan);

int dpd_build(const struct dpd_input *in, struct particles *p, const struct box *box,
              const struct case_common *common, struct err *e, struct dpd *d);

#endif
