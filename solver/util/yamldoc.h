/*
 * yamldoc: a YAML file (libyaml) read into a jansson document tree, with the
 * source location of every key and value recorded in a locmap.
 *
 * Scalars become JSON types by the YAML 1.2 core schema: quoted scalars are
 * strings; plain null/~/empty is null; true/false are booleans; decimal
 * integers are integers; other numbers are reals; everything else is a
 * string.  Anchors and aliases are expanded (deep copies); duplicate keys are
 * an error.  A file holding several documents is an error.
 */
#ifndef CASCADE_YAMLDOC_H
#define CASCADE_YAMLDOC_H

#include <jansson.h>
#include <stdio.h>

#include "util/err.h"
#include "util/locmap.h"

/* Parse `path`.  On success *doc (new reference) and *locs (owned by the
 * caller) are set; on failure returns ERR_INPUT with "file:line:col: ..." */
int yamldoc_load_file(const char *path, json_t **doc, struct locmap **locs, struct err *e);

/* Same for text already in memory; `name` is used in messages. */
int yamldoc_load_string(const char *text, size_t len, const char *name,
                        json_t **doc, struct locmap **locs, struct err *e);

/* Write a JSON tree as block-style YAML (used for case.yaml files written by
 * the campaign runner and for echoing resolved cases).  Keys are sorted.
 * 0, or -1 when writing failed or memory ran out (the output is incomplete). */
int yamldoc_write(FILE *out, const json_t *doc);

#endif
