/* cascade run: run a study's jobs (locally or as rank 0 under mpirun). */
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "backend_mpi.h"
#include "cli.h"
#include "mpi_pool.h"
#include "refine_run.h"
#include "study_run.h"

static const char *usage =
    "usage: cascade run STUDY.yaml [--jobs N] [--db FILE] [--runs DIR] [--solver PATH]\n"
    "                  [--lease SECONDS] [--infra-pause SECONDS] [--backend local|slurm]\n"
    "                  [--quiet]\n"
    "       mpirun -np N cascade run STUDY.yaml [options]\n"
    "\n"
    "Runs every job of the study that is not yet done for the current solver\n"
    "version (so running it again resumes), each attempt in its own process group\n"
    "and directory RUNS/<study>/<key>/attempt-N/ (case.yaml, stdout, stderr,\n"
    "result.json and the solver's files; RUNS/<study>/<key>/current links to the\n"
    "latest recorded attempt), and records runs, metrics and files in the database.\n"
    "Failed, crashed and timed-out jobs are retried as the study's 'retries' says\n"
    "(a crash that repeats at the same step is not).  Infrastructure failures (a\n"
    "run directory that cannot be written, a full disk, a solver that cannot be\n"
    "started) use up no retries: the runner pauses (0.5 s, doubling) and tries\n"
    "again, one job at a time, and stops after 3 in a row, naming the cause.\n"
    "\n"
    "  --jobs N        jobs at a time (default: cores / (threads x mpirun ranks))\n"
    "  --db FILE       results database (default ./" CASCADE_DB_DEFAULT ")\n"
    "  --runs DIR      run directories (default ./runs)\n"
    "  --solver PATH   the solver (default: $CASCADE_SOLVER, or cascade-solver next\n"
    "                  to cascade, or on PATH)\n"
    "  --lease S       job lease length in seconds (default 60); a runner that stops\n"
    "                  heartbeating for that long loses its jobs to the next runner\n"
    "  --infra-pause S the pause after an infrastructure failure (default 0.5;\n"
    "                  doubling with each one in a row)\n"
    "  --backend B     local (child processes here) or slurm (job arrays submitted\n"
    "                  from this host; see docs/campaign.md); default: the study's\n"
    "                  'backend', else local\n"
    "  --quiet         no progress output\n"
    "\n"
    "Ctrl-C once: no new jobs, running ones finish; twice: running jobs are\n"
    "cancelled.  With Slurm, a hang-up (SIGHUP, a closed login) leaves the jobs\n"
    "in Slurm, and 'cascade run' again follows them (nothing is submitted twice).\n"
    "Under mpirun, rank 0 alone opens the database and ranks 1..N-1\n"
    "run the jobs.  Exit code 0 when every job is done, 1 when some failed or the\n"
    "runner had to stop (infrastructure, database), 2 on bad input (nothing is\n"
    "written then), 130 when interrupted.\n";

struct run_args {
    const char *file, *db_path, *runs, *solver, *backend;
    long jobs;
    double lease, infra_pause;
    int quiet;
};

