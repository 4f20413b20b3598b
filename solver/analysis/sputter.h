/*
 * sputter: connected groups of atoms and the groups sputtered from a
 * surface (Guo & Yang 2005, section 3.3: "monomers and small clusters are
 * sputtered out").
 *
 * Two atoms are connected when closer than `cutoff`.  Hot material near an
 * impact stretches bonds beyond the first-shell cutoff for a moment, so a
 * longer connection (md_analysis uses the structure analysis's surface
 * radius, about three neighbour shells) keeps rim atoms attached while an
 * atom that has really left is soon farther than that from everything.  The largest group is the
 * target.  Any other group is sputtered when every one of its atoms lies
 * more than `margin` above the original surface (along +axis) and its
 * centre of mass moves away from the surface.  A projectile still on its
 * way in is therefore not counted, and a fragment that has flown off is
 * counted whether it came from the projectile or the target.
 */
#ifndef CASCADE_SPUTTER_H
#define CASCADE_SPUTTER_H

#include <stdint.h>

#include "analysis/frame.h"
#include "util/err.h"

struct sputter_params {
    int axis;          /* surface normal: 0, 1, 2 (x, y, z), pointing out of the target */
    double surface;    /* Å: original surface position along axis */
    double margin;     /* Å: a sputtered group lies entirely above surface + margin */
    double cutoff;     /* Å: connection distance (<= the frame's range) */
};

struct sputter_stats {
    long groups;       /* connected groups, target included */
    long atoms;        /* atoms in sputtered groups */
    long clusters;     /* sputtered groups (monomers included) */
    long monomers;     /* sputtered single atoms */
    long largest;      /* atoms in the largest sputtered group */
    long target;       /* atoms in the largest group */
};

/* Where each atom is. */
enum { SPUTTER_TARGET = 0, SPUTTER_LEFT = 1, SPUTTER_DETACHED = 2 /* e.g. still incoming */ };

/* f: a frame whose range is at least p->cutoff; v: velocities
 * (3 per owned particle); mass: per particle (NULL: equal masses).  Fills
 * state[i] (SPUTTER_*, may be NULL) and *out. */
int sputter_find(const struct frame *f, const double *v, const double *mass,
                 const struct sputter_params *p, unsigned char *state,
                 struct sputter_stats *out, struct err *e);

/* sputter_find in parts, for atoms spread over MPI ranks
 * (md_analysis_bricks.c), where a group may span ranks. */

/* Union-find over the pairs of f closer than cutoff: root[i] is the
 * smallest index of i's group (root holds f->n entries). */
int sputter_link(const struct frame *f, double cutoff, int *root, struct err *e);

/* One connected group: `label` names it, the sums are over its atoms. */
struct sputter_group {
    int64_t label;
    long size;
    double mass, momentum;   /* sum m, sum m v along the axis */
    double zmin;             /* lowest atom along the axis */
    int left;                /* set by sputter_judge: sputtered */
};

/* The target (the largest group; the first of equal size) and the groups
 * that left (above): fills g[].left and *out; returns the target's index
 * (-1: no groups). */
long sputter_judge(struct sputter_group *g, long ng, const struct sputter_params *p,
                   struct sputter_stats *out);

#endif
