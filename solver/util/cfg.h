/*
 * cfg: validating and resolving a document tree (a case file, a study).
 *
 * Code is the schema: each section of a document is read by a function that
 * asks for its keys with the getters below.  A getter checks the type and the
 * bounds, fills in the default when the key is absent (writing it into the
 * tree, so the resolved document shows every value the run uses) and
 * normalises the JSON type (an integer given for a real becomes a real).
 * cfg_close() then rejects every key nobody asked for, with a suggestion for
 * a near miss.  Messages read "file:line:col: path: what is wrong".
 */
#ifndef CASCADE_CFG_H
#define CASCADE_CFG_H

#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>

#include "util/err.h"
#include "util/locmap.h"

#define CFG_PATH_MAX 256
#define CFG_KEYS_MAX 96

struct cfg {
    const char *file;           /* name used in messages                  */
    const struct locmap *locs;  /* source locations, or NULL (JSON input) */
    struct err *err;
    const char *base_dir;       /* directory relative file names start from */
    int shallow;                /* validate keys only: open no files, build nothing;
                                   CFG_DESCRIBE: that, and list the keys (below) */
};

/* shallow = CFG_DESCRIBE lists the keys a reader asks for (cascade-solver
 * info): a missing required key is marked CFG_REQUIRED_MARK in the tree and
 * a value within its bounds stands in for it. */
#define CFG_DESCRIBE 2
#define CFG_REQUIRED_MARK "(required)"

/* One object of the document while it is read. */
struct cfg_obj {
    struct cfg *cfg;
    json_t *node;               /* borrowed from the document */
    char path[CFG_PATH_MAX];
    int nknown;
    const char *known[CFG_KEYS_MAX];
};

/* Numeric bounds: lo <= x <= hi, either end optionally open. */
struct cfg_bound {
    double lo, hi;
    int lo_open, hi_open;
};
#define CFG_ANY ((struct cfg_bound){-INFINITY, INFINITY, 0, 0})
#define CFG_GT(x) ((struct cfg_bound){(x), INFINITY, 1, 0})
#define CFG_GE(x) ((struct cfg_bound){(x), INFINITY, 0, 0})
#define CFG_RANGE(a, b) ((struct cfg_bound){(a), (b), 0, 0})

/* Pass as the default to make a key required. */
#define CFG_REQUIRED NAN
#define CFG_REQUIRED_INT LONG_MIN

int cfg_root(struct cfg *c, json_t *doc, struct cfg_obj *root);

/* A sub-object.  cfg_section creates an empty one when absent (all its keys
 * then take defaults); cfg_section_opt leaves it absent and sets *present. */
int cfg_section(struct cfg_obj *o, const char *key, struct cfg_obj *child);
int cfg_section_opt(struct cfg_obj *o, const char *key, struct cfg_obj *child, int *present);
int cfg_section_required(struct cfg_obj *o, const char *key, struct cfg_obj *child);
/* cfg_section_opt whose keys a describe read lists all the same (it then
 * opens the section as if given: *present is 1). */
int cfg_section_listed(struct cfg_obj *o, const char *key, struct cfg_obj *child, int *present);

/* Scalars.  def = CFG_REQUIRED / CFG_REQUIRED_INT / NULL makes a key required. */
int cfg_real(struct cfg_obj *o, const char *key, double def, struct cfg_bound b, double *out);
int cfg_int(struct cfg_obj *o, const char *key, long def, struct cfg_bound b, long *out);
int cfg_bool(struct cfg_obj *o, const char *key, int def, int *out);
int cfg_string(struct cfg_obj *o, const char *key, const char *def, const char **out);
/* Optional scalars without a default: *present tells whether it was given. */
int cfg_real_opt(struct cfg_obj *o, const char *key, struct cfg_bound b, double *out, int *present);
int cfg_int_opt(struct cfg_obj *o, const char *key, struct cfg_bound b, long *out, int *present);
int cfg_string_opt(struct cfg_obj *o, const char *key, const char **out, int *present);
/* A string out of a fixed set; *out is the index in `choices` (NULL-ended). */
int cfg_enum(struct cfg_obj *o, const char *key, const char *def, const char *const *choices,
             int *out);

/* Fixed-length numeric arrays (e.g. a vector of 3).  def may be NULL (required). */
int cfg_reals(struct cfg_obj *o, const char *key, int n, const double *def, struct cfg_bound b,
              double *out);
int cfg_ints(struct cfg_obj *o, const char *key, int n, const long *def, struct cfg_bound b,
             long *out);
/* List of strings (at most `max`); pointers borrow from the document. */
int cfg_strings(struct cfg_obj *o, const char *key, int required, const char **out, int max,
                int *n);
/* Variable-length real list: *out malloc'ed (caller frees), *n its length. */
int cfg_real_list(struct cfg_obj *o, const char *key, int required, struct cfg_bound b,
                  double **out, size_t *n);

/* Arrays of objects: cfg_list returns the count (0 when absent and optional);
 * cfg_list_item opens element i as an object. */
int cfg_list(struct cfg_obj *o, const char *key, int required, size_t *n);
int cfg_list_item(struct cfg_obj *o, const char *key, size_t i, struct cfg_obj *child);

/* Mark a key as known without reading it (a sibling reader handles it). */
void cfg_allow(struct cfg_obj *o, const char *key);

/* Reject unknown keys.  Call after every getter of the object has run. */
int cfg_close(struct cfg_obj *o);

/* Errors found later (for example a time step that the physics shows to be
 * unstable) still name the place: "file:line:col: path: message". */
int cfg_error_at(struct cfg *c, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Resolve a file name given in the document: as given when absolute or
 * readable from the current directory, else relative to base_dir.  Returns
 * 0 when a readable file was found (out holds its path), -1 otherwise (out
 * holds the name as given). */
int cfg_find_file(const struct cfg *c, const char *name, char *out, size_t len);

/* Edit distance, used for "did you mean" suggestions. */
int cfg_edit_distance(const char *a, const char *b);

#endif
