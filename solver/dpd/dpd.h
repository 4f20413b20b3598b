/*
 * dpd: dissipative particle dynamics of coarse-grained metal particles, in
 * the isothermal (DPD) and energy-conserving (DPDE) forms of Chen et al.
 * 2014, Eqs. (2.2)-(2.5).
 *
 * Forces on particle i, summed over neighbours j (r_ij = r_i - r_j,
 * e_ij = r_ij / |r_ij|, v_ij = v_i - v_j):
 *   conservative  the coarse-grained Sutton-Chen form (core/sc_form.h) with
 *                 its many-body density term, parameters from cg_params.h
 *   dissipative   f^D = -gamma_ij w^D(r) (e_ij . v_ij) e_ij
 *   random        f^R =  sigma_ij w^R(r) theta_ij e_ij / sqrt(dt)
 * with w^R(r) = 1 - r / r_d for r < r_d (Groot & Warren, J. Chem. Phys.
 * 107, 4423 (1997)), w^D = (w^R)^2 and sigma^2 = 2 gamma kB T (Espanol &
 * Warren, Europhys. Lett. 30, 191 (1995)).  Chen's Eq. (2.5) writes e_i;
 * the pair vector e_ij is used (and, in Eq. (2.4), the projection of v_ij
 * on it), which makes both forces central and antisymmetric: total momentum
 * (and angular momentum) is conserved exactly.
 *
 * DPDE (Espanol, Europhys. Lett. 40, 631 (1997); Avalos & Mackie,
 * Europhys. Lett. 40, 141 (1997)): every particle carries an internal
 * energy u_i with internal temperature theta_i = u_i / (C_v kB); pairs use
 * 1/Theta_ij = (1/theta_i + 1/theta_j) / 2, sigma fixed by the reference
 * temperature T0 and gamma_ij = sigma^2 / (2 kB Theta_ij); the mechanical
 * energy a pair's dissipative and random forces add or remove goes in
 * equal halves out of (or into) the two internal energies, so
 * kinetic + potential + internal energy is conserved.
 *
 * Time integration: Shardlow's splitting (SIAM J. Sci. Comput. 24, 1267
 * (2003)) as used for DPDE by Lisal, Brennan & Bonet Avalos (J. Chem. Phys.
 * 135, 204105 (2011)): each step first sweeps the pairs in a fixed order,
 * integrating each pair's dissipative + random interaction over dt on its
 * own -- here exactly, as the Ornstein-Uhlenbeck process it is for the
 * relative velocity along e_ij (no time-step limit from gamma) -- and then
 * integrates the conservative forces with velocity Verlet.
 *
 * Random numbers come from the counter-based stream of core/rng.h keyed on
 * (seed, step, the pair's two ids, the periodic image between them): a pair
 * draws the same number whatever the thread count or storage order.
 *
 * Rigid bodies (flyers, grips, fixed layers) are groups of particles that
 * move together: `prescribed` bodies keep their velocity (pistons, grips,
 * v = 0 for fixed layers), `free` bodies translate under the sum of the
 * forces on them.  In the pair sweep a body acts as one particle of its
 * total mass (infinite for prescribed bodies).
 */
#ifndef CASCADE_DPD_H
#define CASCADE_DPD_H

#include <stdint.h>

#include "core/box.h"
#include "core/neighbor.h"
#include "core/particles.h"
#include "core/thermostat.h"
#include "core/thread_accum.h"
#include "core/timers.h"
#include "dpd/cg_params.h"
#include "util/err.h"

enum dpd_variant { DPD_ISOTHERMAL = 0, DPD_ENERGY = 1 };   /* "dpd", "dpde" */
extern const char *const dpd_variant_names[];              /* NULL-terminated */

struct dpd_settings {
    enum dpd_variant variant;
    double gamma;          /* amu/ps: dissipation strength (sigma^2 = 2 gamma kB T0) */
    double temperature;    /* K: T0, the bath (DPD) or reference (DPDE) temperature */
    double cutoff;         /* Å: r_d of the weight functions */
    double heat_capacity;  /* kB per particle: internal heat capacity C_v (DPDE) */
    int sweep_cells;       /* sweep the pairs in cell-colour order (dpd_sweep_cells.c), the
                            * same on any rank count; always on bricks (else list order) */
};

#define DPD_MAX_BODIES 4
/* Particle field of the passive partners' frozen F'(rho) on MPI bricks
 * (freeze_passive_fp; dpd_conservative.c). */
#define DPD_FP_FROZEN_FIELD "dpd_fp_frozen"

enum dpd_body_kind { DPD_BODY_PRESCRIBED, DPD_BODY_FREE };

