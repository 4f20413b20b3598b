/*
 * MPI mode: `mpirun -np 3 --oversubscribe cascade run` (rank 0 owns the
 * database, ranks 1 and 2 run the jobs) records the same rows as a local
 * run of the same study -- the same job keys, statuses and metric values --
 * with every run made by rank 0's runner; and the solver processes the
 * worker ranks start do not see the runner's OMPI_* / PMIX_* variables.
 * A local run is never an MPI process (it sets up no MPI at all).
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "helpers/ct.h"

static const char *study = "name: mpi\n"
                           "base: {fake: {action: env}}\n"
                           "sweep:\n"
                           "  grid:\n"
                           "    fake.x: [1, 2, 3, 4]\n"
                           "    fake.y: [0.5, 1.5]\n"
                           "  zip: {fake.action: [env, crash]}\n";

static const char *const mpi_env[] = {"OMPI_ALLOW_RUN_AS_ROOT=1",
                                      "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1",
                                      "OMPI_MCA_rmaps_base_oversubscribe=1", NULL};

/* key|status|metric=value ... for every job, in key order */
static void rows(const char *dir, char *out, size_t len)
{
    sqlite3 *db = ct_db(dir);
    sqlite3_stmt *st;
    cr_assert_eq(sqlite3_prepare_v2(db,
                                    "SELECT j.key || '|' || j.state || '|' || coalesce(("
                                    "SELECT group_concat(m.name || '=' || m.value, ' ') FROM "
                                    "(SELECT name, value FROM metrics WHERE run_id = j.last_run_id "
                                    "ORDER BY name) m), '') FROM jobs j ORDER BY j.key",
                                    -1, &st, NULL),
                 SQLITE_OK);
    out[0] = '\0';
    while (sqlite3_step(st) == SQLITE_ROW) {
        size_t used = strlen(out);
        snprintf(out + used, len - used, "%s\n", (const char *)sqlite3_column_text(st, 0));
    }
    sqlite3_finalize(st);
    sqlite3_close(db);
}

Test(campaign_mpi, same_rows_as_local, .timeout = 120)
{
    char local[64], mpi[64], out[16384];
    ct_mkdir(local, sizeof local);
    ct_mkdir(mpi, sizeof mpi);
    ct_write(0, local, "mpi.yaml", study);
    ct_write(1, mpi, "mpi.yaml", study);
    int rc = ct_cascade(local, NULL, out, sizeof out, "run", "mpi.yaml", "--solver", ct_standin(),
                        "--jobs", "2", NULL);
    cr_assert_eq(rc, 1, "8 crashing jobs must make the local run exit 1: %s", out);
    const char *argv[] = {"/usr/bin/mpirun", "-np", "3", "--oversubscribe", ct_cascade_bin(),
                          "run", "mpi.yaml", "--solver", ct_standin(), NULL};
    rc = ct_exec(mpi, mpi_env, argv, out, sizeof out);
    cr_assert_eq(rc, 1, "mpirun run: %s", out);
    char a[16384], b[16384];
    rows(local, a, sizeof a);
    rows(mpi, b, sizeof b);
    cr_assert_gt(strlen(a), 100);
    cr_assert_str_eq(a, b, "local:\n%s\nmpi:\n%s", a, b);
    sqlite3 *db = ct_db(mpi);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM jobs"), 16);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM runs WHERE status = 'crashed' AND signal = 11"), 8);
    cr_assert_eq(ct_int(db, "SELECT count(DISTINCT runner) FROM runs"), 1);
    /* the solvers the worker ranks started saw no MPI variables of the runner */
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'mpi_env' AND value = 0"),
                 8);
    sqlite3_close(db);
    ct_rmrf(local);
    ct_rmrf(mpi);
}

Test(campaign_mpi, mpirun_launcher_runs_each_job_under_mpirun, .timeout = 120)
{
    /* launcher: mpirun -np 2 -- the job is 2 processes of the stand-in, each
     * started by its own mpirun: there they do see MPI variables (so the
     * count is a real measurement), and the runner itself stays local */
    char dir[64], out[16384];
    ct_mkdir(dir, sizeof dir);
    ct_write(0, dir, "l.yaml",
             "name: launcher\n"
             "base: {fake: {action: env}}\n"
             "sweep: {grid: {fake.x: [1, 2]}}\n"
             "launcher: mpirun -np 2 --oversubscribe\n");
    int rc = ct_cascade(dir, mpi_env, out, sizeof out, "run", "l.yaml", "--solver", ct_standin(),
                        "--jobs", "1", NULL);
    cr_assert_eq(rc, 0, "%s", out);
    sqlite3 *db = ct_db(dir);
    cr_assert_eq(ct_int(db, "SELECT count(*) FROM results WHERE metric = 'mpi_env' AND value > 0"),
                 2);
    char launcher[128];
    ct_text(db, "SELECT launcher FROM runs LIMIT 1", launcher, sizeof launcher);
    cr_assert_str_eq(launcher, "mpirun -np 2 --oversubscribe");
    sqlite3_close(db);
    ct_rmrf(dir);
}
