/*
 * halo: the ghost exchange of a brick decomposition (decomp.h) -- the
 * parallel form of core/ghost.c, in CoMD's and LAMMPS' staged pattern.
 *
 * Each rank owns the particles in its brick.  Ghosts are built in six
 * swaps, two per axis (x, then y, then z): the particles within `range` of
 * the lower face go to the rank below, those within `range` of the upper
 * face to the rank above.  The candidates of an axis' swaps are the owned
 * particles and the ghosts received along earlier axes, so edge and corner
 * ghosts arrive in two or three hops and no diagonal neighbour is ever
 * addressed.  A rank at a periodic face shifts what it sends by one box
 * length: periodic images are ghosts of the same exchange, and a periodic
 * axis of one brick is an exchange with the rank itself.
 *
 * The swaps are recorded (which local particles each sent, where each
 * received block starts), so between list builds
 *   halo_forward      copies owner values to ghosts (positions every step,
 *                     EAM/Sutton-Chen F'(rho), meam/spline U'),
 *   halo_reverse_add  adds ghost partial sums to their owners (forces,
 *                     densities, per-atom energy and virial), swaps in
 *                     reverse order so that a sum reaching a ghost of an
 *                     earlier swap travels on to its owner.
 * halo_migrate moves owned particles that left the brick to their new
 * owner (at each list rebuild), one brick per hop, axis by axis, until
 * every particle is home.
 *
 * half_shell: a half neighbour list (core/neighbor.h) keeps an owned-ghost
 * pair only when the ghost lies above the owned particle in z (ties by y,
 * then x).  A ghost below the brick's lower z face lies below every owned
 * particle at the build, so it is never in such a list: the pair is kept
 * by the rank below, where the owned particle is a ghost above.  With
 * half_shell set the swap that sends the particles near the upper z face
 * up is skipped, and the ghosts are those of the x and y faces and of the
 * upper z face only (the "half shell" of Newton's-third-law decompositions
 * as in CoMD's and NAMD's half-shell methods): a fifth fewer ghosts on
 * cubic bricks, nearly half fewer on the slabs of a 1 x 1 x 2 grid, and
 * one message less per forward and reverse pass.  The lists, the kernels'
 * arithmetic and the trajectory are those of the full shell (the skipped
 * ghosts only ever received zero partial sums).  Only for engines whose
 * every list is such a half list (md.c sets it for LJ, EAM and
 * Sutton-Chen); full lists (three-body terms, DPD's sweep) need the whole
 * shell.
 *
 * A tilted box (decomp.h) is cut in fractional coordinates: the swaps
 * select by the cut coordinate and the range across the faces
 * (decomp_cut_coord, decomp_range_along), and a periodic face shifts by
 * the cell's edge vector, which moves up to all three coordinates -- the
 * ghosts of LAMMPS' triclinic exchange.  The half shell holds: the lower
 * z faces are planes of constant z in the restricted triclinic cell.
 *
 * ghost.c dispatches to these when a particle set has a halo
 * (particles.halo), so the force kernels do not change.
 */
#ifndef CASCADE_HALO_H
#define CASCADE_HALO_H

#include <stdint.h>

#include "core/box.h"
#include "core/decomp.h"
#include "core/particles.h"
#include "util/err.h"

struct halo_swap {
    int dim, dest, src;     /* send to dest, receive from src (-1: none) */
    double shift;           /* added to coordinate dim of what is sent (periodic face) */
    int tilted;             /* a tilted box's face: vec, not shift, is added */
    double vec[3];          /* the edge vector dim of a tilted box, signed as shift */
    int *send;              /* local indices sent */
    int nsend, cap_send;
    int first, nrecv;       /* ghosts received: [first, first + nrecv) */
};

struct halo {
    struct decomp dc;
    struct halo_swap swap[6];
    int nswap;
    int half_shell;         /* no ghosts below the lower z face (above) */
    long natoms;            /* owned particles of all ranks (after the last migration) */
    /* dynamic balance (`parallel.balance_every`; halo_balance_step): the
     * owner's settings, and what the checks found */
    long balance_every;     /* steps between checks, 0: the cuts stay */
    double balance_threshold;
    long balance_checks, balance_shifts;
    double balance_worst;   /* the largest max/mean owned a check measured */
    int balance_pending;    /* the next list build shifts the cuts whatever the
                             * imbalance (DPD's set-up: halo_balance_schedule) */
    long balance_next;      /* the next check at the first build at or after this step */
    void *sbuf, *rbuf;      /* message buffers */
    size_t scap, rcap;
};

int halo_init(struct halo *h, const struct parallel *par, const int grid[3], const struct box *b,
              struct err *e);
/* A second exchange over src's bricks (the same ranks, box and cuts),
 * with swaps of its own: ghosts of another set or range (the distributed
 * analysis, analysis/md_analysis_bricks.c) leave src's untouched. */
int halo_init_like(struct halo *h, const struct halo *src, struct err *e);
void halo_free(struct halo *h);

/* Every rank holds every particle (a set-up or a checkpoint read): keep
 * those of this rank's brick and count them. */
int halo_distribute(struct halo *h, struct particles *p, struct err *e);

