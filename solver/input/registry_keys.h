/*
 * registry_keys: the keys each entry of the solver's registries takes --
 * case types, potential styles, MPM constitutive laws -- for
 * `cascade-solver info`.  Code is the schema (util/cfg.h): each entry's own
 * reader is run on a document that names only the entry, with cfg.shallow =
 * CFG_DESCRIBE, and the tree it leaves behind is the answer: every key it asked for,
 * with its default, or "(required)".
 */
#ifndef CASCADE_REGISTRY_KEYS_H
#define CASCADE_REGISTRY_KEYS_H

#include <jansson.h>

/* {"common": {...keys of every case...},
 *  "case_types": {name: {...}}, "potential_styles": {name: {...}},
 *  "mpm_materials": {name: {...}}}; NULL when out of memory. */
json_t *registry_keys_json(void);

#endif
