/*
 * launch: what it takes to run one attempt at a job, as plain data that can
 * travel to an MPI worker: the run directory, the case text, the command
 * and the time limit.
 *
 *   runs/<study>/<key>/attempt-<N>/   the directory of attempt N (runs.run_dir):
 *        case.yaml                    the resolved case, ${prep:KEY} replaced by
 *                                     the preparation job's recorded run directory
 *   runs/<study>/<key>/current        symlink to the latest recorded attempt
 *   command: [mpirun -np K ...] SOLVER run case.yaml --out DIR --threads T
 *            --quiet --no-progress [--resume EARLIER_ATTEMPT_DIR], started in
 *            the study file's directory
 *            (relative file names in cases are relative to the study)
 *
 * Each attempt writes only its own directory, so a solver left running by
 * a runner that lost its lease cannot touch the files of the attempt that
 * replaced it.
 */
#ifndef CASCADE_CAMPAIGN_LAUNCH_H
#define CASCADE_CAMPAIGN_LAUNCH_H

#include <jansson.h>

#include "solver.h"
#include "study.h"

struct launch_spec {
    long long job_id, run_id;
    long plan_index;      /* the job's index in the plan (for the Slurm backend) */
    char run_dir[4096];
    char cwd[4096];
    char *case_yaml;      /* owned */
    char **argv;          /* owned, NULL-ended */
    int argc;
    double timeout;       /* seconds, 0: none */
    int dir_ready;        /* launch_setup_dir already done (a job claimed ahead,
                             runner.c); not sent to MPI workers */
};

/* The recorded run directory of the preparation job with this key, or NULL
 * (with e set) when it has none. */
typedef const char *(*launch_prep_fn)(void *ctx, const char *key, struct err *e);

/* run_dir: the attempt's directory (launch_attempt_dir).  resume_dir: an
 * earlier attempt's directory with checkpoints (NULL: none); the solver
 * continues from its newest valid checkpoint (--resume), or starts afresh
 * when it has none of this case. */
int launch_build(struct launch_spec *L, const struct study *s, const struct solver *sv,
                 const char *run_dir, const char *key, const char *case_json,
                 launch_prep_fn prep_dir, void *ctx, const char *resume_dir, struct err *e);

/* The newest earlier attempt of the job (job_dir/attempt-M, M < attempt)
 * that left checkpoint files, into out; 0 when there is one, -1 when not. */
int launch_resume_dir(const char *job_dir, int attempt, char *out, size_t len);
void launch_free(struct launch_spec *L);

json_t *launch_to_json(const struct launch_spec *L);
int launch_from_json(struct launch_spec *L, const json_t *j, struct err *e);

/* The directory of attempt N of a job: job_dir/attempt-N (job_dir is
 * runs/<study>/<key>). */
void launch_attempt_dir(const char *job_dir, int attempt, char *out, size_t len);

/* Create the attempt's directory (emptied, should an earlier database have
 * used the same number) and write case.yaml. */
int launch_setup_dir(const struct launch_spec *L, struct err *e);

/* Remove what launch_setup_dir made for an attempt that was never started
 * (case.yaml, the attempt directory, the job directory when now empty);
 * anything else found there is left. */
void launch_remove_dir(const char *run_dir);

/* Point <job dir>/current at the attempt directory run_dir (an atomic
 * rename of a new symlink).  Does nothing for a run directory that is not
 * an attempt-N directory (runs recorded before attempts had their own) or
 * that does not exist. */
int launch_point_current(const char *run_dir, struct err *e);

/* mkdir -p */
int launch_mkdirs(const char *path, struct err *e);

#endif
