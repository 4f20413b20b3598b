/*
 * dpd_mpm: DPD particles on the MPM background grid -- the DPD/MPM-grid
 * model and the concurrent DPD/MPM model of Chen et al. 2014, Sec. 3.
 *
 * DPD/MPM-grid model.  The DPD pair forces f_p = sum_j (f^C + f^D + f^R)_pj
 * (dpd_pair_forces, at the positions and velocities of time t) are mapped
 * to the grid nodes with N_i (Eq. (s3b)) together with the particles' mass
 * and momentum (s1, s2); the MUSL update (s4-s11) then moves the particles
 * with the grid: v_p += dt sum_i N_i a_i (s6), x_p += dt sum_i N_i v_i (s7,
 * s8).  Nodes lighter than a small fraction of a particle's mass are
 * skipped, as the paper does.  Rigid bodies of the DPD model (the flyer,
 * the tensile grips) are not carried by the grid: they interact with the
 * carried particles through their pair forces and move as bodies, free
 * (v_b += F_b dt / M_b) or prescribed, so that they act on the target as
 * they do in the DPD-only model.
 *
 * Concurrent DPD/MPM model.  Material points with a constitutive law share
 * the grid (Eq. (3.1): the DPD forces times N_i minus G_i . sigma_p V_p of
 * the points).  Material points within two DPD cutoffs of a DPD particle
 * get a passive partner in the DPD model (dpd.h, passive_mask), a copy at
 * the point's position and velocity: DPD particles near the interface feel
 * the pair forces of the material points within their cutoff (Eqs.
 * (3.2)-(3.4)) and the partner's density completes the many-body term.
 * The opposite forces -- what the DPD particles exert on those material
 * points -- are mapped at the points' positions with N_i (the points'
 * external force), so that forces between the two kinds of particle are
 * equal and opposite: total momentum is conserved and a uniformly strained
 * body sees no force at the interface, where the points' stress alone
 * would leave the traction of a free surface.
 *
 * DPDE in these models.  The particles no longer move with their own
 * forces, so the internal energies cannot take the change of each pair's
 * relative kinetic energy the way the Shardlow sweep does.  Two things
 * change the mechanical energy besides the conservative forces:
 *   1. The dissipative and random forces.  The kinetic energy of everything
 *      the grid carries changes over a step by exactly
 *        sum_p M_p vbar_p . dv_p = sum_p f_p . w_p dt,
 *        vbar_p = (v_p + v_p') / 2,  w_p = sum_i N_i(x_p) (v_i + v_i') / 2,
 *      v_i = (m v)_i / m_i of s2, v_i' the remapped velocity of s11 (the
 *      centred particle velocities mapped to the nodes and back).  The
 *      D + R part of that work is split over the pairs,
 *      W_ij = f^DR_ij . (w_i - w_j) dt (Galilean invariant), and the pair's
 *      two internal energies each give up W_ij / 2 (dpd_pair_heat).
 *   2. The grid itself.  The particles move with the nodal velocities of s5,
 *      v_i + a_i dt, but carry into the next step the velocity of the remap,
 *      whose nodal value v_i' holds only the smoothed acceleration (the
 *      nodal accelerations interpolated to the particles and mapped back).
 *      Motion below the grid's resolution is lost: to leading order in dt
 *      particle p's conservative force does the work
 *        d_p = f^C_p . sum_i N_i(x_p) (v_i' - (v_i + a_i dt)) dt
 *      that never reaches the kinetic energy (summed over the particles it
 *      is -dt^2 sum_i f_i . (a_i - (S a)_i) <= 0, S the smoothing).  In
 *      DPDE this becomes heat: u_p -= d_p -- the unresolved motion joins
 *      the unresolved degrees of freedom the internal energy stands for.
 * Kinetic + potential + internal (+ strain) energy is then conserved up to
 * the integration error of the conservative forces (test: 2e-5 over 400
 * steps on a 4 Å grid, where the plain update loses 0.8 %).  The reference
 * temperature fixes sigma; gamma_ij follows the internal temperatures as
 * in DPDE.  With a coarse grid the D + R forces of pairs that share their
 * nodes largely cancel there: the grid carries (and thermostats) only the
 * motion it resolves.  Isothermal DPD keeps sigma and gamma at the bath
 * temperature, has no internal energies, and loses the grid's share (2.)
 * like any MUSL run.
 *
 * Particle order.  The DPD model's owned particles must be ordered
 * [carried | partners | bodies] (dpd_mpm_order does it, with id order
 * inside each class, no spatial sorting and canonical neighbour lists, so
 * that a run and its reference run without the flyer see the same pairs in
 * the same order).  The material points keep their order (no reordering).
 *
 * On MPI bricks (d->p->halo: the tensile rod, the flyer/target impact and
 * the concurrent impact): each rank holds its brick's DPD particles (and
 * partners) and the whole grid; the nodes' mass, momentum and force
 * (s1-s3b) and the MUSL remap's momenta (s11) are summed over the ranks,
 * so every rank updates the same nodes; the ghosts' velocities, internal
 * energies and w are forwarded and their share of the pair heat returned;
 * body forces, heats and energies are sums.  The class order is restored
 * after every migration (dpd_fix_class_order) and the counts taken again
 * each step.  The concurrent model's material points are whole on every
 * rank and advanced alike by every rank: their share of the nodes (s1-s3a
 * and their external force; s10) is added on every rank after the sum of
 * the carried particles' share; a partner is owned by the brick that holds
 * it, found its point by id after each migration, its frozen F'(rho)
 * travels as a particle field (DPD_FP_FROZEN_FIELD), and the reaction on
 * the points (Eq. (3.1)), complete on the partners' owners after the
 * reverse communication, is summed over the ranks (3 numbers a point).
 */
