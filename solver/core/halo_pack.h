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

#endif
