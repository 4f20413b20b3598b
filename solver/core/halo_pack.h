/*
 * halo_pack: one particle as a flat record of bytes (position, velocity,
 * force, type, id, group mask, image counts, per-atom energy and virial,
 * every extra field), for migration, ghosts and gathers between ranks.
 */
#ifndef CASCADE_HALO_PACK_H
#define CASCADE_HALO_PACK_H

#include <stddef.h>

#include "core/particles.h"

size_t halo_record_size(const struct particles *p);
/* Write particle i at buf; x[dim] gets shift added (dim < 0: none). */
void halo_pack(const struct particles *p, int i, int dim, double shift, unsigned char *buf);
/* Read a record into slot i (capacity reserved by the caller). */
void halo_unpack(struct particles *p, int i, const unsigned char *buf);

/* A ghost's record: what a neighbour's copy needs (position, velocity,
 * type, id, mask, the owner's image counts and the box shift of the copy
 * that DPD's pair keys use, every extra field; not the force, energy and
 * virial, which a ghost does not carry), 88 bytes instead of 168 for an
 * MD atom: the ghost messages of a list build and the buffers
 * kept for forward and reverse communication shrink with it.  Always at
 * least 6 doubles (the widest forward/reverse row, the virial) and at
 * least every field's row. */
size_t halo_ghost_record_size(const struct particles *p);
/* x[dim] gets shift added, as halo_pack; with vec (a tilted box's edge
 * vector, its sign shift's) x gets vec added instead.  The copy's box
 * shift counts one edge dim more or less by the sign of shift. */
void halo_pack_ghost(const struct particles *p, int i, int dim, double shift, const double *vec,
                     unsigned char *buf);
/* The unpacked ghost's force, energy and virial are zero. */
void halo_unpack_ghost(struct particles *p, int i, const unsigned char *buf);

#endif
