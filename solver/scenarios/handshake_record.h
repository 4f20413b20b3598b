/*
 * handshake_record: what a handshake on MPI bricks adds to result.json's
 * `parallel` record (couple/handshake_bricks.h): its material points per
 * rank with their max/mean imbalance (`mpm_points_per_rank`), and the most
 * MD copies whose point another rank held at any list rebuild
 * (`handshake_remote_copies_max`).  Collective; nothing serially.
 */
#ifndef CASCADE_HANDSHAKE_RECORD_H
#define CASCADE_HANDSHAKE_RECORD_H

#include "couple/handshake.h"
#include "output/result.h"

void handshake_record_parallel(const struct handshake *hs, struct result *res);

#endif
