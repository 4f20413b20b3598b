/*
 * provenance: what built this program -- version, git hash, compiler, flags,
 * library versions.  Written into every output file.
 */
#ifndef CASCADE_PROVENANCE_H
#define CASCADE_PROVENANCE_H

#include <jansson.h>

const char *provenance_version(void);
const char *provenance_git_hash(void);
/* A new JSON object with every provenance field. */
json_t *provenance_json(void);

#endif
