/*
 * solver: the one program cascade asks about cases and runs for jobs.
 *
 * Which program: --solver PATH, else $CASCADE_SOLVER, else cascade-solver
 * next to the cascade executable, else cascade-solver on PATH.  The solver
 * is the authority on case keys, defaults and validation: cascade sends it
 * cases (`resolve --batch`) and keeps what it answers.
 */
#ifndef CASCADE_CAMPAIGN_SOLVER_H
#define CASCADE_CAMPAIGN_SOLVER_H

#include <jansson.h>
#include <stdio.h>

#include "util/err.h"

struct solver {
    char path[4096];
    char version[128];
    char git[128];
};

/* Locate the program (given may be NULL) and ask it `info`. */
int solver_open(struct solver *s, const char *given, struct err *e);

/* Called with each answer line of `resolve --batch`, in input order: `line`
 * is 0-based, `answer` the parsed JSON object (borrowed). */
typedef int (*solver_answer_fn)(void *ctx, long line, json_t *answer, struct err *e);

/* Run `resolve --batch` with `in` (rewound, one JSON case per line) as its
 * stdin; every line must be answered. */
int solver_resolve(const struct solver *s, FILE *in, long nlines, solver_answer_fn fn, void *ctx,
                   struct err *e);

#endif
