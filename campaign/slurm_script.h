/*
 * slurm_script: the batch scripts of the Slurm backend, readable files a
 * user can resubmit by hand.
 *
 *   runs/<study>/<key>/attempt-N/job.sbatch   one attempt: its resources as
 *       #SBATCH lines, stdout/stderr into the attempt's directory, cd to the
 *       study's directory, then the solver (through srun when ntasks > 1)
 *   runs/<study>/slurm/array-R.sbatch         an array of attempts with equal
 *       resources: task i runs the i-th job script of its list
 *
 * Every value in them was checked (slurm_spec.h) or is a path checked by
 * slurm_path_ok; shell words are single-quoted.
 */
#ifndef CASCADE_CAMPAIGN_SLURM_SCRIPT_H
#define CASCADE_CAMPAIGN_SLURM_SCRIPT_H

#include <stdio.h>

#include "launch.h"
#include "slurm_spec.h"

/* Whether a path may stand in an #SBATCH line (no blanks, quotes, '#',
 * '%', '$', '\\' or control characters). */
int slurm_path_ok(const char *path);

/* The resource options of a job ("--partition=x", ...), into opts (at most
 * max); returns how many.  The strings point into jr and sp. */
int slurm_res_args(const struct slurm_job_res *jr, const struct slurm_spec *sp, char (*buf)[160],
                   int max);

struct slurm_job_script {
    const char *study, *key, *job_name;
    int attempt;
    const struct launch_spec *L;
    const struct slurm_job_res *jr;
    const struct slurm_spec *sp;
};
int slurm_write_job_script(const char *path, const struct slurm_job_script *j, struct err *e);

struct slurm_array_script {
    const char *study, *job_name, *output;
    const char *const *job_scripts;
    int n;
    long throttle;            /* %N, 0: none */
    const struct slurm_job_res *jr;
    const struct slurm_spec *sp;
};
int slurm_write_array_script(const char *path, const struct slurm_array_script *a, struct err *e);

#endif