struct dpd_body {
    uint32_t mask;         /* particles with any of these group bits */
    enum dpd_body_kind kind;
    double v[3];           /* Å/ps: common velocity */
    double mass;           /* amu: total */
    int n;                 /* particles */
    double force[3];       /* eV/Å: on the body from everything else, last step
                            * (conservative + dissipative + random) */
};

struct dpd {
    struct particles *p;        /* owned */
    struct box box;
    struct cg_params prm;       /* conservative force, mass */
    struct dpd_settings set;
    struct nlist *nl;           /* owned: half list, cutoff max(rc, r_d) */
    struct thermostat thermo;   /* optional Berendsen / Langevin on free particles */
    double dt, skin;            /* ps, Å */
    int nthreads;
    long step;
    double time;                /* ps */
    uint64_t seed;
    int sort_every;             /* spatial sort every this many rebuilds (0: never) */
    int canonical_lists;        /* order each neighbour list by (id, image) so that the
                                 * pair sweep visits a particle's pairs in the same
                                 * order whatever else is in the system (reference runs) */
    int peratom;                /* keep per-particle energy and virial current */
    int class_order;            /* dpd_fix_class_order: on bricks the owned particles are put
                                 * back in (class, id) order after every migration */
    uint32_t class_mask;        /* its class-1 particles (bodies: class 2, the rest 0) */
    int rebuild_next;           /* rebuild ghosts and list before the next use of them
                                 * (a checkpoint: engine/model_dpd.c) */
    /* For models that integrate the particles themselves (solver/couple):
     * particles with any bit of passive_mask are passive partners -- copies
     * of another model's particles near an interface (Chen 2014, Eqs.
     * (3.2)-(3.4)).  They count in the densities of the many-body term and
     * take part in pairs with the other particles, but a pair of two passive
     * particles exerts no force and its energy is not the DPD model's. */
    uint32_t passive_mask;
    int moved_elsewhere;        /* such a model moves every particle (no pair sweep): on
                                 * bricks the ghost shell is the list's, without the
                                 * cell sweep's reach (set by dpd_fix_class_order) */
    int keep_pair_dr;           /* dpd_pair_forces keeps each pair's D + R force (pair_dr) */
    double *pair_dr;            /* per neighbour-list entry: the D + R force on i along e_ij
                                 * (eV/Å), 0 for pairs without one; from the last
                                 * dpd_pair_forces */
    long pair_dr_cap;
    struct dpd_body body[DPD_MAX_BODIES];
    int nbodies;
    int ufield;                 /* index of the internal-energy field (DPDE), else -1 */
    double epot;                /* eV: conservative energy, last force call */
    double virial[6];           /* eV: conservative virial, last force call */
    double body_impulse[DPD_MAX_BODIES][3];   /* amu Å/ps from the last pair sweep (zero
                                               * when the step had none) */
    long nrebuilds;
    struct timers *timers;      /* borrowed, may be NULL */
    /* scratch */
    double *rho, *fp;
    int freeze_passive_fp;      /* passive partners' F'(rho) fixed at their first force
                                 * evaluation (dpd_conservative.c: the interface forces
                                 * are then conservative) */
    double *fp_frozen;          /* per owned particle, from that evaluation (owned); on
                                 * bricks the particle field DPD_FP_FROZEN_FIELD instead */
    int n_frozen;
    int cap;
    struct thread_accum acc_rho, acc_f, acc_pe, acc_vir;
    /* the vector kernels' scratch (dpd_conservative_fast.c): per owned
     * particle its neighbours inside the conservative cutoff, in list
     * order, at its list offset */
    int *inner, *ninner;
    long inner_cap, r2buf_cap;
    int ninner_cap;
    double *r2buf;
};

/* Take ownership of p; set every particle's type mass to the parameter
 * file's mass, add the internal-energy field for DPDE (initialised to
 * C_v kB T0), build ghosts and lists, compute forces. */
int dpd_init(struct dpd *d, struct particles *p, const struct box *box,
             const struct cg_params *prm, const struct dpd_settings *set, double dt, double skin,
             int nthreads, uint64_t seed, struct err *e);
void dpd_free(struct dpd *d);

/* Declare particles carrying any bit of `mask` a rigid body; its velocity
 * becomes v (prescribed) or v as the start value (free).  Call before
 * stepping; the body gets index d->nbodies - 1.  Returns 0 or an error. */
int dpd_add_body(struct dpd *d, uint32_t mask, enum dpd_body_kind kind, const double v[3],
                 struct err *e);

/* Conservative forces into p->f (owned particles), d->epot, d->virial (and
 * per-particle pe/virial when d->peratom), rebuilding ghosts and lists when
 * particles have moved too far. */
int dpd_compute_forces(struct dpd *d, struct err *e);

