/*
 * dpd_mpm_setup: the `grid` section of the DPD/MPM-grid and concurrent
 * DPD/MPM case types (couple/dpd_mpm.h; Chen et al. 2014, Sec. 3), and
 * placing the grid over the material.
 *
 *   grid:
 *     cell: 4.0            Å: cubic cell edge; must be smaller than the DPD cutoff
 *                          ("within the MPM framework, the DPD cutoff distance should be
 *                          larger than the cubic cell edge length", Chen 2014 Sec. 3)
 *     margin: 0            Å of grid beyond the material on every side; 0: two cells,
 *                          plus along the loading axis the distance the loading moves
 *                          material over the run (flyer or grip velocity x run time)
 *     small_mass: 1.0e-12  nodes lighter than this fraction of a particle's mass are
 *                          skipped (Chen 2014: "less than a small number set by machine
 *                          precision")
 *
 * The grid's low corner is the material's lowest corner less the margin,
 * so a run and its reference run (same material) get the same grid.
 */
#ifndef CASCADE_DPD_MPM_SETUP_H
#define CASCADE_DPD_MPM_SETUP_H

#include "couple/dpd_mpm.h"
#include "scenarios/case_type.h"
#include "util/cfg.h"

struct dpd_mpm_grid_keys {
    double cell, margin, small_mass;
};

/* Read the `grid` section; `cutoff` (Å, > 0 unless shallow) is the DPD
 * cutoff the cell edge must stay below. */
int dpd_mpm_grid_read(struct cfg_obj *root, double cutoff, struct dpd_mpm_grid_keys *k);

/* The grid over the owned particles of p with no bit of `exclude`, with
 * margins lo[d] below and hi[d] above along each axis (Å). */
void dpd_mpm_grid_place(const struct particles *p, uint32_t exclude, const double lo[3],
                        const double hi[3], const struct dpd_mpm_grid_keys *k,
                        struct dpd_mpm_grid *g);


#endif
