/*
 * slurm_spec: the `slurm:` section of a study -- the resources each job asks
 * Slurm for -- read and checked with file:line messages, and resolved for
 * one job of the plan.
 *
 *   backend: slurm                # or `cascade run --backend slurm`
 *   max_running: 20               # at most 20 of the study's jobs run at once
 *   slurm:
 *     partition: compute          # default: the cluster's default partition
 *     nodes: 1
 *     ntasks: 4                   # MPI ranks: srun starts the solver when > 1
 *     cpus_per_task: 2            # default: the study's `threads`
 *     mem: 4G                     # per node: digits and an optional K, M, G or T
 *     time: "01:30:00"            # minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S
 *                                 # (default: the study's `timeout`, when set)
 *     account: proj123
 *     qos: normal
 *     constraint: "intel&ib"
 *     extra: ["--exclusive", "--gres=gpu:1"]   # more sbatch options
 *     poll: 10                    # seconds between looks at the queue
 *     max_submit: 1000            # jobs in the queue at once (default: the
 *                                 # cluster's MaxJobCount / MaxSubmitJobs)
 *
 * Any resource may depend on a swept key, one value per value of the axis:
 *
 *     time: {by: system.lattice.cells, values: ["00:10:00", "01:00:00"],
 *            default: "00:10:00"}          # default: for preparation jobs
 *
 * Values are checked to be what the option takes and nothing else (no
 * blanks, quotes, '#', '$', ';', newlines): no value of a study can add an
 * sbatch option or a line to a batch script.
 */
#ifndef CASCADE_CAMPAIGN_SLURM_SPEC_H
#define CASCADE_CAMPAIGN_SLURM_SPEC_H

#include <jansson.h>

#include "util/err.h"

struct study;

enum slurm_res {
    SR_PARTITION,
    SR_NODES,
    SR_NTASKS,
    SR_CPUS_PER_TASK,
    SR_MEM,
    SR_TIME,
    SR_ACCOUNT,
    SR_QOS,
    SR_CONSTRAINT,
    SR_COUNT
};

#define SLURM_VALUE_MAX 128
#define SLURM_EXTRA_MAX 16

/* One resource: absent, one value, or one value per value of an axis. */
struct slurm_value {
    int axis;                      /* -1: the same for every job */
    int nvals;                     /* 0: not given */
    char (*vals)[SLURM_VALUE_MAX]; /* normalised (time as D-HH:MM:SS) */
    char dflt[SLURM_VALUE_MAX];    /* by an axis: for preparation jobs */
    char where[160];               /* "file:line:col: slurm.time" of the value */
};

struct slurm_spec {
    struct slurm_value res[SR_COUNT];
    char extra[SLURM_EXTRA_MAX][SLURM_VALUE_MAX];
    int nextra;
    double poll_s;
    long max_submit;               /* 0: the cluster's limits */
};

/* The resources of one job, as sbatch options. */
struct slurm_job_res {
    char v[SR_COUNT][SLURM_VALUE_MAX];   /* "" when not asked for */
    const char *where[SR_COUNT];         /* where each came from (borrowed) */
    long time_s;                         /* 0: none asked for */
    long ntasks, cpus_per_task;
};

/* The option name of a resource ("--partition", ...). */
const char *slurm_res_option(enum slurm_res r);

/* Read `slurm` of the study document (node may be NULL: all defaults). */
int slurm_spec_read(struct study *s, json_t *node, struct err *e);
void slurm_spec_free(struct slurm_spec *sp);

/* The resources of sweep job `seq` (-1: a preparation job). */
void slurm_spec_job(const struct study *s, long seq, struct slurm_job_res *r);

/* Seconds of a Slurm time ("90", "1:30:00", "2-12", ...); -1 when it is not one. */
long slurm_time_seconds(const char *text);
/* D-HH:MM:SS */
void slurm_time_format(long seconds, char *out, size_t len);

/* Whether an extra sbatch option is one cascade allows ("--name[=value]"
 * with a plain value, not one cascade sets itself); why says why not. */
int slurm_extra_ok(const char *opt, char *why, size_t len);

#endif
