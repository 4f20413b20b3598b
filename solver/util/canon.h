/*
 * canon: canonical JSON text and the stable job key derived from it.
 *
 * Canonical form: object keys sorted bytewise, no whitespace, integers in
 * decimal, reals in the shortest form that reads back to the same double and
 * always with a '.' or an exponent (so 2 and 2.0 stay distinct types: the
 * solver has already normalised every value to its schema type), strings
 * with the minimal JSON escapes.  The same parameters give the same text on
 * any machine, so the same key.
 */
#ifndef CASCADE_CANON_H
#define CASCADE_CANON_H

#include <jansson.h>

/* Returns a malloc'ed NUL-terminated string, or NULL when out of memory. */
char *canon_json(const json_t *v);
/* The same text into buf (cut to len - 1 bytes): a scalar or an array of
 * scalars needs no allocation; 0, or -1 when out of memory (an object
 * sorts its keys in allocated memory). */
int canon_json_into(const json_t *v, char *buf, size_t len);

/* The job key: the first 16 hex digits of SHA-256 of the canonical text.
 * 0, or -1 when out of memory (key is then "", never the key of another
 * text). */
#define CANON_KEY_LEN 16
int canon_key(const json_t *v, char key[CANON_KEY_LEN + 1]);

/* Shortest round-trip text of a double (for any output that must be exact). */
void canon_real(double x, char *buf, size_t len);

#endif
