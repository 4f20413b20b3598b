/*
 * docpath: case-key paths ("md.timestep", "system.lattice.cells") into a
 * case document, and the ${prep.NAME} references a study may write in any
 * string value of a case.
 *
 * Paths address mapping keys only; each component is a YAML key.  Setting
 * creates missing intermediate mappings; setting null deletes the key.
 */
#ifndef CASCADE_CAMPAIGN_DOCPATH_H
#define CASCADE_CAMPAIGN_DOCPATH_H

#include <jansson.h>
#include <stddef.h>

#define DOCPATH_MAX 256

/* Whether `path` is well formed: non-empty components of [A-Za-z0-9_-]
 * separated by single dots. */
int docpath_valid(const char *path);

/* Borrowed value at path, or NULL. */
json_t *docpath_get(json_t *doc, const char *path);

/* Set (steals `value`; json_null() deletes).  Returns 0, or -1 when a
 * component on the way is not a mapping (*bad names that prefix). */
int docpath_set(json_t *doc, const char *path, json_t *value, char *bad, size_t badlen);

/* Whether a is b or lies under b ("md.timestep" under "md"). */
int docpath_under(const char *a, const char *b);
/* Whether a and b overlap (one under the other). */
int docpath_overlap(const char *a, const char *b);

/* ${prep.NAME} references.  docpath_refs_visit calls fn for each reference
 * in each string of the tree, with the case path of the string; fn returns
 * non-zero to stop (that value is returned). */
typedef int (*docpath_ref_fn)(void *ctx, const char *case_path, const char *name);
int docpath_refs_visit(const json_t *doc, docpath_ref_fn fn, void *ctx);

/* Replace every ${prep.NAME} (or ${prep:KEY}) in the strings of `doc` (in
 * place) by subst(ctx, NAME) -- a string owned by the caller.  Returns 0, or
 * -1 when subst returns NULL for a name. */
typedef const char *(*docpath_subst_fn)(void *ctx, const char *name, int is_key);
int docpath_refs_replace(json_t *doc, docpath_subst_fn subst, void *ctx);

/* Whether a string holds "${" not followed by a well-formed reference. */
int docpath_has_bad_ref(const char *s);

#endif
