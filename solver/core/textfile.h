/*
 * textfile: a whitespace tokenizer over a text file that knows its line
 * numbers, for the readers of potential and configuration files.  Errors
 * read "path:line: message".
 *
 * Numbers in files are parsed strictly (text_parse_real, text_parse_long):
 * decimal only, the whole token, finite -- "1.5x", "0x10", "nan", "1e999"
 * are errors, not 1.5, 16, NaN and infinity.  Text of the file quoted in a
 * message goes through text_excerpt, so a corrupt file cannot fill the
 * message (or the terminal) with its contents.
 */
#ifndef CASCADE_TEXTFILE_H
#define CASCADE_TEXTFILE_H

#include <stdio.h>

#include "util/err.h"

struct textfile {
    FILE *fp;
    char path[512];
    int line;            /* current line number (1-based) */
    char *buf;           /* current line, any length (owned) */
    size_t cap;          /* allocated size of buf */
    char *cursor;        /* next unread character of buf */
    int eof;
    int strip_comments;  /* drop everything after '#' on each line */
};

int textfile_open(struct textfile *t, const char *path, struct err *e);
void textfile_close(struct textfile *t);

/* Read the next whole line (without the newline) into buf; 0 or -1 at EOF. */
int textfile_next_line(struct textfile *t);
/* Next line that is not blank and not a '#' comment; 0 or -1 at EOF. */
int textfile_next_content_line(struct textfile *t);

/* Next token, crossing lines; NULL at end of file. */
const char *textfile_token(struct textfile *t);

/* Read `n` numbers crossing lines; `what` names them in errors.  Reals may
 * use a Fortran exponent (1.0D-03, old DYNAMO files); otherwise as
 * text_parse_real. */
int textfile_doubles(struct textfile *t, double *out, long n, const char *what, struct err *e);
int textfile_double(struct textfile *t, double *out, const char *what, struct err *e);
int textfile_int(struct textfile *t, long *out, const char *what, struct err *e);

/* Strict number parsing of one token: decimal only (no hex, no inf or
 * nan), the whole token consumed, finite and in range.  0 on success. */
int text_parse_real(const char *tok, double *out);
int text_parse_long(const char *tok, long *out);

/* At most TEXT_EXCERPT_MAX characters of s for a message, "..." appended
 * when cut, control characters shown as '?'.  Returns out. */
#define TEXT_EXCERPT_MAX 40
#define TEXT_EXCERPT_SIZE (TEXT_EXCERPT_MAX + 4)
const char *text_excerpt(const char *s, char out[TEXT_EXCERPT_SIZE]);

int textfile_error(struct textfile *t, struct err *e, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* The same for an earlier line (an entry spread over several lines). */
int textfile_error_at(struct textfile *t, int line, struct err *e, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif
