/*
 * md_bricks: whether an MD case runs on bricks, and on which grid, from the
 * case's `parallel` section (input/parallel_settings.h) and the ranks of
 * the run.  Errors name the case file, line and key.
 */
#ifndef CASCADE_MD_BRICKS_H
#define CASCADE_MD_BRICKS_H

#include "core/box.h"
#include "core/halo.h"
#include "input/parallel_settings.h"
#include "util/cfg.h"

struct parallel;

/* *out: a new halo (the caller owns it) for a brick decomposition, or NULL
 * for a serial or replicated-data run.  range: cutoff + skin (Å). */
int md_bricks_plan(const struct parallel *par, const struct parallel_settings *ps,
                   const struct box *b, double range, struct cfg *c, struct halo **out);

#endif
