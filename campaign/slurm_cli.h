/*
 * slurm_cli: running Slurm's client programs (sbatch, squeue, scontrol,
 * scancel, sacct) -- fork and exec with an argument vector, never a shell,
 * so no value reaches a command line other than as one whole argument.
 * Each program is looked up on PATH (a wrapper first in PATH sees every
 * call); the calls are counted per program, for the benchmark and the
 * tests that check the runner asks the controller O(1) times per poll.
 */
#ifndef CASCADE_CAMPAIGN_SLURM_CLI_H
#define CASCADE_CAMPAIGN_SLURM_CLI_H

#include <stddef.h>

#include "util/err.h"

enum slurm_prog { SP_SBATCH, SP_SQUEUE, SP_SCONTROL, SP_SCANCEL, SP_SACCT, SP_SACCTMGR, SP_COUNT };

struct slurm_cli {
    char **env;              /* owned array, borrowed strings (childenv) */
    long calls[SP_COUNT];
    double timeout_s;        /* a call that takes longer is killed */
};

int slurm_cli_init(struct slurm_cli *c, struct err *e);
void slurm_cli_fini(struct slurm_cli *c);
const char *slurm_prog_name(enum slurm_prog p);

/* Run prog with args (NULL-ended, without argv[0]).  *out receives stdout
 * (malloc'ed, NUL-ended; the caller frees), errtext the last of stderr,
 * *status the exit code (128 + signal when killed).  Returns ERR_RUNTIME
 * with e set when the program could not be run at all. */
int slurm_cli_run(struct slurm_cli *c, enum slurm_prog prog, const char *const *args, char **out,
                  char *errtext, size_t errlen, int *status, struct err *e);

#endif
