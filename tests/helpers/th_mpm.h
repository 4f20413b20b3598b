/*
 * th_mpm: helpers for the MPM tests -- small models built through the
 * library API (grids, materials, bodies), and running them.
 */
#ifndef CASCADE_TEST_HELPERS_MPM_H
#define CASCADE_TEST_HELPERS_MPM_H

#include "core/region.h"
#include "mpm/mpm.h"
#include "mpm/mpm_build.h"
#include "mpm/mpm_hgrid.h"

/* Face conditions: all free, or sliding on the y and z faces (a 1-D bar). */
extern const enum mpm_face_bc th_mpm_faces_free[6];
extern const enum mpm_face_bc th_mpm_faces_bar[6];

/* A model on a uniform grid of ncell cells of edge h (Å) from the origin;
 * aborts the test on failure. */
void th_mpm_uniform(struct mpm *m, const long ncell[3], double h, enum mpm_shape_kind shape,
                    const enum mpm_face_bc faces[6], int nthreads);
/* A model on the hierarchical grid built from `levels`. */
void th_mpm_hier(struct mpm *m, const long ncell[3], double h, const struct mpm_hlevel *levels,
                 int nlevels, enum mpm_hanging hanging, const enum mpm_face_bc faces[6],
                 int nthreads);

/* Add a material (taking ownership) and return its index. */
int th_mpm_material(struct mpm *m, struct mpm_material *mat);
/* Add a body of `material` filling box [lo, hi) with n^3 points per cell at
 * velocity v; returns the body index. */
int th_mpm_box(struct mpm *m, const char *name, int material, const double lo[3],
               const double hi[3], int n, const double v[3], int rigid);

/* Run `steps` steps at cfl x the stable step; aborts on error. */
void th_mpm_run(struct mpm *m, long steps, double cfl);

/* Mean of component k (0..5) of the stress of the points whose initial x
 * lies in [x0, x1). */
double th_mpm_mean_stress(const struct mpm *m, int k, double x0, double x1);

#endif
