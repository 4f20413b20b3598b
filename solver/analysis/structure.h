/*
 * structure: local crystalline order of every particle -- common neighbour
 * analysis (CNA; Honeycutt & Andersen, J. Phys. Chem. 91, 4950 (1987);
 * Faken & Jonsson, Comput. Mater. Sci. 2, 279 (1994)) with a fixed cutoff or
 * adaptive (a-CNA; Stukowski, Modelling Simul. Mater. Sci. Eng. 20, 045021
 * (2012)), coordination counting for diamond-structure crystals, and
 * free-surface detection.  These are the "local crystalline order" colours
 * of Guo & Yang 2005, section 3.2: fcc (perfect lattice), hcp (stacking
 * faults), other 12-coordinated, not 12-coordinated, surface; for Si,
 * 4-coordinated, not 4-coordinated, surface.
 *
 * CNA.  Neighbours of atom i are the atoms closer than the cutoff r_c.  For
 * each neighbour j the signature (ncn, nb, lcb) counts the common neighbours
 * of i and j, the bonds among them, and the bonds of their longest
 * connected chain.
 *   fcc  12 neighbours, 12 x (4,2,1)
 *   hcp  12 neighbours,  6 x (4,2,1) + 6 x (4,2,2)
 *   ico  12 neighbours, 12 x (5,5,5)
 *   bcc  14 neighbours,  8 x (6,6,6) + 6 x (4,4,4)
 * Fixed cutoff: r_c halfway between the first two shells of the reference
 * lattice, for fcc exactly 0.5 (1 + 1/sqrt 2) a (bcc: 0.5 (1 + sqrt 2) a;
 * hcp with lattice constant a = nearest-neighbour distance: 0.5 (1 + sqrt 2)
 * a).  Bonds count when r^2 < r_c^2 strictly; see frame.h for why a pair at
 * the cutoff within round-off is still judged the same from both ends.
 * Adaptive: the 12 nearest neighbours and a local cutoff
 * r_c = 0.5 (1 + sqrt 2) mean(r_1..12) (fcc, hcp, ico); failing those, the
 * 14 nearest and r_c = 0.5 (1 + sqrt 2) [(2/sqrt 3) mean(r_1..8) +
 * mean(r_9..14)] / 2 (bcc).  Neither needs the lattice constant, so it
 * follows thermal expansion and compression.
 *
 * Classes that fit no pattern: OTHER12 when the atom has exactly 12
 * neighbours (14 counts as not-12), NOT12 otherwise; for the diamond
 * reference COORD4 (exactly 4 neighbours within 0.5 (sqrt3/4 + 1/sqrt2) a)
 * and NOT4.  An atom with fewer neighbours than the ideal count is SURFACE
 * when it sits at the edge of the material: the centroid of all atoms
 * within the surface radius R_s (a sphere holding the first three shells)
 * is displaced from it by more than surface_offset * R_s.  A half-space
 * displaces it by about 3/8 R_s, a vacancy next door by about r_nn / 40, so
 * atoms next to point defects are not surface while adatoms, sputtered
 * atoms and the walls of a crater are.
 *
 * Displaced atoms (Guo & Yang's definition) are atoms whose class is
 * neither the reference's ideal class nor surface.
 */
#ifndef CASCADE_STRUCTURE_H
#define CASCADE_STRUCTURE_H

#include <stdint.h>

#include "analysis/frame.h"
#include "core/box.h"
#include "core/particles.h"
#include "util/cfg.h"
#include "util/err.h"

/* Codes 0-4 follow OVITO's common neighbour analysis. */
enum structure_class {
    STRUCT_OTHER12 = 0,   /* 12 neighbours, no pattern */
    STRUCT_FCC = 1,
    STRUCT_HCP = 2,
    STRUCT_BCC = 3,
    STRUCT_ICO = 4,
    STRUCT_NOT12 = 5,     /* coordination other than 12 (and not bcc) */
    STRUCT_SURFACE = 6,
    STRUCT_COORD4 = 7,    /* diamond reference: 4-coordinated */
    STRUCT_NOT4 = 8,      /* diamond reference: not 4-coordinated */
    STRUCT_NCLASSES = 9
};
extern const char *const structure_class_names[STRUCT_NCLASSES];

enum structure_ref { STRUCT_REF_FCC, STRUCT_REF_HCP, STRUCT_REF_BCC, STRUCT_REF_DIAMOND };
extern const char *const structure_ref_names[];   /* NULL-terminated, enum order */

enum cna_mode { CNA_FIXED, CNA_ADAPTIVE };
extern const char *const cna_mode_names[];        /* NULL-terminated, enum order */

struct structure_params {
    enum structure_ref ref;
    enum cna_mode mode;
    double a;               /* Å: reference lattice constant (hcp: nearest-neighbour distance);
                             * 0 when the cutoff is given instead */
    double cutoff;          /* Å: fixed cutoff; 0 = from a as above */
    double search_radius;   /* Å: adaptive neighbour search; 0 = 1.45 x cutoff */
    double surface_radius;  /* Å: 0 = between the 3rd and 4th shells of the reference */
    double surface_offset;  /* fraction of surface_radius (default 0.15) */
    int nthreads;
};

/* Fill the defaults above (cutoff from a or a from cutoff, radii).
 * ERR_INPUT when neither a nor cutoff is positive. */
int structure_params_resolve(struct structure_params *p, struct err *e);

/* Read an `analysis.structure`-style section:
 *   reference: fcc | hcp | bcc | diamond     (default from the caller)
 *   method: fixed | adaptive                 (default fixed)
 *   lattice_constant: Å                      (default from the caller)
 *   cutoff: Å (0: from the lattice constant)
 *   surface_offset: 0.15
 * `def` gives the defaults; the result is resolved. */
int structure_params_read(struct cfg_obj *o, const struct structure_params *def,
                          struct structure_params *out);

/* The class that counts as undisturbed for the reference lattice. */
enum structure_class structure_ideal_class(enum structure_ref ref);
static inline int structure_is_displaced(enum structure_ref ref, int cls)
{
    return cls != (int)structure_ideal_class(ref) && cls != STRUCT_SURFACE;
}

/* Classify n particles at positions x (3 each) in box b into cls[i].  The
 * frame is scratch the caller keeps between calls (zero it first, free it
 * with frame_free); after the call it holds the neighbour lists within
 * the neighbour radius used (the cutoff, or the adaptive search radius),
 * which the cluster analysis (sputter.h) reuses. */
int structure_classify(const struct structure_params *p, const double *x, int n,
                       const struct box *b, struct frame *f, int *cls, struct err *e);

/* The farthest a particle's class looks (the neighbour radius or the
 * surface radius, whichever is larger; the frame's range): the class of a
 * particle depends only on the particles closer than this. */
double structure_range(const struct structure_params *p);

/* The same for the owned particles of a particle set. */
int structure_classify_particles(const struct structure_params *p, const struct particles *ps,
                                 const struct box *b, struct frame *f, int *cls, struct err *e);

/* Counts per class over the particles with sel[i] != 0 (sel may be NULL:
 * all); returns the number of particles counted. */
long structure_count(const int *cls, int n, const unsigned char *sel, long counts[STRUCT_NCLASSES]);

#endif
