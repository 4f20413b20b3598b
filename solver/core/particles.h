/*
 * particles: atoms (or mesoparticles) as a structure of arrays.
 *
 * Indices [0, n_owned) are the particles this process owns; [n_owned,
 * n_owned + n_ghost) are ghosts: periodic images (and, under domain
 * decomposition, copies of a neighbour's particles).  Force kernels treat
 * ghosts like any other particle, so they never special-case periodicity;
 * the ghost module (ghost.h) creates ghosts and moves data between ghosts
 * and their owners.
 *
 * Models that need more per-particle data (DPD internal energy, structure
 * classes, ...) register extra fields; every field is resized, permuted and
 * ghost-copied together with the core arrays.
 */
#ifndef CASCADE_PARTICLES_H
#define CASCADE_PARTICLES_H

#include <stdint.h>

#include "util/err.h"

struct parallel;
struct halo;

#define PARTICLES_MAX_TYPES 8
#define PARTICLES_MAX_FIELDS 16

struct particle_field {
    char name[32];
    int ncomp;
    int ghost_copy;     /* copied from the owner when ghosts are refreshed */
    double *data;       /* ncomp * capacity */
};

struct particles {
    int n_owned, n_ghost, capacity;

    double *x;          /* 3 per particle: position (Å)                       */
    double *v;          /* 3: velocity (Å/ps)                                  */
    double *f;          /* 3: force (eV/Å)                                     */
    int *type;          /* 0-based type index                                  */
    int64_t *id;        /* global id, 1-based, stable over the run             */
    uint32_t *mask;     /* group bits (see groups in the owning model)         */
    int *image;         /* 3: periodic image counts of owned particles         */
    int *origin;        /* owned index a ghost images (owned: its own index)   */
    int *gshift;        /* 3: box lengths a ghost is shifted by from origin    */
    double *pe;         /* per-particle potential energy (eV)                  */
    double *virial;     /* 6: per-particle virial xx yy zz xy xz yz (eV)       */

    int ntypes;
    double mass[PARTICLES_MAX_TYPES];        /* amu */
    char type_name[PARTICLES_MAX_TYPES][16]; /* element or label */

    int nfields;
    struct particle_field fields[PARTICLES_MAX_FIELDS];

    /* MPI ranks sharing this (replicated) particle set, or NULL: partial
     * sums passed to ghost_reverse_add are summed over them */
    const struct parallel *par;
    /* the brick decomposition's exchange (core/halo.h), or NULL: ghosts
     * come from neighbour ranks and ghost.c dispatches to it (borrowed) */
    struct halo *halo;
};

struct particles *particles_create(int capacity);
void particles_destroy(struct particles **p);

/* Make room for at least `n` particles (owned + ghost). */
int particles_reserve(struct particles *p, int n, struct err *e);

/* Shrink the arrays to hold n particles (at least owned + ghosts): the
 * memory of a set that lost most of its particles (a rank keeping its
 * brick of a system every rank built) goes back to the system. */
int particles_fit(struct particles *p, int n, struct err *e);

/* Append one owned particle (before any ghosts exist); returns its index or
 * -1 when out of memory. */
int particles_add(struct particles *p, const double x[3], const double v[3], int type, int64_t id);

/* Register an extra per-particle field; returns its index (or -1). */
int particles_add_field(struct particles *p, const char *name, int ncomp, int ghost_copy,
                        struct err *e);
int particles_find_field(const struct particles *p, const char *name);
/* Drop the field named `name` (no-op when absent); later fields move down
 * one index. */
void particles_remove_field(struct particles *p, const char *name);
static inline double *particles_field(struct particles *p, int idx)
{
    return p->fields[idx].data;
}

/* Drop all ghosts. */
static inline void particles_clear_ghosts(struct particles *p) { p->n_ghost = 0; }

/* Copy particle `src` into slot `dst` (all arrays and fields). */
void particles_copy_one(struct particles *p, int dst, int src);

/* Reorder the owned particles: new index k holds old index perm[k].
 * Ghosts must have been cleared.  Returns 0 or ERR_RUNTIME (memory). */
int particles_permute(struct particles *p, const int *perm, struct err *e);

/* Remove owned particles whose keep[i] is 0 (ghosts must be cleared). */
void particles_compact(struct particles *p, const unsigned char *keep);

/* Type index for a name, adding it when absent; -1 when too many types. */
int particles_type_index(struct particles *p, const char *name, double mass);

/* Kinetic tensor sum m v_a v_b of the owned particles (eV; xx yy zz xy xz
 * yz), the kinetic part of the pressure tensor times the volume. */
void particles_kinetic_tensor(const struct particles *p, double k[6]);

#endif