/* Each rank built only its own brick's particles (a distributed set-up;
 * some may lie just outside it: the first list build migrates them): count
 * them over the ranks.  rc: this rank's set-up result, made collective (a
 * failure on one rank fails every rank). */
int halo_adopt(struct halo *h, struct particles *p, int rc, struct err *e);

/* Shifted boundaries (decomp_shift) for this rank's owned particles p in
 * box b, then every particle to its new owner.  Collective. */
int halo_balance(struct halo *h, const struct box *b, struct particles *p, double range,
                 struct err *e);

/* The shifted cuts' schedule (`parallel.balance`, `balance_every`,
 * `balance_threshold`), one for every engine on a halo: checks at the
 * first list build at or after every `every`-th step (0: none), and
 * with at_first_build a shift at the next build whatever the imbalance
 * (an engine whose ghost range is known only there: DPD's cell sweep). */
void halo_balance_schedule(struct halo *h, long every, double threshold, int at_first_build);

/* Before a list build at `step` (ghosts are cleared): when due, wrap
 * and shrink-wrap b as the build will, measure max/mean owned particles
 * over the ranks and, above the threshold (or when the schedule asks
 * for a shift at this build), move the cuts to the particles' present
 * distribution (decomp_shift) and every particle to its new owner.
 * Collective; 0 when nothing is due. */
int halo_balance_step(struct halo *h, struct box *b, struct particles *p, double range,
                      long step, struct err *e);

/* A checkpoint written or read, before the caller migrates and sorts by
 * id: with balance_every, the cuts go to the stored particles now and the
 * next check is set from `step`, so the continuing and the restarted run
 * go on with the same cuts.  Collective. */
int halo_balance_sync(struct halo *h, const struct particles *p, double range, long step,
                      struct err *e);

/* Wrap owned particles into periodic axes, check fixed ones and, when
 * shrink, shrink-wrap free axes to the global extent; the bricks follow
 * the box.  Collective: a failure on any rank fails on every rank. */
int halo_remap(struct halo *h, struct box *b, struct particles *p, int shrink, struct err *e);

/* Owned particles outside the brick go to their owner (ghosts must be
 * cleared). */
int halo_migrate(struct halo *h, struct particles *p, struct err *e);

/* Ghosts within `range` of the brick (existing ghosts are dropped). */
int halo_build(struct halo *h, struct particles *p, double range, struct err *e);

/* Positions of the ghosts from their owners (and fields flagged ghost_copy). */
int halo_update_positions(struct halo *h, struct particles *p);
/* arr[ghost] = arr[owner], ncomp values per particle. */
int halo_forward(struct halo *h, const struct particles *p, double *arr, int ncomp);
/* arr[owner] += arr[ghost] over every ghost of it. */
int halo_reverse_add(struct halo *h, const struct particles *p, double *arr, int ncomp);

/* rc of this rank made collective: when any rank failed, every rank
 * returns an error (its own message, or "another MPI rank failed"), so no
 * rank goes on to an exchange the failed one will never join. */
int halo_agree(const struct halo *h, int rc, struct err *e);

/* Sums, maxima and "any" over the ranks, identical on every rank. */
void halo_sum(const struct halo *h, double *buf, int n);
void halo_max(const struct halo *h, double *buf, int n);
int halo_any(const struct halo *h, int flag);

/* All owned particles, sorted by id, in a new set on rank 0 (*out NULL on
 * other ranks); collective. */
int halo_gather(struct halo *h, const struct particles *p, struct particles **out, struct err *e);

/* The same a window at a time, so rank 0 never holds every particle (the
 * XYZ frames and the final state of a run on bricks): the owned particles
 * of all ranks pass in ascending id order, at most `window` at a time
 * (<= 0: HALO_GATHER_WINDOW), and rank 0 calls visit with each window's
 * particles sorted by id (types, masses and fields as p's); the other
 * ranks call nothing.  An error of visit stops the walk on every rank.
 * Collective. */
enum { HALO_GATHER_WINDOW = 32768 };
int halo_gather_windows(struct halo *h, const struct particles *p, long window,
                        int (*visit)(void *ctx, struct particles *q, struct err *e),
                        void *ctx, struct err *e);

/* Owned counts of every rank (counts holds one entry per rank). */
void halo_counts(const struct halo *h, const struct particles *p, long *counts);
/* v of every rank (out holds one entry per rank). */
void halo_allgather_long(const struct halo *h, long v, long *out);
int halo_nranks(const struct halo *h);

/* The position of each of this rank's n ids (sorted ascending, unique
 * over all ranks) in the ascending order of the ids of all ranks: pos[k]
 * counts the ids of all ranks smaller than ids[k].  Collective; each rank
 * holds only its own ids and one other rank's at a time (they pass round
 * the ranks in a ring), so memory stays per brick.  *shared (may be NULL)
 * counts this rank's ids another rank holds too (0 when they are unique). */
int halo_id_positions(const struct halo *h, const int64_t *ids, int n, long *pos, long *shared,
                      struct err *e);

/* Owned particles reordered by id (ghosts are dropped). */
int halo_sort_by_id(struct particles *p, struct err *e);

#endif
