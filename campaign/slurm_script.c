/* slurm_script: writing the batch scripts of the Slurm backend. */
#include "slurm_script.h"

#include <errno.h>
#include <string.h>

int slurm_path_ok(const char *p)
{
    if (!*p)
        return 0;
    for (const unsigned char *c = (const unsigned char *)p; *c; c++)
        if (*c <= ' ' || *c == 0x7f || strchr("'\"`#%$\\;&|<>*?!()[]{}", *c))
            return 0;
    return 1;
}

/* 'word' for the shell (a ' inside becomes '\'') */
static void put_quoted(FILE *f, const char *w)
{
    fputc('\'', f);
    for (const char *c = w; *c; c++) {
        if (*c == '\'')
            fputs("'\\''", f);
        else
            fputc(*c, f);
    }
    fputc('\'', f);
}

int slurm_res_args(const struct slurm_job_res *jr, const struct slurm_spec *sp, char (*buf)[160],
                   int max)
{
    int n = 0;
    for (int r = 0; r < SR_COUNT && n < max; r++)
        if (jr->v[r][0])
            snprintf(buf[n++], 160, "%s=%s", slurm_res_option((enum slurm_res)r), jr->v[r]);
    for (int i = 0; i < sp->nextra && n < max; i++)
        snprintf(buf[n++], 160, "%s", sp->extra[i]);
    return n;
}

static void put_res(FILE *f, const struct slurm_job_res *jr, const struct slurm_spec *sp)
{
    char opts[SR_COUNT + SLURM_EXTRA_MAX][160];
    int n = slurm_res_args(jr, sp, opts, SR_COUNT + SLURM_EXTRA_MAX);
    for (int i = 0; i < n; i++)
        fprintf(f, "#SBATCH %s\n", opts[i]);
}

static int finish(FILE *f, const char *path, struct err *e)
{
    int bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    return 0;
}

int slurm_write_job_script(const char *path, const struct slurm_job_script *j, struct err *e)
{
    const struct launch_spec *L = j->L;
    if (!slurm_path_ok(L->run_dir))
        return err_set(e, ERR_RUNTIME, "the run directory %s holds characters an #SBATCH line "
                                       "cannot carry (blanks, quotes, %%, #, $, ...): choose "
                                       "another --runs directory",
                       L->run_dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    fprintf(f, "#!/bin/bash\n"
               "# cascade: job %s of study %s, attempt %d (written by cascade run).\n"
               "# cascade submitted it as a task of an array (runs/%s/slurm/); to run this\n"
               "# attempt again by hand: sbatch %s\n"
               "# (cascade records only what it submitted itself).\n",
            j->key, j->study, j->attempt, j->study, path);
    fprintf(f, "#SBATCH --job-name=%s\n", j->job_name);
    fprintf(f, "#SBATCH --output=%s/slurm-%%j.out\n", L->run_dir);
    put_res(f, j->jr, j->sp);
    fputs("exec >", f);
    fprintf(f, "'%s/stdout' 2>'%s/stderr' </dev/null\n", L->run_dir, L->run_dir);
    fputs("cd ", f);
    put_quoted(f, L->cwd);
    fputs(" || exit 127\n", f);
    fputs("exec", f);
    if (j->jr->ntasks > 1)
        fprintf(f, " srun --ntasks=%ld --cpus-per-task=%ld", j->jr->ntasks,
                j->jr->cpus_per_task);
    for (int i = 0; i < L->argc; i++) {
        fputc(' ', f);
        put_quoted(f, L->argv[i]);
    }
    fputc('\n', f);
    return finish(f, path, e);
}

int slurm_write_array_script(const char *path, const struct slurm_array_script *a, struct err *e)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    fprintf(f, "#!/bin/bash\n"
               "# cascade: %d job%s of study %s with the same resources, as one Slurm array\n"
               "# (written by cascade run; submitted held, and released once the runner\n"
               "# recorded the ids).  Task i runs the job script on line i of the list,\n"
               "# each a batch script of its own in the attempt's directory.\n",
            a->n, a->n == 1 ? "" : "s", a->study);
    fprintf(f, "#SBATCH --job-name=%s\n", a->job_name);
    if (a->throttle > 0)
        fprintf(f, "#SBATCH --array=0-%d%%%ld\n", a->n - 1, a->throttle);
    else
        fprintf(f, "#SBATCH --array=0-%d\n", a->n - 1);
    fprintf(f, "#SBATCH --output=%s\n#SBATCH --open-mode=append\n", a->output);
    put_res(f, a->jr, a->sp);
    fputs("jobs=(\n", f);
    for (int i = 0; i < a->n; i++) {
        fputs("  ", f);
        put_quoted(f, a->job_scripts[i]);
        fputc('\n', f);
    }
    fputs(")\nexec /bin/bash \"${jobs[$SLURM_ARRAY_TASK_ID]}\"\n", f);
    return finish(f, path, e);
}
