/*
 * mpm: the material point method -- material points on a background grid,
 * advanced with MUSL (Chen et al. 2014, section 3.2, steps s1-s14) or USL.
 *
 * One step (mpm_step) is a sequence of stages, each a public function, so
 * that couplings can insert their own work between them:
 *
 *   mpm_locate_particles     s9: cell and colouring block of every particle
 *   mpm_clear_grid
 *   mpm_map_to_grid          s1 mass, s2 momentum, s3a internal force from
 *                            stress, s3b per-particle forces times N_i
 *   (caller may add nodal forces to grid.node[i].f here)
 *   mpm_update_grid          s4-s5: nodal momentum update, essential BCs,
 *                            small-mass rule, damping, rigid bodies
 *   mpm_map_to_particles     s6: particle velocity from nodal accelerations,
 *                            and (MUSL) s10: remap particle momenta to nodes
 *   mpm_update_grid_velocity s11: nodal velocities of the remap, BCs (MUSL)
 *   mpm_update_particles     s7-s8: positions from nodal velocities,
 *                            s12-s14: velocity gradient, strain, stress
 *
 * Besides its own material points, an MPM run carries "extra" particle sets
 * (mpm_attach): particles owned by another model that contribute mass,
 * momentum and either per-particle forces (mapped with N_i, Chen 2014 Eq.
 * (s3b) -- DPD particles carried by the grid, and both kinds of particle on
 * one grid as in Eq. (3.1)) or a stress and volume (s3a -- MD atoms of the
 * handshake region I acting as material points, Guo & Yang 2005 section
 * 2.2), and that either follow the grid (their velocities and positions are
 * updated in s6-s8) or only contribute.  solver/mpm knows nothing of MD or
 * DPD; solver/couple fills the views.
 *
 * Threads: particle-to-grid loops run over blocks of one colour at a time
 * (blocks of a colour share no node), grid-to-particle gathers and node
 * loops are independent per item, so the results are bit-for-bit the same
 * for any thread count.
 *
 * Units: metal inside (Å, ps, amu, eV; stress eV/Å^3).  Forces on nodes are
 * eV/Å; accelerations a = f / m * UNITS_FTM2V (Å/ps^2).
 */
#ifndef CASCADE_MPM_H
#define CASCADE_MPM_H

#include <stdint.h>

#include "core/timers.h"
#include "mpm/mpm_grid.h"
#include "mpm/mpm_material.h"
#include "mpm/mpm_points.h"
#include "util/err.h"

#define MPM_MAX_BODIES 32
#define MPM_MAX_MATERIALS 16
#define MPM_MAX_EXTRA 8
#define MPM_SPLIT_EVERY 16   /* steps between timings of the fused pass's mapping share */

enum mpm_algorithm { MPM_MUSL, MPM_USL };

/* What mpm_map_to_grid adds. */
enum {
    MPM_MAP_MASS_MOMENTUM = 1,   /* s1, s2 */
    MPM_MAP_STRESS = 2,          /* s3a: -sum G_i . sigma_p V_p */
    MPM_MAP_FORCE = 4,           /* s3b: sum f_p N_i */
    MPM_MAP_ALL = 7,
};

struct mpm_body {
    char name[32];
    int material;
    int rigid;               /* moves at `velocity`, imposes it on its nodes */
    double velocity[3];      /* Å/ps: initial (deformable) or prescribed (rigid) */
    double lp[3];            /* GIMP half-width of its points (cells)          */
    long npoints;
    double reaction[3];      /* rigid: force the body exerts on the grid in the
                                last step (eV/Å)                                */
};

/* A particle set owned by another model, mapped to the same grid. */
struct mpm_extra {
    const char *name;
    long n;
    double *x, *v;                 /* 3n (Å, Å/ps); written when follow_grid */
    const double *mass;            /* n (amu), or NULL: type_mass[type[i]] */
    const int *type;
    const double *type_mass;
    const double *force;           /* 3n (eV/Å) mapped with N_i (s3b), or NULL */
    const double *stress;          /* 6n (eV/Å^3) with volume: s3a, or NULL */
    const double *volume;          /* n (Å^3) */
    int follow_grid;               /* 1: velocities and positions from the grid */
    double lp[3];                  /* GIMP half-width (cells); 0 means 0.25 */
};