#ifndef CASCADE_DPD_MPM_H
#define CASCADE_DPD_MPM_H

#include <stdint.h>

#include "dpd/dpd.h"
#include "mpm/mpm.h"
#include "util/err.h"

struct dpd_mpm_grid {
    double cell;          /* Å: cubic cell edge, smaller than the DPD cutoff */
    double lo[3];         /* Å: low corner of the grid */
    long ncell[3];        /* cells per direction */
    double small_mass;    /* nodes lighter than this fraction of a DPD particle's
                             mass are skipped (Chen 2014, after s14) */
};

struct dpd_mpm {
    struct dpd *d;              /* borrowed: the DPD model */
    struct mpm m;               /* owned: the grid, and the concurrent model's points */
    uint32_t partner_bit;       /* mask bit of the passive partners */
    int64_t partner_id0;        /* partner id = partner_id0 + material point id */
    long ncarried;              /* DPD particles [0, ncarried) follow the grid */
    long npartner;              /* [ncarried, ncarried + npartner): partners */
    long *partner_point;        /* material point index of each partner */
    long partner_cap;
    int64_t *point_by_id;       /* 2 per material point: (id, index), by id (the points
                                   keep their order; on bricks the partners are found
                                   by id after every migration) */
    unsigned char *partner_was_here;   /* bricks: 1 per material point, scratch of
                                   dpd_mpm_step_forces: its partner was this rank's
                                   before the step's migration */
    long partner_arrivals;      /* bricks: partners that a migration of a step brought to
                                   this rank (from another brick), since the set-up or the
                                   checkpoint read: a diagnostic (dpd_mpm_partner_moves) */
    struct mpm_extra extra;     /* the carried DPD particles as the grid sees them */
    double *f;                  /* 3 per owned DPD particle: pair forces of the step (eV/Å) */
    double *w;                  /* 3 per owned DPD particle: centred grid velocity (Å/ps) */
    double *vprev;              /* 3 per owned DPD particle: velocity before the step */
    double *vbar;               /* 4 per node: centred nodal velocity (scratch) */
    long cap;
    double heat;                /* eV: work of D + R forces taken from the internal
                                   energies, summed over the run */
    double subgrid_heat;        /* eV: conservative work lost to the grid's smoothing
                                   (2. above), given to the internal energies, summed */
    double ke_centred;          /* eV: DPD particles (not partners), sum 1/2 m v(t-dt).v(t) */
    double epot_before;         /* eV: DPD conservative energy at the start of the last step */
    double uint_before;         /* eV: internal energy at the start of the last step */
    double body_vold[DPD_MAX_BODIES][3];   /* Å/ps: body velocities before the step
                                              (scratch of dpd_mpm_step_forces for
                                              dpd_mpm_step_update) */
};

/* Energies after a step (eV).  `total` is kinetic + conservative + internal
 * + strain at the end of the step; `centred` the same at the positions of
 * the step's start with the time-centred kinetic energy
 * sum 1/2 m v(t-dt).v(t) and the internal energy halfway -- the form the
 * explicit (leapfrog-like) update conserves to O(dt^2). */
