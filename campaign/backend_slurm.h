/*
 * backend_slurm: job attempts as Slurm batch jobs, submitted from the
 * runner's host (a login node) as job arrays and followed with one squeue
 * call per poll interval for all of them.
 *
 * Creating the backend asks the cluster for its limits (`scontrol show
 * config`: MaxArraySize, MaxJobCount; `sacctmgr` MaxSubmitJobs when
 * accounting is on) and partitions, and checks every job's resources
 * against them (and with `sbatch --test-only` per group of equal
 * resources): a bad partition or a time limit over the partition's stops
 * the run before anything is written or submitted.
 *
 * start() writes the attempt's directory and its job.sbatch; wait()
 * submits what was started since the last call, one array per group of
 * equal resources (split at MaxArraySize), throttled with %max_running and
 * chained (afterany) to the array before it so that max_running holds for
 * the whole study; each array is submitted held, its ids are handed to the
 * runner (which records them), and only then released.  A runner that dies
 * leaves the jobs in Slurm; the next one adopts them (backend->adopt) by
 * the recorded ids.
 */
#ifndef CASCADE_CAMPAIGN_BACKEND_SLURM_H
#define CASCADE_CAMPAIGN_BACKEND_SLURM_H

#include <stdio.h>

#include "backend.h"
#include "plan.h"
#include "slurm_cli.h"

/* runs_root: the absolute runs directory.  Checks everything (see above). */
int backend_slurm_create(struct backend *b, const struct study *s, const struct plan *p,
                         const char *runs_root, struct err *e);

/* One line: attempts submitted, time per attempt to submit them (array
 * script, sbatch, recording the ids, release: the runner's "claim and
 * start" covers the directory and job script), polls and client calls per
 * poll. */
void backend_slurm_report(const struct backend *b, FILE *out);

#endif
