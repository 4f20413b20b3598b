/*
 * sputter: connected groups of atoms and the groups sputtered from a
 * surface (Guo & Yang 2005, section 3.3: "monomers and small clusters are
 * sputtered out").
 *
 * Two atoms are connected when closer than `cutoff` (the nearest-neighbour
 * shell: the CNA cutoff is the natural choice).  The largest group is the
 * target.  Any other group is sputtered when every one of its atoms lies
 * more than `margin` above the original surface (along +axis) and its
 * centre of mass moves away from the surface.  A projectile still on its
 * way in is therefore not counted, and a fragment that has flown off is
 * counted whether it came from the projectile or the target.
 */
#ifndef CASCADE_SPUTTER_H
#define CASCADE_SPUTTER_H

#include "analysis/frame.h"
#include "util/err.h"

struct sputter_params {
    int axis;          /* surface normal: 0, 1, 2 (x, y, z), pointing out of the target */
    double surface;    /* Å: original surface position along axis */
    double margin;     /* Å: a sputtered group lies entirely above surface + margin */
    double cutoff;     /* Å: connection distance (<= the frame's neighbour radius) */
};

struct sputter_stats {
    long groups;       /* connected groups, target included */
    long atoms;        /* atoms in sputtered groups */
    long clusters;     /* sputtered groups (monomers included) */
    long monomers;     /* sputtered single atoms */
    long largest;      /* atoms in the largest sputtered group */
    long target;       /* atoms in the largest group */
};

/* f: a frame whose neighbour radius is at least p->cutoff; v: velocities
 * (3 per owned particle); mass: per particle (NULL: equal masses).  Fills
 * sputtered[i] (1 or 0, may be NULL) and *out. */
int sputter_find(const struct frame *f, const double *v, const double *mass,
                 const struct sputter_params *p, unsigned char *sputtered,
                 struct sputter_stats *out, struct err *e);

#endif
