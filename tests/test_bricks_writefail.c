/*
 * A file write that fails on one rank of a brick run stops every rank
 * (util/fault.h under mpirun): rank 0 writes thermo.csv and the serial
 * parts of fields.h5 and the checkpoints, every rank writes its own atoms
 * into them collectively (parallel HDF5); before, a failure on one rank
 * left the others waiting in the next exchange (or collective HDF5 call)
 * for a rank that had stopped, and mpirun hung.
 *
 * A 2-rank LJ run with every output on first counts its writes
 * (CASCADE_FAULT_WRITE=0: every rank prints its count; rank 0 has the
 * most), then runs again with the Nth write failing on every rank, N swept over the
 * count: under a 60 s timeout each run must end, with exit 1 and rank 0's
 * message when a write failed (exit 0 only when no write failed), and
 * leave no checkpoint .tmp behind.  The
 * sweep hits the checkpoint writes at both checkpoint steps and the
 * snapshots of fields.h5.
 */
#include <criterion/criterion.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/th.h"

static const char *case_text =
    "seed: 5\nsystem:\n  lattice: {style: fcc, a: 5.26, cells: [6, 6, 6]}\n  element: Ar\n"
    "potential: {style: lj, elements: [Ar], epsilon: [0.0104], sigma: [3.4], cutoff: 8.5}\n"
    "md: {steps: 20, temperature: 60, timestep: 0.002}\n"
    "parallel: {decomposition: bricks}\n"
    "output: {thermo_every: 5, snapshot_every: 10, checkpoint_every: 8}\n";

/* 2 ranks, CASCADE_FAULT_WRITE=spec, at most 60 s (124: timed out). */
static int run_2(const char *path, const char *dir, const char *spec, char *out, size_t len)
{
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMP_NUM_THREADS", "1", 1);
    setenv("ASAN_OPTIONS", "detect_leaks=0", 1);   /* Open MPI's components (test_bricks.c) */
    char env[64];
    snprintf(env, sizeof env, "CASCADE_FAULT_WRITE=%s", spec);
    const char *argv[] = {"/usr/bin/timeout", "60", "/usr/bin/mpirun", "-np", "2",
                          "--oversubscribe", "-x", env, th_solver(), "run", path, "--out", dir,
                          "--quiet", NULL};
    return th_run(argv, out, len);
}

/* The largest count over the ranks' fault reports; *failed: any failed. */
static long write_calls(const char *out, int *failed)
{
    static const char pat[] = "cascade-solver: fault injection: write: ";
    long most = -1;
    *failed = 0;
    for (const char *p = strstr(out, pat); p; p = strstr(p + 1, pat)) {
        char *end;
        long n = strtol(p + strlen(pat), &end, 10);
        const char *f = strstr(end, "failed ");
        cr_assert_not_null(f, "%s", out);
        *failed |= strtol(f + 7, NULL, 10) > 0;
        most = n > most ? n : most;
    }
    cr_assert_geq(most, 0, "no fault injection report in:\n%s", out);
    return most;
}

static int tmp_left(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int found = 0;
    struct dirent *de;
    while ((de = readdir(d)))
        if (strstr(de->d_name, ".h5.tmp") && strncmp(de->d_name, "checkpoint-", 11) == 0)
            found = 1;
    closedir(d);
    return found;
}

Test(bricks_writefail, every_rank_stops_when_one_cannot_write, .timeout = 900)
{
    const char *path = th_write_temp(0, "wf.yaml", case_text);
    static char out[65536];
    char dir[600];
    snprintf(dir, sizeof dir, "%s/wf-count", th_temp_dir());
    int rc = run_2(path, dir, "0", out, sizeof out);
    cr_assert_eq(rc, 0, "counting run: exit %d\n%s", rc, out);
    int failed;
    long total = write_calls(out, &failed);
    cr_assert_gt(total, 40, "only %ld writes counted", total);
    long step = total / 10 > 1 ? total / 10 : 1;
    int saw_checkpoint = 0, saw_fields = 0;
    for (long n = 1; n <= total + 1; n += step) {
        char spec[32];
        snprintf(spec, sizeof spec, "%ld", n);
        snprintf(dir, sizeof dir, "%s/wf-%ld", th_temp_dir(), n);
        rc = run_2(path, dir, spec, out, sizeof out);
        cr_assert_neq(rc, 124, "write %ld failing: the ranks hung (timeout)\n%s", n, out);
        cr_assert(rc == 0 || rc == 1, "write %ld failing: exit %d\n%s", n, rc, out);
        /* a rank that failed exits 1 and mpirun stops the job: the other
         * ranks' fault reports (printed after MPI_Finalize) may be cut
         * off, so only an exit 0 has every report, each saying 0 failed */
        if (rc == 0) {
            write_calls(out, &failed);
            cr_assert(!failed, "write %ld failing: exit 0 with a failed write\n%s", n, out);
        } else {
            const char *msg = strstr(out, "error: ");
            cr_assert_not_null(msg, "write %ld failing: no message\n%s", n, out);
            saw_checkpoint |= strstr(msg, "checkpoint-") != NULL;
            saw_fields |= strstr(msg, "fields.h5") != NULL;
        }
        cr_assert(!tmp_left(dir), "write %ld failing: a checkpoint .tmp is left in %s", n, dir);
    }
    cr_assert(saw_checkpoint, "no run of the sweep failed in a checkpoint");
    cr_assert(saw_fields, "no run of the sweep failed in fields.h5");
}