/* Per-set scratch of the current step (owned by struct mpm). */
struct mpm_bins {
    long cap;
    int32_t *blk;      /* block of each particle                */
    int32_t *order;    /* particles sorted by block             */
    int32_t *cell;     /* hierarchical grid: cell of each particle */
    long *start;       /* nblocks + 1 offsets into order        */
    long *count;       /* nthreads x nblocks counters           */
    long count_cap;
    long blk_step;     /* blk already holds the blocks for this step (set by
                          mpm_update_particles on the linear fast path), or -1 */
};

struct mpm {
    struct mpm_grid grid;
    struct mpm_points pts;
    int nmat;
    struct mpm_material *mat[MPM_MAX_MATERIALS];
    int nbody;
    struct mpm_body body[MPM_MAX_BODIES];
    int nextra;
    struct mpm_extra *extra[MPM_MAX_EXTRA];
    struct mpm_bins bins[1 + MPM_MAX_EXTRA];   /* [0]: material points */

    enum mpm_algorithm algorithm;
    double small_mass_rel;   /* nodes lighter than this fraction of the lightest
                                point are skipped (Chen 2014, after s14)      */
    double small_mass;       /* the absolute threshold (amu), set by mpm_prepare */
    double damping;          /* 1/ps: nodal velocity damping                   */
    double fext_scale;       /* multiplies the points' external forces         */
    int sort_every;          /* steps between reorders of the points (0: never) */
    int nthreads;
    int fuse;                /* let mpm_step fuse s1-s3 of the next step into s7-s14
                                (linear shape functions, uniform grid, no extra sets,
                                no point loads); results equal to round-off */
    int fused_ready;         /* the grid already holds s1-s3 of the coming step */
    int grid_fresh;          /* grid.node holds a fresh mapping (s1-s3), not the
                                updated velocities and accelerations (s5) */

    long step;
    double time;             /* ps */
    double vmax;             /* largest particle speed after the last step (Å/ps) */
    /* Energies of the material points, summed by the kernels of the last step
     * (eV): kinetic sum 1/2 M v^2 after s6, its time-centred form
     * sum 1/2 M v(t-dt).v(t) (centred on the positions before the step), and
     * the strain energy after s14 and before the step. */
    double ke, ke_centred, strain, strain_before;
    double cmax;             /* largest material wave speed (Å/ps)                */
    struct timers *timers;   /* optional */
    double fused_map_seconds;   /* of the last fused pass, the part that mapped the
                                   next step (s1-s3: clearing the second buffer and
                                   the scatter), per thread; mpm_step books it as
                                   p2g when timers are on */
    double fused_map_share;     /* the scatter's share of the fused pass, timed every
                                   MPM_SPLIT_EVERY steps (-1: not yet) */
    double *scratch;         /* reorder scratch, n doubles */
    long scratch_cap;
    /* On bricks (mpm_bricks.h): the cell keys (mpm_lin_cell) of the
     * rank's own brick, [own_lo, own_hi) per axis (own_keys set).  The
     * fused pass counts the points whose new cell lies outside them
     * (fused_leavers) and outside the patch (fused_outside), so the next
     * migration needs no scan of its own. */
    int own_keys;
    long own_lo[3], own_hi[3];
    long fused_leavers, fused_outside;
};

/* Create an empty run over an initialised grid (ownership of the grid's
 * arrays passes to m). */
int mpm_init(struct mpm *m, struct mpm_grid *grid, int nstate, int nthreads, struct err *e);
void mpm_free(struct mpm *m);

/* Add a material (m takes ownership) or a body; return its index or -1. */
int mpm_add_material(struct mpm *m, struct mpm_material *mat, struct err *e);
int mpm_add_body(struct mpm *m, const struct mpm_body *b, struct err *e);

