/*
 * plan: a study expanded into jobs, each resolved by the solver.
 *
 * Preparation jobs come first (in dependency order), then the sweep in
 * product order (the first axis outermost, repeats innermost).  A case that
 * reads a preparation job's output holds ${prep.NAME}; for the key it is
 * replaced by ${prep:KEY} with the preparation job's key, so the key changes
 * whenever the preparation job does, and is the same on every machine.  The
 * real directory is put in only when the job's case.yaml is written.
 *
 * Nothing is written anywhere: a plan either builds completely or returns
 * every error it found (file:line:col, study key, the solver's message).
 */
#ifndef CASCADE_CAMPAIGN_PLAN_H
#define CASCADE_CAMPAIGN_PLAN_H

#include "solver.h"
#include "study.h"

struct plan_job {
    int prep;             /* index into study->preps, or -1 for a sweep job */
    long sweep;           /* index in the sweep (product order), or -1 */
    char key[17];
    char *case_json;      /* canonical resolved case, from the solver */
    char *params_json;    /* canonical {axis: value}; "{}" for preparation jobs */
    int *deps;            /* plan indices of the preparation jobs it reads */
    int ndeps;
};

struct plan {
    const struct study *study;
    struct plan_job *jobs;
    long njobs;
    int nprep;
};

int plan_build(struct plan *p, const struct study *s, const struct solver *sv, struct err *e);
void plan_free(struct plan *p);

/* The job's label for people: "prep equil" or "md.timestep=0.002 seed=3". */
void plan_job_label(const struct plan *p, long j, char *out, size_t len);

#endif
