/*
 * locmap: where each value of a parsed document came from.
 *
 * Document nodes are addressed by their path ("md.timestep",
 * "regions[2].shape"; the root is "").  jansson shares the true/false/null
 * singletons between nodes, so pointers cannot serve as keys; paths can, and
 * the validator knows the path of every node it looks at.
 */
#ifndef CASCADE_LOCMAP_H
#define CASCADE_LOCMAP_H

#include <stddef.h>

struct loc {
    int key_line, key_col;   /* where the key was written (1-based), 0 if none */
    int val_line, val_col;   /* where the value starts (1-based)               */
};

struct locmap;

struct locmap *locmap_create(void);
void locmap_destroy(struct locmap **m);
/* Returns 0, or -1 when out of memory.  A second put for a path replaces. */
int locmap_put(struct locmap *m, const char *path, struct loc loc);
/* Returns NULL when the path is unknown. */
const struct loc *locmap_get(const struct locmap *m, const char *path);

#endif
