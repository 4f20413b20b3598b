/*
 * th_handshake: force probes of the handshake tests that check a crystal
 * under a homogeneous strain (no force on any atom or material point).
 */
#ifndef CASCADE_TH_HANDSHAKE_H
#define CASCADE_TH_HANDSHAKE_H

#include "couple/handshake.h"

/* Largest |f| of the MD atoms outside regions II and III (core and region I). */
double th_hs_md_fmax(const struct particles *p);

/* Largest |f| over the nodes that move material points: all nodes with
 * mass except those on the bar's ends (along x) and those deeper than one
 * cell inside the MD region, which only region I maps to; the components
 * normal to a sliding face are the face's.  The nodes on the four lateral
 * edges (two sliding faces meet) are kept apart in *fedge; *nnodes counts
 * the others. */
double th_hs_grid_fmax(const struct handshake *hs, long *nnodes, double *fedge);

#endif