/* Store the particles for good in the order of (cls[i], id) (cls NULL: id
 * alone), switch to canonical neighbour lists and no further reordering,
 * and recompute the forces: runs that must match particle by particle (a
 * reference run, a coupled model whose kinds sit in blocks) start here. */
int dpd_fix_order(struct dpd *d, const int *cls, struct err *e);

/* dpd_fix_order with the classes 0 (the rest), 1 (any bit of mid_mask)
 * and 2 (rigid bodies), which a run on bricks keeps: after every migration
 * each rank's owned particles return to (class, id) order (the DPD/MPM
 * coupling's [carried | partners | bodies], couple/dpd_mpm.h). */
int dpd_fix_class_order(struct dpd *d, uint32_t mid_mask, struct err *e);

/* Ghosts and list up to date with the current positions (rebuilt when a
 * particle moved too far, else the ghosts' positions refreshed): what the
 * force calls do first; on bricks the owned set may change. */
int dpd_refresh_neighbours(struct dpd *d, struct err *e);

/* Chen 2014, Eq. (s3b) input: the total DPD pair force on every owned
 * particle, f_i = sum_j (f^C_ij + f^D_ij + f^R_ij), at the current positions
 * and velocities, written to f (3 per owned particle, eV/Å) without moving
 * anything.  The random force is that of a step of length dt (Euler-
 * Maruyama: sigma w^R theta / sqrt(dt)), keyed on d->step.  Pairs inside one
 * rigid body are skipped.  Also leaves the conservative part in p->f. */
int dpd_pair_forces(struct dpd *d, double dt, double *f, struct err *e);

/* DPDE energy bookkeeping for models that move the particles themselves
 * (the DPD/MPM-grid and concurrent models): after dpd_pair_forces with
 * d->keep_pair_dr set, and with the positions unchanged since, each pair's
 * dissipative + random force f^DR_ij did the work
 *   W_ij = f^DR_ij . (w_i - w_j) dt
 * on the motion, where w (3 per owned particle, Å/ps) are the velocities the
 * model actually moved the particles with over the step (time-centred); the
 * two internal energies each give up W_ij / 2, so kinetic + potential +
 * internal energy is conserved as in dpd_sweep.  *heat (may be NULL) gets
 * the total taken from the internal energies (eV).  ERR_DIVERGED when an
 * internal energy is driven to zero or below.  No-op for isothermal DPD. */
int dpd_pair_heat(struct dpd *d, double dt, const double *w, double *heat, struct err *e);

/* One step: pair sweep (dissipative + random, exact per pair), velocity
 * Verlet with the conservative forces, rigid bodies, optional thermostat.
 * The composition of the three stages below, which the engine calls one
 * by one (engine/model_dpd.c). */
int dpd_step(struct dpd *d, struct err *e);
/* Stage 1, up to the force call: the pair sweep at the positions of t
 * (after a rebuild of ghosts and list when d->rebuild_next asks), the
 * first half kick with f(t) and the drift to t + dt. */
int dpd_step_sweep_drift(struct dpd *d, struct err *e);
/* Stage 2: conservative forces at t + dt (dpd_compute_forces). */
int dpd_step_forces(struct dpd *d, struct err *e);
/* Stage 3: the second half kick, the Berendsen rescaling, the bodies'
 * forces of the step; d->step and d->time advance. */
void dpd_step_kick(struct dpd *d);

/* Observables of the owned particles (rigid-body particles included);
 * on bricks (p->halo) summed over the ranks, the same on every rank. */
double dpd_kinetic_energy(const struct dpd *d);        /* eV */
double dpd_temperature(const struct dpd *d);           /* K: free particles, 3N - 3 dof */
double dpd_internal_energy(const struct dpd *d);       /* eV: sum of u_i (0 for DPD) */
void dpd_momentum(const struct dpd *d, double P[3]);   /* amu Å/ps */
void dpd_pressure_tensor(const struct dpd *d, double P[6]);   /* eV/Å^3, box volume */

/* Largest stable time step estimate: sqrt(2) / omega_E of the perfect
 * crystal at the parameters' lattice constant (ps). */
double dpd_timestep_limit(const struct cg_params *prm);

/* The ghost range (Å) the cell-ordered sweep needs in this box for pairs
 * within r_d: half a cell (cells at least r_d wide, dpd_sweep_cells.c)
 * plus r_d plus the skin; 0 when a periodic axis is shorter than 3 r_d. */
double dpd_sweep_cells_range(const struct box *box, double rd, double skin);

/* The range of the ghosts and of the list build: list cutoff + skin, or
 * the cell sweep's reach when that is larger (on bricks, or with
 * dpd.sweep: cells). */
double dpd_ghost_range(const struct dpd *d);

/* Particles of all ranks (p->n_owned without bricks). */
long dpd_nparticles(const struct dpd *d);

#endif
