/*
 * case_type: the kinds of simulation a case file can ask for (`type:`),
 * selected by name from a registry.  Each reads its own sections of the
 * case; in a deep read (check, run) it also builds its models.
 *
 * Common top-level keys, read by input/case.c for every type:
 *   type    the case type (default md)
 *   title   free text
 *   seed    random seed (default 1)
 *   output  see run.h
 */
#ifndef CASCADE_CASE_TYPE_H
#define CASCADE_CASE_TYPE_H

#include <stdint.h>

#include "input/parallel_settings.h"
#include "output/run.h"
#include "util/cfg.h"

struct parallel;

struct case_common {
    uint64_t seed;
    const char *title;
    int nthreads;                  /* from the command line, for set-up that needs it */
    const struct parallel *par;    /* MPI ranks of this run (NULL: serial) */
    struct parallel_settings parallel;   /* the case's `parallel` section */
};

struct case_type {
    const char *name;
    const char *summary;
    /* Read the type's sections from the root object.  When the cfg is not
     * shallow, build the models and return them in *state. */
    int (*read)(struct cfg_obj *root, const struct case_common *common, void **state);
    /* Run; returns ERR_DIVERGED when the simulation ran away (the run's
     * result is still written by the caller). */
    int (*run)(void *state, struct run *run, struct err *e);
    void (*destroy)(void *state);
    /* Particle count for timing reports. */
    long (*particles)(const void *state);
    /* Time steps the run takes, for timing reports (NULL: md.steps). */
    long (*steps)(const void *state);
    /* Runs on the engine (engine/sim.h): writes output.checkpoint_every
     * checkpoints and continues from one (run --restart). */
    int checkpoints;
    /* Splits its particles over the ranks in bricks (`parallel` section);
     * other types run replicated data under mpirun. */
    int decomposes;
    /* Moves its brick faces with `parallel.balance: shift`, and again
     * during the run with `parallel.balance_every`; the other types
     * refuse the keys rather than ignore them. */
    int balances;
};

extern const struct case_type *const case_types[];   /* NULL-terminated */

const struct case_type *case_type_find(const char *name);

#endif
