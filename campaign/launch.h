/*
 * launch: what it takes to run one attempt at a job, as plain data that can
 * travel to an MPI worker: the run directory, the case text, the command
 * and the time limit.
 *
 *   runs/<study>/<key>/case.yaml   the resolved case, ${prep:KEY} replaced by
 *                                  the preparation job's run directory
 *   command: [mpirun -np K ...] SOLVER run case.yaml --out DIR --threads T
 *            --quiet --no-progress, started in the study file's directory
 *            (relative file names in cases are relative to the study)
 */
#ifndef CASCADE_CAMPAIGN_LAUNCH_H
#define CASCADE_CAMPAIGN_LAUNCH_H

#include <jansson.h>

#include "solver.h"
#include "study.h"

struct launch_spec {
    long long job_id, run_id;
    char run_dir[4096];
    char cwd[4096];
    char *case_yaml;      /* owned */
    char **argv;          /* owned, NULL-ended */
    int argc;
    double timeout;       /* seconds, 0: none */
};

int launch_build(struct launch_spec *L, const struct study *s, const struct solver *sv,
                 const char *runs_root, const char *key, const char *case_json, struct err *e);
void launch_free(struct launch_spec *L);

json_t *launch_to_json(const struct launch_spec *L);
int launch_from_json(struct launch_spec *L, const json_t *j, struct err *e);

/* Create the run directory, remove the files of an earlier attempt, write
 * case.yaml. */
int launch_setup_dir(const struct launch_spec *L, struct err *e);

/* mkdir -p */
int launch_mkdirs(const char *path, struct err *e);

#endif
