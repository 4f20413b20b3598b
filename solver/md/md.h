/*
 * md: the molecular-dynamics engine -- one particle set in one box driven by
 * one potential with velocity Verlet.
 *
 * The step reads like the algorithm (CoMD): half kick, drift, ghosts or
 * neighbour rebuild, forces, half kick, thermostat.  Particles in the
 * `frozen` groups keep their positions (fixed boundary layers); the
 * `rigid` groups move with their velocity unchanged (pistons, flyers).
 */
#ifndef CASCADE_MD_H
#define CASCADE_MD_H

#include <stdint.h>

#include "core/box.h"
#include "core/particles.h"
#include "core/timers.h"
#include "core/neighbor.h"
#include "md/potential.h"
#include "core/thermostat.h"
#include "util/err.h"

struct md {
    struct particles *p;        /* owned by the md */
    struct box box;
    struct potential *pot;      /* owned by the md */
    struct nlist *nl;           /* owned by the md */
    struct thermostat thermo;
    double dt;                  /* ps */
    double skin;                /* Å */
    int nthreads;
    long step;
    double time;                /* ps */
    int sort_every;             /* spatial sort every this many rebuilds (0 = never) */
    uint32_t frozen_mask;       /* group bits of particles held in place */
    uint32_t rigid_mask;        /* group bits of particles moving at constant velocity */
    int peratom;                /* keep per-particle energy and virial current */
    struct force_result last;   /* energy and virial of the last force call */
    struct timers *timers;      /* borrowed, may be NULL */
    long nrebuilds;
    int rebuild_next;           /* rebuild ghosts and lists at the next force call
                                 * (after a checkpoint: both the continuing and the
                                 * restarted run build them from the same state) */
    uint64_t seed;
    /* the brick decomposition (owned by the md), or NULL: serial or
     * replicated data.  With it p holds this rank's brick and its ghosts;
     * observables below are sums over all ranks. */
    struct halo *halo;
    int sync_rc;                /* an error of the last checkpoint sync, reported by
                                 * the next force call */
};

/* Atoms of the whole system (all ranks). */
long md_natoms(const struct md *md);

/* Run on the bricks of h: the md takes ownership of h; p holds this
 * rank's atoms (md_system_read_split built them; h counted them) and from
 * then on exchanges ghosts and migrates atoms.  Call before md_init. */
void md_adopt(struct md *md, struct particles *p, struct halo *h);

/* A checkpoint was written or read: every rank's atoms go to their owner
 * (after a read every rank holds all of them) in id order, so the
 * continuing and the restarted run build the same ghosts and lists. */
int md_decomposed_sync(struct md *md, int after_read, struct err *e);

/* The interaction range (cutoff + skin) against the box, before any ghost
 * is made: at most max_ghosts periodic images (ghost_estimate) and at most
 * INT_MAX neighbour-list entries, estimated as (n + ghosts) times the atoms
 * within the range at the mean density, halved for a half list (the
 * list's offsets are int).
 * Returns 0, or -1 with the reason in why (the cutoff's source named,
 * `limit` naming max_ghosts). */
int md_range_ok(const struct potential *pot, const struct box *b, long n, double skin,
                double max_ghosts, const char *limit, char *why, size_t len);

/* Take ownership of p and pot, build ghosts and lists, compute forces
 * (the halo md_adopt gave p becomes the md's).
 * Refuses (ERR_INPUT) what md_range_ok refuses with the ghosts particle
 * indices can hold; cases check their own limit first (md_check_range). */
int md_init(struct md *md, struct particles *p, const struct box *box, struct potential *pot,
            double dt, double skin, int nthreads, struct err *e);
void md_free(struct md *md);

/* Recompute forces at the current positions (rebuilding lists if needed). */
int md_compute_forces(struct md *md, struct err *e);

/* One velocity-Verlet step of dt: drift, forces, kick. */
int md_step(struct md *md, struct err *e);
/* The step's stages, for the engine (engine/sim.h): first half kick and
 * drift; forces at the new positions (with the Langevin forces of the
 * step); second half kick, Berendsen rescaling, step and time counters. */
void md_step_drift(struct md *md);
int md_step_forces(struct md *md, struct err *e);
void md_step_kick(struct md *md);

/* Observables of the owned particles. */
double md_kinetic_energy(const struct md *md);            /* eV */
double md_temperature(const struct md *md);               /* K, 3N-3 degrees of freedom */
double md_temperature_of(const struct md *md, double ke); /* the same from a kinetic energy (eV) */
void md_pressure_tensor(const struct md *md, double P[6]); /* eV/Å^3, xx yy zz xy xz yz */
void md_momentum(const struct md *md, double P[3]);        /* amu Å/ps */

/* Per-particle stress -(m v v + W_i) / (V/N) in eV/Å^3 (6 per particle);
 * needs md->peratom. */
void md_peratom_stress(const struct md *md, double *out);
/* The same for a part of the atoms (a window of a decomposed run's
 * output): N is natoms, the count of the whole system. */
void md_peratom_stress_of(const struct md *md, long natoms, double *out);

/* Einstein frequency (rad/ps): the largest sqrt(k/m) over a few particles
 * displaced by 1e-3 Å along each axis with all others held, k the restoring
 * force constant.  0 when nothing binds.  For fcc with nearest-neighbour
 * springs the highest phonon frequency is sqrt(2) times this, so velocity
 * Verlet is unstable above dt = sqrt(2) / omega_E. */
int md_einstein_frequency(struct md *md, double *omega, struct err *e);

#endif