struct dpd_mpm_energy {
    double ke_dpd, ke_points, epot, uint, strain;
    double total, centred;
};

/* Reorder d's owned particles into [carried | partners (mask & partner_bit)
 * | bodies], id order inside each, switch off spatial sorting, use
 * canonical neighbour lists and recompute the forces. */
int dpd_mpm_order(struct dpd *d, uint32_t partner_bit, struct err *e);

/* A coupled model over d (ordered by dpd_mpm_order) on a uniform grid with
 * linear shape functions.  ERR_INPUT when the cell edge is not smaller
 * than the DPD cutoff (Chen 2014, Sec. 3) or a carried particle lies
 * outside the grid. */
int dpd_mpm_init(struct dpd_mpm *c, struct dpd *d, const struct dpd_mpm_grid *g,
                 uint32_t partner_bit, int64_t partner_id0, struct err *e);
void dpd_mpm_free(struct dpd_mpm *c);   /* not the DPD model */

/* Concurrent model: n material points of one body of material `mat` (taken
 * over) at x with velocities v (NULL: at rest), each of the given mass
 * (amu) and volume (Å^3), with ids.  Call before dpd_mpm_prepare. */
int dpd_mpm_add_points(struct dpd_mpm *c, struct mpm_material *mat, long n, const double *x,
                       const double *v, double mass, double volume, const int64_t *id,
                       struct err *e);

/* After the points: map partners to points, thresholds, stability check
 * (ERR_INPUT when the time step exceeds the grid's stable step). */
int dpd_mpm_prepare(struct dpd_mpm *c, struct err *e);

/* One step of d->dt (see the top of this file); ERR_DIVERGED when a
 * particle leaves the grid or a value is not finite.  It is the two halves
 * below, in this order (the engine's force and integrate stages):
 *   dpd_mpm_step_forces   the s3b input: the DPD pair forces at x(t), v(t)
 *                         (partners at their points), their reaction on the
 *                         partners' material points (Eq. (3.1)), the total
 *                         force on each rigid body and the free bodies' kick
 *   dpd_mpm_step_update   MUSL s1-s14 on the grid, the DPDE heat, the rigid
 *                         bodies' drift, step and time */
int dpd_mpm_step(struct dpd_mpm *c, struct err *e);
int dpd_mpm_step_forces(struct dpd_mpm *c, struct err *e);
int dpd_mpm_step_update(struct dpd_mpm *c, struct err *e);

void dpd_mpm_energy(const struct dpd_mpm *c, struct dpd_mpm_energy *en);

/* Bricks: how many times a partner crossed a brick face during the steps
 * since the set-up (or a checkpoint read) -- partners that the migration
 * at a step's list rebuild moved to another rank, summed over the ranks
 * (collective); 0 serially and replicated.  The set-up's distribution and
 * a checkpoint read's are not migrations of a step and are not counted.
 * A diagnostic: it proves that the lookup of the partners' points by id
 * after a migration (and their frozen F'(rho) travelling with them) was
 * exercised. */
long dpd_mpm_partner_moves(const struct dpd_mpm *c);

/* Total momentum of the DPD particles (not partners) and the material
 * points (amu Å/ps). */
void dpd_mpm_momentum(const struct dpd_mpm *c, double P[3]);

/* Bricks: the partners' frozen F'(rho) (DPD_FP_FROZEN_FIELD) is a value
 * of the set-up, not of the checkpoint (a serial checkpoint has no such
 * field).  dpd_mpm_frozen_take removes the field and gives every rank all
 * of it by material point index (*byp, npts values, NULL when there is
 * no field; collective) and the field's index (*at); dpd_mpm_frozen_put
 * gives the field back at that index (the other fields keep theirs) to
 * the partners present, by their ids, after a checkpoint read. */
int dpd_mpm_frozen_take(struct dpd_mpm *c, double **byp, int *at, struct err *e);
int dpd_mpm_frozen_put(struct dpd_mpm *c, const double *byp, int at, struct err *e);

/* Passive partners for a concurrent model: append to p a copy (type 0,
 * mask `bit`, id = id0 + point id) of every point x[k] (k < n, ids id[k])
 * that lies within `range` of one of p's first `nd` particles.  *added gets
 * the number appended. */
int dpd_mpm_partners_create(struct particles *p, int nd, long n, const double *x,
                            const int64_t *id, double range, uint32_t bit, int64_t id0,
                            long *added, struct err *e);

#endif