static int parse(int argc, char **argv, struct run_args *a)
{
    memset(a, 0, sizeof *a);
    a->db_path = CASCADE_DB_DEFAULT;
    a->runs = "runs";
    a->lease = 60;
    for (int i = 0; i < argc; i++) {
        const char *v;
        int m;
        if ((m = cli_opt(argc, argv, &i, "--jobs", &v)) || (m = cli_opt(argc, argv, &i, "-j", &v))) {
            if (m < 0 || cli_int("--jobs", v, 1, 4096, &a->jobs) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--lease", &v))) {
            if (m < 0 || cli_real("--lease", v, 1, &a->lease) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--infra-pause", &v))) {
            if (m < 0 || cli_real("--infra-pause", v, 0.001, &a->infra_pause) != 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--db", &a->db_path)) ||
                   (m = cli_opt(argc, argv, &i, "--runs", &a->runs)) ||
                   (m = cli_opt(argc, argv, &i, "--solver", &a->solver))) {
            if (m < 0)
                return 2;
        } else if ((m = cli_opt(argc, argv, &i, "--backend", &a->backend))) {
            if (m < 0)
                return 2;
            if (strcmp(a->backend, "local") != 0 && strcmp(a->backend, "slurm") != 0)
                return cli_usage_error(usage, "--backend must be local or slurm, not '%s'",
                                       a->backend);
        } else if (strcmp(argv[i], "--quiet") == 0 || strcmp(argv[i], "-q") == 0) {
            a->quiet = 1;
        } else if (argv[i][0] != '-' && !a->file) {
            a->file = argv[i];
        } else {
            return cli_usage_error(usage, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!a->file)
        return cli_usage_error(usage, "give a study file");
    return 0;
}

static void print_summary(const struct study *s, const struct runner_summary *sum,
                          const char *db_path)
{
    printf("study %s: %ld job%s: %ld done (%ld earlier), %ld failed", s->name, sum->total,
           sum->total == 1 ? "" : "s", sum->done, sum->done_before, sum->failed);
    if (sum->cancelled)
        printf(", %ld cancelled", sum->cancelled);
    if (sum->not_run)
        printf(", %ld not run", sum->not_run);
    printf("; results in %s (cascade status %s)\n", db_path, s->name);
}

/* Everything rank 0 (or a local runner) does. */
static int run_study(const struct run_args *a, int mpi_size)
{
    struct err e = {0};
    struct study s;
    int rc = study_load(&s, a->file, &e);
    if (rc) {
        fprintf(stderr, "error: %s\n", e.msg);
        return cli_exit_code(rc);
    }
    if (a->backend)
        s.backend = strcmp(a->backend, "slurm") == 0 ? STUDY_BACKEND_SLURM : STUDY_BACKEND_LOCAL;
    if (s.backend == STUDY_BACKEND_SLURM && (s.mpirun_np || mpi_size > 1)) {
        fprintf(stderr, "error: %s: the Slurm backend runs MPI jobs with slurm.ntasks (srun), "
                        "not with the study's mpirun launcher or under mpirun\n",
                s.file);
        study_free(&s);
        return 2;
    }
    struct study_run_opts o = {a->db_path, a->runs,  a->solver, a->jobs,       a->lease,
                               a->quiet,   mpi_size, NULL,      NULL,          a->infra_pause};
    struct runner_summary sum;
    rc = study_run_any(&s, &o, &sum, &e);   /* a study with refine: adds levels as it goes */
    int code;
    if (rc) {
        if (sum.total)   /* the runner ran, then stopped: say how far it got */
            print_summary(&s, &sum, a->db_path);
        fprintf(stderr, "error: %s\n", e.msg);
        code = cli_exit_code(rc);
    } else {
        print_summary(&s, &sum, a->db_path);
        code = sum.interrupted ? 128 + sum.interrupted : (sum.failed || sum.not_run) ? 1 : 0;
    }
    study_free(&s);
    return code;
}

int cmd_run(int argc, char **argv)
{
    if (cli_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    struct run_args a;
    int rc = parse(argc, argv, &a);
    if (rc)
        return rc;
    /* signals are taken synchronously (sigtimedwait) from before the first child */
    backend_block_signals();
    if (!mpi_pool_wanted())
        return run_study(&a, 1);
    int rank = 0, size = 1;
    struct err e = {0};
    if (mpi_pool_init(NULL, NULL, &rank, &size, &e) != 0) {
        fprintf(stderr, "error: %s\n", e.msg);
        return 1;
    }
    int code;
    if (rank == 0) {
        code = run_study(&a, size);
        backend_mpi_stop_workers(size);
    } else {
        code = backend_mpi_worker();
    }
    mpi_pool_finalize();
    return code;
}
