/*
 * handshake_case: what the MPM/MD handshake case types share -- the common
 * sections of their case files, the bar geometry, building the model, and
 * the outputs (thermo, snapshots with the region of every atom and point,
 * stress profiles along the bar from both sides).
 *
 *   crystal:   {lattice: fcc, element: Cu, a_min: 3.5, a_max: 3.7, orientation: 100}
 *              fcc | bcc | diamond; the lattice constant is the potential's
 *              0 K minimum in [a_min, a_max] (so the crystal starts
 *              stress-free); orientation 100 (cube axes along x, y, z) or
 *              110 (x along [110], y along [-110], z along [001]: the
 *              lengths below are then in edges of the oriented cell along
 *              each axis, a/sqrt2 across [001] for fcc and diamond, sqrt2 a
 *              for bcc, a along z)
 *   potential: {style: eam/alloy, file: Cu_mishin1.eam.alloy}
 *   elastic:   {c11: 0, c12: 0, c44: 0, c11_scale: 1}
 *              GPa, the MPM's cubic constants; 0 = from the potential at
 *              0 K (type: crystal), or give the values of type: elastic at
 *              a temperature; c11_scale multiplies C11 (Guo & Yang Fig. 5)
 *   handshake:
 *     regions: [2, 2, 2]   widths of regions I, II, III (lattice constants)
 *     cell: 1              finest cell (1 or 0.5 lattice constants)
 *     fine: 8              the coarse grid starts this far from the MD region
 *     levels: 2            coarsening levels (0: uniform grid)
 *     coarsen: xyz         directions halved per level
 *     layer: 8             width of each coarse level before the next
 *   md:        {timestep: 0.001, steps: 2000, skin: 1.0}   (ps, Å)
 *   profile:   {slab: 1, every: 100}   slab width (lattice constants) and
 *              steps between the stress profiles along the bar
 *   bar:       {mpm: [48, 48], md: 32, width: 8}   lattice constants: the
 *              MPM parts left and right of the MD region (0 on the right:
 *              the MD reaches the end of the bar), the MD length, the
 *              square cross-section (periodic in MD, sliding in MPM)
 *
 * The case types run on the engine (engine/sim.h) with the handshake model
 * (engine/model_handshake.c): each has case hooks and no loop of its own.
 * The thermo rows and the profile.csv rows are kept in memory so that a
 * checkpoint holds them and a restarted run writes both files whole.
 */
#ifndef CASCADE_HANDSHAKE_CASE_H
#define CASCADE_HANDSHAKE_CASE_H

#include <stdio.h>

#include "couple/handshake.h"
#include "couple/handshake_profile.h"
#include "engine/models.h"
#include "scenarios/case_type.h"
#include "util/wfile.h"

#define HS_PROFILE_COLS 14   /* a profile.csv row */
#define HS_THERMO_MAX_COLS 24   /* thermo columns: the common ones and the case's */

struct hs_case {
    /* read */
    struct potential *pot;        /* until the md owns it */
    char element[16];
    enum hs_lattice lattice;      /* crystal.lattice: fcc (default), bcc, diamond */
    enum hs_orientation orient;   /* crystal.orientation: 100 (default) or 110 */
    double a_min, a_max;
    double c_user[3];             /* GPa, 0: from the potential */
    double c11_scale;
    double regions[3], cell, fine, layer;   /* lattice constants */
    long levels;
    int coarsen;                  /* direction bits */
    double dt, skin;              /* ps, Å */
    long steps;
    double slab;                  /* lattice constants */
    long profile_every;
    double bar_mpm[2], bar_md, bar_width;   /* lattice constants */
    double a_given;               /* Å: lattice constant of MD and MPM (0: the
                                     potential's 0 K minimum; a thermal case sets a(T)) */
    struct cfg *cfg;              /* for errors found while building */
    /* built */
    int built;
    double a;                     /* Å */
    double unit[3];               /* Å: the length unit of the case keys along each
                                     axis (a along [100]; the oriented cell's edges) */
    double cl, cl_md;             /* eV/Å^3: longitudinal modulus along the bar of the
                                     MPM's and of the MD's constants (C11 along [100]) */
    double cxz, cxz_md;           /* eV/Å^3: the x-z coupling (sigma_zz = cxz eps_xx) */
    struct handshake_crystal md_cr;   /* the MD crystal's own constants */
    struct md md;
    struct handshake hs;
    struct hs_profile prof;
    struct handshake_model model;
    /* output */
    FILE *profile_csv;          /* profile_w.f (profile.csv.tmp until the run ends) */
    struct wfile profile_w;
    int64_t *ibuf;
    double *dbuf;
    long cap;
    /* rows written so far (checkpointed): thermo rows of ncols values and
     * profile.csv rows of HS_PROFILE_COLS */
    double *thermo;
    long nthermo, thermo_cap;
    int ncols;
    const char *thermo_names[HS_THERMO_MAX_COLS];   /* the columns (static strings) */
    double *profile;
    long nprofile, profile_cap;
};

/* Read crystal, potential, elastic, handshake, md, profile and bar. */
int hs_case_read(struct cfg_obj *root, struct hs_case *c);

/* Build the bar: material [0, mpm_left + md + mpm_right) x [0, width)^2
 * with the MD region after mpm_left; x faces sliding (x_lo) and
 * `x_hi_face`; with end_margin the grid goes one coarsest cell beyond the
 * x_hi end, so that a loaded free end can move out without its points
 * leaving the grid.  Layout refusals name the case key.  Under mpirun the
 * MD runs on bricks when the case's `parallel` section asks for them or
 * `auto` chooses them (handshake_setup_bricks: the MPM whole on every
 * rank; docs/parallel.md), else every rank builds the whole bar. */
int hs_case_build(struct hs_case *c, enum mpm_face_bc x_hi_face, int end_margin,
                  const struct case_common *common);

void hs_case_free(struct hs_case *c);

/* Case-type callbacks shared by the handshake case types, whose state is a
 * malloc'ed struct with its struct hs_case as the first member. */
void hs_case_destroy(void *state);
long hs_case_particles(const void *state);
long hs_case_steps(const void *state);

/* What the case's lengths are counted in: "lattice constants" along
 * [100], "cell edges" (of the oriented cell, along each axis) along [110]. */
static inline const char *hs_case_unit_name(const struct hs_case *c)
{
    return c->orient == HS_ORIENT_100 ? "lattice constants" : "cell edges";
}

/* Bar coordinates (Å): the interfaces and the ends. */
static inline double hs_case_x_left(const struct hs_case *c) { return c->hs.lay.md_lo[0]; }
static inline double hs_case_x_right(const struct hs_case *c) { return c->hs.lay.md_hi[0]; }
static inline double hs_case_length(const struct hs_case *c) { return c->hs.lay.mat_hi[0]; }

/* Longitudinal wave speed (Å/ps) of a longitudinal modulus cl (eV/Å^3): C11
 * along [100], c->cl or c->cl_md in general. */
double hs_case_wave_speed(const struct hs_case *c, double cl);

/* A traction t (eV/Å^3, +x) on the last cell layer at the x_hi end, as
 * point forces (scaled by the handshake's ramp). */
int hs_apply_end_traction(struct handshake *hs, double t, struct err *e);

/* Run on the engine: the handshake model, c->steps steps of c->dt, the
 * case hooks `ops` with `state` (the case type's struct, hs_case first);
 * run->opt.restart continues from a checkpoint. */
int hs_case_run(struct hs_case *c, struct run *run, const struct sim_case_ops *ops, void *state,
                struct err *e);

/* The rows written so far, in a checkpoint's /case group and back. */
int hs_case_checkpoint_write(const struct hs_case *c, struct ckpt *ck);
int hs_case_checkpoint_read(struct hs_case *c, struct ckpt *ck, struct err *e);

/* Outputs.  `extra` names further thermo columns (with units in the name).
 * After a restore, the rows of the checkpoint go to thermo.csv and
 * profile.csv first. */
int hs_case_output_begin(struct hs_case *c, struct run *run, const char *const *extra, int nextra,
                         struct err *e);
int hs_case_thermo(struct hs_case *c, struct run *run, const double *extra, int nextra,
                   struct err *e);
int hs_case_snapshot(struct hs_case *c, struct run *run, struct err *e);
/* Profile at the current step to profile.csv and the HDF5 file; analytic
 * (may be NULL) gives the analytical sigma_xx (eV/Å^3) at x (Å). */
int hs_case_profile(struct hs_case *c, struct run *run, double (*analytic)(const void *, double),
                    const void *ctx, struct err *e);
/* Metrics every handshake case reports (sizes, constants, energies), the
 * final profile as result series, and closing the outputs. */
int hs_case_output_end(struct hs_case *c, struct run *run, struct err *e);

#endif