/* After points, bodies and materials are in place: thresholds, wave speed,
 * initial speeds.  Call again when they change. */
int mpm_prepare(struct mpm *m, struct err *e);

/* Attach / detach an extra particle set; `x` stays owned by the caller, who
 * keeps its pointers and n up to date between steps. */
int mpm_attach(struct mpm *m, struct mpm_extra *x, struct err *e);
void mpm_detach(struct mpm *m, struct mpm_extra *x);

/* Code that changes the material points between steps (positions,
 * velocities, stresses, masses; other than through the stages) must call
 * this (or mpm_prepare), so the next step locates and maps them afresh. */
static inline void mpm_points_moved(struct mpm *m)
{
    m->bins[0].blk_step = -1;
    m->fused_ready = 0;
}

/* --- stages (see the top of this file) ----------------------------------- */
int mpm_locate_particles(struct mpm *m, struct err *e);
void mpm_clear_grid(struct mpm *m);
void mpm_map_to_grid(struct mpm *m, unsigned what);
void mpm_update_grid(struct mpm *m, double dt);
void mpm_map_to_particles(struct mpm *m, double dt);
void mpm_update_grid_velocity(struct mpm *m);
/* s11, zeroing the nnodes node records at `clear` (if not NULL) in the same
 * loop: the fused pass's second buffer (mpm_grid_next_buffer) */
void mpm_update_grid_velocity_clearing(struct mpm *m, struct mpm_node *clear);
void mpm_update_particles(struct mpm *m, double dt);
/* mpm_update_particles plus s1-s3 of the next step for the material points,
 * into the grid's second buffer, which then becomes the grid; requires the
 * conditions of m->fuse (see mpm_fusable). */
void mpm_update_particles_and_map(struct mpm *m, double dt);
/* The same, told whether the second buffer is already zeroed (by
 * mpm_update_grid_velocity_clearing) */
void mpm_update_particles_and_map_cleared(struct mpm *m, double dt, int cleared);
/* The grid's second node buffer for the fused pass, allocated on first use;
 * NULL without memory (the fused pass then takes the unfused way) */
struct mpm_node *mpm_grid_next_buffer(struct mpm_grid *g);
int mpm_fusable(const struct mpm *m);

/* One whole step; ERR_DIVERGED when a particle leaves the grid or a value
 * is not finite.  It is mpm_step_map then mpm_step_update, the two halves
 * the engine runs as the model's force and integrate stages:
 *   mpm_step_map     s9, then s1-s3 (mass, momentum, internal and external
 *                    nodal forces) unless the last step's fused pass left
 *                    them on the grid;
 *   mpm_step_update  s4-s14 and the step's time and counter. */
int mpm_step(struct mpm *m, double dt, struct err *e);
int mpm_step_map(struct mpm *m, struct err *e);
int mpm_step_update(struct mpm *m, double dt, struct err *e);

/* Explicit stability limit (Courant number 1): smallest cell over the
 * largest wave speed plus the largest particle speed (ps). */
double mpm_stable_dt(const struct mpm *m);

/* --- observables ---------------------------------------------------------- */
struct mpm_totals {
    double mass;          /* amu */
    double momentum[3];   /* amu Å/ps */
    double kinetic;       /* eV: sum 1/2 M v^2 */
    double strain;        /* eV: stress work stored in the points */
    double vmax;          /* Å/ps */
};
/* The explicit step moves velocities half a step ahead of positions, so
 * kinetic + strain energy (m->ke + m->strain) oscillates by O(dt).  The
 * time-centred energy of the state before the last step,
 * sum 1/2 M v(t-dt).v(t) + strain(t-dt), is conserved to O(dt^2). */
static inline double mpm_energy_centred(const struct mpm *m)
{
    return m->ke_centred + m->strain_before;
}
/* Sums over the material points (deformable and rigid). */
void mpm_totals(const struct mpm *m, struct mpm_totals *t);
/* Grid mass (amu) after the last mapping. */
double mpm_grid_mass(const struct mpm *m);

#endif
