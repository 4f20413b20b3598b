/*
 * err: the one error-reporting convention of Cascade.
 *
 * A function that can fail returns an int status (0 = success, otherwise one
 * of the ERR_* classes below) and fills a caller-owned struct err with a
 * message.  Only main() decides how to report and which exit code to use;
 * library code never prints or exits.
 */
#ifndef CASCADE_ERR_H
#define CASCADE_ERR_H

#include <stddef.h>

enum err_class {
    ERR_OK = 0,
    ERR_RUNTIME = 1,   /* a failure while running: I/O, allocation, ...   */
    ERR_INPUT = 2,     /* bad input: case file, data file, option, ...    */
    ERR_DIVERGED = 4,  /* the simulation produced NaN or ran away          */
};

#define ERR_MSG_MAX 2048

struct err {
    int code;
    /* 1 when this rank stopped only because another MPI rank failed: the
     * message worth showing is that rank's (parallel_agree_error) */
    int elsewhere;
    char msg[ERR_MSG_MAX];
};

/* Record an error (printf-style) and return its class, so that
 *     return err_set(e, ERR_INPUT, "bad %s", what);
 * is the idiom.  e may be NULL. */
int err_set(struct err *e, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The same for a rank that stops because another rank failed: keeps the
 * class the caller gives and marks the error as not this rank's own. */
int err_set_elsewhere(struct err *e, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prepend context ("while reading X: ") to an existing message. */
int err_prefix(struct err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Out-of-memory helper: records "out of memory (<what>)". */
int err_nomem(struct err *e, const char *what);

void err_clear(struct err *e);

#endif
